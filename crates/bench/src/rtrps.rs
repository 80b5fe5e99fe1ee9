//! RTRPS measured (seed 004, Suzuki et al. 2010; issue 41): the animated demos' primary rays
//! traced through a top level of bounding spheres culled by each tile's frustum, in turns with
//! raystage's own top-level tree (`raystage-bench rtrps`).
//!
//! RTRPS keeps no tree over the instances. Moving a rigid part moves its bounding sphere's
//! centre, nothing more; a tile of 16×16 camera rays first drops the spheres that lie outside
//! its frustum, and each of its rays then tests the spheres left, nearest entry first, tracing
//! the object of each one it enters (in the object's space) until the next entry lies past its
//! closest hit. raystage instead rebuilds a tree over the instances' world boxes every frame
//! and walks it per ray or per 4×2 packet. [`Rtrps`] is that top level over the same object
//! trees raystage builds (the same builder, options and refit-or-rebuild rule), so that the two
//! differ only in the top level. Every frame is traced a second time, untimed, keeping every
//! ray's hit, to check them against `Frame::intersect` (or `Frame::intersect_many` for packets)
//! ray by ray.

use std::cell::Cell;
use std::time::Instant;

use glam::{Affine3A, Vec3, Vec3A};
use rayon::prelude::*;
use raystage_demo::animated::{Animation, Staged};
use raystage_kernel::{Bvh8, PACKET_SIZE, PreparedRay, Ray};
use raystage_scene::{InstanceId, Mesh, ObjectKind, REBUILD_DEGRADATION};

use crate::dynamic::{FrameTime, HEIGHT, Raystage, System, SystemRun, WIDTH, paired_ratio, primary_rays, run_in_turns};
use crate::kernel::Api;
use crate::rays::in_blocks;

/// Side of a tile in pixels: RTRPS culls per 16×16 camera rays.
pub const TILE: u32 = 16;

/// Relative padding of every sphere and culling test. The tests run in the world while the
/// object trees see rays rounded into object space; a thousandth of a percent of the distances
/// involved is far above that rounding and far below what would cost culling anything.
const SLACK: f32 = 1e-5;

/// A bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Its centre.
    pub centre: Vec3,
    /// Its radius.
    pub radius: f32,
}

impl Sphere {
    /// Around a mesh: centred on its box, reaching its farthest vertex (one pass over the
    /// vertices, done again only when they move).
    pub fn around(mesh: &Mesh) -> Sphere {
        let centre = mesh.bounds().center();
        let reach2 = mesh.positions.iter().fold(0.0f32, |r, &p| r.max(p.distance_squared(centre)));
        Sphere { centre, radius: reach2.sqrt() * (1.0 + SLACK) + SLACK * centre.abs().max_element() }
    }

    /// The sphere carried into the world by `t`: the centre transformed, the radius scaled by
    /// the most `t` stretches any direction. That stretch is the square root of the largest
    /// eigenvalue of `AᵀA` (`A` the linear part), bounded by the largest absolute row sum of
    /// `AᵀA` (Gershgorin): exact for rotations with scaling, whose columns are orthogonal.
    pub fn placed(&self, t: &Affine3A) -> Sphere {
        let m = t.matrix3;
        let cols = [m.x_axis, m.y_axis, m.z_axis];
        let row = |i: usize| cols.iter().map(|c| cols[i].dot(*c).abs()).sum::<f32>();
        let stretch = row(0).max(row(1)).max(row(2)).sqrt();
        let centre = t.transform_point3(self.centre);
        Sphere { centre, radius: self.radius * stretch * (1.0 + SLACK) + SLACK * centre.abs().max_element() }
    }

    /// The parameters where `ray`'s line enters and leaves the sphere, padded outwards (so an
    /// entry is never past a hit inside), or `None` if it misses. Measured from the point of
    /// closest approach, which keeps the rounding small for spheres far down the ray.
    #[inline]
    fn span(&self, ray: &Ray) -> Option<(f32, f32)> {
        let oc = self.centre - ray.origin;
        let dd = ray.dir.length_squared();
        let along = oc.dot(ray.dir) / dd;
        let off = oc - ray.dir * along;
        let reach = self.radius + SLACK * (oc.x.abs() + oc.y.abs() + oc.z.abs());
        let h2 = reach * reach - off.length_squared();
        if h2 < 0.0 {
            return None;
        }
        let half = (h2 / dd).sqrt();
        Some((along - half, along + half))
    }
}

/// The four side planes of a tile's rays, which all leave one eye point: through the eye and
/// two neighbouring corner rays, unit normals pointing out of the tile.
#[derive(Clone, Copy, Debug)]
struct Frustum {
    eye: Vec3A,
    planes: [Vec3A; 4],
}

impl Frustum {
    /// The frustum of a tile whose corner rays are `corners` (in order around the tile), or
    /// `None` if its rays do not all leave one point (a thin lens), for which a tile culls
    /// nothing. The corner rays of a pinhole's pixel centres bound the tile's other rays.
    fn of(rays: &[Ray], corners: [&Ray; 4]) -> Option<Frustum> {
        let eye = corners[0].origin;
        if rays.iter().any(|r| r.origin != eye) {
            return None;
        }
        let inside: Vec3 = corners.iter().map(|r| r.dir).sum();
        let planes = std::array::from_fn(|i| {
            let n = corners[i].dir.cross(corners[(i + 1) % 4].dir).normalize();
            Vec3A::from(if n.dot(inside) > 0.0 { -n } else { n })
        });
        Some(Frustum { eye: eye.into(), planes })
    }

    /// Whether a sphere may reach into the frustum (none of its planes has it wholly outside).
    #[inline]
    fn keeps(&self, s: &Sphere) -> bool {
        let oc = Vec3A::from(s.centre) - self.eye;
        let reach = s.radius + SLACK * oc.abs().element_sum();
        self.planes.iter().all(|n| n.dot(oc) <= reach)
    }

    /// Whether the eye lies inside a sphere, which every ray of the tile then enters where it
    /// starts: a scene's ground or city around the camera needs no test per ray. (Wrong only
    /// by rounding, it would merely skip a test that culls nothing.)
    #[inline]
    fn inside(&self, s: &Sphere) -> bool {
        (Vec3A::from(s.centre) - self.eye).length_squared() < s.radius * s.radius
    }
}

/// A sphere a tile kept: its instance, and whether the tile's eye is inside it.
#[derive(Clone, Copy, Debug)]
struct Kept {
    item: u32,
    around_eye: bool,
}

impl Kept {
    /// Where `ray` enters and leaves the sphere (see [`Sphere::span`]); the whole line for a
    /// sphere around the eye.
    #[inline]
    fn span(&self, sphere: &Sphere, ray: &Ray) -> Option<(f32, f32)> {
        if self.around_eye { Some((f32::NEG_INFINITY, f32::INFINITY)) } else { sphere.span(ray) }
    }
}

/// A closest hit: distance, the instance (by its position in the animation's list) and the
/// triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Found {
    t: f32,
    item: u32,
    prim: u32,
}

impl Found {
    /// Whether a hit at `t` on `item` wins over this one: nearer, or as near on an earlier
    /// instance (the frame's rule, so ties resolve alike).
    #[inline]
    fn loses_to(&self, t: f32, item: u32) -> bool {
        t < self.t || (t == self.t && item < self.item)
    }
}

/// An object as RTRPS keeps it: the mesh, its tree and its bounding sphere in its own space.
struct Object {
    kind: ObjectKind,
    mesh: Mesh,
    tree: Bvh8,
    sphere: Sphere,
}

impl Object {
    /// `mesh` as an object of `kind`, its tree built with the options raystage's scene uses.
    fn new(kind: ObjectKind, mesh: Mesh) -> Object {
        let tree = Bvh8::build(&mesh, &kind.build_options());
        Object { kind, sphere: Sphere::around(&mesh), mesh, tree }
    }

    /// New vertex positions: the sphere recomputed, the tree refitted, or rebuilt where the refit
    /// degraded it past raystage's threshold (RT-DEFORM's rule; raystage also predicts and backs
    /// off failing refits, which this does not).
    fn deform(&mut self, positions: Vec<Vec3>) {
        self.mesh.positions = positions;
        self.sphere = Sphere::around(&self.mesh);
        if self.tree.refit(&self.mesh) > REBUILD_DEGRADATION {
            self.tree.rebuild(&self.mesh, &self.kind.build_options());
        }
    }
}

/// An instance placed for a frame: both directions of its transform, as the frame has them.
#[derive(Clone, Copy, Debug)]
struct Placed {
    object: usize,
    to_object: Affine3A,
    identity: bool,
    sphere: Sphere,
}

impl Placed {
    /// The ray in object space, rounded as the frame rounds it (so hits agree bit for bit);
    /// an instance placed by the identity keeps the world ray.
    #[inline]
    fn local(&self, ray: &Ray) -> Ray {
        if self.identity {
            return *ray;
        }
        Ray { origin: self.to_object.transform_point3(ray.origin), dir: self.to_object.transform_vector3(ray.dir), ..*ray }
    }
}

/// A sphere a packet's rays enter: which rays, where each enters, and the nearest entry.
#[derive(Clone, Copy)]
struct Entered {
    nearest: f32,
    item: u32,
    rays: u32,
    entry: [f32; PACKET_SIZE],
}

/// The RTRPS top level of one frame: the placed instances over the objects.
struct TopLevel<'s> {
    objects: &'s [Object],
    placed: &'s [Placed],
}

impl TopLevel<'_> {
    /// The closest hit of `ray` among the instances `kept`: each sphere it enters, nearest entry
    /// first, until an entry lies past the closest hit so far. `order` is scratch.
    fn closest(&self, ray: &Ray, kept: &[Kept], order: &mut Vec<(f32, u32)>) -> Option<Found> {
        order.clear();
        for k in kept {
            if let Some((enter, leave)) = k.span(&self.placed[k.item as usize].sphere, ray)
                && leave >= ray.tnear
                && enter <= ray.tfar
            {
                order.push((enter, k.item));
            }
        }
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut best: Option<Found> = None;
        for &(enter, item) in order.iter() {
            let tfar = best.map_or(ray.tfar, |b| b.t);
            // Equal distances still go in: an earlier instance wins a tie.
            if enter > tfar {
                break;
            }
            let p = &self.placed[item as usize];
            let hit = self.objects[p.object].tree.intersect(&Ray { tfar, ..p.local(ray) });
            if let Some(h) = hit
                && best.is_none_or(|b| b.loses_to(h.t, item))
            {
                best = Some(Found { t: h.t, item, prim: h.prim });
            }
        }
        best
    }

    /// The closest hits of a packet of [`PACKET_SIZE`] rays (a tile holds whole packets) among
    /// the instances `kept`: each sphere any of them enters, by nearest entry, traced as a packet
    /// by the rays that enter it before their closest hit so far (the others ride along with an
    /// empty segment, so the packet keeps one origin and octant). `entered` is scratch.
    fn closest_packet(&self, rays: &[Ray], kept: &[Kept], entered: &mut Vec<Entered>, found: &mut [Option<Found>]) {
        entered.clear();
        for kept in kept {
            let item = kept.item;
            if kept.around_eye {
                entered.push(Entered { nearest: f32::NEG_INFINITY, item, rays: (1 << rays.len()) - 1, entry: [f32::NEG_INFINITY; PACKET_SIZE] });
                continue;
            }
            let sphere = &self.placed[item as usize].sphere;
            let mut e = Entered { nearest: f32::INFINITY, item, rays: 0, entry: [f32::INFINITY; PACKET_SIZE] };
            for (k, ray) in rays.iter().enumerate() {
                if let Some((enter, leave)) = sphere.span(ray)
                    && leave >= ray.tnear
                    && enter <= ray.tfar
                {
                    (e.rays, e.entry[k], e.nearest) = (e.rays | 1 << k, enter, e.nearest.min(enter));
                }
            }
            if e.rays != 0 {
                entered.push(e);
            }
        }
        entered.sort_unstable_by(|a, b| a.nearest.total_cmp(&b.nearest));
        found.fill(None);
        for e in entered.iter() {
            let tfar = |k: usize| found[k].map_or(rays[k].tfar, |b| b.t);
            let active: u32 = (0..rays.len()).filter(|&k| e.rays >> k & 1 != 0 && e.entry[k] <= tfar(k)).fold(0, |m, k| m | 1 << k);
            if active == 0 {
                continue;
            }
            let p = &self.placed[e.item as usize];
            let local: [Ray; PACKET_SIZE] = std::array::from_fn(|k| {
                let ray = p.local(&rays[k]);
                if active >> k & 1 != 0 { Ray { tfar: tfar(k), ..ray } } else { Ray { tfar: ray.tnear, ..ray } }
            });
            let mut hits = [None; PACKET_SIZE];
            self.objects[p.object].tree.intersect_packet_prepared(&PreparedRay::packet(&local), &mut hits);
            for (k, h) in hits.iter().enumerate() {
                if let Some(h) = h
                    && active >> k & 1 != 0
                    && found[k].is_none_or(|b| b.loses_to(h.t, e.item))
                {
                    found[k] = Some(Found { t: h.t, item: e.item, prim: h.prim });
                }
            }
        }
    }

    /// Traces `tiles` (each [`TILE`]² rays in 4×2 blocks, with its frustum) as `api` hands
    /// the rays over, each tile's hits into its part of `out` if given; returns the spheres kept
    /// and the rays that hit, over all tiles.
    fn trace_tiles(&self, tiles: &[(&[Ray], Option<Frustum>)], api: Api, mut out: Option<&mut [Option<Found>]>) -> (u64, u64) {
        let (mut kept, mut order, mut entered) = (Vec::new(), Vec::new(), Vec::new());
        let (mut total, mut hits) = (0, 0);
        let per_tile = (TILE * TILE) as usize;
        // A tile's hits stay in cache: written out only for the check, as raystage's system
        // keeps none either.
        let mut found = vec![None; per_tile];
        for (t, (rays, frustum)) in tiles.iter().enumerate() {
            kept.clear();
            kept.extend(self.placed.iter().zip(0..).filter_map(|(p, item)| match frustum {
                Some(f) => f.keeps(&p.sphere).then(|| Kept { item, around_eye: f.inside(&p.sphere) }),
                None => Some(Kept { item, around_eye: false }),
            }));
            total += kept.len() as u64;
            match api {
                Api::Single => rays.iter().zip(found.iter_mut()).for_each(|(r, f)| *f = self.closest(r, &kept, &mut order)),
                Api::Packets => {
                    for (rays, found) in rays.chunks(PACKET_SIZE).zip(found.chunks_mut(PACKET_SIZE)) {
                        self.closest_packet(rays, &kept, &mut entered, found);
                    }
                }
            }
            hits += found.iter().flatten().count() as u64;
            if let Some(out) = out.as_deref_mut() {
                out[t * per_tile..(t + 1) * per_tile].copy_from_slice(&found);
            }
        }
        (total, hits)
    }

    /// [`TopLevel::trace_tiles`] on `threads` threads, each a contiguous run of tiles (as the
    /// dynamic bench splits raystage's rays).
    fn trace(&self, tiles: &[(&[Ray], Option<Frustum>)], threads: usize, api: Api, out: Option<&mut [Option<Found>]>) -> (u64, u64) {
        let per_thread = tiles.len().div_ceil(threads);
        let runs = tiles.chunks(per_thread);
        let outs: Vec<Option<&mut [Option<Found>]>> = match out {
            Some(out) => out.chunks_mut(per_thread * (TILE * TILE) as usize).map(Some).collect(),
            None => runs.clone().map(|_| None).collect(),
        };
        std::thread::scope(|s| {
            let handles: Vec<_> = runs.zip(outs).map(|(tiles, out)| s.spawn(move || self.trace_tiles(tiles, api, out))).collect();
            handles.into_iter().map(|h| h.join().expect("trace thread")).fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
        })
    }
}

/// What [`Rtrps`] systems count while they run, for the report.
#[derive(Debug, Default)]
pub struct Tally {
    /// Rays whose hit differed from raystage's.
    pub mismatches: Cell<u64>,
    /// Spheres the tiles kept, summed over tiles and frames.
    pub kept: Cell<u64>,
    /// Tiles traced, over all frames.
    pub tiles: Cell<u64>,
}

impl Tally {
    /// Spheres kept per tile, the mean.
    pub fn kept_per_tile(&self) -> f64 {
        self.kept.get() as f64 / self.tiles.get().max(1) as f64
    }
}

/// RTRPS on an animation, primary rays only, one by one or in 4×2 packets as `api` says. Each
/// frame's hits are checked against the frame of its own copy of the scene (untimed); the rays
/// that differ, and the spheres kept, go to the [`Tally`] it was given.
pub struct Rtrps<'a> {
    animation: &'a dyn Animation,
    objects: Vec<Object>,
    placed: Vec<Placed>,
    /// Rays by tile, tiles row by row, each tile's rays in 4×2 blocks; a frustum per tile.
    rays: Vec<Ray>,
    frusta: Vec<Option<Frustum>>,
    threads: usize,
    api: Api,
    /// The reference: the animation staged in a raystage scene, and its instances' ids by index.
    staged: Staged,
    ids: Vec<InstanceId>,
    tally: &'a Tally,
}

impl<'a> Rtrps<'a> {
    /// `animation` at frame 0 (nothing built yet), traced on `threads` threads, counting in
    /// `tally`.
    pub fn new(animation: &'a dyn Animation, threads: usize, api: Api, tally: &'a Tally) -> Rtrps<'a> {
        let staged = Staged::new(animation).expect("the animation makes a valid scene");
        let ids = staged.scene.instances().map(|(id, _, _)| id).collect();
        let camera = staged.scene.camera();
        let rows = primary_rays(camera);
        let (w, h) = (WIDTH / TILE, HEIGHT / TILE);
        let side = TILE as usize;
        let pixel = |x: u32, y: u32| &rows[(y * WIDTH + x) as usize];
        let frusta = (0..h)
            .flat_map(|ty| (0..w).map(move |tx| (tx * TILE, ty * TILE)))
            .map(|(x, y)| {
                let (x1, y1) = (x + TILE - 1, y + TILE - 1);
                let tile: Vec<Ray> = (y..=y1).flat_map(|py| (x..=x1).map(move |px| *pixel(px, py))).collect();
                Frustum::of(&tile, [pixel(x, y), pixel(x1, y), pixel(x1, y1), pixel(x, y1)])
            })
            .collect();
        let rays = in_blocks(&rows, WIDTH, HEIGHT, (side, side)).chunks(side * side).flat_map(|tile| in_blocks(tile, TILE, TILE, (4, 2))).collect();
        Rtrps { animation, objects: Vec::new(), placed: Vec::new(), rays, frusta, threads: threads.max(1), api, staged, ids, tally }
    }

    /// Brings objects, trees and spheres to a frame, `instances` and `deformed` as the animation
    /// gives them (building every tree the first time).
    fn update(&mut self, instances: &[(usize, Affine3A)], deformed: Vec<(usize, Vec<Vec3>)>) {
        if self.objects.is_empty() {
            let objects = self.animation.objects();
            self.objects = objects.into_iter().map(|o| Object::new(o.kind, Mesh::new(o.mesh.vertices, o.mesh.indices))).collect();
        }
        for (object, positions) in deformed {
            self.objects[object].deform(positions);
        }
        self.placed.clear();
        self.placed.extend(instances.iter().map(|&(object, t)| Placed {
            object,
            to_object: t.inverse(),
            identity: t == Affine3A::IDENTITY,
            sphere: self.objects[object].sphere.placed(&t),
        }));
    }

    /// Rays whose hit in `found` differs from the staged scene's frame: in distance (bit for
    /// bit), instance or triangle.
    fn check(&self, found: &[Option<Found>]) -> u64 {
        let frame = self.staged.scene.frame();
        let (api, ids) = (self.api, &self.ids);
        let chunk = |(rays, found): (&[Ray], &[Option<Found>])| {
            let mut theirs = [None; PACKET_SIZE];
            match api {
                Api::Single => rays.iter().zip(theirs.iter_mut()).for_each(|(r, h)| *h = frame.intersect(r, 0.0)),
                Api::Packets => frame.intersect_many(rays, &mut theirs[..rays.len()], 0.0),
            }
            let same = |a: &Option<Found>, b: &Option<raystage_scene::SceneHit>| match (a, b) {
                (None, None) => true,
                (Some(a), Some(b)) => a.t.to_bits() == b.t.to_bits() && a.prim == b.prim && ids[a.item as usize] == b.instance,
                _ => false,
            };
            found.iter().zip(&theirs).filter(|(a, b)| !same(a, b)).count() as u64
        };
        self.rays.par_chunks(PACKET_SIZE).zip(found.par_chunks(PACKET_SIZE)).map(chunk).sum()
    }
}

impl System for Rtrps<'_> {
    fn name(&self) -> String {
        match self.api {
            Api::Single => "rtrps".into(),
            Api::Packets => "rtrps-packets".into(),
        }
    }

    fn frame(&mut self, f: u32) -> FrameTime {
        let (instances, deformed) = (self.animation.instances(f), self.animation.deform(f));
        // The reference's copy of the frame, made outside the timing.
        let reference = deformed.clone();
        let start = Instant::now();
        self.update(&instances, deformed);
        let update = start.elapsed().as_secs_f64();

        let tiles: Vec<(&[Ray], Option<Frustum>)> = self.rays.chunks((TILE * TILE) as usize).zip(self.frusta.iter().copied()).collect();
        let start = Instant::now();
        let top = TopLevel { objects: &self.objects, placed: &self.placed };
        let (kept, hits) = top.trace(&tiles, self.threads, self.api, None);
        let trace = start.elapsed().as_secs_f64();
        let tally = self.tally;
        tally.kept.set(tally.kept.get() + kept);
        tally.tiles.set(tally.tiles.get() + tiles.len() as u64);

        // The check traces the frame again, untimed, keeping every hit.
        let mut found = vec![None; self.rays.len()];
        top.trace(&tiles, self.threads, self.api, Some(&mut found));
        self.staged.advance(&instances, reference).expect("valid frame");
        tally.mismatches.set(tally.mismatches.get() + self.check(&found));
        FrameTime { update, trace, rays: self.rays.len() as u64, hits }
    }
}

/// One scene's measurement: raystage (primary rays only) and RTRPS in turns frame by frame,
/// rays one by one and then in packets; the systems' runs in that order and what RTRPS counted.
pub fn compare(animation: &dyn Animation, threads: usize, frames: u32) -> (Vec<SystemRun>, Tally) {
    let tally = Tally::default();
    let mut runs = Vec::new();
    for api in [Api::Single, Api::Packets] {
        let mut systems: Vec<Box<dyn System + '_>> =
            vec![Box::new(Raystage::new(animation, threads, api).primary_only()), Box::new(Rtrps::new(animation, threads, api, &tally))];
        runs.extend(run_in_turns(&mut systems, frames));
    }
    (runs, tally)
}

/// The measurement as a table: each system's medians over frames 1..=N, then RTRPS over
/// raystage frame by frame (medians of the frames' ratios, each pair having met the same phase
/// of a shared machine).
pub fn table(scene: &str, instances: usize, threads: usize, runs: &[SystemRun], tally: &Tally) -> String {
    let mut out = format!(
        "scene {scene}: {instances} instances; {WIDTH}x{HEIGHT} primary rays in {TILE}x{TILE} tiles; medians over frames 1..={}; {threads} thread(s); {:.1} of {instances} spheres kept per tile; {} rays differ from raystage's hits\n",
        runs.first().map_or(0, |r| r.frames.len()),
        tally.kept_per_tile(),
        tally.mismatches.get()
    );
    out += "| system | update ms | trace ms | frame ms | Mrays/s |\n|---|---:|---:|---:|---:|\n";
    for r in runs {
        let d = r.report(scene, threads, 0, instances);
        out += &format!("| {} | {:.3} | {:.2} | {:.2} | {:.1} |\n", d.system, d.update_ms, d.trace_ms, d.frame_ms, d.mrays);
    }
    for pair in runs.chunks(2) {
        let [raystage, rtrps] = pair else { continue };
        let ratio = |of: fn(&FrameTime) -> f64| paired_ratio(rtrps, raystage, of);
        out += &format!(
            "{} / {}: update {:.2}x, trace {:.2}x, frame {:.2}x\n",
            rtrps.system,
            raystage.system,
            ratio(|f| f.update),
            ratio(|f| f.trace),
            ratio(|f| f.update + f.trace)
        );
    }
    out
}
