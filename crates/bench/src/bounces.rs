//! The bounce benchmark: a path tracer's rays bounce by bounce, traced one by one on one thread
//! in the order the path tracer makes them and after sorting them by where they start, with what
//! each walk did per ray; Bikker's tables of single-ray rates and node visits per diffuse bounce
//! (seed 003, `[003 L98-144]`) measured on raystage's kernel.
//!
//! RayGrid and wavefront path tracers batch a bounce's rays by data locality so that rays
//! starting in one part of the scene are traced while that part is in cache. raystage traces one
//! path at a time (docs/performance.md, "Paths in waves (issue 42): measured, not kept"); this
//! benchmark shows, bounce by bounce, how coherent the rays are as made and what sorting them
//! gains.
//!
//! The rays: one camera ray through each pixel centre, then for each further bounce one ray from
//! each hit of the previous one, cosine-distributed about the hit triangle's normal turned to
//! the side the ray came from ([`crate::rays::bounce`]): the diffuse bounce the path tracer makes
//! on these scenes, whose surfaces are Lambertian. They follow the path tracer's distribution,
//! not its recorded rays: no Russian roulette (which would only drop a random share of the
//! later bounces), and paths end where the path tracer ends them, in the sky and on the light
//! (whose surface is black).
//!
//! The tree: one kernel [`Bvh8`] over the scene's triangles in world space, built with the
//! options the scene builds a static object's tree with ([`raystage_scene::ObjectKind::build_options`];
//! glTF's meshes import as static objects), so that every walk can be counted. The path tracer walks the scene's two levels (a top-level tree over
//! instances, then each object's tree); these rooms are a few objects side by side, each
//! instanced once, so the object trees the path tracer reaches hold the same triangles.

use std::time::Instant;

use glam::Vec3;
use raystage_demo::{Mesh, StandardScene};
use raystage_kernel::morton::{self, radix_sort};
use raystage_kernel::{Aabb, Bvh8, Hit, Ray, WalkCounts};
use serde::Serialize;

use crate::kernel::{Api, Calls, PerRay, Schedule, Traced, Tracer, trace_all};
use crate::pathtrace::PathScene;
use crate::rays::{self, PrimaryHit};

/// Bits of each axis of a ray's origin cell in its sort key: 64³ cells over the scene's bounds,
/// the cells of the throwaway probe that docs/performance.md reports (branch
/// `wavefront-experiment`).
pub const CELL_BITS: u32 = 6;

// A key, three bits per level of the cell and three of the octant, fits the radix sort's keys.
const _: () = assert!(3 * CELL_BITS + 3 <= 3 * morton::BITS);

/// The seed of the primary hits' bounce, the kernel benchmark's (so the first bounce draws the
/// numbers its bounce rays draw); bounce `k` draws from `BOUNCE_SEED + k - 1`, so that no two
/// bounces of a path reuse one sequence of random numbers.
const BOUNCE_SEED: u64 = rays::PROBE_BOUNCE_SEED;

/// A scene of the benchmark.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BounceScene {
    /// The path-tracing benchmark's Cornell room, 32 triangles ([`PathScene::Room`]).
    Room,
    /// The room with a million triangles of spheres on its floor ([`PathScene::Spheres`]).
    Spheres,
    /// The kernel benchmark's sphere grid under an open sky ([`StandardScene::Spheres`]), seen
    /// by its camera: most bounces leave the scene.
    SphereGrid,
}

impl BounceScene {
    /// Every scene, in the order `--scene all` runs them.
    pub const ALL: [BounceScene; 3] = [BounceScene::Room, BounceScene::Spheres, BounceScene::SphereGrid];

    /// Its name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            BounceScene::Room => PathScene::Room.name(),
            BounceScene::Spheres => PathScene::Spheres.name(),
            BounceScene::SphereGrid => "sphere-grid",
        }
    }

    /// The scene named `name`.
    pub fn from_name(name: &str) -> Option<BounceScene> {
        BounceScene::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The scene's triangles in world space and its camera rays through the centres of a
    /// `size × size` image, row by row.
    pub fn world(self, size: u32) -> Result<World, String> {
        let path_scene = match self {
            BounceScene::Room => PathScene::Room,
            BounceScene::Spheres => PathScene::Spheres,
            BounceScene::SphereGrid => {
                let mesh = StandardScene::Spheres.mesh();
                let ends_paths = vec![false; mesh.indices.len()];
                return Ok(World { mesh, ends_paths, primary: rays::primary(StandardScene::Spheres, size, size) });
            }
        };
        let scene = path_scene.scene()?;
        let mut world = World { mesh: Mesh::default(), ends_paths: Vec::new(), primary: Vec::new() };
        for (_, object, to_world) in scene.instances() {
            let mesh = scene.mesh(object).map_err(|e| e.to_string())?;
            let first = world.mesh.vertices.len() as u32;
            world.mesh.vertices.extend(mesh.positions.iter().map(|&p| to_world.transform_point3(p)));
            world.mesh.indices.extend(mesh.indices.iter().map(|t| t.map(|i| first + i)));
            for k in 0..mesh.indices.len() {
                let shader = match mesh.shaders.get(k) {
                    Some(&id) => scene.shader(id).map_err(|e| e.to_string())?,
                    None => scene.default_shader(),
                };
                // The room's only emitter is its light, whose surface reflects nothing: the
                // path tracer ends a path that reaches it.
                world.ends_paths.push(shader.emits());
            }
        }
        let camera = scene.camera().rays(size, size);
        world.primary = (0..size).flat_map(|y| (0..size).map(move |x| (x, y))).map(|(x, y)| camera.ray(x as f32 + 0.5, y as f32 + 0.5, [0.5, 0.5])).collect();
        Ok(world)
    }
}

/// A scene flattened for the kernel: its triangles in world space, which of them end a path,
/// and its camera rays.
pub struct World {
    /// Every instance's triangles, carried into the world by its transform.
    pub mesh: Mesh,
    /// Per triangle of `mesh`: whether a path that reaches it ends there.
    pub ends_paths: Vec<bool>,
    /// One camera ray per pixel centre, row by row.
    pub primary: Vec<Ray>,
}

impl World {
    /// What `rays` hit in `bvh` (this world's tree) where the path goes on: distance and unit
    /// normal, `None` for a miss or a hit that ends the path.
    fn continuing_hits(&self, bvh: &Bvh8, rays: &[Ray]) -> Vec<Option<PrimaryHit>> {
        rays.iter()
            .map(|r| {
                let hit = bvh.intersect(r).filter(|h| !self.ends_paths[h.prim as usize])?;
                Some(PrimaryHit { t: hit.t, normal: rays::probe_normal(&self.mesh.triangle(hit.prim)) })
            })
            .collect()
    }

    /// The camera rays and then `bounces` diffuse bounces, each one's rays in the order of the
    /// paths they continue (pixel order), through `bvh`, this world's tree.
    pub fn bounces(&self, bvh: &Bvh8, bounces: u32) -> Vec<Vec<Ray>> {
        let mut all = vec![self.primary.clone()];
        for k in 1..=u64::from(bounces) {
            let last = all.last().expect("the camera rays");
            let next = rays::bounce(last, &self.continuing_hits(bvh, last), BOUNCE_SEED + k - 1);
            all.push(next);
        }
        all
    }
}

/// The name of bounce `k` in reports: `primary`, then `bounce 1`, `bounce 2`, …
pub fn bounce_name(k: usize) -> String {
    if k == 0 { "primary".to_string() } else { format!("bounce {k}") }
}

/// The grid of cells a ray's origin is sorted by: 2^[`CELL_BITS`] per axis over the scene's
/// bounds.
#[derive(Clone, Copy, Debug)]
pub struct Cells {
    min: Vec3,
    /// Cells per unit length along each axis.
    scale: Vec3,
}

impl Cells {
    /// The cells over `bounds`.
    pub fn over(bounds: &Aabb) -> Cells {
        let cells = (1u32 << CELL_BITS) as f32;
        Cells { min: bounds.min, scale: cells / (bounds.max - bounds.min).max(Vec3::splat(f32::MIN_POSITIVE)) }
    }

    /// Where a ray starts and which way it goes, as one sortable number: the Morton code of
    /// its origin's cell (origins outside the bounds go to the nearest cell), then its
    /// direction's octant. Morton order keeps cells that are near each other near in the order
    /// at every scale, so a batch of any size holds rays from a compact region.
    pub fn key(&self, ray: &Ray) -> u32 {
        let last = ((1u32 << CELL_BITS) - 1) as f32;
        let cell = ((ray.origin - self.min) * self.scale).clamp(Vec3::ZERO, Vec3::splat(last));
        let octant = u32::from(ray.dir.x < 0.0) | u32::from(ray.dir.y < 0.0) << 1 | u32::from(ray.dir.z < 0.0) << 2;
        morton::code(cell.x as u32, cell.y as u32, cell.z as u32) << 3 | octant
    }
}

/// A bounce's rays reordered for tracing.
pub struct Sorted {
    /// `rays[j]` is the original ray `order[j]`.
    pub order: Vec<u32>,
    /// The rays in their new order.
    pub rays: Vec<Ray>,
}

/// `rays` sorted by their [`Cells::key`] in `cells` in consecutive batches of `batch`, each
/// batch on its own, as a wavefront tracer sorts the rays it holds at a time; ties keep their
/// order.
pub fn sort(rays: &[Ray], cells: &Cells, batch: usize) -> Sorted {
    let batch = batch.max(1);
    let keyed: Vec<(u32, u32)> = rays.iter().enumerate().map(|(i, r)| (cells.key(r), i as u32)).collect();
    let mut order = Vec::with_capacity(rays.len());
    let (mut items, mut spare) = (Vec::with_capacity(batch.min(rays.len())), Vec::new());
    // A radix sort, as the fast builder sorts its primitives: the keys are short, and a
    // wavefront tracer that sorts every bounce's rays wants the linear-time sort.
    for chunk in keyed.chunks(batch) {
        items.clear();
        items.extend_from_slice(chunk);
        radix_sort(&mut items, &mut spare);
        order.extend(items.iter().map(|&(_, i)| i));
    }
    let rays = order.iter().map(|&i| rays[i as usize]).collect();
    Sorted { order, rays }
}

/// Checks that `sorted` holds `rays` in a new order and that `bvh` finds, for each ray, a hit
/// bit for bit the same as that ray's in the original order; returns the rays that hit.
pub fn same_hits(bvh: &Bvh8, rays: &[Ray], sorted: &Sorted) -> Result<usize, String> {
    if sorted.order.len() != rays.len() || sorted.rays.len() != rays.len() {
        return Err(format!("{} rays sorted into {} places and {} rays", rays.len(), sorted.order.len(), sorted.rays.len()));
    }
    let mut seen = vec![false; rays.len()];
    for (j, &i) in sorted.order.iter().enumerate() {
        let i = i as usize;
        if i >= rays.len() || std::mem::replace(&mut seen[i], true) {
            return Err(format!("place {j} holds ray {i}, out of range or twice"));
        }
        if bits(&sorted.rays[j]) != bits(&rays[i]) {
            return Err(format!("place {j} holds a ray other than ray {i}"));
        }
    }
    let as_made: Vec<Option<Hit>> = rays.iter().map(|r| bvh.intersect(r)).collect();
    let mut hits = 0;
    for (j, ray) in sorted.rays.iter().enumerate() {
        let i = sorted.order[j] as usize;
        let (a, b) = (bvh.intersect(ray), as_made[i]);
        if a.map(hit_bits) != b.map(hit_bits) {
            return Err(format!("ray {i} hits {b:?} in its order, {a:?} sorted"));
        }
        hits += usize::from(a.is_some());
    }
    Ok(hits)
}

/// A ray's numbers as bits, so that comparing them is bit for bit.
fn bits(r: &Ray) -> [u32; 8] {
    [r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar].map(f32::to_bits)
}

/// A hit's numbers as bits.
fn hit_bits(h: Hit) -> [u32; 7] {
    [h.t.to_bits(), h.prim, h.u.to_bits(), h.v.to_bits(), h.ng.x.to_bits(), h.ng.y.to_bits(), h.ng.z.to_bits()]
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct Config {
    /// The scenes.
    pub scenes: Vec<BounceScene>,
    /// Image side in pixels: a camera ray per pixel.
    pub size: u32,
    /// Bounces after the camera rays.
    pub bounces: u32,
    /// Batch sizes the rays are sorted in; all of a bounce's rays at once is measured too.
    pub batches: Vec<usize>,
    /// Repetitions; the best is reported.
    pub reps: usize,
    /// Threads of the tree builds (every trace runs on one thread).
    pub build_threads: usize,
}

/// One line of the JSON report: one system tracing one bounce's rays in one order, on one
/// thread, one ray per call (`rtcIntersect1` for Embree); the best of the repetitions (see [`run`]).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct TraceReport {
    /// `raystage` or `embree`.
    pub system: &'static str,
    /// Which scene ([`BounceScene::name`]).
    pub scene: &'static str,
    /// `primary`, `bounce 1`, …
    pub bounce: String,
    /// `as made` (pixel order), `sorted in N` (batches of N rays) or `all sorted`.
    pub order: String,
    /// Rays of the bounce.
    pub rays: usize,
    /// Million rays per second, tracing alone.
    pub mrays: f64,
    /// Million rays per second with the sorting's time added (`None` as made).
    pub mrays_with_sort: Option<f64>,
    /// `mrays` over this system's rate for the same rays as made.
    pub vs_as_made: f64,
    /// Rays that hit.
    pub hits: u64,
    /// Sum of the hit distances.
    pub tsum: f64,
}

/// One line of the JSON report: the time to sort one bounce's rays in one way (computing the
/// keys, sorting, and gathering the rays in their new order), the best of the repetitions.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SortReport {
    /// `sorting`: these lines make a table of their own.
    pub measurement: &'static str,
    /// Which scene.
    pub scene: &'static str,
    /// `primary`, `bounce 1`, …
    pub bounce: String,
    /// `sorted in N` or `all sorted`.
    pub order: String,
    /// Milliseconds.
    pub sort_ms: f64,
    /// Nanoseconds per ray.
    pub sort_ns_per_ray: f64,
}

/// One line of the JSON report: what raystage's closest-hit walks did per ray of one bounce
/// (the same in every order: each ray's walk is its own).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct WalkReport {
    /// `walks`: these lines make a table of their own.
    pub measurement: &'static str,
    /// Which scene.
    pub scene: &'static str,
    /// Its triangles.
    pub scene_triangles: usize,
    /// `primary`, `bounce 1`, …
    pub bounce: String,
    /// Rays of the bounce.
    pub rays: usize,
    /// The share of them that hit something.
    pub hit_share: f64,
    /// The counts per ray.
    #[serde(flatten)]
    pub per_ray: PerRay,
}

/// Everything measured on one scene.
pub struct SceneRun {
    /// The scene.
    pub scene: BounceScene,
    /// Its triangles.
    pub triangles: usize,
    /// Each bounce's walks.
    pub walks: Vec<WalkReport>,
    /// Each bounce's sorting times.
    pub sorting: Vec<SortReport>,
    /// Each system's rates, bounce by bounce and order by order.
    pub traces: Vec<TraceReport>,
}

/// The orders a bounce's rays are traced in: as made (`None`), then sorted in each of
/// `batches` and all at once (`Some(batch)`), with their names in reports.
fn orders(batches: &[usize], rays: usize) -> Vec<(String, Option<usize>)> {
    let mut orders = vec![("as made".to_string(), None)];
    orders.extend(batches.iter().filter(|&&b| b > 0 && b < rays).map(|&b| (format!("sorted in {b}"), Some(b))));
    orders.push(("all sorted".to_string(), Some(rays.max(1))));
    orders
}

/// Million rays per second of `rays` rays in the fastest of `seconds`.
fn best_rate(rays: usize, seconds: impl Iterator<Item = f64>) -> f64 {
    rays as f64 / seconds.fold(f64::INFINITY, f64::min) / 1e6
}

/// Runs the benchmark on each scene of `config`, logging progress through `progress`.
///
/// Every figure is the best of `config.reps` repetitions, not their median as in the kernel
/// benchmark: a trace here takes milliseconds, a burst of another process's work on a shared
/// machine lasts longer than that, and the fastest repetition is the one it disturbed least.
pub fn run(config: &Config, mut progress: impl FnMut(&str)) -> Result<Vec<SceneRun>, String> {
    config.scenes.iter().map(|&scene| run_scene(config, scene, &mut progress)).collect()
}

/// The benchmark on one scene.
fn run_scene(config: &Config, scene: BounceScene, progress: &mut impl FnMut(&str)) -> Result<SceneRun, String> {
    progress(&format!("{}: generating the scene", scene.name()));
    let world = scene.world(config.size)?;
    let (bvh, build_s) = crate::kernel::build_raystage(&world.mesh, config.build_threads);
    progress(&format!("{}: {} triangles, raystage's tree in {build_s:.3} s", scene.name(), world.mesh.indices.len()));
    #[allow(unused_mut)]
    let mut tracers: Vec<(&'static str, Box<dyn Tracer>)> = Vec::new();
    #[cfg(feature = "embree")]
    {
        use crate::embree::{Device, Quality, Scene};
        let device = Device::new(config.build_threads)?;
        // HIGH, the tree the kernel benchmark traces Embree's single rays in.
        let (embree, secs) = Scene::build(&device, &world.mesh, Quality::High);
        progress(&format!("{}: Embree {} HIGH build in {secs:.3} s", scene.name(), device.version()));
        tracers.push(("embree", Box::new(embree)));
    }
    let bounces = world.bounces(&bvh, config.bounces);
    let cells = Cells::over(&bvh.bounds());
    let mut walks = Vec::new();
    let mut sorting = Vec::new();
    let mut traces = Vec::new();
    for (k, rays) in bounces.iter().enumerate() {
        let bounce = bounce_name(k);
        let mut counts = WalkCounts::default();
        let hits = rays.iter().filter(|r| bvh.intersect_counted(r, &mut counts).is_some()).count();
        let n = counts.rays.max(1) as f64;
        walks.push(WalkReport {
            measurement: "walks",
            scene: scene.name(),
            scene_triangles: world.mesh.indices.len(),
            bounce: bounce.clone(),
            rays: rays.len(),
            hit_share: hits as f64 / n,
            per_ray: PerRay::of(&counts),
        });
        let orders = orders(&config.batches, rays.len());
        // Per order, per system: each repetition's trace, and the order's sorting seconds.
        let systems = 1 + tracers.len();
        let mut samples = vec![vec![Vec::<Traced>::new(); systems]; orders.len()];
        let mut sort_seconds = vec![Vec::new(); orders.len()];
        for rep in 0..config.reps.max(1) {
            for (o, (name, batch)) in orders.iter().enumerate() {
                let sorted = batch.map(|b| {
                    let start = Instant::now();
                    let sorted = sort(rays, &cells, b);
                    sort_seconds[o].push(start.elapsed().as_secs_f64());
                    sorted
                });
                if rep == 0
                    && let Some(sorted) = &sorted
                {
                    same_hits(&bvh, rays, sorted).map_err(|e| format!("{} {bounce} {name}: {e}", scene.name()))?;
                }
                let traced = sorted.as_ref().map_or(rays, |s| &s.rays);
                // The systems take turns, who goes first alternating from one repetition to
                // the next, so that drift in the machine's speed falls on both alike.
                for s in (0..systems).map(|s| (s + rep) % systems) {
                    let tracer: &dyn Tracer = if s == 0 { &bvh } else { tracers[s - 1].1.as_ref() };
                    samples[o][s].push(trace_all(tracer, traced, 1, Calls::Closest(Api::Single), Schedule::Halves));
                }
            }
        }
        let rate = |runs: &[Traced]| best_rate(rays.len(), runs.iter().map(|t| t.seconds));
        for (o, (order, _)) in orders.iter().enumerate() {
            if !sort_seconds[o].is_empty() {
                let seconds = sort_seconds[o].iter().copied().fold(f64::INFINITY, f64::min);
                sorting.push(SortReport {
                    measurement: "sorting",
                    scene: scene.name(),
                    bounce: bounce.clone(),
                    order: order.clone(),
                    sort_ms: seconds * 1e3,
                    sort_ns_per_ray: seconds * 1e9 / rays.len().max(1) as f64,
                });
            }
            for s in 0..systems {
                let runs = &samples[o][s];
                let with_sort =
                    (!sort_seconds[o].is_empty()).then(|| best_rate(rays.len(), runs.iter().zip(&sort_seconds[o]).map(|(t, sort)| t.seconds + sort)));
                let last = runs.last().copied().unwrap_or_default();
                traces.push(TraceReport {
                    system: if s == 0 { "raystage" } else { tracers[s - 1].0 },
                    scene: scene.name(),
                    bounce: bounce.clone(),
                    order: order.clone(),
                    rays: rays.len(),
                    mrays: rate(runs),
                    mrays_with_sort: with_sort,
                    vs_as_made: rate(runs) / rate(&samples[0][s]),
                    hits: last.hits,
                    tsum: last.tsum,
                });
            }
        }
        let line: Vec<String> = traces[traces.len() - orders.len() * systems..].iter().map(|t| format!("{} {} {:.2}", t.system, t.order, t.mrays)).collect();
        progress(&format!("{} {bounce}: {} rays; Mrays/s {}", scene.name(), rays.len(), line.join(", ")));
    }
    Ok(SceneRun { scene, triangles: world.mesh.indices.len(), walks, sorting, traces })
}
