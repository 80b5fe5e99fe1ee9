//! Frames rendered as jobs, after OSPRay's and ANARI's frame futures and the C ABI's
//! `rtRenderFrameAsync`: a client starts a frame, polls its progress while it does other work,
//! cancels it, or fetches its PNG when it is done, instead of waiting for minutes. A job renders
//! the scene as it was when the job started (frame semantics), queued and budgeted as any frame.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

use serde::Serialize;
use utoipa::ToSchema;

use crate::config::Limits;
use crate::error::{Error, ErrorDetail, Result};
use crate::stats::FrameReport;

/// A rendered frame.
pub struct Rendered {
    /// The PNG.
    pub png: Vec<u8>,
    /// What it cost.
    pub report: FrameReport,
}

/// One render job.
pub struct Job {
    id: u32,
    scene: u32,
    width: u32,
    height: u32,
    /// Rows finished so far.
    rows: Arc<AtomicU32>,
    /// `None` while it renders.
    outcome: Mutex<Option<Result<Rendered>>>,
    /// When it finished (rendered, failed or stopped).
    finished: OnceLock<Instant>,
    /// Stops the render (dropping its future cancels it) when the job is deleted.
    task: Mutex<Option<tokio::task::AbortHandle>>,
}

/// The render jobs of a server, by id.
#[derive(Default)]
pub struct Jobs {
    jobs: Mutex<BTreeMap<u32, Arc<Job>>>,
    /// Ids handed out: ids are never reused, so a deleted job's id stays unknown.
    issued: AtomicU32,
}

impl Jobs {
    /// A new job rendering a `width × height` frame of scene `scene`. At most
    /// [`Limits::max_render_jobs`] jobs are held at once, finished ones included until deleted or
    /// expired; past it the oldest finished job is dropped, and only if every job still renders
    /// is the new one refused (too large, naming the limit, as for `max_scenes`: the client holds
    /// them and must delete some).
    pub fn add(&self, scene: u32, width: u32, height: u32, limits: &Limits) -> Result<Arc<Job>> {
        let mut held = self.held(limits);
        if held.len() >= limits.max_render_jobs && !Jobs::drop_oldest_finished(&mut held, None) {
            let message = format!("the server holds {} render jobs, all still rendering, its limit: delete some first", limits.max_render_jobs);
            return Err(Error::too_large(None, message).limit("max_render_jobs"));
        }
        let id = self.issued.fetch_add(1, Ordering::Relaxed) + 1;
        let job = Arc::new(Job {
            id,
            scene,
            width,
            height,
            rows: Arc::default(),
            outcome: Mutex::new(None),
            finished: OnceLock::new(),
            task: Mutex::new(None),
        });
        held.insert(id, Arc::clone(&job));
        Ok(job)
    }

    /// Every job, by id.
    pub fn list(&self, limits: &Limits) -> Vec<Arc<Job>> {
        self.held(limits).values().cloned().collect()
    }

    /// Deletes the job `id` names, stopping its render if it is still running (its turn and
    /// memory go to the next render once the work has stopped).
    pub fn delete(&self, id: &str, limits: &Limits) -> Result<()> {
        let job = self.get(id, limits)?;
        self.jobs.lock().unwrap_or_else(|e| e.into_inner()).remove(&job.id);
        if let Some(task) = job.task.lock().unwrap_or_else(|e| e.into_inner()).take() {
            task.abort();
        }
        Ok(())
    }

    /// Stops the jobs still rendering scene `scene`, which was deleted: each fails with that
    /// reason (and stays listed until deleted, so a client polling it learns why), and its render
    /// stops at once instead of running on to the time limit.
    pub fn stop_scene(&self, scene: u32) {
        let held: Vec<Arc<Job>> = self.jobs.lock().unwrap_or_else(|e| e.into_inner()).values().filter(|j| j.scene == scene).cloned().collect();
        for job in held {
            let mut outcome = job.outcome.lock().unwrap_or_else(|e| e.into_inner());
            if outcome.is_none() {
                *outcome = Some(Err(Error::not_found(Some("scene".into()), format!("scene {scene} was deleted while the job rendered"))));
                let _ = job.finished.set(Instant::now());
                if let Some(task) = job.task.lock().unwrap_or_else(|e| e.into_inner()).take() {
                    task.abort();
                }
            }
        }
    }

    /// The job `id` names (not found if there is none, or it expired).
    pub fn get(&self, id: &str, limits: &Limits) -> Result<Arc<Job>> {
        let unknown = || {
            let expiry = limits.job_expiry_seconds;
            Error::not_found(Some("id".into()), format!("unknown render job {id} (a finished job is kept {expiry} s, or until newer ones need its room)"))
        };
        let id: u32 = id.parse().map_err(|_| unknown())?;
        self.held(limits).get(&id).cloned().ok_or_else(unknown)
    }

    /// The jobs, those that expired dropped first (see [`Limits::job_expiry_seconds`]).
    fn held(&self, limits: &Limits) -> std::sync::MutexGuard<'_, BTreeMap<u32, Arc<Job>>> {
        let mut jobs = self.jobs.lock().unwrap_or_else(|e| e.into_inner());
        let expiry = Duration::from_secs(limits.job_expiry_seconds);
        jobs.retain(|_, job| job.finished.get().is_none_or(|at| at.elapsed() < expiry));
        jobs
    }

    /// Drops the finished job that finished first, other than `keep`; false if there is none.
    fn drop_oldest_finished(jobs: &mut BTreeMap<u32, Arc<Job>>, keep: Option<u32>) -> bool {
        let oldest = jobs.values().filter(|j| Some(j.id) != keep).filter_map(|j| Some((*j.finished.get()?, j.id))).min();
        oldest.is_some_and(|(_, id)| jobs.remove(&id).is_some())
    }

    /// Records `job`'s outcome. A rendered image that would take the finished jobs' images past
    /// [`Limits::max_job_image_bytes`] drops the oldest finished jobs first, and fails the job
    /// (413 naming the limit) if it alone is larger.
    pub fn finish(&self, job: &Job, outcome: Result<Rendered>, limits: &Limits) {
        let budget = limits.max_job_image_bytes;
        let outcome = outcome.and_then(|mut rendered| {
            // Kept for minutes: without the room the encoder left to grow into.
            rendered.png.shrink_to_fit();
            if rendered.png.len() > budget {
                let message = format!("the frame's PNG is {} bytes, more than the {budget} finished render jobs may hold", rendered.png.len());
                return Err(Error::too_large(None, message).limit("max_job_image_bytes"));
            }
            let mut jobs = self.held(limits);
            let image_bytes = |jobs: &BTreeMap<u32, Arc<Job>>| -> usize { jobs.values().filter(|j| j.id != job.id).map(|j| j.image_bytes()).sum() };
            while image_bytes(&jobs) + rendered.png.len() > budget && Self::drop_oldest_finished(&mut jobs, Some(job.id)) {}
            Ok(rendered)
        });
        let mut slot = job.outcome.lock().unwrap_or_else(|e| e.into_inner());
        // A job stopped meanwhile (its scene deleted) keeps that reason.
        if slot.is_none() {
            *slot = Some(outcome);
        }
        let _ = job.finished.set(Instant::now());
        drop(slot);
        // The render's film and buffers are gone; its PNG stays for minutes, and is counted.
        crate::budget::give_back_memory();
    }
}

/// Where a job is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum JobStatus {
    /// Waiting for its turn or rendering.
    Running,
    /// Its image is ready.
    Done,
    /// It failed (`error` says why).
    Failed,
}

/// A render job as the API shows it.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct RenderJobInfo {
    /// Its id.
    pub id: u32,
    /// The scene it renders.
    pub scene: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Where it is.
    pub status: JobStatus,
    /// The share of the image's rows rendered, 0 to 1 (never decreasing).
    pub progress: f32,
    /// Why it failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<ErrorDetail>,
    /// What the frame cost, once done.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub report: Option<FrameReport>,
}

impl Job {
    /// The bytes of its PNG, once rendered.
    fn image_bytes(&self) -> usize {
        match &*self.outcome.lock().unwrap_or_else(|e| e.into_inner()) {
            Some(Ok(rendered)) => rendered.png.len(),
            _ => 0,
        }
    }

    /// Its id.
    pub fn id(&self) -> u32 {
        self.id
    }

    /// The count of its rows finished, which its render adds to.
    pub fn rows(&self) -> Arc<AtomicU32> {
        Arc::clone(&self.rows)
    }

    /// Stops `task`, the job's render, when the job is deleted or its scene is.
    pub fn set_task(&self, task: tokio::task::AbortHandle) {
        *self.task.lock().unwrap_or_else(|e| e.into_inner()) = Some(task);
    }

    /// Its PNG once rendered, or why it failed; `None` while it renders.
    pub fn image(&self) -> Option<std::result::Result<Vec<u8>, String>> {
        match &*self.outcome.lock().unwrap_or_else(|e| e.into_inner()) {
            Some(Ok(rendered)) => Some(Ok(rendered.png.clone())),
            Some(Err(e)) => Some(Err(e.detail.message.clone())),
            None => None,
        }
    }

    /// The job as the API shows it.
    pub fn info(&self) -> RenderJobInfo {
        let outcome = self.outcome.lock().unwrap_or_else(|e| e.into_inner());
        let (status, error, report) = match &*outcome {
            None => (JobStatus::Running, None, None),
            Some(Ok(rendered)) => (JobStatus::Done, None, Some(rendered.report.clone())),
            Some(Err(e)) => (JobStatus::Failed, Some(e.detail.clone()), None),
        };
        let rows = self.rows.load(Ordering::Relaxed) as f32 / self.height as f32;
        let progress = if status == JobStatus::Done { 1.0 } else { rows.min(1.0) };
        RenderJobInfo { id: self.id, scene: self.scene, width: self.width, height: self.height, status, progress, error, report }
    }
}
