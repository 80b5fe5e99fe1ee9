//! Computing a report: the reference, the knobs that apply to the scene, every setting
//! rendered several times (interleaved), and the BVH comparison.

use glam::Vec3;
use rayon::prelude::*;
use raystage_kernel::{BuildOptions, BuildQuality, Bvh8, Hit, Ray};
use raystage_render::{EffectSet, Film, Integrator, MIN_ADAPTIVE_SAMPLES, RenderSettings, render};
use raystage_scene::{Frame, Scene};

use crate::Error;
use crate::metrics::{Comparison, Errors, Split};
use crate::reference::{ReferenceSource, read_image};
use crate::scenes::SceneSource;
use crate::timing::{Spread, timed};

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
    /// The reference.
    pub reference: ReferenceSource,
    /// Image width; `None` to follow the external reference's size, else the scene camera's
    /// aspect ratio (4:3 if it has none) with the longer side `long_side`.
    pub width: Option<u32>,
    /// Image height, as `width`.
    pub height: Option<u32>,
    /// The longer side of the image when no size is given.
    pub long_side: u32,
    /// How many times every setting is rendered (independent seeds, interleaved with the other
    /// settings): at least 3, for a median and a spread of the time and a split of the error
    /// into bias and noise.
    pub repeats: u32,
    /// The samples-per-pixel sweep (path tracer, depth `max_depth`).
    pub spp: Vec<u32>,
    /// Samples per pixel of the other sweeps.
    pub knob_spp: u32,
    /// The path-depth sweep.
    pub depths: Vec<u32>,
    /// The shadow-rays-per-area-light sweep.
    pub light_samples: Vec<u32>,
    /// The Whitted integrator's recursion-depth sweep.
    pub whitted_depths: Vec<u32>,
    /// The distribution integrator's samples-per-pixel sweep (lens, time and light samples
    /// ride on the pixel samples).
    pub distribution_spp: Vec<u32>,
    /// The adaptive-sampling sweep: noise thresholds (`None`: every pixel takes
    /// `adaptive_spp`).
    pub noise_thresholds: Vec<Option<f32>>,
    /// The most samples per pixel of the adaptive sweep.
    pub adaptive_spp: u32,
    /// The path depth of every path-traced image but the depth sweep's.
    pub max_depth: u32,
    /// Camera rays per pixel of the BVH comparison (each followed by one diffuse bounce ray).
    pub bvh_rays_per_pixel: u32,
    /// The error a user wants, relative RMSE on 4×4 blocks: "time to reach the target" is
    /// measured against it.
    pub target: f64,
    /// A run too short for its timings to rank settings: the report says so and ranks none.
    pub quick: bool,
}

impl Options {
    /// The full report: 160 pixels on the long side, a 1024-spp reference, three repeats of
    /// each setting. A few minutes for a small scene on two cores (release build).
    pub fn full(scene: SceneSource) -> Options {
        Options {
            scene,
            reference: ReferenceSource::Converged { spp: 1024 },
            width: None,
            height: None,
            long_side: 160,
            repeats: 3,
            spp: vec![1, 2, 4, 8, 16, 32, 64],
            knob_spp: 16,
            depths: vec![1, 2, 3, 4, 6, 8, 12, 16],
            light_samples: vec![1, 2, 4, 8],
            whitted_depths: vec![1, 2, 3, 4, 6, 8],
            distribution_spp: vec![4, 16, 64],
            noise_thresholds: vec![None, Some(0.2), Some(0.1), Some(0.05)],
            adaptive_spp: 64,
            max_depth: 16,
            bvh_rays_per_pixel: 4,
            target: 0.05,
            quick: false,
        }
    }

    /// A tiny report for tests and a first look: 32 pixels on the long side, a 64-spp
    /// reference, three repeats of two or three settings per knob. Seconds; its timings are too
    /// short to rank settings.
    pub fn quick(scene: SceneSource) -> Options {
        let full = Options::full(scene);
        Options {
            reference: ReferenceSource::Converged { spp: 64 },
            long_side: 32,
            spp: vec![1, 2, 4],
            knob_spp: 2,
            depths: vec![1, 2, 4],
            light_samples: vec![1, 2],
            whitted_depths: vec![1, 3],
            distribution_spp: vec![1, 4],
            noise_thresholds: vec![None, Some(0.1)],
            adaptive_spp: MIN_ADAPTIVE_SAMPLES,
            max_depth: 8,
            bvh_rays_per_pixel: 1,
            quick: true,
            ..full
        }
    }
}

/// One measured setting of a knob, rendered `repeats` times.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The setting, as the tables show it.
    pub setting: String,
    /// The knob's value, where it is a number (samples, depth, rays per light, threshold).
    pub value: Option<f64>,
    /// Wall time of each render.
    pub wall: Spread,
    /// CPU time of each render (all threads).
    pub cpu: Spread,
    /// Rays of the first render.
    pub rays: u64,
    /// Each render's errors against the reference.
    pub errors: Vec<Errors>,
    /// The error of one render split into bias and noise.
    pub split: Split,
}

impl Row {
    /// The main error measure (relative RMSE on 4×4 blocks) of each render.
    pub fn error(&self) -> Spread {
        Spread { samples: self.errors.iter().map(|e| e.relative_blocks).collect() }
    }

    /// One channel's mean ratio to the reference, over the renders.
    pub fn mean_ratio(&self, channel: usize) -> Spread {
        Spread { samples: self.errors.iter().map(|e| e.mean_ratio[channel]).collect() }
    }

    /// The image's brightness against the reference: the three channels' mean ratios
    /// averaged, over the renders.
    pub fn level(&self) -> Spread {
        Spread { samples: self.errors.iter().map(|e| e.mean_ratio.iter().sum::<f64>() / 3.0).collect() }
    }

    /// The bias, where the measurements can tell it from zero: the block estimate carries about
    /// 2 × noise / √repeats of uncertainty of its own (heavy-tailed noise at low sample counts
    /// makes it larger still), and a bias below that is taken as none — unless the image's
    /// overall brightness, measured over every pixel and so far more precisely, is off the
    /// reference's by more than 0.5 % and three times its spread: then the larger of the two.
    pub fn resolved_bias(&self) -> f64 {
        let resolution = 2.0 * self.split.noise / (self.errors.len().max(1) as f64).sqrt();
        let level = self.level();
        let shift = (level.median() - 1.0).abs();
        let brightness_off = shift > 0.005 && shift > 3.0 * level.half_range();
        if self.split.bias > resolution || brightness_off { self.split.bias.max(shift) } else { 0.0 }
    }

    /// Wall time to reach `target` error with this setting, taking more samples (noise falls
    /// as 1/√time, bias stays): one figure per render, from its time and its error relative
    /// to the median. `None` if the (resolved) bias alone is at or above 90 % of the target.
    pub fn time_to(&self, target: f64) -> Option<Spread> {
        let bias = self.resolved_bias();
        let room = target * target - bias * bias;
        if bias >= 0.9 * target || room <= 0.0 {
            return None;
        }
        // Each render's own time and error: the spread of both widens the range, so that a
        // noise estimate that three renders got lucky with cannot pass for a better setting.
        let (median, scale) = (self.error().median().max(1e-30), self.split.noise * self.split.noise / room);
        let samples = self.wall.samples.iter().zip(&self.errors).map(|(wall, e)| wall * (e.relative_blocks / median).powi(2) * scale).collect();
        Some(Spread { samples })
    }
}

/// One knob swept: its settings, measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Knob {
    /// Short identifier (file names): `spp`, `depth`, `light-samples`, `roulette`,
    /// `adaptive`, `integrator`, `whitted-depth`, `distribution-spp`, `kernel`.
    pub id: &'static str,
    /// Its name in the report.
    pub name: &'static str,
    /// What was held fixed.
    pub fixed: String,
    /// The settings in sweep order.
    pub rows: Vec<Row>,
}

impl Knob {
    /// Whether the settings are an ordered sweep (joined by a line in the plots) rather than
    /// alternatives.
    pub fn ordered(&self) -> bool {
        !matches!(self.id, "roulette" | "integrator" | "kernel")
    }
}

/// A knob left out of the report, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct LeftOut {
    /// The knob's name.
    pub name: &'static str,
    /// Why it does not apply to the scene.
    pub why: &'static str,
}

/// One BVH builder measured on the scene's triangles and rays.
#[derive(Clone, Debug, PartialEq)]
pub struct BvhRow {
    /// `fast` (Morton-order LBVH) or `sah` (binned SAH).
    pub quality: &'static str,
    /// Each build's time, in seconds.
    pub build: Spread,
    /// Each trace of every ray (closest hit, on all threads), in seconds.
    pub trace: Spread,
    /// Rays traced.
    pub rays: u64,
    /// Inner nodes and leaf blocks of the tree.
    pub nodes: usize,
    /// Rays whose hit differs from the SAH tree's (always 0: every tree returns the same
    /// closest hit, ties included).
    pub mismatches: u64,
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
    /// Where the size came from.
    pub size_from: &'static str,
    /// Triangles in the scene (instances baked).
    pub triangles: usize,
    /// Threads the renders and builds ran on.
    pub threads: usize,
    /// The options the report ran with.
    pub options: Options,
    /// Wall time of the converged reference (0 for an external one).
    pub reference_seconds: f64,
    /// The reference image (linear radiance).
    pub reference: Film,
    /// The share of pixels measured: the others see an emitter or the background.
    pub measured_share: f64,
    /// The converged reference's own noise (relative, on 4×4 blocks), estimated from the spp
    /// sweep and taken off every bias; `None` for an external reference.
    pub reference_noise: Option<f64>,
    /// The effects the scene calls for under the path tracer.
    pub effects: EffectSet,
    /// The render knobs that apply to the scene.
    pub knobs: Vec<Knob>,
    /// The knobs that do not, and why.
    pub left_out: Vec<LeftOut>,
    /// The BVH builders, SAH first.
    pub bvh: Vec<BvhRow>,
    /// Images for the strip, with what they are: the reference first.
    pub images: Vec<(String, Film)>,
}

/// The settings every measured image starts from: the path tracer at `spp`, depth
/// `options.max_depth`, one shadow ray per light, Russian roulette on.
fn baseline(options: &Options, width: u32, height: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        integrator: Integrator::Path,
        samples_per_pixel: spp,
        max_depth: options.max_depth,
        light_samples: 1,
        russian_roulette: true,
        seed: 0,
        ..RenderSettings::default()
    }
}

/// The image size: given, the external reference's, or the camera's aspect.
fn image_size(options: &Options, aspect: Option<f32>, external: Option<&Film>) -> Result<(u32, u32, &'static str), Error> {
    let bad = |message: String| Error::Unsupported(message);
    if let Some(film) = external {
        let (w, h) = (film.width(), film.height());
        if options.width.is_some_and(|x| x != w) || options.height.is_some_and(|y| y != h) {
            return Err(bad(format!("the reference is {w}x{h}: --width and --height must match it or be left out")));
        }
        return Ok((w, h, "the reference image's size"));
    }
    let aspect = aspect.unwrap_or(4.0 / 3.0) as f64;
    // The other side at the camera's aspect, at least a pixel.
    let height_of = |w: u32| (w as f64 / aspect).round().max(1.0) as u32;
    let width_of = |h: u32| (h as f64 * aspect).round().max(1.0) as u32;
    let (w, h, from) = match (options.width, options.height) {
        (Some(w), Some(h)) => (w, h, "given"),
        (Some(w), None) => (w, height_of(w), "the given width at the camera's aspect"),
        (None, Some(h)) => (width_of(h), h, "the given height at the camera's aspect"),
        (None, None) if aspect >= 1.0 => (options.long_side, height_of(options.long_side), "the camera's aspect"),
        (None, None) => (width_of(options.long_side), options.long_side, "the camera's aspect"),
    };
    if w == 0 || h == 0 || w > 4096 || h > 4096 {
        return Err(bad(format!("a report image of {w}x{h} pixels: each side must be in 1..=4096")));
    }
    Ok((w, h, from))
}

/// One setting to measure: which knob, its label and value, and the render.
struct Setting {
    knob: usize,
    label: String,
    value: Option<f64>,
    settings: RenderSettings,
    /// Whether the strip shows its first render.
    shown: bool,
}

/// The knobs that apply to the scene, their settings, and the ones left out.
fn plan(options: &Options, base: &RenderSettings, path: &EffectSet, whitted: &EffectSet, distribution: &EffectSet) -> (Vec<Knob>, Vec<Setting>, Vec<LeftOut>) {
    let (mut knobs, mut settings, mut left_out) = (Vec::new(), Vec::new(), Vec::new());
    let with = |spp: u32| RenderSettings { samples_per_pixel: spp, ..*base };
    let knob_spp = options.knob_spp;
    let depth = options.max_depth;
    let mut add = |knob: Knob, rows: Vec<(String, Option<f64>, RenderSettings, bool)>| {
        let index = knobs.len();
        knobs.push(knob);
        settings.extend(rows.into_iter().map(|(label, value, settings, shown)| Setting { knob: index, label, value, settings, shown }));
    };
    let knob = |id, name, fixed: String| Knob { id, name, fixed, rows: Vec::new() };

    let last = options.spp.len().saturating_sub(1);
    add(
        knob("spp", "Samples per pixel", format!("path tracer, depth {depth}, 1 shadow ray per light, Russian roulette on")),
        options.spp.iter().enumerate().map(|(i, &s)| (format!("{s} spp"), Some(s as f64), with(s), i == 0 || i == last / 2 || i == last)).collect(),
    );
    add(
        knob("adaptive", "Adaptive sampling", format!("path tracer, at most {} spp, depth {depth}; a tile stops when each pixel's standard error is below the threshold × its mean", options.adaptive_spp)),
        options
            .noise_thresholds
            .iter()
            .map(|&t| {
                let label = t.map_or(format!("off ({} spp)", options.adaptive_spp), |t| format!("threshold {t}"));
                (label, t.map(f64::from), RenderSettings { noise_threshold: t, ..with(options.adaptive_spp) }, false)
            })
            .collect(),
    );
    if path.global_illumination {
        add(
            knob("depth", "Path depth", format!("path tracer, {knob_spp} spp, 1 shadow ray per light, Russian roulette on")),
            options.depths.iter().map(|&d| (format!("depth {d}"), Some(d as f64), RenderSettings { max_depth: d, ..with(knob_spp) }, false)).collect(),
        );
        add(
            knob("roulette", "Russian roulette", format!("path tracer, {knob_spp} spp, depth {depth}, 1 shadow ray per light")),
            [true, false]
                .into_iter()
                .map(|on| (format!("roulette {}", if on { "on" } else { "off" }), None, RenderSettings { russian_roulette: on, ..with(knob_spp) }, false))
                .collect(),
        );
    } else {
        left_out.push(LeftOut { name: "Path depth and Russian roulette", why: "the scene has no geometry for light to bounce off" });
    }
    if path.area_lights {
        add(
            knob("light-samples", "Shadow rays per area light", format!("path tracer, {knob_spp} spp, depth {depth}, Russian roulette on")),
            options.light_samples.iter().map(|&n| (format!("{n} per light"), Some(n as f64), RenderSettings { light_samples: n, ..with(knob_spp) }, false)).collect(),
        );
    } else {
        left_out.push(LeftOut { name: "Shadow rays per area light", why: "the scene has no area light, emitting surface or environment light" });
    }
    add(
        knob("integrator", "Integrator", format!("{knob_spp} spp, depth {depth}")),
        Integrator::ALL
            .into_iter()
            .map(|i| (i.name().to_string(), None, RenderSettings { integrator: i, ..with(knob_spp) }, i != Integrator::Path))
            .collect(),
    );
    if whitted.reflection || whitted.refraction {
        add(
            knob("whitted-depth", "Whitted recursion depth", format!("Whitted integrator, {knob_spp} spp")),
            options
                .whitted_depths
                .iter()
                .map(|&d| (format!("depth {d}"), Some(d as f64), RenderSettings { integrator: Integrator::Whitted, max_depth: d, ..with(knob_spp) }, false))
                .collect(),
        );
    } else {
        left_out.push(LeftOut { name: "Whitted recursion depth", why: "no surface of the scene reflects or refracts specularly" });
    }
    if distribution.depth_of_field || distribution.motion_blur || distribution.area_lights {
        add(
            knob("distribution-spp", "Distribution samples per pixel", format!("distribution integrator, depth {depth}, 1 shadow ray per light; each pixel sample also samples the lens, the shutter and the lights")),
            options
                .distribution_spp
                .iter()
                .map(|&s| (format!("{s} spp"), Some(s as f64), RenderSettings { integrator: Integrator::Distribution, ..with(s) }, false))
                .collect(),
        );
    } else {
        left_out.push(LeftOut { name: "Distribution samples", why: "no lens blur, motion blur or area light for the distribution integrator to sample" });
    }
    add(
        knob("kernel", "Shading kernel", format!("path tracer, {knob_spp} spp, depth {depth}; the same image either way, by construction")),
        [true, false]
            .into_iter()
            .map(|on| (if on { "specialised".to_string() } else { "general".to_string() }, None, RenderSettings { specialize: on, ..with(knob_spp) }, false))
            .collect(),
    );
    (knobs, settings, left_out)
}

/// The pixels that see an emitter or the background directly: those a path of one segment
/// (the camera ray alone) makes bright.
fn emitter_pixels(frame: &Frame<'_>, base: &RenderSettings) -> Result<Vec<bool>, Error> {
    let settings = RenderSettings { max_depth: 1, samples_per_pixel: 4, seed: 0xE417, ..*base };
    let (film, _) = render(frame, &settings)?;
    Ok(film.pixels().iter().map(|p| p.max_element() > 0.0).collect())
}

/// The effects the frame calls for under `integrator` (from a tiny render: cheap, and the
/// renderer's own answer).
fn effects(frame: &Frame<'_>, base: &RenderSettings, integrator: Integrator) -> Result<EffectSet, Error> {
    let settings = RenderSettings { width: 8, height: 6, samples_per_pixel: 2, integrator, ..*base };
    Ok(render(frame, &settings)?.1.effects)
}

/// Runs the report on the current rayon pool, telling `progress` how far it got.
pub fn run(options: &Options, progress: &mut dyn Progress) -> Result<Report, Error> {
    if options.repeats < 3 {
        return Err(Error::Unsupported(format!("--repeats must be at least 3 (a median and a spread), got {}", options.repeats)));
    }
    if !(options.target > 0.0 && options.target < 1.0) {
        return Err(Error::Unsupported(format!("--target must be in (0, 1), got {}", options.target)));
    }
    let (scene, aspect) = options.scene.scene()?;
    let external = match &options.reference {
        ReferenceSource::External(path) => Some(read_image(path)?),
        ReferenceSource::Converged { .. } => None,
    };
    let (width, height, size_from) = image_size(options, aspect, external.as_ref())?;
    let frame = scene.frame();
    let base = baseline(options, width, height, 1);

    let path_effects = effects(&frame, &base, Integrator::Path)?;
    let whitted_effects = effects(&frame, &base, Integrator::Whitted)?;
    let distribution_effects = effects(&frame, &base, Integrator::Distribution)?;
    let (mut knobs, settings, left_out) = plan(options, &base, &path_effects, &whitted_effects, &distribution_effects);

    let reference_spp = match options.reference {
        ReferenceSource::Converged { spp } => spp,
        ReferenceSource::External(_) => 0,
    };
    let spp_units: u64 = settings.iter().map(|s| s.settings.samples_per_pixel as u64).sum();
    progress.start(reference_spp as u64 + spp_units * options.repeats as u64 + 8);

    // The reference also builds every object tree, so no measured render pays for a build; an
    // external reference leaves that to the mask's render.
    let (reference, reference_seconds) = match external {
        Some(film) => (film, 0.0),
        None => {
            let settings = RenderSettings { samples_per_pixel: reference_spp, seed: 0x5EED, ..base };
            let (film, wall, _) = timed(|| render(&frame, &settings));
            (film?.0, wall)
        }
    };
    progress.advance(reference_spp as u64, "reference");
    let comparison = Comparison::new(&reference, &emitter_pixels(&frame, &base)?);

    // Every setting once per round, rounds in turn, each round starting one place further on:
    // a slow phase of a shared machine spreads over the settings instead of landing on one.
    let mut measured: Vec<(Spread, Spread, u64, Vec<Errors>, Vec<Vec<Vec3>>)> = settings.iter().map(|_| Default::default()).collect();
    let mut images = vec![(reference_label(&options.reference), reference.clone())];
    for round in 0..options.repeats {
        for k in 0..settings.len() {
            let i = (k + round as usize * settings.len() / options.repeats as usize) % settings.len();
            let setting = &settings[i];
            let render_settings = RenderSettings { seed: round + 1, ..setting.settings };
            let (result, wall, cpu) = timed(|| render(&frame, &render_settings));
            let (film, stats) = result?;
            let m = &mut measured[i];
            m.0.samples.push(wall);
            m.1.samples.push(cpu);
            if round == 0 {
                m.2 = stats.rays.total();
                if setting.shown {
                    images.push((format!("{}, {}", knobs[setting.knob].name, setting.label), film.clone()));
                }
            }
            m.3.push(comparison.errors(&film));
            m.4.push(comparison.blocks(&film));
            progress.advance(setting.settings.samples_per_pixel as u64, knobs[setting.knob].name);
        }
    }
    for (setting, (wall, cpu, rays, errors, blocks)) in settings.into_iter().zip(measured) {
        let split = comparison.split(&blocks);
        knobs[setting.knob].rows.push(Row { setting: setting.label, value: setting.value, wall, cpu, rays, errors, split });
    }
    // A converged raystage reference has noise of its own, which every setting's mean would
    // otherwise count as bias. It is the path tracer's noise at the reference's sample count:
    // the spp sweep's last row (the same settings) scaled by its samples over the reference's.
    let reference_noise = match options.reference {
        ReferenceSource::Converged { spp } => knobs[0].rows.last().and_then(|r| Some(r.split.noise * (r.value? / spp as f64).sqrt())),
        ReferenceSource::External(_) => None,
    };
    if let Some(noise) = reference_noise {
        for row in knobs.iter_mut().flat_map(|k| k.rows.iter_mut()) {
            row.split.bias = (row.split.bias.powi(2) - noise * noise).max(0.0).sqrt();
        }
    }

    let triangles = baked_triangles(&scene);
    let bvh = compare_builders(&scene, &triangles, options.repeats, width, height, options.bvh_rays_per_pixel);
    progress.advance(8, "BVH builders");

    Ok(Report {
        scene: options.scene.name(),
        description: options.scene.description(),
        width,
        height,
        size_from,
        triangles: triangles.len(),
        threads: rayon::current_num_threads(),
        options: options.clone(),
        reference_seconds,
        reference,
        measured_share: comparison.measured_share(),
        reference_noise,
        effects: path_effects,
        knobs,
        left_out,
        bvh,
        images,
    })
}

fn reference_label(reference: &ReferenceSource) -> String {
    match reference {
        ReferenceSource::Converged { spp } => format!("reference, path tracer, {spp} spp"),
        ReferenceSource::External(path) => format!("reference, {}", path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())),
    }
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

/// Builds the fast and the SAH tree over the scene's triangles (`repeats` times each,
/// interleaved) and traces the same rays through both (`repeats` times each, after one untimed
/// pass): jittered camera rays, and one cosine-distributed bounce ray from each camera ray's
/// hit.
fn compare_builders(scene: &Scene, tris: &[[Vec3; 3]], repeats: u32, w: u32, h: u32, per: u32) -> Vec<BvhRow> {
    let qualities = [BuildQuality::Sah, BuildQuality::Fast];
    let mut builds = [Spread::default(), Spread::default()];
    let mut trees: [Option<Bvh8>; 2] = [None, None];
    for _ in 0..repeats {
        for (q, quality) in qualities.into_iter().enumerate() {
            let (tree, wall, _) = timed(|| Bvh8::build(tris, &BuildOptions { quality, ..BuildOptions::default() }));
            builds[q].samples.push(wall);
            trees[q] = Some(tree);
        }
    }
    let [Some(sah), Some(fast)] = trees else { unreachable!("repeats ≥ 1 built both trees") };

    let per = per.max(1);
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
    let trace = |bvh: &Bvh8| timed(|| rays.par_iter().map(|r| bvh.intersect(r)).collect::<Vec<Option<Hit>>>());
    // Once each untimed (caches, page faults), then timed, interleaved.
    let (sah_hits, _, _) = trace(&sah);
    let (fast_hits, _, _) = trace(&fast);
    let mut traces = [Spread::default(), Spread::default()];
    for _ in 0..repeats {
        traces[0].samples.push(trace(&sah).1);
        traces[1].samples.push(trace(&fast).1);
    }
    let mismatches = sah_hits.iter().zip(&fast_hits).filter(|(a, b)| a != b).count() as u64;
    let size = |b: &Bvh8| {
        let s = b.stats();
        s.nodes + s.leaves
    };
    let [sah_trace, fast_trace] = traces;
    let [sah_build, fast_build] = builds;
    vec![
        BvhRow { quality: "sah", build: sah_build, trace: sah_trace, rays: rays.len() as u64, nodes: size(&sah), mismatches: 0 },
        BvhRow { quality: "fast", build: fast_build, trace: fast_trace, rays: rays.len() as u64, nodes: size(&fast), mismatches },
    ]
}
