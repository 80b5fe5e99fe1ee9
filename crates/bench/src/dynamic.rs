//! The dynamic benchmark: animated scenes after BART (robots, museum, terrain), updated and
//! traced frame by frame by raystage and (with the `embree` feature) Embree 3 in the same run,
//! taking turns frame by frame.
//!
//! Every frame both systems take the same instance transforms and vertex positions, then trace
//! the same 1280×720 primary rays and, from each primary hit, one shadow ray towards the sun;
//! each system traces the primary rays once one by one and once in 4×2-pixel packets (the
//! renderer's camera rays; Embree's `rtcIntersect8`), and the shadow rays alike: one by one, or
//! a packet's together (parallel rays from neighbouring hits; Embree's `rtcOccluded8`).
//! *Update* is what a system spends bringing its acceleration structures up to date (raystage:
//! setting transforms, the top-level build and the lazy object builds and refits; Embree: setting
//! transforms and committing geometry and scenes). *Trace* is the rest of the frame. Frame 0
//! (the initial builds) is reported apart; the per-frame figures are medians over frames 1..=N.

use std::time::Instant;

use raystage_demo::animated::{Animation, Staged};
use raystage_kernel::{PACKET_SIZE, Ray};
use raystage_scene::{Camera, Frame};
use serde::Serialize;

use crate::kernel::{Api, median};

/// Image size of the traced frames.
pub const WIDTH: u32 = 1280;
/// Image size of the traced frames.
pub const HEIGHT: u32 = 720;

/// One frame of one system.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameTime {
    /// Seconds bringing the acceleration structures up to date.
    pub update: f64,
    /// Seconds tracing.
    pub trace: f64,
    /// Rays traced (primary + shadow).
    pub rays: u64,
    /// Primary rays that hit.
    pub hits: u64,
}

/// One system's run over an animation: the first frame and every later one.
#[derive(Clone, Debug, Default)]
pub struct SystemRun {
    /// `raystage`, or `embree` with its quality.
    pub system: String,
    /// Frame 0: initial builds and the first trace.
    pub first: FrameTime,
    /// Frames 1..=N.
    pub frames: Vec<FrameTime>,
}

/// Medians of a run, one JSON object per system and scene.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct DynamicReport {
    /// `raystage` or `embree-<quality>`.
    pub system: String,
    /// Scene name.
    pub scene: String,
    /// Threads tracing.
    pub threads: usize,
    /// Triangles after instancing.
    pub triangles: u64,
    /// Instances.
    pub instances: usize,
    /// Frame 0 milliseconds (builds and trace).
    pub first_frame_ms: f64,
    /// Median update milliseconds per frame.
    pub update_ms: f64,
    /// Median trace milliseconds per frame.
    pub trace_ms: f64,
    /// Median frame milliseconds (update + trace).
    pub frame_ms: f64,
    /// Frames per second at the median frame time.
    pub fps: f64,
    /// Million rays per second while tracing.
    pub mrays: f64,
}

impl SystemRun {
    /// Medians as a report line.
    pub fn report(&self, scene: &str, threads: usize, triangles: u64, instances: usize) -> DynamicReport {
        let pick = |f: fn(&FrameTime) -> f64| median(&self.frames.iter().map(f).collect::<Vec<_>>());
        let frame_ms = pick(|f| f.update + f.trace) * 1e3;
        DynamicReport {
            system: self.system.clone(),
            scene: scene.to_string(),
            threads,
            triangles,
            instances,
            first_frame_ms: (self.first.update + self.first.trace) * 1e3,
            update_ms: pick(|f| f.update) * 1e3,
            trace_ms: pick(|f| f.trace) * 1e3,
            frame_ms,
            fps: 1e3 / frame_ms,
            mrays: pick(|f| f.rays as f64 / f.trace / 1e6),
        }
    }
}

/// The 1280×720 primary rays of an animation's view.
pub fn primary_rays(camera: &Camera) -> Vec<Ray> {
    (0..HEIGHT)
        .flat_map(|y| (0..WIDTH).map(move |x| camera.ray(x as f32 + 0.5, y as f32 + 0.5, WIDTH, HEIGHT)))
        .collect()
}

/// The shadow ray from the hit at `t` of `ray` towards the sun: it starts a hair before the hit
/// point along the ray (so it does not find the surface it leaves) and is unbounded.
fn shadow_ray(ray: &Ray, t: f32, sun: glam::Vec3) -> Ray {
    Ray::new(ray.at(t * (1.0 - 1e-4)), -sun.normalize())
}

/// A closest-hit query for a packet of rays: each ray's hit distance into the second slice.
pub type PacketQuery<'a> = &'a (dyn Fn(&[Ray], &mut [Option<f32>]) + Sync);

/// How a system traces: its closest-hit query for one ray and for a packet of up to
/// [`PACKET_SIZE`] (camera rays of 4×2 pixels), and its occlusion query.
pub struct Queries<'a> {
    /// One ray: its closest hit distance.
    pub closest: &'a (dyn Fn(&Ray) -> Option<f32> + Sync),
    /// A packet: each ray's closest hit distance.
    pub closest_packet: PacketQuery<'a>,
    /// Whether a segment is blocked.
    pub occluded: &'a (dyn Fn(&Ray) -> bool + Sync),
    /// Which of up to a packet of segments are blocked (bit `i` for ray `i`).
    pub occluded_packet: &'a (dyn Fn(&[Ray]) -> u32 + Sync),
}

/// The system name of a run: `base`, with `-packets` when primary rays go in packets.
fn system_name(base: &str, api: Api) -> String {
    match api {
        Api::Single => base.to_string(),
        Api::Packets => format!("{base}-packets"),
    }
}

/// The frame's primary rays as `api` hands them over: row by row, or in 4×2-pixel packets.
fn rays_for(camera: &Camera, api: Api) -> Vec<Ray> {
    let rays = primary_rays(camera);
    match api {
        Api::Single => rays,
        Api::Packets => crate::rays::in_blocks(&rays, WIDTH, HEIGHT, (4, 2)),
    }
}

/// Traces primary rays and, given the `sun`, a shadow ray per hit (one by one, or in packets
/// with `api`), on `threads` threads; returns (rays traced, primary hits).
fn trace_frame(rays: &[Ray], sun: Option<glam::Vec3>, threads: usize, api: Api, queries: &Queries<'_>) -> (u64, u64) {
    let chunk = |rays: &[Ray]| {
        let (mut traced, mut hits) = (0u64, 0u64);
        let mut found = [None; PACKET_SIZE];
        let group = if api == Api::Packets { PACKET_SIZE } else { 1 };
        for rays in rays.chunks(group) {
            let found = &mut found[..rays.len()];
            match api {
                Api::Single => found[0] = (queries.closest)(&rays[0]),
                Api::Packets => (queries.closest_packet)(rays, found),
            }
            let mut shadows = [Ray::new(glam::Vec3::ZERO, glam::Vec3::X); PACKET_SIZE];
            let mut n = 0;
            for (ray, t) in rays.iter().zip(found.iter()) {
                traced += 1;
                if let Some(t) = t {
                    hits += 1;
                    if let Some(sun) = sun {
                        traced += 1;
                        shadows[n] = shadow_ray(ray, *t, sun);
                        n += 1;
                    }
                }
            }
            match api {
                Api::Single => shadows[..n].iter().for_each(|s| _ = std::hint::black_box((queries.occluded)(s))),
                // The packet's shadow rays, parallel towards the sun from neighbouring hits.
                Api::Packets if n > 0 => _ = std::hint::black_box((queries.occluded_packet)(&shadows[..n])),
                Api::Packets => {}
            }
        }
        (traced, hits)
    };
    if threads <= 1 {
        return chunk(rays);
    }
    std::thread::scope(|s| {
        let per = rays.len().div_ceil(threads).next_multiple_of(PACKET_SIZE);
        let handles: Vec<_> = rays.chunks(per).map(|c| s.spawn(move || chunk(c))).collect();
        handles.into_iter().map(|h| h.join().expect("trace thread")).fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
    })
}

/// One system of the benchmark, brought up to date and traced one frame at a time, so that
/// several systems can take turns frame by frame (see [`run_in_turns`]).
pub trait System {
    /// Its name in the tables: `raystage` or `embree-<quality>` (`-robust` in robust mode),
    /// with `-packets` when primary rays go in packets.
    fn name(&self) -> String;
    /// Moves to frame `f` of the animation (frames come in order from 0) and traces it.
    fn frame(&mut self, f: u32) -> FrameTime;
}

/// raystage on an animation: primary rays handed over as `api` says (packets go through
/// `Frame::intersect_many`, as the renderer's camera rays do), and shadow rays unless
/// [`Raystage::primary_only`].
pub struct Raystage<'a> {
    animation: &'a dyn Animation,
    staged: Staged,
    rays: Vec<Ray>,
    threads: usize,
    api: Api,
    pool: rayon::ThreadPool,
    shadows: bool,
}

impl<'a> Raystage<'a> {
    /// `animation` loaded at frame 0 (nothing built yet), to be traced on `threads` threads.
    pub fn new(animation: &'a dyn Animation, threads: usize, api: Api) -> Raystage<'a> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
        let staged = Staged::new(animation).expect("the animation makes a valid scene");
        let rays = rays_for(staged.scene.camera(), api);
        Raystage { animation, staged, rays, threads, api, pool, shadows: true }
    }

    /// The same system tracing the primary rays alone, to be set beside a system that traces
    /// only those (the RTRPS experiment, [`crate::rtrps`]).
    pub fn primary_only(self) -> Raystage<'a> {
        Raystage { shadows: false, ..self }
    }
}

impl System for Raystage<'_> {
    fn name(&self) -> String {
        system_name("raystage", self.api)
    }

    fn frame(&mut self, f: u32) -> FrameTime {
        let (instances, deformed) = (self.animation.instances(f), self.animation.deform(f));
        let start = Instant::now();
        self.staged.advance(&instances, deformed).expect("valid frame");
        let frame: Frame<'_> = self.staged.scene.frame();
        let placed = start.elapsed().as_secs_f64();
        let trace_start = Instant::now();
        let closest_packet = |rays: &[Ray], found: &mut [Option<f32>]| {
            let mut hits = [None; PACKET_SIZE];
            frame.intersect_many(rays, &mut hits[..rays.len()], 0.0);
            found.iter_mut().zip(&hits).for_each(|(f, h)| *f = h.map(|h| h.t));
        };
        let queries = Queries {
            closest: &|r| frame.intersect(r, 0.0).map(|h| h.t),
            closest_packet: &closest_packet,
            occluded: &|r| frame.occluded(r, 0.0),
            occluded_packet: &|rays| frame.occluded_many(rays, 0.0),
        };
        let sun = self.shadows.then(|| self.animation.view().sun);
        let (traced, hits) = self.pool.install(|| trace_frame(&self.rays, sun, self.threads, self.api, &queries));
        let traced_seconds = trace_start.elapsed().as_secs_f64();
        // Lazy builds and refits happened inside the trace; count them as update.
        let built = frame.work().build_seconds.min(traced_seconds);
        FrameTime { update: placed + built, trace: traced_seconds - built, rays: traced, hits }
    }
}

/// Embree on an animation: static and animated objects at MEDIUM, unstructured ones at the
/// quality [`Embree::new`] is given, top level LOW; primary rays one by one (`rtcIntersect1`) or
/// in packets (`rtcIntersect8`) as `api` says.
#[cfg(feature = "embree")]
pub struct Embree<'a> {
    animation: &'a dyn Animation,
    // Declared before the device, so dropped first.
    scene: crate::embree::InstancedScene,
    _device: crate::embree::Device,
    /// Seconds of the initial commits, frame 0's update.
    built: f64,
    quality: crate::embree::Quality,
    robust: bool,
    rays: Vec<Ray>,
    threads: usize,
    api: Api,
}

#[cfg(feature = "embree")]
impl<'a> Embree<'a> {
    /// `animation` built at frame 0 with moving objects at `unstructured_quality`, in robust
    /// mode if `robust` (see [`crate::embree::Scene::build_robust`]), to be traced on `threads`
    /// threads.
    pub fn new(animation: &'a dyn Animation, threads: usize, unstructured_quality: crate::embree::Quality, robust: bool, api: Api) -> Embree<'a> {
        use crate::embree::{Device, InstancedScene, Quality};
        use raystage_scene::ObjectKind;

        let device = Device::new(threads).expect("Embree device");
        let objects = animation.objects();
        let specs: Vec<_> = objects
            .iter()
            .map(|o| match o.kind {
                ObjectKind::Unstructured => (&o.mesh, unstructured_quality, true),
                _ => (&o.mesh, Quality::Medium, false),
            })
            .collect();
        let view = animation.view();
        let camera = Camera::look_at(view.eye, view.target, glam::Vec3::Y, view.fov_y_degrees).expect("valid view");
        let (scene, built) = InstancedScene::build(&device, &specs, &animation.instances(0), Quality::Low, robust);
        Embree { animation, scene, _device: device, built, quality: unstructured_quality, robust, rays: rays_for(&camera, api), threads, api }
    }
}

#[cfg(feature = "embree")]
impl System for Embree<'_> {
    fn name(&self) -> String {
        let robust = if self.robust { "-robust" } else { "" };
        system_name(&format!("embree-{}{robust}", self.quality.name().to_lowercase()), self.api)
    }

    fn frame(&mut self, f: u32) -> FrameTime {
        let update = if f == 0 { self.built } else { self.scene.update(&self.animation.instances(f), &self.animation.deform(f)) };
        let start = Instant::now();
        let scene = &self.scene;
        let queries = Queries {
            closest: &|r| scene.intersect(r),
            closest_packet: &|rays, found| scene.intersect8(rays, found),
            occluded: &|r| scene.occluded(r),
            occluded_packet: &|rays| scene.occluded8(rays),
        };
        let (traced, hits) = trace_frame(&self.rays, Some(self.animation.view().sun), self.threads, self.api, &queries);
        FrameTime { update, trace: start.elapsed().as_secs_f64(), rays: traced, hits }
    }
}

/// Runs `systems` over frames 0..=`frames`, taking turns within each frame (the first to go
/// rotating from frame to frame): a shared machine's speed drifts by tens of percent within a
/// minute, and systems run one after the other would each meet a different phase of it.
pub fn run_in_turns(systems: &mut [Box<dyn System + '_>], frames: u32) -> Vec<SystemRun> {
    let mut runs: Vec<SystemRun> = systems.iter().map(|s| SystemRun { system: s.name(), ..SystemRun::default() }).collect();
    for f in 0..=frames {
        for k in 0..systems.len() {
            let i = (k + f as usize) % systems.len();
            let time = systems[i].frame(f);
            if f == 0 { runs[i].first = time } else { runs[i].frames.push(time) }
        }
    }
    runs
}

/// The median over frames 1..=N of `ours`' frame measure `of` over `theirs`' in the same
/// frame (the two ran in turns, so each frame's pair met the same machine).
pub fn paired_ratio(ours: &SystemRun, theirs: &SystemRun, of: fn(&FrameTime) -> f64) -> f64 {
    let ratios: Vec<f64> = ours.frames.iter().zip(&theirs.frames).map(|(a, b)| of(a) / of(b)).collect();
    median(&ratios)
}

/// Triangles after instancing.
pub fn instanced_triangles(animation: &dyn Animation) -> u64 {
    let per_object: Vec<u64> = animation.objects().iter().map(|o| o.mesh.indices.len() as u64).collect();
    animation.instances(0).iter().map(|(o, _)| per_object[*o]).sum()
}
