//! The render benchmark: what shading costs on top of the kernel, what specialising the
//! shading kernel to the frame's effect set saves, and how fast the path tracer converges.
//!
//! *Shading cost*: on the probe's sphere grid at 1920×1080, the kernel's bare primary rays (in
//! 4×2 packets, as the renderer traces camera rays, and balanced between threads as the
//! renderer balances its bands, not split in halves as the probe splits its rows, which leaves
//! one thread idle once it is through the sky) against whole frames through the renderer:
//! the eye-light preview, and Whitted with one point light and shadows. *Specialisation*: a
//! Whitted frame of the same purely diffuse grid under an area light (sampled at its centre,
//! with a shadow ray from every hit, all through the recursion, where reflection and refraction
//! code would sit; under delta lights the matte first hits are shaded in packets with no
//! recursion at all) through the kernel compiled for its effect set and through the general one
//! with reflection and refraction compiled in, which must give the identical image. All
//! systems take turns within each repetition, on the same thread count; times are medians over
//! repetitions, ratios the medians of each repetition's ratio.
//! *Convergence*: the path tracer on the closed Cornell room, accumulated progressively to 1, 2,
//! 4, … samples per pixel and compared with a high-sample reference of another seed; the RMSE
//! should fall at least as 1/√spp, a slope of −0.5 on log-log axes (faster while the sampler's
//! stratification pays).

use std::time::Instant;

use glam::Vec3;
use raystage_demo::StandardScene;
use raystage_kernel::Bvh8;
use raystage_render::{Film, FrameStats, Integrator, Progressive, RayCounts, RenderSettings};
use raystage_scene::{Light, LightId, Scene};
use serde::Serialize;

use crate::kernel::{Api, Calls, Schedule, build_raystage, median, trace_all};
use crate::rays::{self, HEIGHT, WIDTH};

/// The light of the shading measurements, replacing the sphere scene's two directional lights:
/// above and in front of the grid, bright enough that the middle rows are lit like under the sun.
pub const POINT_LIGHT: Light = Light::Point { position: Vec3::new(0.0, 20.0, 5.0), intensity: Vec3::splat(1800.0) };

/// The light of the specialisation measurement: a 4 × 4 square where [`POINT_LIGHT`] is, facing
/// down, about as bright.
pub const AREA_LIGHT: Light =
    Light::Area { corner: Vec3::new(-2.0, 20.0, 3.0), edge_u: Vec3::new(4.0, 0.0, 0.0), edge_v: Vec3::new(0.0, 0.0, 4.0), radiance: Vec3::splat(112.0) };

/// The probe's sphere grid as a retained scene lit by [`POINT_LIGHT`] alone.
pub fn point_lit_spheres() -> Scene {
    spheres_lit_by(POINT_LIGHT)
}

/// The probe's sphere grid lit by `light` alone (instead of its two directional lights).
fn spheres_lit_by(light: Light) -> Scene {
    let mut scene = StandardScene::Spheres.scene().expect("the standard scene is valid");
    let suns: Vec<LightId> = scene.lights().map(|(id, _)| id).collect();
    for id in suns {
        scene.remove_light(id).expect("the light was just listed");
    }
    scene.add_light(light).expect("the light is valid");
    scene
}

/// What one system of the shading measurements computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum System {
    /// The kernel alone: the probe's primary rays in 4×2 packets through a [`Bvh8`].
    Kernel,
    /// A whole eye-light frame through the renderer.
    EyeLight,
    /// A whole Whitted frame (one point light, shadows).
    Whitted,
    /// A whole Whitted frame of the area-lit grid through the kernel specialised for the
    /// frame's effect set: no reflection or refraction code.
    AreaSpecialised,
    /// The same frame through the general kernel, reflection and refraction compiled in.
    AreaGeneral,
}

impl System {
    /// Every system, in the order of the first repetition.
    pub const ALL: [System; 5] = [System::Kernel, System::EyeLight, System::Whitted, System::AreaSpecialised, System::AreaGeneral];

    /// Its name in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            System::Kernel => "kernel",
            System::EyeLight => "eyelight",
            System::Whitted => "whitted",
            System::AreaSpecialised => "whitted-area",
            System::AreaGeneral => "whitted-area-general",
        }
    }

    /// The renderer's settings of its frame (none for the bare kernel).
    fn settings(self) -> Option<RenderSettings> {
        let frame = |integrator, specialize| RenderSettings { width: WIDTH, height: HEIGHT, integrator, specialize, ..RenderSettings::default() };
        match self {
            System::Kernel => None,
            System::EyeLight => Some(frame(Integrator::EyeLight, true)),
            System::Whitted | System::AreaSpecialised => Some(frame(Integrator::Whitted, true)),
            System::AreaGeneral => Some(frame(Integrator::Whitted, false)),
        }
    }

    /// Whether its frame is of the area-lit grid (else of the point-lit one).
    fn area_lit(self) -> bool {
        matches!(self, System::AreaSpecialised | System::AreaGeneral)
    }
}

/// One measured frame of one system.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measured {
    /// Wall seconds: tracing the rays (kernel) or the whole `render` call, frame start included.
    pub seconds: f64,
    /// Rays traced, by kind (the kernel's are all primary).
    pub rays: RayCounts,
}

/// How two images differ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct PixelDifference {
    /// Pixels whose linear RGB values are not bit-identical.
    pub differing: u64,
    /// Largest difference of one channel.
    pub largest: f32,
}

/// Compares two films of the same size pixel by pixel.
pub fn compare(a: &Film, b: &Film) -> PixelDifference {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()), "films of one size");
    let mut diff = PixelDifference::default();
    for y in 0..a.height() {
        for x in 0..a.width() {
            let (p, q) = (a.pixel(x, y), b.pixel(x, y));
            if p != q {
                diff.differing += 1;
                diff.largest = diff.largest.max((p - q).abs().max_element());
            }
        }
    }
    diff
}

/// Everything the shading measurements found.
pub struct ShadingRun {
    /// Threads of every measurement.
    pub threads: usize,
    /// Triangles of the scene.
    pub triangles: usize,
    /// Seconds of the renderer's lazy object-tree build (the warm-up frame, not timed).
    pub object_build_seconds: f64,
    /// Samples per system, in [`System::ALL`] order.
    pub samples: Vec<(System, Vec<Measured>)>,
    /// How the specialised and general Whitted images differ (they should not).
    pub specialisation_difference: PixelDifference,
}

impl ShadingRun {
    /// The samples of `system`.
    fn of(&self, system: System) -> &[Measured] {
        self.samples.iter().find(|(s, _)| *s == system).map_or(&[], |(_, m)| m)
    }

    /// Median seconds of `system`.
    pub fn median_seconds(&self, system: System) -> f64 {
        median(&self.of(system).iter().map(|m| m.seconds).collect::<Vec<_>>())
    }

    /// The median over repetitions of `system`'s time over `baseline`'s in the same repetition:
    /// paired, so that the machine's speed drifting between repetitions cancels out.
    pub fn ratio(&self, system: System, baseline: System) -> f64 {
        let pairs = self.of(system).iter().zip(self.of(baseline));
        median(&pairs.map(|(a, b)| a.seconds / b.seconds).collect::<Vec<_>>())
    }

    /// The rays `system` traced in its last frame.
    pub fn rays(&self, system: System) -> RayCounts {
        self.of(system).last().map_or_else(RayCounts::default, |m| m.rays)
    }

    /// One JSON line per system, then one for the specialisation.
    pub fn reports(&self) -> (Vec<ShadingReport>, SpecialisationReport) {
        let shading = System::ALL
            .iter()
            .map(|&system| {
                let rays = self.rays(system);
                ShadingReport {
                    measurement: "shading",
                    system: system.name(),
                    scene: StandardScene::Spheres.name(),
                    width: WIDTH,
                    height: HEIGHT,
                    threads: self.threads,
                    ms: self.median_seconds(system) * 1e3,
                    vs_kernel: self.ratio(system, System::Kernel),
                    primary_rays: rays.primary,
                    shadow_rays: rays.shadow,
                    rays: rays.total(),
                }
            })
            .collect();
        let specialisation = SpecialisationReport {
            measurement: "specialisation",
            scene: StandardScene::Spheres.name(),
            threads: self.threads,
            specialised_ms: self.median_seconds(System::AreaSpecialised) * 1e3,
            general_ms: self.median_seconds(System::AreaGeneral) * 1e3,
            general_over_specialised: self.ratio(System::AreaGeneral, System::AreaSpecialised),
            difference: self.specialisation_difference,
        };
        (shading, specialisation)
    }
}

/// One system of the shading measurements as a JSON line (medians).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ShadingReport {
    /// Always `shading`.
    pub measurement: &'static str,
    /// [`System::name`].
    pub system: &'static str,
    /// `sphere`.
    pub scene: &'static str,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Threads.
    pub threads: usize,
    /// Median milliseconds per frame.
    pub ms: f64,
    /// Median over repetitions of the time over the bare kernel's in the same repetition.
    pub vs_kernel: f64,
    /// Camera rays per frame.
    pub primary_rays: u64,
    /// Shadow rays per frame.
    pub shadow_rays: u64,
    /// All rays per frame.
    pub rays: u64,
}

/// Specialised against general Whitted shading as a JSON line (medians).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SpecialisationReport {
    /// Always `specialisation`.
    pub measurement: &'static str,
    /// `sphere`.
    pub scene: &'static str,
    /// Threads.
    pub threads: usize,
    /// Kernel compiled for the effect set, median milliseconds.
    pub specialised_ms: f64,
    /// General kernel, median milliseconds.
    pub general_ms: f64,
    /// Median over repetitions of the general time over the specialised time of the same
    /// repetition.
    pub general_over_specialised: f64,
    /// How the two images differ (nothing, if all is well).
    pub difference: PixelDifference,
}

/// Renders one frame of `scene` with `settings` and times the whole call; panics if the frame
/// had to build or refit an object tree (the timed frames must come after a warm-up).
fn render_timed(scene: &Scene, settings: &RenderSettings) -> (Measured, Film) {
    let start = Instant::now();
    let (film, stats) = raystage_render::render(&scene.frame(), settings).expect("valid settings");
    let seconds = start.elapsed().as_secs_f64();
    assert_no_tree_work(&stats);
    (Measured { seconds, rays: stats.rays }, film)
}

/// Panics if a frame built, refitted or rebuilt an object tree.
fn assert_no_tree_work(stats: &FrameStats) {
    let w = stats.work;
    assert!(
        w.built + w.refitted + w.rebuilt == 0 && stats.phases.object_builds == 0.0,
        "a timed frame did tree work ({w:?}): it would not measure shading alone"
    );
}

/// Measures every [`System`] `reps` times on `threads` threads, the systems taking turns (the
/// first one rotating from repetition to repetition), so that drift in machine speed affects all
/// alike. `progress` receives a line per step.
pub fn run_shading(threads: usize, reps: usize, mut progress: impl FnMut(&str)) -> ShadingRun {
    let reps = reps.max(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    progress("shading: building the point-lit and the area-lit sphere scenes and the kernel's BVH");
    let (point_lit, area_lit) = (point_lit_spheres(), spheres_lit_by(AREA_LIGHT));
    let mesh = StandardScene::Spheres.mesh();
    let (bvh, kernel_build) = build_raystage(&mesh, threads);
    progress(&format!("shading: kernel BVH built in {kernel_build:.3} s"));
    let packets = rays::in_blocks(&rays::primary(StandardScene::Spheres, WIDTH, HEIGHT), WIDTH, HEIGHT, (4, 2));
    let warm_up = System::EyeLight.settings().expect("a rendered system");
    let (_, stats) = pool.install(|| raystage_render::render(&point_lit.frame(), &warm_up)).expect("valid settings");
    pool.install(|| raystage_render::render(&area_lit.frame(), &warm_up)).expect("valid settings");
    measure_kernel(&bvh, &packets, threads);
    progress(&format!("shading: warm-up frames built each scene's {} object tree(s) in {:.3} s", stats.work.built, stats.work.build_seconds));
    let mut samples: Vec<(System, Vec<Measured>)> = System::ALL.iter().map(|&s| (s, Vec::new())).collect();
    for rep in 0..reps {
        for k in 0..System::ALL.len() {
            let index = (k + rep) % System::ALL.len();
            let system = System::ALL[index];
            let measured = match system.settings() {
                None => measure_kernel(&bvh, &packets, threads),
                Some(settings) => {
                    let scene = if system.area_lit() { &area_lit } else { &point_lit };
                    // Each film is dropped at once, so that its buffer goes back to the renderer
                    // for the next frame as it would in an application (a film kept here would
                    // make a later frame map fresh pages and time the page faults).
                    pool.install(|| render_timed(scene, &settings)).0
                }
            };
            progress(&format!("shading: rep {}/{reps} {}: {:.1} ms", rep + 1, system.name(), measured.seconds * 1e3));
            samples[index].1.push(measured);
        }
    }
    // The specialisation's two images, compared once the timing is done.
    let film = |system: System| pool.install(|| render_timed(&area_lit, &system.settings().expect("a rendered system")).1);
    ShadingRun {
        threads,
        triangles: mesh.indices.len(),
        object_build_seconds: stats.work.build_seconds,
        samples,
        specialisation_difference: compare(&film(System::AreaSpecialised), &film(System::AreaGeneral)),
    }
}

/// What the physically based material costs against `Diffuse`: one integrator's
/// frame of the point-lit sphere grid with every sphere `Diffuse`, and with every sphere
/// `PhysicallyBased` of the same base colour (a dielectric of roughness 0.5), medians over the
/// repetitions, the two taking turns.
#[derive(Clone, Debug, Serialize)]
pub struct MaterialCost {
    /// The integrator.
    pub integrator: &'static str,
    /// Image size and samples per pixel.
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Median frame times.
    pub diffuse_ms: f64,
    pub physically_based_ms: f64,
    /// The median of each repetition's physically based time over its diffuse time.
    pub ratio: f64,
}

/// The point-lit sphere grid with every `Diffuse` shader turned `PhysicallyBased` of the same
/// colour (metallic 0, roughness 0.5).
fn physically_based_spheres() -> Scene {
    let mut scene = point_lit_spheres();
    let diffuse: Vec<(raystage_scene::ShaderId, Vec3)> =
        scene.shaders().filter(|(_, s)| s.class().name == "Diffuse").map(|(id, s)| (id, s.color("diffuse"))).collect();
    for (id, colour) in diffuse {
        scene.define_shader(id, "PhysicallyBased").expect("a built-in class");
        for (name, value) in [
            ("base_color", raystage_scene::ParamValue::Color(colour)),
            ("metallic", raystage_scene::ParamValue::Float(0.0)),
            ("roughness", raystage_scene::ParamValue::Float(0.5)),
        ] {
            scene.set_param(id, name, value).expect("a parameter of the class");
        }
    }
    scene
}

/// Measures [`MaterialCost`] for the eye-light preview (1 spp at 1920×1080) and the path
/// tracer (4 spp at 960×540), `reps` times each on `threads` threads.
pub fn run_material_cost(threads: usize, reps: usize, mut progress: impl FnMut(&str)) -> Vec<MaterialCost> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    let scenes = [point_lit_spheres(), physically_based_spheres()];
    let cases = [(Integrator::EyeLight, WIDTH, HEIGHT, 1), (Integrator::Path, WIDTH / 2, HEIGHT / 2, 4)];
    cases
        .into_iter()
        .map(|(integrator, width, height, spp)| {
            let settings = RenderSettings { width, height, integrator, samples_per_pixel: spp, ..RenderSettings::default() };
            // Warm-up frames build each scene's tree.
            scenes.iter().for_each(|scene| drop(pool.install(|| raystage_render::render(&scene.frame(), &settings))));
            let mut times = [Vec::new(), Vec::new()];
            for rep in 0..reps.max(1) {
                for k in 0..2 {
                    let which = (k + rep) % 2;
                    times[which].push(pool.install(|| render_timed(&scenes[which], &settings)).0.seconds);
                }
            }
            let ratios: Vec<f64> = times[1].iter().zip(&times[0]).map(|(p, d)| p / d).collect();
            let cost = MaterialCost {
                integrator: integrator.name(),
                width,
                height,
                spp,
                diffuse_ms: median(&times[0]) * 1e3,
                physically_based_ms: median(&times[1]) * 1e3,
                ratio: median(&ratios),
            };
            progress(&format!("material cost, {}: Diffuse {:.1} ms, PhysicallyBased {:.1} ms, {:.2}x", cost.integrator, cost.diffuse_ms, cost.physically_based_ms, cost.ratio));
            cost
        })
        .collect()
}

/// Traces the primary rays, in 4×2 packets, through `bvh` on `threads` threads.
fn measure_kernel(bvh: &Bvh8, packets: &[raystage_kernel::Ray], threads: usize) -> Measured {
    let traced = trace_all(bvh, packets, threads, Calls::Closest(Api::Packets), Schedule::Shared);
    Measured { seconds: traced.seconds, rays: RayCounts { primary: packets.len() as u64, ..RayCounts::default() } }
}

/// Width of the convergence images.
pub const CONVERGENCE_WIDTH: u32 = 128;
/// Height of the convergence images.
pub const CONVERGENCE_HEIGHT: u32 = 96;
/// Seed of the reference image's sample sequences.
const REFERENCE_SEED: u32 = 0x5EED;
/// Seed of the measured images' sample sequences: not the reference's, so that their errors are
/// independent.
const MEASURED_SEED: u32 = 1;

/// The error of the progressive image at one sample count.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ConvergencePoint {
    /// Samples per pixel accumulated.
    pub spp: u32,
    /// Root-mean-square difference from the reference over every pixel and channel (linear RGB).
    pub rmse: f64,
    /// Seconds rendering up to this count, from the first sample.
    pub seconds: f64,
}

/// Everything the convergence measurement found.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceRun {
    /// Threads rendering.
    pub threads: usize,
    /// Samples per pixel of the reference.
    pub reference_spp: u32,
    /// Seconds rendering the reference.
    pub reference_seconds: f64,
    /// One point per power of two.
    pub points: Vec<ConvergencePoint>,
    /// Least-squares slope of log RMSE against log spp over every point (−0.5 for Monte Carlo
    /// convergence; steeper while the sampler's stratification still pays).
    pub slope: f64,
    /// The same over the last [`TAIL_POINTS`] points only: the trend at high sample counts.
    pub tail_slope: f64,
}

/// Points of the tail slope: the last factor of 8 in samples per pixel.
pub const TAIL_POINTS: usize = 4;

impl ConvergenceRun {
    /// One JSON line per sample count.
    pub fn reports(&self) -> Vec<ConvergenceReport> {
        self.points
            .iter()
            .map(|p| ConvergenceReport {
                measurement: "convergence",
                scene: "cornell",
                width: CONVERGENCE_WIDTH,
                height: CONVERGENCE_HEIGHT,
                threads: self.threads,
                reference_spp: self.reference_spp,
                point: *p,
                slope: self.slope,
                tail_slope: self.tail_slope,
            })
            .collect()
    }
}

/// One sample count of the convergence measurement as a JSON line.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ConvergenceReport {
    /// Always `convergence`.
    pub measurement: &'static str,
    /// `cornell`.
    pub scene: &'static str,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Threads.
    pub threads: usize,
    /// Samples per pixel of the reference.
    pub reference_spp: u32,
    /// Sample count, error and time.
    #[serde(flatten)]
    pub point: ConvergencePoint,
    /// Fitted log-log slope over every sample count of the run.
    pub slope: f64,
    /// Fitted log-log slope over the last [`TAIL_POINTS`] sample counts.
    pub tail_slope: f64,
}

/// Path-traces the Cornell room: a reference at `reference_spp`, then one progressive
/// accumulation of another seed compared with it at 1, 2, 4, … up to `max_spp` samples per
/// pixel. `progress` receives a line per step.
pub fn run_convergence(threads: usize, reference_spp: u32, max_spp: u32, mut progress: impl FnMut(&str)) -> ConvergenceRun {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    let scene = raystage_demo::shading::cornell_room().expect("the Cornell room is valid");
    let settings = |seed| RenderSettings {
        width: CONVERGENCE_WIDTH,
        height: CONVERGENCE_HEIGHT,
        integrator: Integrator::Path,
        seed,
        ..RenderSettings::default()
    };
    let frame = scene.frame();
    progress(&format!("convergence: reference, {reference_spp} spp"));
    let start = Instant::now();
    let reference = RenderSettings { samples_per_pixel: reference_spp, ..settings(REFERENCE_SEED) };
    let (reference, _) = pool.install(|| raystage_render::render(&frame, &reference)).expect("valid settings");
    let reference_seconds = start.elapsed().as_secs_f64();
    progress(&format!("convergence: reference took {reference_seconds:.1} s"));
    let mut progressive = Progressive::new(settings(MEASURED_SEED)).expect("valid settings");
    let mut points = Vec::new();
    let mut seconds = 0.0;
    for spp in std::iter::successors(Some(1u32), |n| n.checked_mul(2)).take_while(|&n| n <= max_spp) {
        let start = Instant::now();
        pool.install(|| progressive.add(&frame, spp - progressive.samples()));
        seconds += start.elapsed().as_secs_f64();
        let point = ConvergencePoint { spp, rmse: rmse(&progressive.film(), &reference), seconds };
        progress(&format!("convergence: {spp} spp, RMSE {:.5}", point.rmse));
        points.push(point);
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|p| (p.spp as f64, p.rmse)).collect();
    let slope = log_log_slope(&logs);
    let tail_slope = log_log_slope(&logs[logs.len().saturating_sub(TAIL_POINTS)..]);
    ConvergenceRun { threads, reference_spp, reference_seconds, points, slope, tail_slope }
}

/// Root-mean-square difference of two films of the same size over every pixel and channel.
pub fn rmse(a: &Film, b: &Film) -> f64 {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()), "films of one size");
    let mut sum = 0.0f64;
    for y in 0..a.height() {
        for x in 0..a.width() {
            let d = (a.pixel(x, y) - b.pixel(x, y)).as_dvec3();
            sum += d.length_squared();
        }
    }
    (sum / (3.0 * a.width() as f64 * a.height() as f64)).sqrt()
}

/// Least-squares slope of `ln y` against `ln x` over `(x, y)` points (NaN below two distinct x).
pub fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let n = logs.len() as f64;
    let (mx, my) = (logs.iter().map(|p| p.0).sum::<f64>() / n, logs.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_an_inverse_square_root_is_minus_a_half() {
        let points: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0, 256.0].iter().map(|&n: &f64| (n, 0.3 / n.sqrt())).collect();
        assert!((log_log_slope(&points) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn rmse_averages_over_pixels_and_channels() {
        let a = Film::from_pixels(2, 1, vec![Vec3::ZERO, Vec3::ZERO]);
        let b = Film::from_pixels(2, 1, vec![Vec3::new(2.0, 0.0, 0.0), Vec3::ZERO]);
        assert!((rmse(&a, &b) - (4.0f64 / 6.0).sqrt()).abs() < 1e-12);
        assert_eq!(rmse(&a, &a), 0.0);
    }

    #[test]
    fn compare_counts_differing_pixels_and_the_largest_difference() {
        let a = Film::from_pixels(3, 1, vec![Vec3::ONE; 3]);
        let b = Film::from_pixels(3, 1, vec![Vec3::ONE, Vec3::new(1.0, 1.25, 1.0), Vec3::new(0.5, 1.0, 1.0)]);
        assert_eq!(compare(&a, &b), PixelDifference { differing: 2, largest: 0.5 });
        assert_eq!(compare(&a, &a), PixelDifference::default());
    }
}
