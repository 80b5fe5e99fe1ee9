//! # raystage-cluster
//!
//! Serving from every rank of a cluster (`mpirun -n N raystage serve --mpi`), as OpenRT served
//! its applications from a cluster: rank 0 runs the server, every other rank is a render
//! worker ([`work`]) holding a replica of every scene. Rank 0's [`Cluster`] is the service's
//! [`Workers`]; a C program's scene reaches the workers through a [`Mirror`] (`rtInitMPI`).
//!
//! - **Edits** are replicated as they happen: rank 0 applies an [`Edit`] under the scene's
//!   write lock, sends the same value to every worker, each applies it and answers, and rank 0
//!   tells all whether it stands (every rank applied it) or is refused everywhere (some rank
//!   could not). Every rank so holds the same scene at the same version; files (images, glTF)
//!   go once, as the client sent them.
//! - **Frames** are progressive passes: every rank adds the pass's samples to its share of the
//!   frame (the static interleave of tiles of [`Share`]: no messages while it renders)
//!   and rank 0 gathers the shares' pixel means into the film. Streams accumulate across ranks
//!   as on one machine, and the image is the one a single process renders, to the bit.
//! - **One exchange at a time**: the messages of an edit or a pass go out and their answers
//!   come back under one lock, so that every worker sees them in one order; renders wait for
//!   each other here, as a cluster renders one frame at a time with all its ranks.
//! - **Faults**: a worker that does not answer, or take rank 0's message, within the timeout
//!   is given up: rank 0 says so in its log and in the error of that request, and serves alone
//!   from then on (its scenes are whole, the workers' replicas are only copies). A worker that
//!   dies makes `mpirun` end the whole job. A worker that refuses an edit (an error where rank
//!   0 had none) has it refused everywhere.
//!
//! The messages travel over a [`Transport`] (MPI with the `mpi` feature, `MpiTransport`;
//! channels between threads in the tests), encoded as CBOR: compact, and self-describing enough
//! for the API's untagged values. Nothing here speaks HTTP: the C library joins a cluster
//! without linking the HTTP server.

#[cfg(feature = "mpi")]
mod mpi;
mod wire;
mod worker;

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use raystage_render::{Cancel, Error as RenderError, Film, FrameStats, Progressive, RenderSettings, Share};
use raystage_scene::{Frame, SceneEdit};

use raystage_service::{Accumulate, ClusterTimes, Edit, Error, SceneBuild, SceneStart, Workers};
use wire::{Message, PassMessage, Reply, decode, encode};
pub use worker::work;
#[cfg(feature = "mpi")]
pub use mpi::{MpiJob, MpiTransport};

/// How rank 0 and the workers exchange messages: MPI, in the command line.
pub trait Transport: Send + Sync + 'static {
    /// This process's rank: 0 serves, the others are workers.
    fn rank(&self) -> u32;
    /// Processes in the job, this one included.
    fn ranks(&self) -> u32;
    /// Sends `message` to `rank`, waiting until `deadline` at most (`None`: as long as it
    /// takes) for the transport to take it; `Ok(false)` if the deadline passed first (the
    /// message may still arrive later, or never).
    fn send(&self, rank: u32, message: &[u8], deadline: Option<Instant>) -> Result<bool, String>;
    /// The next message from `rank`, waiting until `deadline` at most (`None`: as long as it
    /// takes); `Ok(None)` if the deadline passed first.
    fn receive(&self, rank: u32, deadline: Option<Instant>) -> Result<Option<Vec<u8>>, String>;
}

/// Rank 0's side of a cluster: the workers, and whether they still answer.
pub struct Cluster {
    transport: Box<dyn Transport>,
    /// How long rank 0 waits for a worker's answer before giving it up.
    timeout: Duration,
    /// Held for each exchange; `Some(why)` once the workers were given up.
    link: Mutex<Option<String>>,
    /// Keys of accumulations (see [`Accumulator`]).
    next_key: AtomicU64,
    /// Accumulations ended since the last pass: their workers' state is dropped with the next.
    ended: Mutex<Vec<u64>>,
}

impl Cluster {
    /// Rank 0's side of the job `transport` reaches, giving up a worker that takes longer
    /// than `timeout` to answer.
    pub fn new(transport: Box<dyn Transport>, timeout: Duration) -> Arc<Cluster> {
        Arc::new(Cluster { transport, timeout, link: Mutex::new(None), next_key: AtomicU64::new(1), ended: Mutex::default() })
    }

    /// Ends the job's workers (they return from [`work`]); `Err` with why if they were given
    /// up: then they cannot be reached, and the job must be aborted.
    pub fn stop(&self) -> Result<(), String> {
        let mut link = self.lock();
        if let Some(why) = link.as_ref() {
            return Err(why.clone());
        }
        self.send_all(&mut link, &encode(&Message::<&Edit>::Stop)).map(|_| ())
    }

    fn lock(&self) -> MutexGuard<'_, Option<String>> {
        self.link.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Sends `message` to every worker; gives them up on a failure, or if one does not take
    /// it in time (a worker that stopped, alive but not receiving, would otherwise hold rank 0
    /// in its send once MPI's buffers towards it are full). Returns the seconds taken.
    fn send_all(&self, link: &mut Option<String>, message: &[u8]) -> Result<f64, String> {
        let start = Instant::now();
        let deadline = start + self.timeout;
        for rank in 1..self.transport.ranks() {
            match self.transport.send(rank, message, Some(deadline)) {
                Ok(true) => {}
                Ok(false) => return Err(self.give_up(link, format!("rank {rank} did not take a message within {} s", self.timeout.as_secs_f64()))),
                Err(e) => return Err(self.give_up(link, format!("cannot send to rank {rank}: {e}"))),
            }
        }
        Ok(start.elapsed().as_secs_f64())
    }

    /// Every worker's answer, in rank order; gives them up if one does not answer in time.
    fn collect(&self, link: &mut Option<String>) -> Result<Vec<Reply>, String> {
        let deadline = Instant::now() + self.timeout;
        let mut replies = Vec::new();
        for rank in 1..self.transport.ranks() {
            let reply = match self.transport.receive(rank, Some(deadline)) {
                Ok(Some(bytes)) => decode::<Reply>(&bytes).map_err(|e| format!("rank {rank} answered with a message that cannot be read: {e}")),
                Ok(None) => Err(format!("rank {rank} did not answer within {} s", self.timeout.as_secs_f64())),
                Err(e) => Err(format!("cannot receive from rank {rank}: {e}")),
            };
            match reply {
                Ok(reply) => replies.push(reply),
                Err(why) => return Err(self.give_up(link, why)),
            }
        }
        Ok(replies)
    }

    /// Gives the workers up for `why`, once, saying so in the log; returns the message.
    fn give_up(&self, link: &mut Option<String>, why: String) -> String {
        let message = format!("{why}: the cluster's workers are given up, rank 0 renders alone from now on");
        eprintln!("error: {message}");
        *link = Some(message.clone());
        message
    }
}

/// Rank 0's side of a cluster, as the service's scenes are replicated and their frames
/// rendered (see [`Workers`] for what each call does).
impl Workers for Cluster {
    fn ranks(&self) -> u32 {
        if self.lock().is_some() { 1 } else { self.transport.ranks() }
    }

    fn replicate(&self, message: &[u8]) -> raystage_service::Result<()> {
        let mut link = self.lock();
        if link.is_some() {
            return Ok(());
        }
        if self.send_all(&mut link, message).is_err() {
            return Ok(());
        }
        let Ok(replies) = self.collect(&mut link) else { return Ok(()) };
        let refused = replies.iter().enumerate().find_map(|(i, r)| match r {
            Reply::Refused(why) => Some(format!("rank {} could not apply the edit: {why}", i + 1)),
            Reply::Applied => None,
            _ => Some(format!("rank {} answered the edit out of turn", i + 1)),
        });
        let _ = self.send_all(&mut link, &encode(&Message::<&Edit>::Verdict { stands: refused.is_none() }));
        match refused {
            None => Ok(()),
            Some(why) => Err(Error::internal(format!("{why}; the edit is refused on every rank"))),
        }
    }

    fn edit_message(&self, scene: u32, edit: &Edit) -> Vec<u8> {
        encode(&Message::Edit { scene, edit })
    }

    fn replicate_new_scene(&self, id: u32, origin: &str, build: &SceneBuild) -> raystage_service::Result<()> {
        self.replicate(&encode(&Message::<&Edit>::NewScene { id, origin: origin.to_string(), build: build.clone() }))
    }

    fn replicate_delete(&self, id: u32) {
        if let Err(e) = self.replicate(&encode(&Message::<&Edit>::DeleteScene { id })) {
            eprintln!("warning: deleting scene {id} on the workers: {}", e.detail.message);
        }
    }

    fn accumulate(self: Arc<Self>, settings: RenderSettings) -> Result<Box<dyn Accumulate>, RenderError> {
        Ok(Box::new(Accumulator::new(settings, &self)?))
    }
}

/// A scene an application holds itself (the C ABI's `rtInitMPI`), kept on every worker as
/// scene 1: the edits the application made since the last frame (its scene's journal) go to the
/// workers when a frame starts, and the frame renders across the ranks.
pub struct Mirror {
    cluster: Arc<Cluster>,
    /// The workers' replica's version: one more with each non-empty journal.
    version: u64,
}

impl Mirror {
    /// The scene the workers mirror.
    const SCENE: u32 = 1;

    /// Makes the workers' replica: an empty scene, as the application's starts.
    pub fn new(cluster: Arc<Cluster>) -> Result<Mirror, String> {
        let build = SceneBuild { start: SceneStart::Empty, environment: None };
        cluster.replicate_new_scene(Mirror::SCENE, "application", &build).map_err(|e| e.detail.message)?;
        Ok(Mirror { cluster, version: 0 })
    }

    /// Ranks rendering now: all of the job's, or 1 once the workers were given up.
    pub fn ranks(&self) -> u32 {
        self.cluster.ranks()
    }

    /// Starts the workers' replica over, empty (the application's scene was).
    pub fn restart(&mut self) -> Result<(), String> {
        self.cluster.replicate_delete(Mirror::SCENE);
        let build = SceneBuild { start: SceneStart::Empty, environment: None };
        self.cluster.replicate_new_scene(Mirror::SCENE, "application", &build).map_err(|e| e.detail.message)?;
        self.version = 0;
        Ok(())
    }

    /// The cluster, to stop it when the application is done.
    pub fn cluster(&self) -> &Arc<Cluster> {
        &self.cluster
    }

    /// Sends `edits` (the application's scene's journal since the last call) to every worker;
    /// `Err` naming the rank that could not replay them (the replicas then differ: no frame can
    /// be rendered across the ranks, and none is).
    pub fn sync(&mut self, edits: Vec<SceneEdit>) -> Result<(), String> {
        if edits.is_empty() {
            return Ok(());
        }
        let edit = Edit::Journal { edits };
        self.cluster.replicate(&self.cluster.edit_message(Mirror::SCENE, &edit)).map_err(|e| e.detail.message)?;
        self.version += 1;
        Ok(())
    }

    /// Renders `frame` (of the scene as the workers hold it after [`Mirror::sync`]) with every
    /// rank: one pass of all its samples, the image the one this process would render alone.
    pub fn render(&self, frame: &Frame<'_>, settings: RenderSettings) -> Result<(Film, FrameStats, Option<ClusterTimes>), RenderError> {
        let mut accumulator = Accumulator::new(settings, &self.cluster)?;
        let stats = accumulator.add(Mirror::SCENE, frame, self.version, settings.samples_per_pixel, true, &Cancel::new())?;
        Ok((accumulator.film(), stats, accumulator.times()))
    }
}

/// An accumulation of samples rendered by every rank of a cluster, or by rank 0 alone once the
/// cluster failed: the stream's and `frame.png`'s renders in a cluster, and a C program's frames.
struct Accumulator {
    progressive: Progressive,
    /// The cluster rendering it and the accumulation's key there; `None` alone.
    cluster: Option<(Arc<Cluster>, u64)>,
    /// The whole image, the workers' shares included (in a cluster).
    film: Option<Film>,
    /// What the last pass cost on rank 0.
    times: Option<ClusterTimes>,
}

impl Accumulator {
    /// An empty accumulation of `settings`, across `cluster`'s ranks if its workers still
    /// answer.
    fn new(settings: RenderSettings, cluster: &Arc<Cluster>) -> Result<Accumulator, RenderError> {
        let cluster = Some(cluster).filter(|c| c.ranks() > 1);
        let mut progressive = Progressive::new(settings)?;
        let cluster = match cluster {
            Some(cluster) => {
                progressive = progressive.with_share(Share { index: 0, count: cluster.transport.ranks() })?;
                Some((Arc::clone(cluster), cluster.next_key.fetch_add(1, Ordering::Relaxed)))
            }
            None => None,
        };
        Ok(Accumulator { progressive, cluster, film: None, times: None })
    }

    /// Goes on alone, from an empty image.
    fn alone(&mut self) -> Result<(), RenderError> {
        let settings = *self.progressive.settings();
        self.forget();
        *self = Accumulator { progressive: Progressive::new(settings)?, cluster: None, film: None, times: None };
        Ok(())
    }

    fn add_across(&mut self, cluster: &Cluster, key: u64, (scene_id, frame, version): (u32, &Frame<'_>, u64), samples: u32, last: bool, cancel: &Cancel) -> Result<FrameStats, Failed> {
        let mut link = cluster.lock();
        if let Some(why) = link.as_ref() {
            return Err(Failed::Cluster(why.clone()));
        }
        let ended = std::mem::take(&mut *cluster.ended.lock().unwrap_or_else(|e| e.into_inner()));
        let pass = PassMessage {
            key,
            scene: scene_id,
            version,
            settings: *self.progressive.settings(),
            samples,
            reset: self.progressive.samples() == 0,
            last,
            ended,
        };
        let send_seconds = cluster.send_all(&mut link, &encode(&Message::<&Edit>::Pass(pass))).map_err(Failed::Cluster)?;
        let start = Instant::now();
        let own = self.progressive.add_cancellable(frame, samples, cancel);
        let render_seconds = start.elapsed().as_secs_f64();
        // Collected even when rank 0's share was cancelled: the workers answer every pass.
        let replies = cluster.collect(&mut link).map_err(Failed::Cluster)?;
        drop(link);
        let gather_seconds = start.elapsed().as_secs_f64() - render_seconds;
        let mut stats = own.map_err(Failed::Render)?;
        let ranks = cluster.transport.ranks();
        let mut film = self.progressive.film();
        let mut times = ClusterTimes { ranks, send_seconds, render_seconds, gather_seconds, ..ClusterTimes::default() };
        for (i, reply) in replies.into_iter().enumerate() {
            let rank = i as u32 + 1;
            let share = Share { index: rank, count: ranks };
            let (values, counts, seconds) = match reply {
                Reply::Share { pixels, counts, seconds } => (pixels, counts, seconds),
                Reply::Failed(why) => return Err(Failed::Cluster(format!("rank {rank}: {why}"))),
                _ => return Err(Failed::Cluster(format!("rank {rank} answered the pass out of turn"))),
            };
            let floats: Vec<f32> = values.0.chunks_exact(4).map(|b| f32::from_le_bytes(b.try_into().expect("four bytes"))).collect();
            if values.0.len() % 4 != 0 || !film.set_share_values(share, &floats) {
                let owned = share.pixel_count(film.width(), film.height());
                return Err(Failed::Cluster(format!("rank {rank} sent {} bytes for its share of {owned} pixels", values.0.len())));
            }
            stats.add_share_counts(counts);
            times.slowest_share_seconds = times.slowest_share_seconds.max(seconds);
            times.gathered_bytes += values.0.len() as u64;
        }
        self.film = Some(film);
        self.times = Some(times);
        if last {
            // The workers dropped it with this pass.
            self.cluster = None;
        }
        Ok(stats)
    }

    /// Tells the workers (with the next pass) that this accumulation's state can go.
    fn forget(&mut self) {
        if let Some((cluster, key)) = self.cluster.take() {
            cluster.ended.lock().unwrap_or_else(|e| e.into_inner()).push(key);
        }
    }
}

impl Accumulate for Accumulator {
    fn settings(&self) -> &RenderSettings {
        self.progressive.settings()
    }

    fn samples(&self) -> u32 {
        self.progressive.samples()
    }

    fn film(&self) -> Film {
        self.film.clone().unwrap_or_else(|| self.progressive.film())
    }

    fn times(&self) -> Option<ClusterTimes> {
        self.times
    }

    /// Rank 0's share stops soon after `cancel` says so (the workers finish theirs: they are
    /// not reached while they render). If the cluster fails (a worker gave up, or lacks the
    /// version), the accumulation goes on alone from an empty image, rendering this pass.
    /// With `last` the workers drop their state at once.
    fn add(&mut self, scene_id: u32, frame: &Frame<'_>, version: u64, samples: u32, last: bool, cancel: &Cancel) -> Result<FrameStats, RenderError> {
        let Some((cluster, key)) = self.cluster.clone() else {
            return self.progressive.add_cancellable(frame, samples, cancel);
        };
        match self.add_across(&cluster, key, (scene_id, frame, version), samples, last, cancel) {
            Ok(stats) => Ok(stats),
            Err(Failed::Render(e)) => Err(e),
            Err(Failed::Cluster(why)) => {
                eprintln!("warning: a pass across the cluster failed ({why}): rendering it on rank 0 alone");
                self.alone()?;
                self.progressive.add_cancellable(frame, samples, cancel)
            }
        }
    }
}

impl Drop for Accumulator {
    fn drop(&mut self) {
        self.forget();
    }
}

/// Why a pass across the cluster failed.
enum Failed {
    /// Rank 0's own share: cancelled, or bad settings.
    Render(RenderError),
    /// The cluster: the pass is rendered alone instead.
    Cluster(String),
}
