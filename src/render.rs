//! `raystage render`: build a demo scene, render one frame, write a PNG.

use std::fs::File;
use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, bail, ensure};
use raystage_demo::animated::Demo;
use raystage_render::{FrameStats, Integrator, RenderSettings, render};

/// Largest accepted image width or height in pixels.
pub const MAX_DIMENSION: u32 = 16_384;

/// Largest accepted number of render threads.
pub const MAX_THREADS: usize = 1024;

/// What to render and where to write it.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderJob {
    /// The demo scene.
    pub demo: Demo,
    /// The frame of an animated demo (0 for the first).
    pub frame: u32,
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

/// Runs `job`: builds the scene, renders the frame (object trees are built lazily, by the
/// first rays that need them) and writes the PNG, logging a one-line summary to `log`.
///
/// The job is checked first and the output file created before any work, so that bad arguments
/// and unwritable paths fail at once rather than after the render.
pub fn render_demo(job: &RenderJob, log: &mut impl Write) -> Result<RenderReport> {
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

    let scene = job.demo.scene(job.frame).context("cannot build the demo scene")?;
    let integrator = job.integrator.unwrap_or(if scene.lights().next().is_some() { Integrator::Whitted } else { Integrator::EyeLight });
    let settings = RenderSettings { width: job.width, height: job.height, integrator, samples_per_pixel: job.samples, ..RenderSettings::default() };
    let (film, frame) = pool.install(|| render(&scene.frame(), &settings)).context("bad render settings")?;
    out.write_all(&film.encode_png()?).with_context(|| format!("cannot write {}", job.out.display()))?;

    let triangles = scene.object_ids().map(|id| scene.mesh(id).map_or(0, |m| m.indices.len())).sum();
    let report = RenderReport { triangles, threads: pool.current_num_threads(), frame };
    writeln!(
        log,
        "{}x{} {} ({} triangles), {} at {} spp [{}]: {:.3} s on {} {} (lazy BVH builds {:.3} s of it), {} rays ({} primary, {} shadow) at {:.1} Mrays/s -> {}",
        job.width,
        job.height,
        job.demo.name(),
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
