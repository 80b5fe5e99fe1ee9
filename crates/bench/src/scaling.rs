//! How frames scale with threads: every integrator on the sphere grid at 1920×1080 and
//! on the Cornell room at 256×256, at 1, 2, 4, … threads up to the machine's cores. Each thread
//! count starts from a fresh scene, so its first frame builds the object trees lazily (the build
//! time is reported apart); the frame time is the best of the warm frames that follow. Beside the
//! speedup, the frame's tasks: how many it offers and the largest one's share of the work, which
//! say whether more threads than this machine has would be kept busy.

use raystage_demo::StandardScene;
use raystage_render::{FrameStats, Integrator, RenderSettings, render};
use raystage_scene::Scene;
use serde::Serialize;

/// A scene of the benchmark and the image size and samples per pixel of each integrator there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BenchScene {
    /// The sphere grid (1,000,002 triangles in one object), 1920×1080.
    Spheres,
    /// The Cornell room (a few dozen triangles), 256×256.
    Room,
}

impl BenchScene {
    /// Both, in report order.
    pub const ALL: [BenchScene; 2] = [BenchScene::Spheres, BenchScene::Room];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            BenchScene::Spheres => "spheres",
            BenchScene::Room => "room",
        }
    }

    /// Parses a name of [`BenchScene::name`].
    pub fn from_name(name: &str) -> Option<BenchScene> {
        BenchScene::ALL.into_iter().find(|s| s.name() == name)
    }

    /// A fresh copy, nothing built.
    fn scene(self) -> Scene {
        match self {
            BenchScene::Spheres => StandardScene::Spheres.scene(),
            BenchScene::Room => raystage_demo::shading::cornell_room(),
        }
        .expect("the demo scenes are valid")
    }

    fn size(self) -> (u32, u32) {
        match self {
            BenchScene::Spheres => (1920, 1080),
            BenchScene::Room => (256, 256),
        }
    }

    /// Samples per pixel: enough for a frame of a fraction of a second to a few seconds on one
    /// core, so that the whole benchmark runs in minutes.
    fn spp(self, integrator: Integrator) -> u32 {
        match (self, integrator) {
            (BenchScene::Spheres, _) => 1,
            (BenchScene::Room, Integrator::EyeLight | Integrator::Whitted) => 16,
            (BenchScene::Room, _) => 8,
        }
    }
}

/// What to measure.
pub struct Config {
    /// The thread counts, in increasing order; the first is the speedups' base.
    pub threads: Vec<usize>,
    pub scenes: Vec<BenchScene>,
    pub integrators: Vec<Integrator>,
    /// Warm frames per measurement; the best is reported.
    pub reps: usize,
}

/// One integrator on one scene at one thread count.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    pub integrator: &'static str,
    pub scene: &'static str,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub threads: usize,
    /// Seconds of a frame with every tree built (the best of the warm frames).
    pub frame_s: f64,
    /// Seconds of the first frame, lazy builds included.
    pub first_frame_s: f64,
    /// Wall seconds of the first frame spent building object trees.
    pub build_s: f64,
    /// `frame_s` at the first thread count over `frame_s` here.
    pub speedup: f64,
    /// The speedup over the thread count's ratio to the first (1 is linear).
    pub efficiency: f64,
    /// Tasks (tiles) a frame offers.
    pub tasks: u32,
    /// The largest task's share of the frame's summed task time (warm frame).
    pub largest_task_share: f64,
    pub mrays_per_s: f64,
}

/// Runs every measurement of `config`, logging progress.
pub fn run(config: &Config, log: impl Fn(&str)) -> Vec<Point> {
    let mut points: Vec<Point> = Vec::new();
    for &bench in &config.scenes {
        let (width, height) = bench.size();
        for &integrator in &config.integrators {
            let spp = bench.spp(integrator);
            let settings = RenderSettings { width, height, integrator, samples_per_pixel: spp, ..RenderSettings::default() };
            let mut base: Option<(usize, f64)> = None;
            for &threads in &config.threads {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
                let scene = bench.scene();
                let frame = |scene: &Scene| -> FrameStats { pool.install(|| render(&scene.frame(), &settings).expect("valid settings").1) };
                let first = frame(&scene);
                let warm: Vec<FrameStats> = (0..config.reps.max(1)).map(|_| frame(&scene)).collect();
                let best = warm.iter().min_by(|a, b| a.seconds.total_cmp(&b.seconds)).expect("at least one warm frame");
                let (base_threads, base_s) = *base.get_or_insert((threads, best.seconds));
                let speedup = base_s / best.seconds;
                let point = Point {
                    integrator: integrator.name(),
                    scene: bench.name(),
                    width,
                    height,
                    spp,
                    threads,
                    frame_s: best.seconds,
                    first_frame_s: first.seconds,
                    build_s: first.phases.object_builds,
                    speedup,
                    efficiency: speedup / (threads as f64 / base_threads as f64),
                    tasks: best.tasks.count,
                    largest_task_share: best.tasks.largest_share(),
                    mrays_per_s: best.mrays_per_second(),
                };
                log(&format!(
                    "{} on {} at {threads} thread(s): {:.3} s ({:.2}x), first frame {:.3} s of which {:.3} s building; {} tasks, the largest {:.2} % of the work",
                    point.integrator,
                    point.scene,
                    point.frame_s,
                    point.speedup,
                    point.first_frame_s,
                    point.build_s,
                    point.tasks,
                    100.0 * point.largest_task_share
                ));
                points.push(point);
            }
        }
    }
    points
}

/// The thread counts 1, 2, 4, … below `max`, then `max` itself.
pub fn thread_counts(max: usize) -> Vec<usize> {
    let mut counts: Vec<usize> = std::iter::successors(Some(1usize), |n| Some(n * 2)).take_while(|&n| n < max).collect();
    counts.push(max.max(1));
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_counts_double_up_to_the_machine() {
        assert_eq!(thread_counts(1), vec![1]);
        assert_eq!(thread_counts(2), vec![1, 2]);
        assert_eq!(thread_counts(12), vec![1, 2, 4, 8, 12]);
        assert_eq!(thread_counts(16), vec![1, 2, 4, 8, 16]);
    }

    #[test]
    fn a_point_per_integrator_and_thread_count_with_its_tasks() {
        let config = Config { threads: vec![1, 2], scenes: vec![BenchScene::Room], integrators: vec![Integrator::EyeLight], reps: 1 };
        let points = run(&config, |_| {});
        assert_eq!(points.len(), 2);
        assert_eq!(points[0].speedup, 1.0);
        // 256 × 256 in 16-pixel tiles: 256 tasks, enough for 64 threads. The largest task's
        // share is a timing (a task preempted on a loaded machine takes longer): only its range
        // is checked, no threshold.
        assert!(points.iter().all(|p| p.tasks == 256 && p.largest_task_share > 0.0 && p.largest_task_share <= 1.0), "{points:?}");
        assert!(points.iter().all(|p| p.frame_s > 0.0 && p.first_frame_s > 0.0));
    }
}
