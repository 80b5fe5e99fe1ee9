//! Where and how lazy object builds run: on a thread pool of their own, while the rendering
//! threads that need the tree wait, and what they cost a frame in wall time.
//!
//! A tree is built the first time a ray reaches its object, on whichever rendering thread traced
//! that ray, and the builder is itself parallel (rayon). Run on the rendering pool, a build would
//! deadlock or serialise: a worker waiting for its half of a `rayon::join` steals other work,
//! which may be a tile that needs the very object it is building (rayon-rs/rayon#1251), and the
//! workers blocked on the unbuilt object cannot help. So the build is handed to a separate pool
//! of as many threads as the rendering pool has, and the rendering thread blocks (in the kernel,
//! not in rayon) until it is done: the cores the blocked workers leave idle build the tree. The
//! build pool's tasks never wait on rendering work, so nothing can wait in a circle. An image's
//! mip pyramid, built the first time a lookup needs it, runs there for the same reasons.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock, mpsc};
use std::time::Instant;

/// What a build did to an object's tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BuildOutcome {
    /// Built from scratch.
    Built,
    /// Refitted to moved geometry.
    Refitted,
    /// A refit abandoned for a rebuild because the tree had degraded.
    Rebuilt,
}

/// Counts of the tree work done while tracing a frame (objects no ray reached do none), and the
/// wall time it took.
#[derive(Debug, Default)]
pub(crate) struct BuildCounters {
    pub built: AtomicU32,
    pub refitted: AtomicU32,
    pub rebuilt: AtomicU32,
    /// Nanoseconds of wall time during which at least one build ran. Builds of different
    /// objects overlap; summing their durations would count the same second once per thread.
    wall_nanos: AtomicU64,
    /// Builds running now, and since when the count has been above zero.
    running: Mutex<(u32, Option<Instant>)>,
}

impl BuildCounters {
    /// Seconds of wall time during which some object was being built.
    pub fn wall_seconds(&self) -> f64 {
        self.wall_nanos.load(Ordering::Relaxed) as f64 * 1e-9
    }

    /// Runs `build` on the build pool from the calling (rendering) thread, counting it.
    pub fn run<T: Send + 'static>(&self, build: impl FnOnce() -> (T, BuildOutcome) + Send + 'static) -> T {
        self.started();
        let result = on_build_pool(build);
        self.finished();
        let (tree, outcome) = result.unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        let counter = match outcome {
            BuildOutcome::Built => &self.built,
            BuildOutcome::Refitted => &self.refitted,
            BuildOutcome::Rebuilt => &self.rebuilt,
        };
        counter.fetch_add(1, Ordering::Relaxed);
        tree
    }

    fn started(&self) {
        let mut running = self.running.lock().unwrap_or_else(|e| e.into_inner());
        running.0 += 1;
        running.1.get_or_insert_with(Instant::now);
    }

    fn finished(&self) {
        let mut running = self.running.lock().unwrap_or_else(|e| e.into_inner());
        running.0 -= 1;
        if running.0 == 0
            && let Some(since) = running.1.take()
        {
            self.wall_nanos.fetch_add(since.elapsed().as_nanos() as u64, Ordering::Relaxed);
        }
    }
}

/// Runs `job` on the build pool sized like the calling thread's rayon pool and blocks until it
/// is done; a panic in the job comes back as the error.
pub(crate) fn on_build_pool<R: Send + 'static>(job: impl FnOnce() -> R + Send + 'static) -> std::thread::Result<R> {
    let pool = build_pool(rayon::current_num_threads());
    let (done, result) = mpsc::sync_channel(1);
    pool.spawn(move || {
        // The receiver lives until this sends: `recv` below waits for it.
        let _ = done.send(std::panic::catch_unwind(std::panic::AssertUnwindSafe(job)));
    });
    result.recv().expect("the build pool runs every job it is given")
}

/// The build pool of `threads` threads, made the first time a build needs it and kept for the
/// process (there is one per size of rendering pool in use, usually one).
fn build_pool(threads: usize) -> Arc<rayon::ThreadPool> {
    static POOLS: OnceLock<Mutex<HashMap<usize, Arc<rayon::ThreadPool>>>> = OnceLock::new();
    let mut pools = POOLS.get_or_init(Mutex::default).lock().unwrap_or_else(|e| e.into_inner());
    Arc::clone(pools.entry(threads).or_insert_with(|| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("raystage-build-{i}"))
            .build()
            .expect("the operating system starts the build pool's threads");
        Arc::new(pool)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_build_runs_on_the_build_pool_and_is_counted() {
        let counters = BuildCounters::default();
        let name = counters.run(|| (std::thread::current().name().map(str::to_owned), BuildOutcome::Refitted));
        assert!(name.is_some_and(|n| n.starts_with("raystage-build-")));
        assert_eq!(counters.refitted.load(Ordering::Relaxed), 1);
        assert_eq!(counters.built.load(Ordering::Relaxed), 0);
    }

    #[test]
    fn overlapping_builds_count_their_wall_time_once() {
        let counters = BuildCounters::default();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
        let start = Instant::now();
        pool.install(|| {
            rayon::scope(|s| {
                for _ in 0..4 {
                    s.spawn(|_| counters.run(|| (std::thread::sleep(std::time::Duration::from_millis(50)), BuildOutcome::Built)));
                }
            })
        });
        let wall = start.elapsed().as_secs_f64();
        assert_eq!(counters.built.load(Ordering::Relaxed), 4);
        // Four 50 ms builds at once on four build threads: about 50 ms, never the 200 ms sum.
        assert!(counters.wall_seconds() >= 0.05 && counters.wall_seconds() <= wall, "{} of {wall}", counters.wall_seconds());
    }

    #[test]
    fn a_panicking_build_panics_in_the_caller() {
        let counters = BuildCounters::default();
        let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| counters.run::<()>(|| panic!("bad mesh"))));
        assert!(caught.is_err());
        // Not left counted as running: a later build's wall time starts afresh.
        assert_eq!(counters.running.lock().unwrap().0, 0);
    }
}
