//! `raystage render`: load a scene (a built-in demo or a glTF file), render one frame with a
//! progress bar, write a PNG.

use std::fs::File;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail, ensure};
use indicatif::{ProgressBar, ProgressStyle};
use raystage_demo::animated::Demo;
use raystage_render::{FrameStats, Integrator, Progressive, RenderSettings};
use raystage_scene::Scene;

/// Largest accepted image width or height in pixels.
pub const MAX_DIMENSION: u32 = 16_384;

/// Largest accepted number of render threads.
pub const MAX_THREADS: usize = 1024;

/// Where a scene comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneSource {
    /// A built-in demo scene, at a frame of its animation (0 for the first; still scenes
    /// ignore it).
    Demo {
        /// The demo.
        demo: Demo,
        /// The frame.
        frame: u32,
    },
    /// A glTF 2.0 file (`.gltf` or `.glb`), seen through its camera or, if it has none, one
    /// that frames everything.
    File(PathBuf),
}

impl SceneSource {
    /// The scene a command line names: a file, or a demo at a frame; `None` for neither.
    pub fn from_args(file: Option<PathBuf>, demo: Option<Demo>, frame: u32) -> Option<SceneSource> {
        file.map(SceneSource::File).or(demo.map(|demo| SceneSource::Demo { demo, frame }))
    }

    /// Builds or reads the scene. A file's notes (what it had that was left out) go to `log`.
    pub fn load(&self, log: &mut impl Write) -> Result<Scene> {
        match self {
            SceneSource::Demo { demo, frame } => demo.scene(*frame).context("cannot build the demo scene"),
            SceneSource::File(path) => {
                let import = raystage_gltf_import::read_file(path, &raystage_gltf_import::Limits::default())
                    .with_context(|| format!("cannot import {}", path.display()))?;
                for note in import.notes() {
                    writeln!(log, "note: {}: {note}", path.display())?;
                }
                import.into_scene().with_context(|| format!("cannot import {}", path.display()))
            }
        }
    }

    /// The name in logs: the demo's, or the file's.
    pub fn name(&self) -> String {
        match self {
            SceneSource::Demo { demo, .. } => demo.name(),
            SceneSource::File(path) => path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned()),
        }
    }
}

/// What to render and where to write it.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderJob {
    /// The scene.
    pub scene: SceneSource,
    /// Image width in pixels, `1..=MAX_DIMENSION`.
    pub width: u32,
    /// Image height in pixels, `1..=MAX_DIMENSION`.
    pub height: u32,
    /// Threads for the BVH build and the render, `1..=MAX_THREADS`; `None` for one per core.
    pub threads: Option<usize>,
    /// How pixels are shaded; `None` for Whitted's ray tracing if the scene has lights and the
    /// eye-light preview if it has none.
    pub integrator: Option<Integrator>,
    /// Samples per pixel.
    pub samples: u32,
    /// The PNG file to write (created or replaced).
    pub out: PathBuf,
}

/// What a render cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderReport {
    /// Triangles in the scene.
    pub triangles: usize,
    /// Threads used.
    pub threads: usize,
    /// The frame's statistics, lazy BVH builds included.
    pub frame: FrameStats,
}

/// Parses an integrator name: eyelight, whitted, distribution or path.
pub fn parse_integrator(name: &str) -> Result<Integrator> {
    match Integrator::from_name(name) {
        Some(integrator) => Ok(integrator),
        None => bail!("unknown integrator `{name}`: expected eyelight, whitted, distribution or path"),
    }
}

/// Parses a demo scene name (see [`Demo::NAMES`]).
pub fn parse_demo(name: &str) -> Result<Demo> {
    match Demo::from_name(name) {
        Some(demo) => Ok(demo),
        None => bail!("unknown demo scene `{name}`: expected {}", Demo::NAMES),
    }
}

/// Runs `job`: loads the scene, renders the frame (object trees are built lazily, by the first
/// rays that need them) and writes the PNG, logging a one-line summary to `log`. A render of
/// several samples per pixel shows a progress bar on a terminal.
///
/// The job is checked first and the output file created before any work, so that bad arguments
/// and unwritable paths fail at once rather than after the render.
pub fn render_scene(job: &RenderJob, log: &mut impl Write) -> Result<RenderReport> {
    for (name, value) in [("width", job.width), ("height", job.height)] {
        ensure!((1..=MAX_DIMENSION).contains(&value), "--{name} must be between 1 and {MAX_DIMENSION}, got {value}");
    }
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(threads) = job.threads {
        ensure!((1..=MAX_THREADS).contains(&threads), "--threads must be between 1 and {MAX_THREADS}, got {threads}");
        pool = pool.num_threads(threads);
    }
    let pool = pool.build().context("cannot start the render threads")?;
    let mut out = File::create(&job.out).with_context(|| format!("cannot create {}", job.out.display()))?;

    let scene = job.scene.load(log)?;
    let integrator = job.integrator.unwrap_or(if scene.lights().next().is_some() { Integrator::Whitted } else { Integrator::EyeLight });
    let settings = RenderSettings { width: job.width, height: job.height, integrator, samples_per_pixel: job.samples, ..RenderSettings::default() };
    let (png, frame) = pool.install(|| render_with_progress(&scene, &settings)).context("bad render settings")?;
    out.write_all(&png).with_context(|| format!("cannot write {}", job.out.display()))?;

    let triangles = scene.object_ids().map(|id| scene.mesh(id).map_or(0, |m| m.indices.len())).sum();
    let report = RenderReport { triangles, threads: pool.current_num_threads(), frame };
    writeln!(
        log,
        "{}x{} {} ({} triangles), {} at {} spp [{}]: {:.3} s on {} {} (lazy BVH builds {:.3} s of it), {} rays ({} primary, {} shadow) at {:.1} Mrays/s -> {}",
        job.width,
        job.height,
        job.scene.name(),
        triangles,
        integrator.name(),
        job.samples,
        frame.effects.names().join(", "),
        frame.seconds,
        report.threads,
        if report.threads == 1 { "thread" } else { "threads" },
        frame.work.build_seconds,
        frame.rays.total(),
        frame.rays.primary,
        frame.rays.shadow,
        frame.mrays_per_second(),
        job.out.display()
    )?;
    Ok(report)
}

/// Renders `settings.samples_per_pixel` samples in passes (about a hundred at most), advancing
/// a progress bar on standard error after each (drawn only on a terminal); returns the PNG and
/// the statistics of the whole frame. The passes continue each pixel's sample sequence, so the
/// image is the one a single pass would give.
fn render_with_progress(scene: &Scene, settings: &RenderSettings) -> Result<(Vec<u8>, FrameStats)> {
    let start = Instant::now();
    let mut progressive = Progressive::new(*settings)?;
    let total = settings.samples_per_pixel;
    let bar = ProgressBar::new(total as u64).with_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} samples per pixel, {eta} left").expect("a valid template"),
    );
    let frame = scene.frame();
    let per_pass = total.div_ceil(100);
    let mut stats: Option<FrameStats> = None;
    while progressive.samples() < total {
        let pass = progressive.add(&frame, per_pass.min(total - progressive.samples()));
        stats = Some(match stats {
            None => pass,
            Some(mut sum) => {
                sum.rays += pass.rays;
                sum.time_samples += pass.time_samples;
                sum.lens_samples += pass.lens_samples;
                sum.phases.trace_and_shade += pass.phases.trace_and_shade;
                FrameStats { effects: pass.effects, work: pass.work, accumulated_samples: pass.accumulated_samples, ..sum }
            }
        });
        bar.set_position(progressive.samples() as u64);
    }
    bar.finish_and_clear();
    let mut stats = stats.expect("at least one sample per pixel");
    stats.samples_per_pixel = total;
    stats.phases.object_builds = stats.work.build_seconds;
    stats.seconds = start.elapsed().as_secs_f64();
    Ok((progressive.film().encode_png()?, stats))
}
