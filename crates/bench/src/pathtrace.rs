//! The path-tracing benchmark: what accuracy costs in time, raystage against Mitsuba 3
//! on the same scene in the same run.
//!
//! The scenes are the classic Cornell box (`raystage_demo::cornell_box`) and, as a scene too
//! large for the caches, the same room with a million triangles of spheres on its floor instead
//! of the blocks ([`PathScene`]), written as glTF; raystage imports each, and
//! `scripts/references/cornell_box.py` builds the same scene in Mitsuba from the same file. A
//! converged reference comes from Mitsuba's `scalar_rgb` path tracer; then, for each sample
//! count, raystage and each Mitsuba variant render the room in turns on the same threads (who
//! goes first alternates), each timed over its render alone (Mitsuba's scene loading and
//! Python's start are left out), and each image is compared with the reference by the relative
//! RMSE of 4×4 block means over the room without the light
//! ([`raystage_demo::cornell_box::Comparison`]). From those points, the time each system needs to
//! reach 5 %, 2 % and 1 % follows by interpolation on log-log axes.
//!
//! Without Mitsuba (the `mitsuba` PyPI package), the bench says how to get it and measures
//! raystage alone, against a reference of its own at the reference sample count.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use glam::Vec3;
use raystage_demo::cornell_box::{self, Comparison};
use raystage_render::{Film, Integrator, RenderSettings, render};
use raystage_scene::Scene;
use serde::Serialize;

/// The errors every system is timed to.
pub const TARGETS: [f64; 3] = [0.05, 0.02, 0.01];

/// A scene of the benchmark.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathScene {
    /// The classic Cornell box: 32 triangles.
    Room,
    /// The room with [`cornell_box::SPHERES_PER_SIDE`]² spheres on its floor instead of the
    /// blocks: a million triangles.
    Spheres,
}

impl PathScene {
    /// Every scene, in the order `--scene all` runs them.
    pub const ALL: [PathScene; 2] = [PathScene::Room, PathScene::Spheres];

    /// Its name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            PathScene::Room => "room",
            PathScene::Spheres => "spheres",
        }
    }

    /// The scene named `name`.
    pub fn from_name(name: &str) -> Option<PathScene> {
        PathScene::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The scene as glTF.
    fn gltf(self) -> String {
        match self {
            PathScene::Room => cornell_box::gltf(),
            PathScene::Spheres => cornell_box::spheres_gltf(),
        }
    }

    /// The scene as raystage imports it from its glTF, the file Mitsuba reads.
    pub fn scene(self) -> Result<Scene, String> {
        raystage_gltf_scene(&self.gltf())
    }
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct Config {
    /// The scenes, each with its image side in pixels (a multiple of 4).
    pub scenes: Vec<(PathScene, u32)>,
    /// Sample counts to compare.
    pub spp: Vec<u32>,
    /// Samples per pixel of the reference.
    pub reference_spp: u32,
    /// Threads of every render.
    pub threads: usize,
    /// Mitsuba variants to time (`scalar_rgb`, `llvm_ad_rgb`).
    pub variants: Vec<String>,
    /// The Python interpreter that has Mitsuba.
    pub python: String,
    /// Where to write the scene, the reference and the renders.
    pub dir: PathBuf,
}

/// One render of a scene.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    /// `raystage` or `mitsuba-<variant>`.
    pub system: String,
    /// Which scene ([`PathScene::name`]).
    pub scene: &'static str,
    /// Samples per pixel.
    pub spp: u32,
    /// Seconds of the render.
    pub seconds: f64,
    /// Relative RMSE of 4×4 block means against the reference.
    pub rmse: f64,
    /// Per channel, the mean over the room (the light left out) over the reference's.
    pub channel_ratio: [f32; 3],
}

/// Everything one run measured of one scene.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Which scene ([`PathScene::name`]).
    pub scene: &'static str,
    /// Its image side in pixels.
    pub size: u32,
    /// Who rendered the reference, at how many samples per pixel.
    pub reference: String,
    /// Every render, in the order they ran.
    pub points: Vec<Point>,
    /// raystage's time for one frame at the first sample count, on one thread and on
    /// `threads`, and the speedup.
    pub scaling: Scaling,
}

/// raystage's thread scaling on a scene.
#[derive(Clone, Debug, Serialize)]
pub struct Scaling {
    /// Which scene ([`PathScene::name`]).
    pub scene: &'static str,
    /// Samples per pixel of the frames.
    pub spp: u32,
    /// Seconds on one thread.
    pub one_thread_s: f64,
    /// Threads of the other measurement.
    pub threads: usize,
    /// Seconds on `threads` threads.
    pub threads_s: f64,
    /// One thread's time over the many's.
    pub speedup: f64,
    /// The tasks a frame is cut into.
    pub tasks: usize,
}

/// A summary line per scene, system and target error: the time to reach it.
#[derive(Clone, Debug, Serialize)]
pub struct TimeToTarget {
    /// The system.
    pub system: String,
    /// Which scene ([`PathScene::name`]).
    pub scene: &'static str,
    /// The relative RMSE, one of [`TARGETS`].
    pub target: f64,
    /// Seconds to reach `target`, interpolated; `None` if no two measured points
    /// bracket it (or extrapolated from the last two when the error never got there).
    pub seconds: Option<f64>,
    /// Whether `seconds` is extrapolated beyond the measured points.
    pub extrapolated: bool,
    /// raystage's time over this system's.
    pub raystage_ratio: Option<f64>,
}

/// Runs the benchmark on each scene of `config`, logging progress through `log`.
pub fn run(config: &Config, log: impl Fn(&str)) -> Result<Vec<Report>, String> {
    std::fs::create_dir_all(&config.dir).map_err(|e| format!("cannot create {}: {e}", config.dir.display()))?;
    let mitsuba = mitsuba_available(&config.python);
    if !mitsuba {
        log("Mitsuba 3 is not installed for this Python: `pip install mitsuba numpy` (and for llvm_ad_rgb, \
             `apt-get install libllvm19` and DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so); measuring raystage alone");
    }
    config.scenes.iter().map(|&(scene, size)| run_scene(config, scene, size, mitsuba, &log)).collect()
}

/// The benchmark on `scene` at `size`² pixels, with Mitsuba if it is `mitsuba`.
fn run_scene(config: &Config, which: PathScene, size: u32, mitsuba: bool, log: &impl Fn(&str)) -> Result<Report, String> {
    let json = which.gltf();
    let gltf = config.dir.join(format!("{}.gltf", which.name()));
    std::fs::write(&gltf, &json).map_err(|e| format!("cannot write {}: {e}", gltf.display()))?;
    let scene = raystage_gltf_scene(&json)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(config.threads).build().map_err(|e| e.to_string())?;
    let mitsuba_render = |variant: &str, spp: u32, seed: u32| mitsuba_render(config, &gltf, size, variant, spp, seed);
    // Mitsuba's times leave out loading the scene, its BVH build included: raystage's trees,
    // built lazily when a ray first needs them and kept with the scene, are built here, by a
    // frame whose camera rays meet every object of the room, before any render is timed.
    pool.install(|| raystage_render(&scene, size, 1, 0));
    let reference_by = if mitsuba { "mitsuba scalar_rgb" } else { "raystage" };
    log(&format!("{}: reference by {reference_by} at {} spp, {size}x{size}", which.name(), config.reference_spp));
    let reference = if mitsuba {
        mitsuba_render("scalar_rgb", config.reference_spp, 1_000_003)?.0
    } else {
        pool.install(|| raystage_render(&scene, size, config.reference_spp, 1_000_003)).0
    };
    let systems: Vec<String> = std::iter::once("raystage".to_string())
        .chain(config.variants.iter().filter(|_| mitsuba).map(|v| format!("mitsuba-{v}")))
        .collect();
    let mut points = Vec::new();
    for (round, &spp) in config.spp.iter().enumerate() {
        // Who goes first alternates from one sample count to the next.
        let mut order = systems.clone();
        order.rotate_left(round % systems.len());
        for system in order {
            let (image, seconds) = match system.strip_prefix("mitsuba-") {
                Some(variant) => mitsuba_render(variant, spp, round as u32)?,
                None => pool.install(|| raystage_render(&scene, size, spp, round as u32)),
            };
            let c = Comparison::of(&image, &reference, size as usize);
            let point = Point { system, scene: which.name(), spp, seconds, rmse: c.block_rmse as f64, channel_ratio: c.channel_ratio.to_array() };
            log(&format!("{:>20} {:>6} spp  {:>8.3} s  RMSE {:.4}", point.system, spp, seconds, point.rmse));
            points.push(point);
        }
    }
    let scaling = scaling(&scene, which, size, config, log);
    Ok(Report { scene: which.name(), size, reference: format!("{reference_by} at {} spp", config.reference_spp), points, scaling })
}

impl Report {
    /// Each system's time to each of [`TARGETS`], and raystage's ratio to it.
    pub fn times_to_target(&self) -> Vec<TimeToTarget> {
        let mut systems: Vec<&str> = self.points.iter().map(|p| p.system.as_str()).collect();
        systems.sort_unstable();
        systems.dedup();
        let by_system: Vec<(&str, Vec<&Point>)> = systems
            .iter()
            .map(|&s| {
                let mut points: Vec<&Point> = self.points.iter().filter(|p| p.system == s).collect();
                points.sort_by_key(|p| p.spp);
                (s, points)
            })
            .collect();
        TARGETS
            .iter()
            .flat_map(|&target| {
                let times: Vec<(&str, Option<(f64, bool)>)> = by_system.iter().map(|(s, points)| (*s, time_to(points, target))).collect();
                let raystage = times.iter().find(|(s, _)| *s == "raystage").and_then(|(_, t)| t.map(|t| t.0));
                times.into_iter().map(move |(system, t)| TimeToTarget {
                    system: system.to_string(),
                    scene: self.scene,
                    target,
                    raystage_ratio: raystage.zip(t).map(|(r, (t, _))| r / t),
                    seconds: t.map(|t| t.0),
                    extrapolated: t.is_some_and(|t| t.1),
                })
            })
            .collect()
    }
}

/// The time at which the error of `points` (ascending sample counts) reaches `target`: on the
/// line through the two points around it in log time and log error, or past the last two.
fn time_to(points: &[&Point], target: f64) -> Option<(f64, bool)> {
    let line = |a: &Point, b: &Point| {
        let (x0, x1, y0, y1) = (a.seconds.ln(), b.seconds.ln(), a.rmse.ln(), b.rmse.ln());
        (y1 != y0).then(|| (x0 + (target.ln() - y0) * (x1 - x0) / (y1 - y0)).exp())
    };
    if let Some(w) = points.windows(2).find(|w| w[0].rmse > target && w[1].rmse <= target) {
        return line(w[0], w[1]).map(|t| (t, false));
    }
    match points {
        [.., a, b] if b.rmse > target => line(a, b).map(|t| (t, true)),
        [first, ..] if first.rmse <= target => Some((first.seconds, false)),
        _ => None,
    }
}

/// A scene as raystage imports it from its glTF, `json`: the very bytes Mitsuba reads.
fn raystage_gltf_scene(json: &str) -> Result<Scene, String> {
    let import = raystage_gltf_import::read(json.as_bytes(), None, &raystage_gltf_import::Limits::default()).map_err(|e| e.to_string())?;
    import.into_scene().map_err(|e| e.to_string())
}

/// raystage's render of the room at `spp` (paths of up to 64 segments, a box filter, as the
/// reference), and its seconds.
fn raystage_render(scene: &Scene, size: u32, spp: u32, seed: u32) -> (Vec<Vec3>, f64) {
    let settings = RenderSettings { width: size, height: size, integrator: Integrator::Path, samples_per_pixel: spp, max_depth: 64, seed, ..RenderSettings::default() };
    let frame = scene.frame();
    let start = Instant::now();
    let (film, _) = render(&frame, &settings).expect("valid settings");
    (film.pixels().to_vec(), start.elapsed().as_secs_f64())
}

/// Whether `python` can import Mitsuba.
fn mitsuba_available(python: &str) -> bool {
    Command::new(python).args(["-c", "import mitsuba, numpy"]).output().is_ok_and(|o| o.status.success())
}

/// Mitsuba's render of the scene in `gltf` at `size`² pixels with `variant` at `spp` (through
/// the reference script), and the seconds it reports for the render alone.
fn mitsuba_render(config: &Config, gltf: &Path, size: u32, variant: &str, spp: u32, seed: u32) -> Result<(Vec<Vec3>, f64), String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/references/cornell_box.py");
    let stem = gltf.file_stem().map_or("scene".into(), |s| s.to_string_lossy());
    let out = config.dir.join(format!("mitsuba-{stem}-{variant}-{spp}.pfm"));
    let output = Command::new(&config.python)
        .arg(&script)
        .arg(gltf)
        .arg(&out)
        .args(["--size", &size.to_string(), "--spp", &spp.to_string(), "--variant", variant])
        .args(["--seed", &seed.to_string(), "--threads", &config.threads.to_string(), "--time"])
        .output()
        .map_err(|e| format!("cannot run {}: {e}", config.python))?;
    if !output.status.success() {
        return Err(format!("Mitsuba ({variant}) failed: {}", String::from_utf8_lossy(&output.stderr)));
    }
    let timing: serde_json::Value = serde_json::from_slice(&output.stdout).map_err(|e| format!("Mitsuba's timing: {e}"))?;
    let seconds = timing["seconds"].as_f64().ok_or("Mitsuba printed no seconds")?;
    let bytes = std::fs::read(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let film = Film::from_pfm(&bytes).map_err(|e| format!("{}: {e}", out.display()))?;
    if (film.width(), film.height()) != (size, size) {
        return Err(format!("{} is not {size}x{size}", out.display()));
    }
    Ok((film.pixels().to_vec(), seconds))
}

/// raystage's frame time on `which` (`scene`, at `size`² pixels) on one thread and on
/// `config.threads`, at the first sample count (the better of two frames each).
fn scaling(scene: &Scene, which: PathScene, size: u32, config: &Config, log: &impl Fn(&str)) -> Scaling {
    let spp = config.spp.first().copied().unwrap_or(16);
    let time = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
        (0..2).map(|seed| pool.install(|| raystage_render(scene, size, spp, seed).1)).fold(f64::INFINITY, f64::min)
    };
    let (one, many) = (time(1), time(config.threads));
    let tasks = raystage_render::tasks(size, size);
    log(&format!("raystage at {spp} spp: {one:.3} s on 1 thread, {many:.3} s on {}: {:.2}x; {tasks} tasks a frame", config.threads, one / many));
    Scaling { scene: which.name(), spp, one_thread_s: one, threads: config.threads, threads_s: many, speedup: one / many, tasks }
}
