//! `raystage render`: build the BVH of a demo scene, render one eye-light frame, write a PNG.

use std::fs::File;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail, ensure};
use raystage_demo::{Mesh, ProbeCamera, StandardScene};
use raystage_kernel::{BuildOptions, Bvh8, Ray};
use raystage_render::{Camera, EyeLight, FrameStats, Geometry, render_frame};

/// Largest accepted image width or height in pixels.
pub const MAX_DIMENSION: u32 = 16_384;

/// Largest accepted number of render threads.
pub const MAX_THREADS: usize = 1024;

/// Triangles per sphere of the demo sphere grid (100 × 50 segments, two triangles each); the
/// eye-light palette gives each sphere its own colour.
const TRIANGLES_PER_SPHERE: u32 = 10_000;

/// Triangles per colour group in the soup, whose triangles have no objects to colour by.
const SOUP_GROUP: u32 = 1024;

/// What to render and where to write it.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderJob {
    /// The demo scene.
    pub demo: StandardScene,
    /// Image width in pixels, `1..=MAX_DIMENSION`.
    pub width: u32,
    /// Image height in pixels, `1..=MAX_DIMENSION`.
    pub height: u32,
    /// Threads for the BVH build and the render, `1..=MAX_THREADS`; `None` for one per core.
    pub threads: Option<usize>,
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
    /// Wall-clock time of the BVH build, in seconds.
    pub build_seconds: f64,
    /// The frame's statistics.
    pub frame: FrameStats,
}

/// Parses a demo scene name: `spheres` (or `sphere`) or `soup`.
pub fn parse_demo(name: &str) -> Result<StandardScene> {
    match StandardScene::from_name(name) {
        Some(demo) => Ok(demo),
        None => bail!("unknown demo scene `{name}`: expected spheres, sphere or soup"),
    }
}

/// Runs `job`: builds the scene's BVH, renders the frame and writes the PNG, logging the build
/// time and a one-line summary to `log`.
///
/// The job is checked first and the output file created before any work, so that bad arguments
/// and unwritable paths fail at once rather than after the build and the render.
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

    let mesh = job.demo.mesh();
    let start = Instant::now();
    let bvh = pool.install(|| Bvh8::build(&mesh.as_indexed(), &BuildOptions::default()));
    let build_seconds = start.elapsed().as_secs_f64();
    writeln!(log, "built the BVH of `{}` ({} triangles) in {build_seconds:.3} s", job.demo.name(), mesh.indices.len())?;

    let geometry = Geometry { triangles: mesh.as_indexed(), bvh: &bvh };
    let camera = DemoCamera(job.demo.camera());
    let shader = palette(job.demo, &mesh);
    let (film, frame) = pool.install(|| render_frame(&geometry, &camera, &shader, job.width, job.height));
    out.write_all(&film.encode_png()?).with_context(|| format!("cannot write {}", job.out.display()))?;

    let report =
        RenderReport { triangles: mesh.indices.len(), threads: pool.current_num_threads(), build_seconds, frame };
    writeln!(
        log,
        "{}x{} {}: build {:.3} s, render {:.3} s, {:.1} Mrays/s ({} {}) -> {}",
        job.width,
        job.height,
        job.demo.name(),
        build_seconds,
        frame.seconds,
        frame.mrays_per_second(),
        report.threads,
        if report.threads == 1 { "thread" } else { "threads" },
        job.out.display()
    )?;
    Ok(report)
}

/// The demo scenes' camera, as the renderer sees it.
struct DemoCamera(ProbeCamera);

impl Camera for DemoCamera {
    fn primary_ray(&self, x: u32, y: u32, width: u32, height: u32) -> Ray {
        Ray::new(self.0.origin, self.0.dir(x, y, width, height))
    }
}

/// The eye-light palette of a demo: one colour per sphere and a grey ground plane (the grid's
/// last two triangles), or colour groups of consecutive soup triangles.
fn palette(demo: StandardScene, mesh: &Mesh) -> EyeLight {
    match demo {
        StandardScene::Spheres => {
            EyeLight { group_size: TRIANGLES_PER_SPHERE, plain_from: mesh.indices.len() as u32 - 2 }
        }
        StandardScene::Soup => EyeLight { group_size: SOUP_GROUP, plain_from: u32::MAX },
    }
}
