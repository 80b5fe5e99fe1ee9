//! `/scenes/{scene}/renders` and `/renders/{id}`: frames rendered as jobs, after OSPRay's and
//! ANARI's frame futures and the C ABI's `rtRenderFrameAsync`. A client starts a frame, polls its
//! progress while it does other work, cancels it, or fetches its PNG when it is done, instead of
//! holding a request open for minutes. A job renders from the scene as it was when the job
//! started (frame semantics), queued and budgeted as `frame.png` is.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

use axum::Json;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use utoipa::ToSchema;

use crate::config::Limits;
use crate::error::{ApiError, ApiResult, ErrorBody, ErrorDetail};
use crate::extract::{Params, Target};
use crate::render::{FrameQuery, Rendered, render_png};
use crate::state::AppState;
use crate::stats::FrameReport;

/// One render job.
pub(crate) struct Job {
    id: u32,
    scene: u32,
    width: u32,
    height: u32,
    /// Rows finished so far.
    rows: Arc<AtomicU32>,
    /// `None` while it renders.
    outcome: Mutex<Option<ApiResult<Rendered>>>,
    /// When it finished (rendered, failed or stopped).
    finished: OnceLock<Instant>,
    /// Stops the render (dropping its future cancels it) when the job is deleted.
    task: Mutex<Option<tokio::task::AbortHandle>>,
}

/// The render jobs of a server, by id.
#[derive(Default)]
pub(crate) struct Jobs {
    jobs: Mutex<BTreeMap<u32, Arc<Job>>>,
    /// Ids handed out: ids are never reused, so a deleted job's id stays unknown.
    issued: AtomicU32,
}

impl Jobs {
    /// Stops the jobs still rendering scene `scene`, which was deleted: each fails with that
    /// reason (and stays listed until deleted, so a client polling it learns why), and its render
    /// stops at once instead of running on to the time limit.
    pub(crate) fn stop_scene(&self, scene: u32) {
        let held: Vec<Arc<Job>> = self.jobs.lock().unwrap_or_else(|e| e.into_inner()).values().filter(|j| j.scene == scene).cloned().collect();
        for job in held {
            let mut outcome = job.outcome.lock().unwrap_or_else(|e| e.into_inner());
            if outcome.is_none() {
                *outcome = Some(Err(ApiError::not_found(Some("scene".into()), format!("scene {scene} was deleted while the job rendered"))));
                let _ = job.finished.set(Instant::now());
                if let Some(task) = job.task.lock().unwrap_or_else(|e| e.into_inner()).take() {
                    task.abort();
                }
            }
        }
    }

    fn get(&self, id: &str, limits: &Limits) -> ApiResult<Arc<Job>> {
        let unknown = || {
            let expiry = limits.job_expiry_seconds;
            ApiError::not_found(Some("id".into()), format!("unknown render job {id} (a finished job is kept {expiry} s, or until newer ones need its room)"))
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
    fn finish(&self, job: &Job, outcome: ApiResult<Rendered>, limits: &Limits) {
        let budget = limits.max_job_image_bytes;
        let outcome = outcome.and_then(|rendered| {
            if rendered.png.len() > budget {
                let message = format!("the frame's PNG is {} bytes, more than the {budget} finished render jobs may hold", rendered.png.len());
                return Err(ApiError::too_large(None, message).limit("max_job_image_bytes"));
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

    fn info(&self) -> RenderJobInfo {
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

/// Starts rendering a frame of the scene (the query as `frame.png` takes it) and answers at
/// once, 202 with the job; `Location` names it. At most `max_render_jobs` jobs are held at once,
/// finished ones included until deleted or expired; past it the oldest finished job is dropped,
/// and only if every job still renders is the new one refused (413 naming the limit, as for
/// `max_scenes`: the client holds them and must delete some, so it is not the server failing,
/// which a 5xx would say).
#[utoipa::path(post, path = "/scenes/{scene}/renders", tag = "frames",
    params(("scene" = u32, Path, description = "The scene's id"), FrameQuery),
    responses(
        (status = 202, description = "Started", body = RenderJobInfo),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
        (status = 413, description = "As many render jobs as the server holds", body = ErrorBody),
    ))]
pub(crate) async fn start(State(state): State<AppState>, target: Target, Params(query): Params<FrameQuery>) -> ApiResult<Response> {
    let limits = state.config().limits;
    let frame = query.check(&limits)?;
    let jobs = state.jobs();
    let job = {
        let mut held = jobs.held(&limits);
        if held.len() >= limits.max_render_jobs && !Jobs::drop_oldest_finished(&mut held, None) {
            let message = format!("the server holds {} render jobs, all still rendering, its limit: delete some first", limits.max_render_jobs);
            return Err(ApiError::too_large(None, message).limit("max_render_jobs"));
        }
        let id = jobs.issued.fetch_add(1, Ordering::Relaxed) + 1;
        let job = Arc::new(Job {
            id,
            scene: target.scene.id,
            width: frame.render.width,
            height: frame.render.height,
            rows: Arc::default(),
            outcome: Mutex::new(None),
            finished: OnceLock::new(),
            task: Mutex::new(None),
        });
        held.insert(id, Arc::clone(&job));
        job
    };
    // The job takes its turns as the connection that made it: a backlog of jobs is one client's.
    let (runner, slot, client) = (Arc::clone(&job), target.scene, target.client);
    // Frame semantics: the job renders the scene as it is now, whatever is edited meanwhile.
    let _ = slot.follow_clock(&state).await;
    let snapshot = slot.snapshot().await;
    let task = tokio::spawn(async move {
        let outcome = render_png(&state, &slot, client, Some(snapshot), frame, Arc::clone(&runner.rows)).await;
        state.jobs().finish(&runner, outcome, &state.config().limits);
    });
    *job.task.lock().unwrap_or_else(|e| e.into_inner()) = Some(task.abort_handle());
    let location = format!("/renders/{}", job.id);
    Ok((StatusCode::ACCEPTED, [(header::LOCATION, location)], Json(job.info())).into_response())
}

/// Every render job, by id.
#[utoipa::path(get, path = "/renders", tag = "frames", responses((status = 200, description = "Success", body = [RenderJobInfo])))]
pub(crate) async fn list(State(state): State<AppState>) -> Json<Vec<RenderJobInfo>> {
    let jobs: Vec<Arc<Job>> = state.jobs().held(&state.config().limits).values().cloned().collect();
    Json(jobs.iter().map(|j| j.info()).collect())
}

/// A render job: its status and progress, and once done its statistics.
#[utoipa::path(get, path = "/renders/{id}", tag = "frames",
    params(("id" = u32, Path, description = "The job's id")),
    responses(
        (status = 200, description = "Success", body = RenderJobInfo),
        (status = 404, description = "No such job", body = ErrorBody),
    ))]
pub(crate) async fn get(State(state): State<AppState>, Path(id): Path<String>) -> ApiResult<Json<RenderJobInfo>> {
    Ok(Json(state.jobs().get(&id, &state.config().limits)?.info()))
}

/// A finished job's image, as PNG (409 while it renders, or if it failed).
#[utoipa::path(get, path = "/renders/{id}/image.png", tag = "frames",
    params(("id" = u32, Path, description = "The job's id")),
    responses(
        (status = 200, description = "The frame", content_type = "image/png", body = crate::model::Binary),
        (status = 404, description = "No such job", body = ErrorBody),
        (status = 409, description = "Not done: still rendering, or failed", body = ErrorBody),
    ))]
pub(crate) async fn image(State(state): State<AppState>, Path(id): Path<String>) -> ApiResult<Response> {
    let job = state.jobs().get(&id, &state.config().limits)?;
    let outcome = job.outcome.lock().unwrap_or_else(|e| e.into_inner());
    match &*outcome {
        Some(Ok(rendered)) => Ok(([(header::CONTENT_TYPE, "image/png"), (header::CACHE_CONTROL, "no-store")], rendered.png.clone()).into_response()),
        Some(Err(e)) => Err(ApiError::conflict(format!("render job {id} failed: {}", e.detail.message))),
        None => Err(ApiError::conflict(format!("render job {id} is still rendering: poll /renders/{id} until its status is done"))),
    }
}

/// Deletes a job, stopping its render if it is still running (its turn and memory go to the
/// next render once the work has stopped).
#[utoipa::path(delete, path = "/renders/{id}", tag = "frames",
    params(("id" = u32, Path, description = "The job's id")),
    responses(
        (status = 204, description = "Deleted"),
        (status = 404, description = "No such job", body = ErrorBody),
    ))]
pub(crate) async fn delete(State(state): State<AppState>, Path(id): Path<String>) -> ApiResult<StatusCode> {
    let jobs = state.jobs();
    let job = jobs.get(&id, &state.config().limits)?;
    jobs.jobs.lock().unwrap_or_else(|e| e.into_inner()).remove(&job.id);
    if let Some(task) = job.task.lock().unwrap_or_else(|e| e.into_inner()).take() {
        task.abort();
    }
    Ok(StatusCode::NO_CONTENT)
}
