//! The server's state: its configuration and its scenes, each behind a lock with a version
//! number that every edit advances (streams restart their accumulation when it changes).

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, RwLock};
use std::time::Instant;

use raystage_render::{Error as RenderError, Progressive, RenderSettings};
use raystage_scene::{Play, Scene};
use tokio::sync::{OwnedSemaphorePermit, Semaphore, watch};

use crate::build::SceneBuild;
use crate::clock::{Clock, ClockChange, ClockState, TICK};
use crate::config::{Config, Limits};
use crate::edit::{Applied, Edit, apply};
use crate::error::{Error, Result};
use crate::jobs::Jobs;
use crate::model::{Command, CommandResult, SetTime};
use crate::stats::FrameReport;
use crate::turns::{Client, Turn, Turns, Urgency};
use crate::workers::{Accumulate, Workers};

/// The unit in which render memory is reserved.
const MIB: usize = 1 << 20;

/// Everything the handlers share; cheap to clone.
#[derive(Clone)]
pub struct AppState(Arc<Shared>);

struct Shared {
    config: Config,
    scenes: RwLock<BTreeMap<u32, Arc<SceneSlot>>>,
    next_scene: AtomicU32,
    /// Turns to render, shared round robin between clients; a turn moves into the blocking
    /// task that renders, so it is given back when the work stops, not when the client stops
    /// waiting.
    renders: Turns,
    /// Renders running now (see [`AppState::active_renders`]).
    active_renders: AtomicUsize,
    /// The memory of images being rendered, in MiB (see [`Limits::max_render_bytes`]).
    render_memory: Arc<Semaphore>,
    streams: AtomicUsize,
    jobs: Jobs,
    /// What every scene's memory adds up to (see [`Limits::max_total_scene_bytes`]).
    scene_bytes: Arc<AtomicU64>,
    /// The cluster whose workers replicate the scenes and render with this server (rank 0 of
    /// `raystage serve --mpi`), if any.
    cluster: Option<Arc<dyn Workers>>,
}

/// A scene held by the server.
pub struct SceneSlot {
    /// Its id.
    pub id: u32,
    /// Where it came from (`empty`, `demo:spheres`, `gltf`, ...).
    pub origin: String,
    /// The scene. Edits hold the write lock; renders take a snapshot under a brief read lock
    /// and hold no lock while they run, so edits never wait for a frame.
    scene: Arc<tokio::sync::RwLock<Scene>>,
    /// The last snapshot and its version, shared by every render of that version (a stream's
    /// passes, frames asked for by several clients); dropped by the next edit, so that it does
    /// not make the edit copy what it changes.
    last_snapshot: Mutex<Option<(u64, Arc<Scene>)>>,
    /// The number of edits so far, changed only while the write lock is held.
    version: watch::Sender<u64>,
    /// The last frame rendered by `frame.png` or a stream.
    pub last_frame: Mutex<Option<FrameReport>>,
    /// Whether the scene was deleted (its streams end).
    deleted: AtomicBool,
    /// The memory the scene takes ([`Scene::memory_bytes`]), as of its last edit.
    bytes: AtomicU64,
    /// The server's memory budget for scenes, which every edit is checked against.
    budget: Budget,
    /// The animation clock, once the scene has been posed or its clock set (see
    /// [`crate::clock`]).
    clock: Mutex<Option<Clock>>,
    /// Wakes what waits for a paused clock ([`SceneSlot::clock_due`]) when the clock is set.
    clock_set: tokio::sync::Notify,
}

/// The limits on scenes' memory and what the server's scenes take together.
#[derive(Clone)]
struct Budget {
    per_scene: u64,
    total: u64,
    used: Arc<AtomicU64>,
}

impl Budget {
    /// Moves a scene from `before` to `after` bytes if both limits allow it; else 413 naming the
    /// limit, and nothing is counted.
    fn change(&self, before: u64, after: u64) -> Result<()> {
        if after > self.per_scene {
            let message = format!("the scene would take {after} bytes of geometry, trees and images: the limit is {}", self.per_scene);
            return Err(Error::too_large(None, message).limit("max_scene_bytes"));
        }
        self.used
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |used| {
                let next = used - before.min(used) + after;
                (after <= before || next <= self.total).then_some(next)
            })
            .map(|_| ())
            .map_err(|used| {
                let message = format!("the server's scenes take {used} bytes and this would add {}: the limit is {}", after - before, self.total);
                Error::too_large(None, message).limit("max_total_scene_bytes")
            })
    }
}

impl AppState {
    /// A server with no scenes.
    pub fn new(config: Config) -> AppState {
        AppState::build(config, None)
    }

    /// A server with no scenes that renders with `cluster`'s workers and replicates its
    /// scenes' edits to them (rank 0 of `raystage serve --mpi`).
    pub fn clustered(config: Config, cluster: Arc<dyn Workers>) -> AppState {
        AppState::build(config, Some(cluster))
    }

    fn build(config: Config, cluster: Option<Arc<dyn Workers>>) -> AppState {
        let renders = Turns::new(config.limits.concurrent_renders);
        let render_memory = Arc::new(Semaphore::new(config.limits.max_render_bytes / MIB));
        AppState(Arc::new(Shared {
            config,
            scenes: RwLock::default(),
            next_scene: AtomicU32::new(1),
            renders,
            active_renders: AtomicUsize::new(0),
            render_memory,
            streams: AtomicUsize::new(0),
            jobs: Default::default(),
            scene_bytes: Arc::default(),
            cluster,
        }))
    }

    /// The cluster this server renders with, if any.
    pub fn cluster(&self) -> Option<&Arc<dyn Workers>> {
        self.0.cluster.as_ref()
    }

    /// An empty accumulation of `settings`, rendered across the cluster's ranks if the server
    /// has a cluster whose workers still answer, else in this process.
    pub fn accumulator(&self, settings: RenderSettings) -> Result<Box<dyn Accumulate>, RenderError> {
        match self.cluster().filter(|c| c.ranks() > 1) {
            Some(cluster) => Arc::clone(cluster).accumulate(settings),
            None => Ok(Box::new(Progressive::new(settings)?)),
        }
    }

    /// The render jobs.
    pub fn jobs(&self) -> &Jobs {
        &self.0.jobs
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.0.config
    }

    /// Adds a scene; returns its id (ids start at 1 and are never reused). Refused (413) if the
    /// server holds as many scenes as it may, or the scene's memory is past the budget.
    pub fn add_scene(&self, scene: Scene, origin: impl Into<String>) -> Result<u32> {
        self.insert(None, scene, origin.into())
    }

    /// Adds a scene a request built from `build` and, in a cluster, has every worker build and
    /// add it too (refused everywhere if one cannot). Returns its id.
    pub fn create_scene(&self, scene: Scene, origin: String, build: &SceneBuild) -> Result<u32> {
        let id = self.insert(None, scene, origin.clone())?;
        if let Some(cluster) = self.cluster()
            && let Err(e) = cluster.replicate_new_scene(id, &origin, build)
        {
            let _ = self.forget_scene(id);
            return Err(e);
        }
        Ok(id)
    }

    /// Adds a scene as `id` (a worker's replica of rank 0's scene `id`), with the same checks
    /// as [`AppState::add_scene`].
    pub fn insert_scene(&self, id: u32, scene: Scene, origin: String) -> Result<u32> {
        self.insert(Some(id), scene, origin)
    }

    fn insert(&self, id: Option<u32>, scene: Scene, origin: String) -> Result<u32> {
        let mut scenes = self.0.scenes.write().unwrap_or_else(|e| e.into_inner());
        self.room_for(scenes.len())?;
        if id.is_some_and(|id| scenes.contains_key(&id)) {
            return Err(Error::internal(format!("scene {} exists already", id.unwrap_or_default())));
        }
        let limits = &self.0.config.limits;
        let budget = Budget { per_scene: limits.max_scene_bytes, total: limits.max_total_scene_bytes, used: Arc::clone(&self.0.scene_bytes) };
        let bytes = scene.memory_bytes();
        budget.change(0, bytes)?;
        let id = id.unwrap_or_else(|| self.0.next_scene.fetch_add(1, Ordering::Relaxed));
        let slot = SceneSlot {
            id,
            origin,
            scene: Arc::new(tokio::sync::RwLock::new(scene)),
            version: watch::Sender::new(0),
            last_frame: Mutex::new(None),
            last_snapshot: Mutex::new(None),
            deleted: AtomicBool::new(false),
            bytes: AtomicU64::new(bytes),
            budget,
            clock: Mutex::new(None),
            clock_set: tokio::sync::Notify::new(),
        };
        scenes.insert(id, Arc::new(slot));
        Ok(id)
    }

    /// 413 naming `max_scenes` if the server holds as many scenes as it may. Checked before a
    /// scene is built, so that a request past the limit costs nothing (and again when it is
    /// added, as others may have been added meanwhile).
    pub fn check_room_for_scene(&self) -> Result<()> {
        self.room_for(self.0.scenes.read().unwrap_or_else(|e| e.into_inner()).len())
    }

    fn room_for(&self, held: usize) -> Result<()> {
        let limit = self.0.config.limits.max_scenes;
        if held >= limit {
            return Err(Error::too_large(None, format!("the server holds {limit} scenes, its limit: delete one first")).limit("max_scenes"));
        }
        Ok(())
    }

    /// The scene with id `id` (404 if there is none).
    pub fn scene(&self, id: u32) -> Result<Arc<SceneSlot>> {
        let scenes = self.0.scenes.read().unwrap_or_else(|e| e.into_inner());
        scenes.get(&id).cloned().ok_or_else(|| Error::not_found(Some("scene".into()), format!("unknown scene {id}")))
    }

    /// Every scene, by id.
    pub fn scenes(&self) -> Vec<Arc<SceneSlot>> {
        self.0.scenes.read().unwrap_or_else(|e| e.into_inner()).values().cloned().collect()
    }

    /// Forgets a scene: its render jobs stop, its streams end; in a cluster, the workers forget
    /// their replicas.
    pub async fn delete_scene(&self, id: u32) -> Result<()> {
        self.forget_scene(id)?;
        if let Some(cluster) = self.cluster().cloned() {
            tokio::task::spawn_blocking(move || cluster.replicate_delete(id)).await.map_err(|e| Error::internal(e.to_string()))?;
        }
        Ok(())
    }

    /// Forgets a scene here: its render jobs stop (failed, naming the deletion), frames being
    /// rendered for a request finish with their snapshots, its streams end.
    pub fn forget_scene(&self, id: u32) -> Result<()> {
        let mut scenes = self.0.scenes.write().unwrap_or_else(|e| e.into_inner());
        let slot = scenes.remove(&id).ok_or_else(|| Error::not_found(Some("scene".into()), format!("unknown scene {id}")))?;
        slot.deleted.store(true, Ordering::Release);
        // Renders and streams that still hold it finish with their snapshots; new scenes may
        // have its share of the budget.
        let bytes = slot.bytes.load(Ordering::Acquire);
        let _ = slot.budget.change(bytes, 0);
        // Wakes the streams waiting for a change.
        slot.version.send_modify(|_| ());
        drop(scenes);
        self.jobs().stop_scene(id);
        Ok(())
    }

    /// Waits for a turn to render for `client` (at most `concurrent_renders` at once, the
    /// turns going round the waiting clients, edits first: see [`Urgency`]). Move the turn into
    /// the task that renders and call [`RenderTurn::running`] there.
    pub async fn render_permit(&self, client: Client, urgency: Urgency) -> RenderTurn {
        RenderTurn { _turn: self.0.renders.take(client, urgency).await, state: self.clone() }
    }

    /// Renders running now, frames and stream passes: at most
    /// [`Limits::concurrent_renders`](crate::Limits::concurrent_renders), and back to 0
    /// soon after the last client waiting for one has gone (its render is cancelled).
    pub fn active_renders(&self) -> usize {
        self.0.active_renders.load(Ordering::Relaxed)
    }

    /// Reserves `bytes` of the memory for images being rendered, until the reservation is
    /// dropped: 413 if that is more than all of it, 503 if it does not fit beside the images
    /// in progress (both naming `max_render_bytes`).
    pub fn reserve_render_memory(&self, bytes: u64) -> Result<OwnedSemaphorePermit> {
        let limit = self.0.config.limits.max_render_bytes;
        let mib = bytes.div_ceil(MIB as u64);
        let too_large = || Error::too_large(None, format!("the image takes {bytes} bytes to render: the limit is {limit}")).limit("max_render_bytes");
        if mib > (limit / MIB) as u64 {
            return Err(too_large());
        }
        let mib = u32::try_from(mib).map_err(|_| too_large())?;
        self.0.render_memory.clone().try_acquire_many_owned(mib).map_err(|_| {
            Error::busy(format!("the images being rendered leave no room for {bytes} bytes more (the limit is {limit}): try again")).limit("max_render_bytes")
        })
    }

    /// Counts a new stream in, if there is room: the guard counts it out when dropped.
    pub fn open_stream(&self) -> Result<StreamGuard> {
        let limit = self.0.config.limits.max_streams;
        let open = self.0.streams.fetch_add(1, Ordering::Relaxed);
        let guard = StreamGuard(self.clone());
        if open >= limit {
            return Err(Error::busy(format!("{limit} streams are open, the server's limit")));
        }
        Ok(guard)
    }
}

/// A turn to render, held by the work itself: dropping it gives the turn to the next render.
pub struct RenderTurn {
    _turn: Turn,
    state: AppState,
}

impl RenderTurn {
    /// Counts the render as running until the guard is dropped (call it on the thread that
    /// renders, where the work starts).
    pub fn running(&self) -> RunningRender {
        self.state.0.active_renders.fetch_add(1, Ordering::Relaxed);
        RunningRender(self.state.clone())
    }
}

/// A render counted in [`AppState::active_renders`] until dropped.
pub struct RunningRender(AppState);

impl Drop for RunningRender {
    fn drop(&mut self) {
        self.0.0.active_renders.fetch_sub(1, Ordering::Relaxed);
    }
}

/// An open stream, counted until dropped.
pub struct StreamGuard(AppState);

impl Drop for StreamGuard {
    fn drop(&mut self) {
        self.0.0.streams.fetch_sub(1, Ordering::Relaxed);
    }
}

impl SceneSlot {
    /// Applies `edit` to the scene under the write lock, on a blocking thread (in a cluster,
    /// on every rank: see [`SceneSlot::edit_blocking`]). Returns what it gave back and the
    /// version after it.
    pub async fn edit(self: &Arc<Self>, state: &AppState, edit: Edit) -> Result<(Applied, u64)> {
        self.edit_as(state, edit, true).await
    }

    /// [`SceneSlot::edit`]; where `sets_clock`, an edit that poses the scene at a new time
    /// (`set_time`) sets the clock to it. The clock's own moves do not, or every tick would
    /// lose the time the edit took.
    async fn edit_as(self: &Arc<Self>, state: &AppState, edit: Edit, sets_clock: bool) -> Result<(Applied, u64)> {
        let mut guard = self.scene.clone().write_owned().await;
        let posed = guard.posed();
        let slot = self.clone();
        let limits = state.config().limits;
        let cluster = state.cluster().cloned();
        tokio::task::spawn_blocking(move || {
            // Encoded before it is applied, which consumes it.
            let message = cluster.as_ref().map(|cluster| cluster.edit_message(slot.id, &edit));
            let edited = slot.edit_locked(&mut guard, edit, &limits, |local| match (local, &cluster, message) {
                (Ok(()), Some(cluster), Some(message)) => cluster.replicate(&message),
                _ => Ok(()),
            });
            if sets_clock
                && edited.is_ok()
                && let Some((play, time)) = guard.posed().filter(|p| Some(*p) != posed)
            {
                slot.set_clock(&guard, play, f64::from(time), |_| {});
            }
            edited
        })
        .await
        .map_err(|e| Error::internal(format!("an edit failed: {e}")))?
    }

    /// Runs commands on the scene, each checked before any is applied: a batch's (all or nothing, labels
    /// allowed) or one resource request's. Returns their results and the version after them.
    pub async fn commands(self: &Arc<Self>, state: &AppState, commands: Vec<Command>, in_batch: bool) -> Result<(Vec<CommandResult>, u64)> {
        match self.edit(state, Edit::Commands { commands, in_batch }).await? {
            (Applied::Commands(results), version) => Ok((results, version)),
            _ => Err(Error::internal("commands gave back something else")),
        }
    }

    /// Sets the clock to `time` (held within the animation) of `play` (`scene` says how long
    /// that lasts), keeping whether it plays, its rate and looping, then lets `change` change
    /// it further; a scene without a clock gets a paused one.
    fn set_clock(&self, scene: &Scene, play: Play, time: f64, change: impl FnOnce(&mut Clock)) -> ClockState {
        let duration = play.duration(&scene.animations());
        let now = Instant::now();
        let state = {
            let mut clock = self.clock.lock().unwrap_or_else(|e| e.into_inner());
            let clock = clock.get_or_insert_with(|| Clock::paused(play, f64::from(duration), time));
            clock.play = play;
            clock.duration = f64::from(duration);
            // The scene's time is an f32: the clock reads what the scene was posed at.
            clock.set(f64::from(time as f32).min(clock.duration), now);
            change(clock);
            clock.state(now)
        };
        self.clock_set.notify_waiters();
        state
    }

    /// Changes the clock as `change` says: fields left out stay (a new clock starts paused at
    /// 0 s of the first animation, at rate 1, looping). The scene is posed at the clock's time
    /// at once, which checks the animation (unprocessable for a scene without animations).
    pub async fn change_clock(self: &Arc<Self>, state: &AppState, change: ClockChange) -> Result<ClockState> {
        change.check()?;
        let current = self.clock();
        let time = change.time.or(current.as_ref().map(|c| c.time)).unwrap_or(0.0);
        let animation = change.animation.clone().or(current.map(|c| c.animation));
        // Posing checks the animation and moves the scene to the time now.
        self.commands(state, vec![Command::SetTime(SetTime { seconds: time, animation })], false).await?;
        let (scene, _) = self.snapshot().await;
        let (play, _) = scene.posed().ok_or_else(|| Error::internal("a scene just posed has no pose"))?;
        Ok(self.set_clock(&scene, play, time, |clock| {
            if let Some(rate) = change.rate {
                clock.rate = rate;
            }
            if let Some(looping) = change.looping {
                clock.looping = looping;
            }
            if let Some(playing) = change.playing {
                clock.playing = playing;
            }
            clock.last_tick = None;
        }))
    }

    /// The clock now (`None` before the scene was first posed or its clock set).
    pub fn clock(&self) -> Option<ClockState> {
        let now = Instant::now();
        let mut clock = self.clock.lock().unwrap_or_else(|e| e.into_inner());
        clock.as_mut().map(|c| {
            c.settle(now);
            c.state(now)
        })
    }

    /// The clock now; a scene posed without one (a glTF file opens posed at 0 s of its first
    /// animation) gets a paused clock at its pose. `None` for a scene never posed: one
    /// without animations.
    pub async fn current_clock(&self) -> Option<ClockState> {
        if let Some(clock) = self.clock() {
            return Some(clock);
        }
        let (scene, _) = self.snapshot().await;
        let (play, time) = scene.posed()?;
        Some(self.set_clock(&scene, play, f64::from(time), |_| {}))
    }

    /// Moves the scene to its clock's time, if the clock plays and has not moved it within the
    /// last `clock::TICK`: an ordinary `set_time` edit, so that it is ordered with every other edit
    /// and reaches a cluster's ranks. Renders call this before they take their snapshot. An
    /// edit that fails (the animation can no longer be posed) pauses the clock.
    pub async fn follow_clock(self: &Arc<Self>, state: &AppState) -> Result<()> {
        let now = Instant::now();
        let (play, time) = {
            let mut clock = self.clock.lock().unwrap_or_else(|e| e.into_inner());
            let Some(clock) = clock.as_mut().filter(|c| c.playing) else { return Ok(()) };
            if clock.last_tick.is_some_and(|t| now.saturating_duration_since(t) < TICK) {
                return Ok(());
            }
            clock.last_tick = Some(now);
            clock.settle(now);
            (clock.play, clock.time_at(now))
        };
        let command = Command::SetTime(SetTime { seconds: time, animation: Some(play.into()) });
        let edited = self.edit_as(state, Edit::Commands { commands: vec![command], in_batch: false }, false).await;
        if edited.is_err()
            && let Some(clock) = self.clock.lock().unwrap_or_else(|e| e.into_inner()).as_mut()
        {
            clock.playing = false;
        }
        edited.map(|_| ())
    }

    /// Completes when a playing clock is due to move the scene again; if it is not playing,
    /// when the clock is next set. A stream whose image is finished waits for this beside the
    /// scene's edits.
    pub async fn clock_due(&self) {
        // Listening before looking: a clock set playing just after the look still wakes this.
        // (Setting the clock poses the scene first, and the edit woke the stream before the
        // clock played: a stream that finished that pose quickly waited on a paused clock for
        // good.)
        let set = self.clock_set.notified();
        tokio::pin!(set);
        set.as_mut().enable();
        let playing = self.clock.lock().unwrap_or_else(|e| e.into_inner()).as_ref().is_some_and(|c| c.playing);
        if playing {
            tokio::time::sleep(TICK).await;
        } else {
            set.await;
        }
    }

    /// [`SceneSlot::edit`] on this thread (a cluster's worker, which has no runtime), asking
    /// `vote` once the edit was tried here (with its error's message if it failed) whether it
    /// stands.
    pub fn edit_blocking(
        &self,
        edit: Edit,
        limits: &Limits,
        vote: impl FnOnce(Result<(), String>) -> Result<()>,
    ) -> Result<(Applied, u64)> {
        let mut guard = self.scene.blocking_write();
        self.edit_locked(&mut guard, edit, limits, vote)
    }

    /// Applies `edit` to `scene` (the scene, its write lock held); if it succeeds, changes
    /// something and stays within the memory budget, and `vote` agrees, advances the version.
    /// `vote` is asked in every case, with the edit's error message if it failed here: in a
    /// cluster it answers whether every rank applied the edit. An edit that fails, or is voted
    /// down, leaves the scene as it was (a clone shares its objects and images, so keeping it
    /// is cheap).
    fn edit_locked(&self, scene: &mut Scene, edit: Edit, limits: &Limits, vote: impl FnOnce(Result<(), String>) -> Result<()>) -> Result<(Applied, u64)> {
        *self.last_snapshot.lock().unwrap_or_else(|e| e.into_inner()) = None;
        let before = scene.clone();
        let old = self.bytes.load(Ordering::Acquire);
        let outcome = apply(scene, edit, limits).and_then(|(applied, changed)| {
            let new = if changed { scene.memory_bytes() } else { old };
            self.budget.change(old, new)?;
            Ok((applied, changed, new))
        });
        let voted = vote(outcome.as_ref().map(|_| ()).map_err(|e| e.detail.message.clone()));
        match (outcome, voted) {
            (Ok((applied, changed, new)), Ok(())) => {
                if changed {
                    self.bytes.store(new, Ordering::Release);
                    self.version.send_modify(|v| *v += 1);
                }
                Ok((applied, *self.version.borrow()))
            }
            (outcome, voted) => {
                if let Ok((_, _, new)) = &outcome {
                    // Voted down: its memory goes back to the budget.
                    let _ = self.budget.change(*new, old);
                }
                *scene = before;
                Err(match outcome {
                    Err(e) => e,
                    Ok(_) => voted.expect_err("the other case"),
                })
            }
        }
    }

    /// Runs `read` on a snapshot of the scene, on a blocking thread (it may trace rays or build
    /// trees), with the version the scene had.
    pub async fn read<R: Send + 'static>(self: &Arc<Self>, read: impl FnOnce(&Scene, u64) -> R + Send + 'static) -> Result<R> {
        let (scene, version) = self.snapshot().await;
        tokio::task::spawn_blocking(move || read(&scene, version)).await.map_err(|e| Error::internal(format!("a read failed: {e}")))
    }

    /// The scene as it is now, as an immutable snapshot, and its version (consistent: edits
    /// change both under the write lock). Taking one holds the read lock only while the scene is
    /// cloned, which shares its objects, trees, shaders and textures (see [`Scene`]).
    pub async fn snapshot(&self) -> (Arc<Scene>, u64) {
        self.snapshot_of(&*self.scene.read().await)
    }

    /// [`SceneSlot::snapshot`] on this thread (a cluster's worker, which has no runtime).
    pub fn snapshot_blocking(&self) -> (u64, Arc<Scene>) {
        let (scene, version) = self.snapshot_of(&self.scene.blocking_read());
        (version, scene)
    }

    /// The snapshot of `guard`, the scene with its lock held.
    fn snapshot_of(&self, guard: &Scene) -> (Arc<Scene>, u64) {
        let version = *self.version.borrow();
        let mut last = self.last_snapshot.lock().unwrap_or_else(|e| e.into_inner());
        match &*last {
            Some((v, scene)) if *v == version => (Arc::clone(scene), version),
            _ => {
                let scene = Arc::new(guard.clone());
                *last = Some((version, Arc::clone(&scene)));
                (scene, version)
            }
        }
    }

    /// Whether the scene was deleted.
    pub fn is_deleted(&self) -> bool {
        self.deleted.load(Ordering::Acquire)
    }

    /// The version now.
    pub fn version(&self) -> u64 {
        *self.version.borrow()
    }

    /// A receiver told of every new version.
    pub fn watch(&self) -> watch::Receiver<u64> {
        self.version.subscribe()
    }
}
