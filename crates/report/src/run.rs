//! Computing a report: the reference, the sweeps, the BVH comparison.

use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use raystage_kernel::{BuildOptions, BuildQuality, Bvh8, Hit, Ray};
use raystage_render::{Film, Integrator, RenderSettings, render};
use raystage_scene::{Frame, Scene};

use crate::metrics::Errors;
use crate::scenes::SceneSource;
use crate::Error;

/// Receives progress while a report runs, in units of work (about one sample per pixel of one
/// image each). The command line draws a progress bar with it; `()` ignores it.
pub trait Progress {
    /// The run is about to do `total` units.
    fn start(&mut self, _total: u64) {}
    /// `units` more are done; `what` names the step that just finished.
    fn advance(&mut self, _units: u64, _what: &str) {}
}

impl Progress for () {}

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// The scene.
    pub scene: SceneSource,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel of the reference (path tracer, depth `max_depth`, Russian roulette on,
    /// another seed than the measured images, so that its noise is independent of theirs).
    pub reference_spp: u32,
    /// The samples-per-pixel sweep (path tracer, depth `max_depth`).
    pub spp: Vec<u32>,
    /// Samples per pixel of the other sweeps.
    pub knob_spp: u32,
    /// The path-depth sweep.
    pub depths: Vec<u32>,
    /// The shadow-rays-per-area-light sweep.
    pub light_samples: Vec<u32>,
    /// The path depth of every image but the depth sweep's.
    pub max_depth: u32,
    /// Camera rays per pixel of the BVH comparison (each followed by one diffuse bounce ray).
    pub bvh_rays_per_pixel: u32,
}

impl Options {
    /// The full report: 160×120, a 1024-spp reference, sweeps up to 64 spp. About a minute for
    /// a small scene on two cores (release build).
    pub fn full(scene: SceneSource) -> Options {
        Options {
            scene,
            width: 160,
            height: 120,
            reference_spp: 1024,
            spp: vec![1, 2, 4, 8, 16, 32, 64],
            knob_spp: 16,
            depths: vec![1, 2, 3, 4, 6, 8, 12, 16],
            light_samples: vec![1, 2, 4, 8],
            max_depth: 16,
            bvh_rays_per_pixel: 4,
        }
    }

    /// A tiny report for tests: 32×24, a 64-spp reference, three settings per sweep.
    pub fn quick(scene: SceneSource) -> Options {
        Options {
            scene,
            width: 32,
            height: 24,
            reference_spp: 64,
            spp: vec![1, 2, 4],
            knob_spp: 2,
            depths: vec![1, 2, 4],
            light_samples: vec![1, 2],
            max_depth: 8,
            bvh_rays_per_pixel: 1,
        }
    }

    /// The units of work of the whole run (see [`Progress`]).
    fn units(&self) -> u64 {
        let renders: u64 = self.spp.iter().map(|&s| s as u64).sum::<u64>()
            + (self.depths.len() + self.light_samples.len() + 2 + Integrator::ALL.len()) as u64 * self.knob_spp as u64;
        self.reference_spp as u64 + renders + self.bvh_units()
    }

    fn bvh_units(&self) -> u64 {
        self.knob_spp as u64 * 2
    }
}

/// One measured setting of a knob.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The setting, as the table shows it.
    pub setting: String,
    /// Wall time of the render in seconds.
    pub seconds: f64,
    /// Rays it traced.
    pub rays: u64,
    /// Its errors against the reference.
    pub errors: Errors,
}

impl Row {
    /// Monte Carlo inefficiency, MSE × time: constant across sample counts for an unbiased
    /// estimator, lower is better (its inverse is Veach's efficiency).
    pub fn inefficiency(&self) -> f64 {
        self.errors.mse() * self.seconds
    }
}

/// One knob swept: its settings, measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Knob {
    /// Short identifier (file names): `spp`, `depth`, `light-samples`, `roulette`, `integrator`.
    pub id: &'static str,
    /// Its name in the report.
    pub name: &'static str,
    /// What was held fixed.
    pub fixed: String,
    /// The settings in sweep order.
    pub rows: Vec<Row>,
}

impl Knob {
    /// The row with the lowest MSE × time.
    pub fn best_trade(&self) -> Option<&Row> {
        self.rows.iter().min_by(|a, b| a.inefficiency().total_cmp(&b.inefficiency()))
    }

    /// The row with the lowest RMSE.
    pub fn most_accurate(&self) -> Option<&Row> {
        self.rows.iter().min_by(|a, b| a.errors.rmse.total_cmp(&b.errors.rmse))
    }
}

/// One BVH builder measured on the scene's triangles and rays.
#[derive(Clone, Debug, PartialEq)]
pub struct BvhRow {
    /// `fast` (Morton-order LBVH) or `sah` (binned SAH).
    pub quality: &'static str,
    /// Best of three builds, in seconds.
    pub build_seconds: f64,
    /// Tracing every ray once (closest hit, on all threads), in seconds.
    pub trace_seconds: f64,
    /// Rays traced.
    pub rays: u64,
    /// Inner nodes and leaf blocks of the tree.
    pub nodes: usize,
    /// Rays whose hit differs from the SAH tree's (always 0: every tree returns the same
    /// closest hit, ties included).
    pub mismatches: u64,
}

impl BvhRow {
    /// Build plus trace.
    pub fn total_seconds(&self) -> f64 {
        self.build_seconds + self.trace_seconds
    }
}

/// A report: the reference and every knob's measurements.
#[derive(Clone, Debug)]
pub struct Report {
    /// The scene's name.
    pub scene: String,
    /// A phrase saying what the scene is.
    pub description: String,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// Triangles in the scene (instances baked).
    pub triangles: usize,
    /// Threads the renders and builds ran on.
    pub threads: usize,
    /// The options the report ran with.
    pub options: Options,
    /// Wall time of the reference.
    pub reference_seconds: f64,
    /// The reference image (linear radiance).
    pub reference: Film,
    /// The render knobs.
    pub knobs: Vec<Knob>,
    /// The BVH builders, SAH first.
    pub bvh: Vec<BvhRow>,
    /// Images for the strip, with what they are: the reference first.
    pub images: Vec<(String, Film)>,
}

/// The settings every measured image starts from: the path tracer at `spp`, depth
/// `options.max_depth`, one shadow ray per light, Russian roulette on.
fn baseline(options: &Options, spp: u32) -> RenderSettings {
    RenderSettings {
        width: options.width,
        height: options.height,
        integrator: Integrator::Path,
        samples_per_pixel: spp,
        max_depth: options.max_depth,
        light_samples: 1,
        russian_roulette: true,
        seed: 0,
        ..RenderSettings::default()
    }
}

/// Renders with `settings`, times it and compares it with `reference`.
fn measure(frame: &Frame<'_>, settings: &RenderSettings, setting: String, reference: &Film) -> Result<(Row, Film), Error> {
    let start = Instant::now();
    let (film, stats) = render(frame, settings)?;
    let seconds = start.elapsed().as_secs_f64();
    let errors = Errors::between(&film, reference);
    Ok((Row { setting, seconds, rays: stats.rays.total(), errors }, film))
}

/// Runs the report on the current rayon pool, telling `progress` how far it got.
pub fn run(options: &Options, progress: &mut dyn Progress) -> Result<Report, Error> {
    let scene = options.scene.scene()?;
    progress.start(options.units());
    let frame = scene.frame();

    // The reference also builds every object tree, so no measured render pays for a build.
    let reference_settings = RenderSettings { seed: 0x5EED, ..baseline(options, options.reference_spp) };
    let start = Instant::now();
    let (reference, _) = render(&frame, &reference_settings)?;
    let reference_seconds = start.elapsed().as_secs_f64();
    progress.advance(options.reference_spp as u64, "reference");

    let mut images = vec![(format!("reference, path tracer, {} spp", options.reference_spp), reference.clone())];
    let mut knobs = Vec::new();
    let fixed = format!("path tracer, depth {}, 1 shadow ray per light, Russian roulette on", options.max_depth);

    let mut rows = Vec::new();
    for (i, &spp) in options.spp.iter().enumerate() {
        let (row, film) = measure(&frame, &baseline(options, spp), format!("{spp} spp"), &reference)?;
        if i == 0 || i == options.spp.len() / 2 || i + 1 == options.spp.len() {
            images.push((format!("path tracer, {spp} spp"), film));
        }
        rows.push(row);
        progress.advance(spp as u64, "samples per pixel");
    }
    knobs.push(Knob { id: "spp", name: "Samples per pixel", fixed: fixed.clone(), rows });

    let spp = options.knob_spp;
    let depth = options.max_depth;
    let mut rows = Vec::new();
    for &depth in &options.depths {
        let settings = RenderSettings { max_depth: depth, ..baseline(options, options.knob_spp) };
        rows.push(measure(&frame, &settings, format!("depth {depth}"), &reference)?.0);
        progress.advance(options.knob_spp as u64, "path depth");
    }
    knobs.push(Knob { id: "depth", name: "Path depth", fixed: format!("path tracer, {spp} spp, 1 shadow ray per light, Russian roulette on"), rows });

    let mut rows = Vec::new();
    for &light_samples in &options.light_samples {
        let settings = RenderSettings { light_samples, ..baseline(options, options.knob_spp) };
        rows.push(measure(&frame, &settings, format!("{light_samples} per light"), &reference)?.0);
        progress.advance(options.knob_spp as u64, "light samples");
    }
    knobs.push(Knob { id: "light-samples", name: "Shadow rays per area light", fixed: format!("path tracer, {spp} spp, depth {depth}, Russian roulette on"), rows });

    let mut rows = Vec::new();
    for russian_roulette in [true, false] {
        let settings = RenderSettings { russian_roulette, ..baseline(options, options.knob_spp) };
        rows.push(measure(&frame, &settings, format!("roulette {}", if russian_roulette { "on" } else { "off" }), &reference)?.0);
        progress.advance(options.knob_spp as u64, "Russian roulette");
    }
    knobs.push(Knob { id: "roulette", name: "Russian roulette", fixed: format!("path tracer, {spp} spp, depth {depth}, 1 shadow ray per light"), rows });

    let mut rows = Vec::new();
    for integrator in Integrator::ALL {
        let settings = RenderSettings { integrator, ..baseline(options, options.knob_spp) };
        let (row, film) = measure(&frame, &settings, integrator.name().to_string(), &reference)?;
        if integrator != Integrator::Path {
            images.push((format!("{}, {} spp", integrator.name(), options.knob_spp), film));
        }
        rows.push(row);
        progress.advance(options.knob_spp as u64, "integrators");
    }
    knobs.push(Knob {
        id: "integrator",
        name: "Integrator",
        fixed: format!("{} spp, depth {}; error against the path-traced reference", options.knob_spp, options.max_depth),
        rows,
    });

    let triangles = baked_triangles(&scene);
    let bvh = compare_builders(&scene, &triangles, options);
    progress.advance(options.bvh_units(), "BVH builders");

    Ok(Report {
        scene: options.scene.name(),
        description: options.scene.description(),
        width: options.width,
        height: options.height,
        triangles: triangles.len(),
        threads: rayon::current_num_threads(),
        options: options.clone(),
        reference_seconds,
        reference,
        knobs,
        bvh,
        images,
    })
}

/// Every instanced triangle in world space.
fn baked_triangles(scene: &Scene) -> Vec<[Vec3; 3]> {
    let mut tris = Vec::new();
    for (_, object, transform) in scene.instances() {
        let Ok(mesh) = scene.mesh(object) else { continue };
        tris.extend(mesh.indices.iter().map(|t| t.map(|i| transform.transform_point3(mesh.positions[i as usize]))));
    }
    tris
}

/// SplitMix64, for the jitter of the BVH comparison's rays.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn uniform(seed: u64) -> f32 {
    (mix(seed) >> 40) as f32 / (1u64 << 24) as f32
}

/// Builds the fast and the SAH tree over the scene's triangles (best of three each) and traces
/// the same rays through both: jittered camera rays, and one cosine-distributed bounce ray from
/// each camera ray's hit.
fn compare_builders(scene: &Scene, tris: &Vec<[Vec3; 3]>, options: &Options) -> Vec<BvhRow> {
    let build = |quality| {
        let mut best = f64::INFINITY;
        let mut tree = None;
        for _ in 0..3 {
            let start = Instant::now();
            let built = Bvh8::build(tris, &BuildOptions { quality, ..BuildOptions::default() });
            best = best.min(start.elapsed().as_secs_f64());
            tree = Some(built);
        }
        (tree.expect("built"), best)
    };
    let (sah, sah_build) = build(BuildQuality::Sah);
    let (fast, fast_build) = build(BuildQuality::Fast);

    let (w, h) = (options.width, options.height);
    let per = options.bvh_rays_per_pixel.max(1);
    let camera = *scene.camera();
    let primary: Vec<Ray> = (0..w * h * per)
        .map(|i| {
            let (pixel, k) = (i / per, i as u64);
            let (x, y) = (pixel % w, pixel / w);
            camera.ray(x as f32 + uniform(2 * k), y as f32 + uniform(2 * k + 1), w, h)
        })
        .collect();
    let primary_hits: Vec<Option<Hit>> = primary.par_iter().map(|r| sah.intersect(r)).collect();
    let bounce: Vec<Ray> = primary
        .iter()
        .zip(&primary_hits)
        .enumerate()
        .filter_map(|(i, (ray, hit))| {
            let hit = (*hit)?;
            let tri = tris[hit.prim as usize];
            let mut n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
            if n.dot(ray.dir) > 0.0 {
                n = -n;
            }
            let p = ray.at(hit.t);
            let (u1, u2) = (uniform(7 * i as u64 + 3), uniform(7 * i as u64 + 5));
            let (r, phi) = (u1.sqrt(), std::f32::consts::TAU * u2);
            let (t, b) = n.any_orthonormal_pair();
            let dir = t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u1).max(0.0).sqrt();
            Some(Ray::new(p + n * (1e-4 * p.abs().max_element().max(1.0)), dir))
        })
        .collect();
    let rays: Vec<Ray> = primary.into_iter().chain(bounce).collect();
    let trace = |bvh: &Bvh8| {
        let start = Instant::now();
        let hits: Vec<Option<Hit>> = rays.par_iter().map(|r| bvh.intersect(r)).collect();
        (hits, start.elapsed().as_secs_f64())
    };
    // Once each untimed (caches, page faults), then timed.
    let _ = (trace(&sah), trace(&fast));
    let (sah_hits, sah_trace) = trace(&sah);
    let (fast_hits, fast_trace) = trace(&fast);
    let mismatches = sah_hits.iter().zip(&fast_hits).filter(|(a, b)| a != b).count() as u64;
    let size = |b: &Bvh8| {
        let s = b.stats();
        s.nodes + s.leaves
    };
    vec![
        BvhRow { quality: "sah", build_seconds: sah_build, trace_seconds: sah_trace, rays: rays.len() as u64, nodes: size(&sah), mismatches: 0 },
        BvhRow { quality: "fast", build_seconds: fast_build, trace_seconds: fast_trace, rays: rays.len() as u64, nodes: size(&fast), mismatches },
    ]
}
