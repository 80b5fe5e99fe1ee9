//! The kernel benchmark: build time and single-ray throughput on the probe's standard scenes,
//! for raystage and (with the `embree` feature) Embree 3, on identical rays in the same run.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use raystage_demo::{Mesh, StandardScene};
use raystage_kernel::{BuildOptions, Bvh8, PACKET_SIZE, Ray, WalkCounts};
use serde::Serialize;

use crate::rays::{self, HEIGHT, PrimaryHit, WIDTH};

/// Rays of a 4×4-pixel group, Embree's largest packet (`rtcIntersect16`).
pub const GROUP_SIZE: usize = 16;

/// Something that answers closest-hit and any-hit queries: raystage's BVH or Embree's scene.
pub trait Tracer: Sync {
    /// Distance of the closest hit, if any: the single-ray API.
    fn trace(&self, ray: &Ray) -> Option<f32>;
    /// Closest-hit distances of up to [`PACKET_SIZE`] rays traced as one packet.
    fn trace_packet(&self, rays: &[Ray], out: &mut [Option<f32>]);
    /// Closest-hit distances of up to [`GROUP_SIZE`] rays of a 4×4-pixel group, traced together
    /// as the system traces such a group fastest.
    fn trace_group(&self, rays: &[Ray], out: &mut [Option<f32>]);
    /// Whether anything blocks the segment: the single-ray any-hit API.
    fn occluded(&self, ray: &Ray) -> bool;
    /// Which of up to [`GROUP_SIZE`] segments are blocked (bit `i` for `rays[i]`), traced
    /// together.
    fn occluded_group(&self, rays: &[Ray]) -> u32;
}

impl Tracer for Bvh8 {
    #[inline]
    fn trace(&self, ray: &Ray) -> Option<f32> {
        self.intersect(ray).map(|h| h.t)
    }

    #[inline]
    fn trace_packet(&self, rays: &[Ray], out: &mut [Option<f32>]) {
        let mut hits = [None; GROUP_SIZE];
        self.intersect_packets(rays, &mut hits[..rays.len()]);
        for (o, h) in out.iter_mut().zip(&hits) {
            *o = h.map(|h| h.t);
        }
    }

    /// Two packets of 4×2 pixels: raystage's packets are eight rays, one per AVX2 lane.
    #[inline]
    fn trace_group(&self, rays: &[Ray], out: &mut [Option<f32>]) {
        self.trace_packet(rays, out);
    }

    #[inline]
    fn occluded(&self, ray: &Ray) -> bool {
        Bvh8::occluded(self, ray)
    }

    /// Two packets of eight.
    fn occluded_group(&self, rays: &[Ray]) -> u32 {
        rays.chunks(PACKET_SIZE).enumerate().fold(0, |mask, (k, packet)| {
            let prepared = raystage_kernel::PreparedRay::packet(packet);
            mask | self.occluded_packet_prepared(&prepared[..packet.len()]) << (k * PACKET_SIZE)
        })
    }
}

#[cfg(feature = "embree")]
impl Tracer for crate::embree::Scene {
    #[inline]
    fn trace(&self, ray: &Ray) -> Option<f32> {
        self.intersect(ray).map(|h| h.t)
    }

    #[inline]
    fn trace_packet(&self, rays: &[Ray], out: &mut [Option<f32>]) {
        self.intersect8(rays, out);
    }

    #[inline]
    fn trace_group(&self, rays: &[Ray], out: &mut [Option<f32>]) {
        self.intersect16(rays, out);
    }

    #[inline]
    fn occluded(&self, ray: &Ray) -> bool {
        crate::embree::Scene::occluded(self, ray)
    }

    #[inline]
    fn occluded_group(&self, rays: &[Ray]) -> u32 {
        self.occluded16(rays)
    }
}

/// One traced ray set: wall time and the probe's checksum (hit count, sum of hit distances).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Traced {
    /// Seconds for all rays.
    pub seconds: f64,
    /// Rays that hit something.
    pub hits: u64,
    /// Sum of the hit distances.
    pub tsum: f64,
}

/// How a frame's rays are handed to a tracer (the dynamic bench's frames too).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Api {
    /// One ray per call.
    Single,
    /// Consecutive groups of [`PACKET_SIZE`] rays per call.
    Packets,
}

/// What [`trace_all`] asks of a tracer per call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Calls {
    /// The closest hits of rays handed over as the [`Api`] says.
    Closest(Api),
    /// The closest hits of consecutive groups of [`GROUP_SIZE`] rays.
    ClosestGroups,
    /// Whether one segment is blocked; a blocked segment counts as a hit at distance 0.
    Occluded,
    /// Which of consecutive groups of [`GROUP_SIZE`] segments are blocked.
    OccludedGroups,
}

/// How the rays are shared out between threads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Schedule {
    /// Each thread takes one contiguous chunk, as the probe splits the image's rows: faithful to
    /// the probe, but a thread with the cheaper half (more sky) then waits for the other.
    Halves,
    /// Threads take runs of [`SHARED_RUN`] rays in turn until none are left, balanced as the
    /// renderer's work stealing balances its bands.
    Shared,
}

/// Rays a thread takes at a time with [`Schedule::Shared`]: 64 packets.
pub const SHARED_RUN: usize = 64 * PACKET_SIZE;

/// Traces `rays` on `threads` threads, shared out by `schedule`.
pub fn trace_all(tracer: &dyn Tracer, rays: &[Ray], threads: usize, calls: Calls, schedule: Schedule) -> Traced {
    let chunk = |rays: &[Ray]| {
        let (mut hits, mut tsum) = (0u64, 0f64);
        let mut count = |t: Option<f32>| {
            if let Some(t) = t {
                hits += 1;
                tsum += t as f64;
            }
        };
        let mut out = [None; GROUP_SIZE];
        match calls {
            Calls::Closest(Api::Single) => rays.iter().for_each(|ray| count(tracer.trace(ray))),
            Calls::Closest(Api::Packets) => {
                for packet in rays.chunks(PACKET_SIZE) {
                    tracer.trace_packet(packet, &mut out[..packet.len()]);
                    out[..packet.len()].iter().for_each(|&t| count(t));
                }
            }
            Calls::ClosestGroups => {
                for group in rays.chunks(GROUP_SIZE) {
                    tracer.trace_group(group, &mut out[..group.len()]);
                    out[..group.len()].iter().for_each(|&t| count(t));
                }
            }
            Calls::Occluded => rays.iter().for_each(|ray| count(tracer.occluded(ray).then_some(0.0))),
            Calls::OccludedGroups => {
                for group in rays.chunks(GROUP_SIZE) {
                    let blocked = tracer.occluded_group(group);
                    (0..group.len()).for_each(|i| count((blocked >> i & 1 != 0).then_some(0.0)));
                }
            }
        }
        (hits, tsum)
    };
    let start = Instant::now();
    let parts: Vec<(u64, f64)> = if threads <= 1 {
        vec![chunk(rays)]
    } else {
        // Shared: runs taken in turn from the next unclaimed ray.
        let next = AtomicUsize::new(0);
        let runs = || {
            let mut sums = (0u64, 0f64);
            loop {
                let start = next.fetch_add(SHARED_RUN, Ordering::Relaxed);
                if start >= rays.len() {
                    break sums;
                }
                let (hits, tsum) = chunk(&rays[start..(start + SHARED_RUN).min(rays.len())]);
                sums = (sums.0 + hits, sums.1 + tsum);
            }
        };
        std::thread::scope(|s| {
            let handles: Vec<_> = match schedule {
                Schedule::Halves => {
                    let per = rays.len().div_ceil(threads).next_multiple_of(GROUP_SIZE);
                    rays.chunks(per.max(1)).map(|c| s.spawn(move || chunk(c))).collect()
                }
                Schedule::Shared => (0..threads).map(|_| s.spawn(runs)).collect(),
            };
            handles.into_iter().map(|h| h.join().expect("trace thread panicked")).collect()
        })
    };
    let seconds = start.elapsed().as_secs_f64();
    let (hits, tsum) = parts.iter().fold((0, 0.0), |(h, t), p| (h + p.0, t + p.1));
    Traced { seconds, hits, tsum }
}

/// Builds raystage's BVH on a pool of `threads` threads; returns it and the build seconds.
pub fn build_raystage(mesh: &Mesh, threads: usize) -> (Bvh8, f64) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    pool.install(|| {
        let start = Instant::now();
        let bvh = Bvh8::build(&mesh.as_indexed(), &BuildOptions::default());
        let seconds = start.elapsed().as_secs_f64();
        (bvh, seconds)
    })
}

/// The probe's primary hits as seen by raystage (distance and unit normal), in pixel order.
pub fn primary_hits(bvh: &Bvh8, mesh: &Mesh, primary: &[Ray]) -> Vec<Option<PrimaryHit>> {
    primary
        .iter()
        .map(|r| bvh.intersect(r).map(|h| PrimaryHit { t: h.t, normal: rays::probe_normal(&mesh.triangle(h.prim)) }))
        .collect()
}

/// The identical ray sets every system traces.
pub struct RaySets {
    /// 1920×1080 primary rays, row by row.
    pub primary: Vec<Ray>,
    /// The same primary rays grouped in 4×2-pixel packets (tile rows of 480 packets).
    pub packets: Vec<Ray>,
    /// The same primary rays grouped in 4×4-pixel groups (rows of 480 groups).
    pub groups: Vec<Ray>,
    /// 1920×1080 random incoherent rays.
    pub incoherent: Vec<Ray>,
    /// Bounce rays from raystage's primary hits.
    pub bounce: Vec<Ray>,
    /// Shadow rays from the scene's point light ([`rays::light`]) to raystage's primary hits,
    /// stopping just short of them, in the 4×4 groups' order.
    pub shadow: Vec<Ray>,
}

impl RaySets {
    /// Generates the probe's ray sets for `scene`; bounce and shadow rays go from and to `bvh`'s
    /// primary hits.
    pub fn new(scene: StandardScene, mesh: &Mesh, bvh: &Bvh8) -> RaySets {
        let primary = rays::primary(scene, WIDTH, HEIGHT);
        let packets = rays::in_blocks(&primary, WIDTH, HEIGHT, (4, 2));
        let groups = rays::in_blocks(&primary, WIDTH, HEIGHT, (4, 4));
        let incoherent = rays::incoherent(scene, (WIDTH * HEIGHT) as usize);
        let hits = primary_hits(bvh, mesh, &primary);
        let bounce = rays::bounce(&primary, &hits, rays::PROBE_BOUNCE_SEED);
        let shadow = rays::shadows(rays::light(scene), &groups, &rays::in_blocks(&hits, WIDTH, HEIGHT, (4, 4)));
        RaySets { primary, packets, groups, incoherent, bounce, shadow }
    }
}

/// One line of the JSON report: one system on one scene at one thread count (medians).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct KernelReport {
    /// `raystage`, `embree` or `embree-robust`.
    pub system: String,
    /// `sphere` or `soup`.
    pub scene: String,
    /// Threads used to build and trace.
    pub threads: usize,
    /// BVH build seconds (Embree: `RTC_BUILD_QUALITY_HIGH`, the tree it traces).
    pub build_s: f64,
    /// Embree only: `RTC_BUILD_QUALITY_MEDIUM` (binned SAH) build seconds.
    pub medium_build_s: Option<f64>,
    /// raystage only: the surface-area cost of its tree ([`raystage_kernel::Bvh8Stats::sah_cost`]).
    pub sah_cost: Option<f32>,
    /// Primary rays traced one per call (`rtcIntersect1` for Embree), million per second; the
    /// rates are `None` when only builds were measured.
    pub primary_mrays: Option<f64>,
    /// Primary rays traced in packets of eight, 4×2 pixels (`rtcIntersect8` for Embree).
    pub primary_packet_mrays: Option<f64>,
    /// Primary rays traced in groups of 4×4 pixels (`rtcIntersect16` for Embree, two packets
    /// of eight for raystage).
    pub primary_group_mrays: Option<f64>,
    /// Random incoherent rays, million per second.
    pub incoherent_mrays: Option<f64>,
    /// Diffuse bounce rays, million per second.
    pub bounce_mrays: Option<f64>,
    /// Shadow rays to one point light, one per any-hit call (`rtcOccluded1`).
    pub shadow_mrays: Option<f64>,
    /// The same shadow rays in groups of 4×4 pixels (`rtcOccluded16`; two packets of eight for
    /// raystage).
    pub shadow_group_mrays: Option<f64>,
    /// Primary rays that hit.
    pub hits: u64,
    /// Sum of primary hit distances.
    pub tsum: f64,
}

/// One line of the JSON report: what raystage's closest-hit walks did per ray of one ray set
/// (single rays, the tree the 1-thread build made), as MLRTA's Table 2 gives it (seed 000).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct WalkReport {
    /// `walks`: these lines make a table of their own.
    pub measurement: &'static str,
    /// `sphere` or `soup`.
    pub scene: String,
    /// `primary`, `incoherent` or `bounce`.
    pub rays: &'static str,
    /// The counts.
    #[serde(flatten)]
    pub per_ray: PerRay,
}

/// Traversal statistics per ray set, as MLRTA's Table 2 gives them (seed 000).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walks {
    /// Primary rays.
    pub primary: PerRay,
    /// Random incoherent rays.
    pub incoherent: PerRay,
    /// Diffuse bounce rays.
    pub bounce: PerRay,
}

/// What a closest-hit walk does per ray, on average.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct PerRay {
    /// Inner nodes whose eight child boxes were tested.
    pub nodes: f64,
    /// Leaves (blocks of up to eight triangles) tested.
    pub leaves: f64,
    /// Triangles in those leaves.
    pub triangles: f64,
}

impl PerRay {
    /// The counts of `counts` per ray walked.
    pub fn of(counts: &WalkCounts) -> PerRay {
        let n = counts.rays.max(1) as f64;
        PerRay { nodes: counts.nodes as f64 / n, leaves: counts.leaves as f64 / n, triangles: counts.triangles as f64 / n }
    }
}

impl Walks {
    /// Walks every ray of `sets` through `bvh`, counting, on the current rayon pool.
    pub fn of(bvh: &Bvh8, sets: &RaySets) -> Walks {
        use rayon::prelude::*;
        let per_ray = |rays: &[Ray]| {
            let c = rays
                .par_chunks(SHARED_RUN)
                .map(|chunk| {
                    let mut counts = WalkCounts::default();
                    for ray in chunk {
                        bvh.intersect_counted(ray, &mut counts);
                    }
                    counts
                })
                .reduce(WalkCounts::default, |mut a, b| {
                    a += b;
                    a
                });
            PerRay::of(&c)
        };
        Walks { primary: per_ray(&sets.primary), incoherent: per_ray(&sets.incoherent), bounce: per_ray(&sets.bounce) }
    }
}

/// Per-repetition samples of one system at one thread count.
#[derive(Clone, Debug, Default)]
pub struct Samples {
    /// Build seconds per repetition.
    pub build: Vec<f64>,
    /// Primary rays per repetition.
    pub primary: Vec<Traced>,
    /// Primary rays in packets per repetition.
    pub packets: Vec<Traced>,
    /// Primary rays in 4×4 groups per repetition.
    pub groups: Vec<Traced>,
    /// Incoherent rays per repetition.
    pub incoherent: Vec<Traced>,
    /// Bounce rays per repetition.
    pub bounce: Vec<Traced>,
    /// Shadow rays one by one per repetition.
    pub shadow: Vec<Traced>,
    /// Shadow rays in 4×4 groups per repetition.
    pub shadow_groups: Vec<Traced>,
}

/// Median of a non-empty sample.
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

impl Traced {
    /// The two runs together: one run over both ray sets.
    fn plus(self, o: Traced) -> Traced {
        Traced { seconds: self.seconds + o.seconds, hits: self.hits + o.hits, tsum: self.tsum + o.tsum }
    }
}

/// Ray sets and ways of tracing them that [`trace_interleaved`] measures.
pub const SETS: usize = 7;

/// Rays per slice when systems take turns (see [`trace_interleaved`]).
const SLICE: usize = 1 << 16;

/// Traces every ray set once with every tracer, the tracers taking turns slice by slice
/// (65,536 rays), so that the machine's speed drifting during the run (these are shared virtual
/// machines) affects all systems alike; returns one `Traced` per tracer and set, in
/// [`Samples::record`]'s order.
pub fn trace_interleaved(tracers: &[&dyn Tracer], sets: &RaySets, threads: usize) -> Vec<[Traced; SETS]> {
    let plan = [
        (&sets.primary, Calls::Closest(Api::Single)),
        (&sets.packets, Calls::Closest(Api::Packets)),
        (&sets.groups, Calls::ClosestGroups),
        (&sets.incoherent, Calls::Closest(Api::Single)),
        (&sets.bounce, Calls::Closest(Api::Single)),
        (&sets.shadow, Calls::Occluded),
        (&sets.shadow, Calls::OccludedGroups),
    ];
    let mut totals = vec![[Traced::default(); SETS]; tracers.len()];
    for (set, (rays, calls)) in plan.iter().enumerate() {
        for slice in rays.chunks(SLICE) {
            for (k, tracer) in tracers.iter().enumerate() {
                totals[k][set] = totals[k][set].plus(trace_all(*tracer, slice, threads, *calls, Schedule::Halves));
            }
        }
    }
    totals
}

impl Samples {
    /// Records one repetition, as returned by [`trace_interleaved`] for one tracer: primary rays
    /// one by one, in packets and in groups, incoherent and bounce rays, shadow rays one by one
    /// and in groups.
    pub fn record(&mut self, traced: [Traced; SETS]) {
        let [primary, packets, groups, incoherent, bounce, shadow, shadow_groups] = traced;
        self.primary.push(primary);
        self.packets.push(packets);
        self.groups.push(groups);
        self.incoherent.push(incoherent);
        self.bounce.push(bounce);
        self.shadow.push(shadow);
        self.shadow_groups.push(shadow_groups);
    }

    /// Medians as a report line (without the fields only one system has).
    pub fn report(&self, system: &str, scene: StandardScene, threads: usize, sets: Option<&RaySets>) -> KernelReport {
        let mrays = |runs: &[Traced], n: fn(&RaySets) -> usize| {
            let n = n(sets?);
            (!runs.is_empty()).then(|| median(&runs.iter().map(|r| n as f64 / r.seconds / 1e6).collect::<Vec<_>>()))
        };
        let last = self.primary.last().copied().unwrap_or_default();
        KernelReport {
            system: system.to_string(),
            scene: scene.name().to_string(),
            threads,
            build_s: median(&self.build),
            medium_build_s: None,
            sah_cost: None,
            primary_mrays: mrays(&self.primary, |s| s.primary.len()),
            primary_packet_mrays: mrays(&self.packets, |s| s.packets.len()),
            primary_group_mrays: mrays(&self.groups, |s| s.groups.len()),
            incoherent_mrays: mrays(&self.incoherent, |s| s.incoherent.len()),
            bounce_mrays: mrays(&self.bounce, |s| s.bounce.len()),
            shadow_mrays: mrays(&self.shadow, |s| s.shadow.len()),
            shadow_group_mrays: mrays(&self.shadow_groups, |s| s.shadow.len()),
            hits: last.hits,
            tsum: last.tsum,
        }
    }
}

/// Everything measured on one scene.
pub struct SceneRun {
    /// The scene.
    pub scene: StandardScene,
    /// Its triangle count.
    pub triangles: usize,
    /// The identical rays every system traced (`None` when only builds were measured).
    pub sets: Option<RaySets>,
    /// `(system, threads, samples)` for every measured combination. Embree's `build` samples are
    /// its `RTC_BUILD_QUALITY_HIGH` builds (spatial splits), the tree it traces.
    pub runs: Vec<(&'static str, usize, Samples)>,
    /// Embree's `RTC_BUILD_QUALITY_MEDIUM` build seconds per thread count, one per repetition:
    /// the binned SAH build, the like-for-like counterpart of raystage's.
    pub embree_medium_build: Vec<(usize, Vec<f64>)>,
    /// The surface-area cost of raystage's tree per thread count ([`raystage_kernel::Bvh8Stats::sah_cost`]):
    /// a build made faster must not make it worse.
    pub sah_cost: Vec<(usize, f32)>,
    /// What raystage's walks did per ray (`None` when only builds were measured).
    pub walks: Option<Walks>,
}

impl SceneRun {
    /// Median report lines, one per system and thread count.
    pub fn reports(&self) -> Vec<KernelReport> {
        self.runs
            .iter()
            .map(|(system, threads, s)| KernelReport {
                medium_build_s: self.medium_build(*threads).filter(|_| *system == "embree"),
                sah_cost: self.sah_cost.iter().find(|(t, _)| t == threads).map(|c| c.1).filter(|_| *system == "raystage"),
                ..s.report(system, self.scene, *threads, self.sets.as_ref())
            })
            .collect()
    }

    /// What raystage's walks did per ray, a report line per ray set (none when only builds were
    /// measured): lines of their own, as only raystage has them.
    pub fn walk_reports(&self) -> Vec<WalkReport> {
        let Some(w) = self.walks else { return Vec::new() };
        [("primary", w.primary), ("incoherent", w.incoherent), ("bounce", w.bounce)]
            .into_iter()
            .map(|(rays, per_ray)| WalkReport { measurement: "walks", scene: self.scene.name().to_string(), rays, per_ray })
            .collect()
    }

    /// Embree's median MEDIUM build seconds at `threads` threads, if measured.
    pub fn medium_build(&self, threads: usize) -> Option<f64> {
        self.embree_medium_build.iter().find(|(t, _)| *t == threads).map(|(_, v)| median(v))
    }
}

/// Measures `scene` at 1 thread and at `threads` threads (if more than one), `reps` times, every
/// system on the same rays, alternating systems within each repetition so that drift in machine
/// speed affects both alike: the builds take turns build by build (raystage, Embree MEDIUM,
/// Embree HIGH), the traces slice by slice. With `build_only`, no rays are traced. `progress`
/// receives a line per step.
pub fn run(scene: StandardScene, threads: usize, reps: usize, build_only: bool, mut progress: impl FnMut(&str)) -> SceneRun {
    let reps = reps.max(1);
    let mut counts = vec![1];
    if threads > 1 {
        counts.push(threads);
    }
    progress(&format!("{}: generating triangles", scene.name()));
    let mesh = scene.mesh();
    let mut runs: Vec<(&'static str, usize, Samples)> = Vec::new();
    for &t in &counts {
        runs.push(("raystage", t, Samples::default()));
        if cfg!(feature = "embree") {
            runs.push(("embree", t, Samples::default()));
        }
    }
    let mut embree_medium_build: Vec<(usize, Vec<f64>)> = counts.iter().map(|&t| (t, Vec::new())).collect();
    let mut bvhs: Vec<Option<Bvh8>> = counts.iter().map(|_| None).collect();
    #[cfg(feature = "embree")]
    let devices: Vec<crate::embree::Device> = counts.iter().map(|&t| crate::embree::Device::new(t).expect("Embree device")).collect();
    #[cfg(feature = "embree")]
    let mut embree_high: Vec<Option<crate::embree::Scene>> = counts.iter().map(|_| None).collect();
    let mut record_build = |system: &str, t: usize, seconds: f64| {
        let entry = runs.iter_mut().find(|(s, th, _)| *s == system && *th == t).expect("run registered");
        entry.2.build.push(seconds);
    };
    for rep in 0..reps {
        for (i, &t) in counts.iter().enumerate() {
            // Drop the previous repetition's trees first, so that no build runs beside another's
            // memory any more than the first one did.
            bvhs[i] = None;
            let (b, s) = build_raystage(&mesh, t);
            progress(&format!("{}: rep {}/{reps} raystage build, {t} thread(s): {s:.3} s", scene.name(), rep + 1));
            record_build("raystage", t, s);
            bvhs[i] = Some(b);
            #[cfg(feature = "embree")]
            {
                use crate::embree::{Quality, Scene};
                let device = &devices[i];
                let secs = Scene::build(device, &mesh, Quality::Medium).1;
                progress(&format!("{}: rep {}/{reps} embree {} MEDIUM build, {t} thread(s): {secs:.3} s", scene.name(), rep + 1, device.version()));
                embree_medium_build[i].1.push(secs);
                embree_high[i] = None;
                let (s, secs) = Scene::build(device, &mesh, Quality::High);
                progress(&format!("{}: rep {}/{reps} embree HIGH build, {t} thread(s): {secs:.3} s", scene.name(), rep + 1));
                record_build("embree", t, secs);
                embree_high[i] = Some(s);
            }
        }
    }
    if !cfg!(feature = "embree") {
        embree_medium_build.clear();
    }
    let bvhs: Vec<Bvh8> = bvhs.into_iter().map(|b| b.expect("reps >= 1")).collect();
    let sah_cost = counts.iter().zip(&bvhs).map(|(&t, b)| (t, b.stats().sah_cost)).collect();
    if build_only {
        return SceneRun { scene, triangles: mesh.indices.len(), sets: None, runs, embree_medium_build, sah_cost, walks: None };
    }
    progress(&format!("{}: generating rays", scene.name()));
    let sets = RaySets::new(scene, &mesh, &bvhs[0]);
    progress(&format!("{}: counting raystage's walk steps", scene.name()));
    let walks = Some(Walks::of(&bvhs[0], &sets));
    // Embree in robust mode traces too (built once per thread count at HIGH; its build is shown
    // but not interleaved with the others).
    #[cfg(feature = "embree")]
    let embree_scenes: Vec<(crate::embree::Scene, crate::embree::Scene)> = counts
        .iter()
        .zip(&devices)
        .zip(embree_high)
        .map(|((&t, device), high)| {
            use crate::embree::{Quality, Scene};
            let (robust, secs) = Scene::build_robust(device, &mesh, Quality::High);
            progress(&format!("{}: embree HIGH robust build, {t} thread(s): {secs:.3} s", scene.name()));
            runs.push(("embree-robust", t, Samples { build: vec![secs], ..Samples::default() }));
            (high.expect("reps >= 1"), robust)
        })
        .collect();
    for rep in 0..reps {
        for (i, &t) in counts.iter().enumerate() {
            #[allow(unused_mut)]
            let mut tracers: Vec<(&str, &dyn Tracer)> = vec![("raystage", &bvhs[i])];
            #[cfg(feature = "embree")]
            {
                tracers.push(("embree", &embree_scenes[i].0));
                tracers.push(("embree-robust", &embree_scenes[i].1));
            }
            let only: Vec<&dyn Tracer> = tracers.iter().map(|(_, tr)| *tr).collect();
            for ((name, _), traced) in tracers.iter().zip(trace_interleaved(&only, &sets, t)) {
                let entry = runs.iter_mut().find(|(s, th, _)| s == name && *th == t).expect("run registered");
                entry.2.record(traced);
                progress(&format!(
                    "{}: rep {}/{reps} {name} {t} thread(s): primary {:.2} Mrays/s",
                    scene.name(),
                    rep + 1,
                    sets.primary.len() as f64 / traced[0].seconds / 1e6
                ));
            }
        }
    }
    SceneRun { scene, triangles: mesh.indices.len(), sets: Some(sets), runs, embree_medium_build, sah_cost, walks }
}
