//! A frame: the scene frozen for rendering. Starting one resolves every reference by id (frame
//! semantics), places the instances and rebuilds the top level over their world boxes; tracing
//! then builds or refits each object's tree the first time a ray reaches it.

use std::borrow::Cow;
use std::collections::HashSet;
use std::ops::Range;
use std::sync::Arc;
use std::time::Instant;

use glam::{Vec2, Vec3, Vec4};
use raystage_kernel::{Aabb, BoxTree, Bvh8, Entries, PACKET_SIZE, PreparedRay, Ray};

use crate::camera::Camera;
use crate::ids::{InstanceId, ObjectId, ShaderId};
use crate::instance::{Instance, Placed, world_bounds};
use crate::light::Light;
use crate::builds::BuildCounters;
use crate::object::Object;
use crate::scene::{Background, Scene};
use crate::shader::{Shader, ShadingModel};

mod visibility;

use visibility::Visibility;

/// An instance as a frame sees it.
struct FrameInstance<'a> {
    id: InstanceId,
    object_id: ObjectId,
    object: &'a Arc<Object>,
    instance: Instance,
    /// The placement at shutter time 0, used by every ray of a still instance.
    placed: Placed,
    /// Whether some of its shaders make hits not count (see [`Visibility`]): then every hit on
    /// it is tested.
    filtered: bool,
}

impl FrameInstance<'_> {
    /// The placement at shutter time `time`.
    /// (Borrowed for a still instance: the placement is two matrices, and rays look it up on
    /// every visit.)
    #[inline]
    fn placed_at(&self, time: f32) -> Cow<'_, Placed> {
        if self.instance.end.is_some() && time != 0.0 { Cow::Owned(Placed::at(&self.instance, time)) } else { Cow::Borrowed(&self.placed) }
    }
}

/// An instance a packet's rays touch: which rays, where each enters its box, and the nearest
/// entry.
#[derive(Clone, Copy)]
struct Touched {
    nearest: f32,
    item: u32,
    entries: Entries,
}

/// The closest hit of a ray in the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneHit {
    /// Ray parameter (shared by world and object space).
    pub t: f32,
    /// The instance hit.
    pub instance: InstanceId,
    /// Its object.
    pub object: ObjectId,
    /// The triangle, by index in the object's mesh.
    pub prim: u32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of its third vertex.
    pub v: f32,
    /// The triangle's unnormalised geometric normal `(v1 − v0) × (v2 − v0)` in the object's
    /// space (see [`raystage_kernel::Hit::ng`]).
    pub ng: Vec3,
    /// The instance's position in the frame's list.
    item: u32,
}

/// What a shader needs to know about a hit point, in world space.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint<'a> {
    /// The hit point, computed from the triangle's vertices and barycentrics in the object's
    /// space and carried into the world by the instance's transform.
    pub position: Vec3,
    /// A conservative bound on the absolute rounding error of `position`, per component: the
    /// true surface point lies within it. [`SurfacePoint::spawn_ray`] starts secondary rays
    /// outside it.
    pub position_error: Vec3,
    /// The hit point in the object's own space (where solid textures are evaluated, so that
    /// they move with the object).
    pub local_position: Vec3,
    /// Unit geometric normal, facing the side the ray came from.
    pub geometric_normal: Vec3,
    /// Whether the ray hit the triangle's front (the side its counter-clockwise winding faces
    /// in the object's own space, the outside of a consistently wound closed mesh; an instance
    /// that mirrors the object keeps its outside the front).
    pub front_face: bool,
    /// Unit shading normal (interpolated vertex normals if the mesh has them), on the same side.
    pub shading_normal: Vec3,
    /// Interpolated vertex colour, if the mesh has colours.
    pub color: Option<Vec3>,
    /// Interpolated texture coordinates, if the mesh has them.
    pub uv: Option<Vec2>,
    /// Interpolated second texture coordinates, if the mesh has them.
    pub uv1: Option<Vec2>,
    /// The triangle's shader, and its id (`None` for the scene's default shader).
    pub shader: &'a Shader,
    pub shader_id: Option<ShaderId>,
}

/// What the eye-light preview needs of a hit point (see [`Frame::preview`]).
#[derive(Clone, Copy, Debug)]
pub struct PreviewPoint {
    /// Shading normal in the world, on either side of the surface, not normalised (a preview
    /// normalises the normals of a packet of hits together).
    pub normal: Vec3,
    /// The id of the triangle's shader, `None` if the triangle has none. A shader that the
    /// scene has removed since stands for the default shader, as in [`SurfacePoint`].
    pub shader_id: Option<ShaderId>,
}

/// What a textured or vertex-coloured surface needs of a hit point besides its normal (see
/// [`Frame::preview_attributes`]).
#[derive(Clone, Copy, Debug)]
pub struct PreviewAttributes {
    /// The point in the object's own space, from the ray (for solid textures).
    pub local_position: Vec3,
    /// Interpolated vertex colour, if the mesh has colours.
    pub color: Option<Vec3>,
    /// Interpolated texture coordinates, if the mesh has them.
    pub uv: Option<Vec2>,
    /// Interpolated second texture coordinates, if the mesh has them.
    pub uv1: Option<Vec2>,
    /// The point in the world, from the ray.
    pub position: Vec3,
}

/// A triangle of an instance, placed in the world (see [`Frame::world_triangles`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldTriangle {
    /// Its corners in the world at the shutter's opening, in the mesh's order.
    pub corners: [Vec3; 3],
    /// The unit normal on its front (the side its counter-clockwise winding faces in the
    /// object's own space, as [`SurfacePoint::front_face`] has it).
    pub front: Vec3,
    /// Its area in the world.
    pub area: f32,
    /// Its shader's id, `None` for the scene's default shader.
    pub shader_id: Option<ShaderId>,
    /// Its corners in the object's own space (where solid textures are evaluated).
    pub local: [Vec3; 3],
    /// Its corners' first and second texture coordinates, where the mesh has them (for
    /// textured emission).
    pub uvs: [Option<[Vec2; 3]>; 2],
}

/// Tree work done for a frame so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameWork {
    /// Object trees built from scratch.
    pub built: u32,
    /// Object trees refitted to moved geometry.
    pub refitted: u32,
    /// Refits abandoned for a rebuild because the tree had degraded.
    pub rebuilt: u32,
    /// Instanced objects whose tree no ray has needed (and which were not built before): the
    /// work lazy building saved.
    pub skipped: u32,
    /// Wall-clock seconds during which some object tree was being built or refitted.
    pub build_seconds: f64,
}

/// Bytes a frame holds per instance, for memory budgets: the instance as placed, its world box
/// and its share of the top-level tree. A scene that renders holds a frame most of the time.
pub(crate) const FRAME_BYTES_PER_INSTANCE: usize = size_of::<FrameInstance<'static>>() + size_of::<Aabb>() + BoxTree::BYTES_PER_BOX;

/// Bytes a frame holds per light, for memory budgets: its copy of the light (a frame sees the
/// lights as they were when it started).
pub(crate) const FRAME_BYTES_PER_LIGHT: usize = size_of::<Light>();

/// The scene frozen for rendering: see the module documentation.
pub struct Frame<'a> {
    scene: &'a Scene,
    instances: Vec<FrameInstance<'a>>,
    top: BoxTree,
    /// The instances' world boxes (over the shutter interval), by item.
    boxes: Vec<Aabb>,
    counters: BuildCounters,
    lights: Vec<Light>,
    top_level_seconds: f64,
    /// Of each shader (by id; ids without a shader have the default shader's) and of the default
    /// shader: which of their hits count, `None` where all do.
    visibility: Vec<Option<Visibility<'a>>>,
    default_visibility: Option<Visibility<'a>>,
    /// Whether some instance is filtered.
    filtered: bool,
}

impl<'a> Frame<'a> {
    pub(crate) fn new(scene: &'a Scene) -> Frame<'a> {
        let start = Instant::now();
        // Ids without a shader (removed ones) stand for the default shader, as in `shader_of`.
        let default_visibility = Visibility::of(scene.default_shader(), scene);
        let mut visibility: Vec<Option<Visibility<'a>>> = Vec::new();
        for (id, shader) in scene.shaders() {
            let index = id.0 as usize;
            if visibility.len() <= index {
                visibility.resize(index + 1, default_visibility);
            }
            visibility[index] = Visibility::of(shader, scene);
        }
        let instances: Vec<FrameInstance<'a>> = scene
            .instance_records()
            .filter_map(|(id, instance)| {
                let object = scene.object_record(instance.object)?;
                let placed = Placed::at(instance, 0.0);
                let filtered = object.shaders_used.iter().any(|s| visibility.get(s.0 as usize).unwrap_or(&default_visibility).is_some())
                    || (object.uses_default_shader && default_visibility.is_some());
                Some(FrameInstance { id, object_id: instance.object, object, instance: *instance, placed, filtered })
            })
            .collect();
        let filtered = instances.iter().any(|fi| fi.filtered);
        let boxes: Vec<_> = instances
            .iter()
            .map(|fi| {
                let (bounds, cover) = (&fi.object.bounds, &fi.object.cover[..]);
                let b = world_bounds(bounds, cover, &fi.instance.start);
                match fi.instance.end {
                    Some(end) => b.union(world_bounds(bounds, cover, &end)),
                    None => b,
                }
            })
            .collect();
        let top = BoxTree::build(&boxes);
        let lights = scene.light_records().map(|(_, l)| *l).collect();
        Frame {
            scene,
            instances,
            top,
            boxes,
            counters: BuildCounters::default(),
            lights,
            top_level_seconds: start.elapsed().as_secs_f64(),
            visibility,
            default_visibility,
            filtered,
        }
    }

    /// Whether hit `h` of `ray` (at shutter time `time`) on instance `fi`, placed by `placed`,
    /// counts: see [`Visibility`]. Instances that are not filtered count every hit.
    fn admits(&self, fi: &FrameInstance<'a>, placed: &Placed, ray: &Ray, h: &raystage_kernel::Hit) -> bool {
        if !fi.filtered {
            return true;
        }
        let mesh = &fi.object.mesh;
        let visibility = match fi.object.shader(h.prim) {
            Some(id) => self.visibility.get(id.0 as usize).unwrap_or(&self.default_visibility),
            None => &self.default_visibility,
        };
        let Some(visibility) = visibility else { return true };
        let front = placed.normal_to_world(h.ng).dot(ray.dir) < 0.0;
        let uvs = || {
            let corners = mesh.indices[h.prim as usize].map(|i| i as usize);
            let w = [1.0 - h.u - h.v, h.u, h.v];
            [interpolated(&mesh.uvs, corners, w), interpolated(&mesh.uvs1, corners, w)]
        };
        let key = || {
            let bits = [ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z].map(f32::to_bits);
            bits.iter().fold(crate::sampling::hash(h.prim ^ fi.id.0.rotate_left(16)), |k, &b| crate::sampling::hash(k ^ b))
        };
        visibility.admits(front, uvs, key)
    }

    /// Hits of a packet's `rays` that do not count (see [`Frame::admits`]), replaced by what
    /// [`Frame::intersect`] finds for the ray alone.
    fn admit_packet(&self, rays: &[Ray], hits: &mut [Option<SceneHit>], time: f32) {
        for (ray, hit) in rays.iter().zip(hits.iter_mut()) {
            let Some(h) = *hit else { continue };
            let fi = &self.instances[h.item as usize];
            let found = raystage_kernel::Hit { t: h.t, prim: h.prim, u: h.u, v: h.v, ng: h.ng };
            if !self.admits(fi, &fi.placed_at(time), ray, &found) {
                *hit = self.intersect(ray, time);
            }
        }
    }

    /// The closest hit of `ray` at shutter time `time` in `[0, 1]` (0 for a still frame). Ties
    /// between instances at exactly the same distance go to the earlier instance.
    pub fn intersect(&self, ray: &Ray, time: f32) -> Option<SceneHit> {
        // Prepared once: instances placed by the identity trace the world ray as it is.
        let world = PreparedRay::new(ray);
        let mut best: Option<SceneHit> = None;
        let visit = |item: u32, tfar: f32| self.closest_in(item, ray, &world, time, tfar, &mut best);
        self.top.closest(&world, visit);
        best
    }

    /// The closest hit in instance `item` of `ray` (prepared as `world`) up to `tfar`, kept in
    /// `best` if it wins; returns the new closest distance.
    fn closest_in(&self, item: u32, ray: &Ray, world: &PreparedRay, time: f32, tfar: f32, best: &mut Option<SceneHit>) -> f32 {
        let fi = &self.instances[item as usize];
        let placed = fi.placed_at(time);
        let bvh = fi.object.accel(&self.counters);
        let local = if placed.identity { world.with_tfar(tfar) } else { PreparedRay::new(&Ray { tfar, ..placed.ray_to_object(ray) }) };
        // Only hits that count can be the closest: one walk that asks of each candidate.
        let found = if fi.filtered { bvh.intersect_where(&local, |h| self.admits(fi, &placed, ray, h)) } else { bvh.intersect_prepared(&local) };
        let Some(h) = found else {
            return tfar;
        };
        if best.is_none_or(|b| h.t < b.t || (h.t == b.t && item < b.item)) {
            *best = Some(SceneHit { t: h.t, instance: fi.id, object: fi.object_id, prim: h.prim, u: h.u, v: h.v, ng: h.ng, item });
        }
        best.map_or(tfar, |b| b.t)
    }

    /// The closest hits of many rays, `hits[i]` for `rays[i]`, at shutter time `time`: exactly
    /// what [`Frame::intersect`] returns for each. Consecutive groups of [`PACKET_SIZE`] rays
    /// (camera rays of a 4×2 block of pixels, say) go through each instance they touch as a
    /// packet, sharing the object tree's node tests.
    ///
    /// # Panics
    /// If `rays` and `hits` differ in length.
    pub fn intersect_many(&self, rays: &[Ray], hits: &mut [Option<SceneHit>], time: f32) {
        assert_eq!(rays.len(), hits.len(), "one hit slot per ray");
        for (rays, hits) in rays.chunks(PACKET_SIZE).zip(hits.chunks_mut(PACKET_SIZE)) {
            if rays.len() == PACKET_SIZE {
                self.intersect_packet(rays, hits, time);
                if self.filtered {
                    self.admit_packet(rays, hits, time);
                }
            } else {
                for (ray, hit) in rays.iter().zip(hits) {
                    *hit = self.intersect(ray, time);
                }
            }
        }
    }

    /// One packet of [`Frame::intersect_many`]: the instances any of its rays touch, nearest
    /// first for the first ray that touches them, each traced with the rays that touch it, each
    /// ray limited to its closest hit so far.
    fn intersect_packet(&self, rays: &[Ray], hits: &mut [Option<SceneHit>], time: f32) {
        thread_local! {
            /// The instances the rays touch. Reused from packet to packet.
            static TOUCHED: std::cell::RefCell<Vec<Touched>> = const { std::cell::RefCell::new(Vec::new()) };
        }
        TOUCHED.with_borrow_mut(|touched| self.intersect_touched(rays, hits, time, touched));
    }

    /// [`Frame::intersect_packet`] with a scratch list for the instances touched.
    ///
    /// Instances are visited in the order of the nearest entry of any ray into their boxes:
    /// every instance a ray reaches before its own closest hit is then also reached by that ray
    /// traced alone, so a packet builds no object that its rays alone would not.
    fn intersect_touched(&self, rays: &[Ray], hits: &mut [Option<SceneHit>], time: f32, touched: &mut Vec<Touched>) {
        touched.clear();
        let prepared = PreparedRay::packet(rays);
        if let Some((only, tree)) = self.only_in_place(&prepared, rays, time) {
            let mut found = [None; PACKET_SIZE];
            if let Some(tree) = tree {
                tree.intersect_packet_prepared(&prepared, &mut found);
            }
            let mesh = &only.object.mesh;
            for (hit, h) in hits.iter_mut().zip(&found) {
                *hit = h.map(|h| {
                    raystage_kernel::prefetch(&mesh.shaders, h.prim as usize);
                    raystage_kernel::prefetch(&mesh.indices, h.prim as usize);
                    SceneHit { t: h.t, instance: only.id, object: only.object_id, prim: h.prim, u: h.u, v: h.v, ng: h.ng, item: 0 }
                });
            }
            return;
        }
        let mut touch = |item: u32, entries: &Entries| touched.push(Touched { nearest: entries.nearest(), item, entries: *entries });
        let all = (1 << PACKET_SIZE) - 1;
        if self.instances.len() == 1 {
            // The only instance: every ray, entering at once (the object's own root test culls
            // those that miss).
            touch(0, &Entries { rays: all, entry: [f32::NEG_INFINITY; PACKET_SIZE] });
        } else if !self.top.touched(&prepared, touch) {
            // The rays went one by one: merge what each found of the same instance.
            merge_touched(touched);
        }
        touched.sort_unstable_by(|a, b| a.nearest.total_cmp(&b.nearest).then(a.item.cmp(&b.item)));
        hits.fill(None);
        // Keeps the hits `found` in instance `item` that beat the closest so far.
        let record = |hits: &mut [Option<SceneHit>], found: &[Option<raystage_kernel::Hit>; PACKET_SIZE], fi: &FrameInstance<'_>, item: u32| {
            for (hit, h) in hits.iter_mut().zip(found) {
                let Some(h) = h else { continue };
                if hit.is_none_or(|b| h.t < b.t || (h.t == b.t && item < b.item)) {
                    *hit = Some(SceneHit { t: h.t, instance: fi.id, object: fi.object_id, prim: h.prim, u: h.u, v: h.v, ng: h.ng, item });
                }
            }
        };
        let mut local = prepared;
        let mut found = [None; PACKET_SIZE];
        for &Touched { item, entries, .. } in touched.iter() {
            let fi = &self.instances[item as usize];
            let tfar: [f32; PACKET_SIZE] = std::array::from_fn(|i| hits[i].map_or(rays[i].tfar, |h| h.t));
            // Only rays that reach the box before their closest hit so far go in: instances
            // behind the hits are skipped without carrying the rays into them, and an object no
            // ray has needed yet is built only if some ray reaches it, as a single ray would.
            let mask = entries.within(&tfar);
            if mask == 0 {
                continue;
            }
            let placed = fi.placed_at(time);
            let tree = fi.object.accel(&self.counters);
            if placed.identity && mask == all && hits.iter().all(Option::is_none) {
                // Every ray, over its whole segment, in the world's own frame: as prepared.
                tree.intersect_packet_prepared(&prepared, &mut found);
                record(hits, &found, fi, item);
                continue;
            }
            // Camera rays share their origin: it is carried into the object once.
            let origin = (!placed.identity).then(|| placed.to_object.transform_point3(rays[0].origin));
            for (i, ray) in rays.iter().enumerate() {
                // Rays that do not reach the box get an empty segment.
                let tfar = if mask & (1 << i) == 0 { ray.tnear } else { tfar[i] };
                local[i] = match origin {
                    None => prepared[i].with_tfar(tfar),
                    Some(origin) if ray.origin.to_array().map(f32::to_bits) == rays[0].origin.to_array().map(f32::to_bits) => {
                        PreparedRay::new(&Ray { origin, dir: placed.to_object.transform_vector3(ray.dir), tnear: ray.tnear, tfar })
                    }
                    Some(_) => PreparedRay::new(&Ray { tfar, ..placed.ray_to_object(ray) }),
                };
            }
            tree.intersect_packet_prepared(&local, &mut found);
            record(hits, &found, fi, item);
        }
    }

    /// Whether anything is hit in `(tnear, tfar]` at shutter time `time` (a hit that does not
    /// count, see [`Visibility`], blocks nothing).
    pub fn occluded(&self, ray: &Ray, time: f32) -> bool {
        let world = PreparedRay::new(ray);
        let blocks = |item: u32| {
            let fi = &self.instances[item as usize];
            let placed = fi.placed_at(time);
            let bvh = fi.object.accel(&self.counters);
            let local = if placed.identity { world } else { PreparedRay::new(&placed.ray_to_object(ray)) };
            if fi.filtered {
                // Only hits that count block: one any-hit walk that asks of each.
                bvh.occluded_where(&local, |h| self.admits(fi, &placed, ray, h))
            } else {
                bvh.occluded_prepared(&local)
            }
        };
        self.top.any(&world, blocks)
    }

    /// Which of up to [`PACKET_SIZE`] rays are blocked in `(tnear, tfar]` at shutter time `time`:
    /// bit `i` for `rays[i]`, exactly what [`Frame::occluded`] says of each. Rays that share
    /// their origin (shadow rays traced from a point light towards the points it lights) or
    /// their direction (shadow rays towards a distant light) walk the top level and go through
    /// each instance they touch as a packet, sharing the trees' node tests, and stop walking
    /// once all are blocked; an object is built only if a ray not yet blocked reaches its box,
    /// as for single rays.
    ///
    /// # Panics
    /// If `rays` holds more than [`PACKET_SIZE`] rays.
    pub fn occluded_many(&self, rays: &[Ray], time: f32) -> u32 {
        assert!(rays.len() <= PACKET_SIZE, "at most a packet");
        let n = rays.len();
        if n == 0 {
            return 0;
        }
        let blocked = self.occluded_packet(rays, time);
        if !self.filtered {
            return blocked;
        }
        // The packet counted every hit: a ray it found blocked may be blocked only by hits that
        // do not count (one it found open is open).
        (0..n).filter(|&i| blocked & (1 << i) != 0 && self.occluded(&rays[i], time)).fold(0, |b, i| b | 1 << i)
    }

    /// [`Frame::occluded_many`] of a non-empty packet, every hit counting.
    fn occluded_packet(&self, rays: &[Ray], time: f32) -> u32 {
        let n = rays.len();
        let all = (1u32 << n) - 1;
        let prepared = PreparedRay::packet(rays);
        if let Some((_, tree)) = self.only_in_place(&prepared[..n], rays, time) {
            return tree.map_or(0, |tree| tree.occluded_packet_prepared(&prepared[..n]));
        }
        let mut local = prepared;
        // Shadow rays towards a distant light are parallel: in each instance their direction
        // is carried into the object, and prepared, once.
        let parallel = rays.iter().all(|r| r.dir.to_array().map(f32::to_bits) == rays[0].dir.to_array().map(f32::to_bits));
        // The rays among `live` that instance `item` blocks, `live` being exactly the rays not
        // blocked yet whose segment touches its box: those traced through it together.
        let block = |item: u32, live: u32| -> u32 {
            let fi = &self.instances[item as usize];
            let placed = fi.placed_at(time);
            let tree = fi.object.accel(&self.counters);
            if placed.identity && live == all {
                // Every ray, over its whole segment, in the world's own frame: as prepared.
                return tree.occluded_packet_prepared(&prepared[..n]);
            }
            let first = (parallel && !placed.identity).then(|| PreparedRay::new(&placed.ray_to_object(&rays[0])));
            for (i, ray) in rays.iter().enumerate() {
                // Rays that are blocked already or miss the box get an empty segment.
                let tfar = if live & (1 << i) == 0 { ray.tnear } else { ray.tfar };
                local[i] = match first {
                    _ if placed.identity => prepared[i].with_tfar(tfar),
                    Some(first) => first.moved(placed.to_object.transform_point3(ray.origin), ray.tnear, tfar),
                    None => PreparedRay::new(&Ray { tfar, ..placed.ray_to_object(ray) }),
                };
            }
            tree.occluded_packet_prepared(&local[..n]) & live
        };
        // The walk leaves the rest of the top level to the rays no instance blocked yet.
        self.top.occluded_by(&prepared[..n], block)
    }

    /// For a packet of `rays`, prepared as `prepared`, in a frame whose only instance sits where
    /// its object is (a single mesh): that instance, and its tree if the packet needs it. The
    /// packet then goes straight into the tree, whose root box culls the rays that miss it; a
    /// tree not built yet is built only if some ray reaches its box. `None` for other frames.
    fn only_in_place(&self, prepared: &[PreparedRay], rays: &[Ray], time: f32) -> Option<(&FrameInstance<'a>, Option<&Bvh8>)> {
        let [only] = &self.instances[..] else { return None };
        if !only.placed_at(time).identity {
            return None;
        }
        let reached = || prepared.iter().zip(rays).any(|(p, r)| self.boxes[0].intersect(p, r.tfar).is_some());
        Some((only, (only.object.is_built() || reached()).then(|| only.object.accel(&self.counters))))
    }

    /// Everything a shader needs to know about `hit` of `ray` (at shutter time `time`).
    pub fn surface(&self, ray: &Ray, hit: &SceneHit, time: f32) -> SurfacePoint<'a> {
        let fi = &self.instances[hit.item as usize];
        let placed = fi.placed_at(time);
        let mesh = &fi.object.mesh;
        let (w, corners) = barycentrics(mesh, hit);
        let outward = placed.normal_to_world(hit.ng).normalize_or_zero();
        let front_face = outward.dot(ray.dir) < 0.0;
        let geometric_normal = if front_face { outward } else { -outward };
        let (position, local_position, position_error) = crate::spawn::hit_point(&corners.map(|i| mesh.positions[i]), w, &placed);
        let [a, b, c] = corners;
        let [w0, w1, w2] = w;
        let (shader, shader_id) = self.shader_of(fi.object, hit.prim);
        SurfacePoint {
            position,
            position_error,
            local_position,
            geometric_normal,
            front_face,
            shading_normal: shading_normal(mesh, &placed, corners, w, geometric_normal),
            color: (!mesh.colors.is_empty()).then(|| mesh.colors[a] * w0 + mesh.colors[b] * w1 + mesh.colors[c] * w2),
            uv: interpolated(&mesh.uvs, corners, w),
            uv1: interpolated(&mesh.uvs1, corners, w),
            shader,
            shader_id,
        }
    }

    /// The tangent at `hit` (at shutter time `time`) for a normal map on texture coordinates
    /// `set` (0 or 1), in the world, not normalised: the mesh's tangents interpolated or, for a
    /// mesh without them, the triangle's own from those coordinates; `w` is the handedness of
    /// the bitangent
    /// `w · n × tangent` for the outward normal `n` (an instance that mirrors the object turns
    /// it). `None` where there is none: no texture coordinates, degenerate ones, or zero
    /// tangents.
    pub fn tangent(&self, hit: &SceneHit, time: f32, set: usize) -> Option<Vec4> {
        let fi = &self.instances[hit.item as usize];
        let mesh = &fi.object.mesh;
        let (w, corners) = barycentrics(mesh, hit);
        let local = if mesh.tangents.is_empty() {
            let set = if set == 0 { &mesh.uvs } else { &mesh.uvs1 };
            let uvs = corners.map(|i| set.get(i).copied());
            let [Some(a), Some(b), Some(c)] = uvs else { return None };
            let (tangent, up) = crate::tangents::triangle_tangents(corners.map(|i| mesh.positions[i]), [a, b, c])?;
            tangent.extend(if hit.ng.cross(tangent).dot(up) < 0.0 { -1.0 } else { 1.0 })
        } else {
            let t = corners.map(|i| mesh.tangents[i]);
            // The handedness of the corner that weighs most: it is constant across a triangle
            // unless the texture is mirrored at it.
            let heaviest = (0..3).fold(0, |best, k| if w[k] > w[best] { k } else { best });
            (t[0].truncate() * w[0] + t[1].truncate() * w[1] + t[2].truncate() * w[2]).extend(t[heaviest].w.signum())
        };
        if local.truncate().length_squared() == 0.0 || !local.is_finite() {
            return None;
        }
        let placed = fi.placed_at(time);
        if placed.identity {
            return Some(local);
        }
        let mirrored = placed.to_world.matrix3.determinant() < 0.0;
        Some(placed.to_world.transform_vector3(local.truncate()).extend(if mirrored { -local.w } else { local.w }))
    }

    /// What a preview needs of `hit`: its shading normal (facing either way) and its shader.
    /// Unlike [`Frame::surface`] it computes no hit point, so a mesh without vertex normals is
    /// read only for the triangle's shader: the normal comes with the hit. Surfaces whose colour
    /// varies add [`Frame::preview_attributes`].
    #[inline(always)]
    pub fn preview(&self, hit: &SceneHit) -> PreviewPoint {
        let fi = &self.instances[hit.item as usize];
        let mesh = &fi.object.mesh;
        let normal = if mesh.normals.is_empty() {
            hit.ng
        } else {
            let (w, [a, b, c]) = barycentrics(mesh, hit);
            mesh.normals[a] * w[0] + mesh.normals[b] * w[1] + mesh.normals[c] * w[2]
        };
        PreviewPoint { normal: fi.placed.normal_to_world(normal), shader_id: fi.object.shader(hit.prim) }
    }

    /// The interpolated attributes the mesh of `hit` of `ray` has, and an approximate
    /// object-space point from the ray: what textures and vertex colours of a preview read.
    pub fn preview_attributes(&self, ray: &Ray, hit: &SceneHit) -> PreviewAttributes {
        let fi = &self.instances[hit.item as usize];
        let mesh = &fi.object.mesh;
        let (w, [a, b, c]) = barycentrics(mesh, hit);
        let position = ray.at(hit.t);
        PreviewAttributes {
            local_position: if fi.placed.identity { position } else { fi.placed.to_object.transform_point3(position) },
            color: (!mesh.colors.is_empty()).then(|| mesh.colors[a] * w[0] + mesh.colors[b] * w[1] + mesh.colors[c] * w[2]),
            uv: interpolated(&mesh.uvs, [a, b, c], w),
            uv1: interpolated(&mesh.uvs1, [a, b, c], w),
            position,
        }
    }

    /// How many units of texture coordinates `set` (0 or 1) one unit of length in the world
    /// spans on the triangle of `hit` at shutter time `time`: the square root of the ratio of
    /// the triangle's area in texture space to its area in the world, which turns a footprint
    /// in the world into one in the texture. `None` without those coordinates, or for a
    /// triangle degenerate in either space.
    pub fn texture_density(&self, hit: &SceneHit, time: f32, set: usize) -> Option<f32> {
        let fi = &self.instances[hit.item as usize];
        texture_density(&fi.object.mesh, hit.prim, &fi.placed_at(time), set)
    }

    /// The shader of triangle `prim` of `object`, as the frame resolves it, and its id (`None`
    /// for the default shader).
    fn shader_of(&self, object: &Object, prim: u32) -> (&'a Shader, Option<ShaderId>) {
        match object.shader(prim).and_then(|id| Some((self.scene.shader(id).ok()?, Some(id)))) {
            Some(found) => found,
            None => (self.scene.default_shader(), None),
        }
    }

    /// `map` of every triangle of every instance whose shader `select` picks (called once per
    /// shader an object uses, with its id, `None` for the default shader), placed in the world
    /// at the shutter's opening, in instance and triangle order; triangles of no area are left
    /// out, and those `map` turns to `None`. Lights made of geometry (emitting triangles) are
    /// gathered with it when a frame starts, so an object none of whose shaders is picked costs
    /// nothing however many triangles it has, and the rest are mapped in parallel, in chunks:
    /// a scene of a million emitting triangles must not hold every frame up on one core, nor
    /// allocate the large [`WorldTriangle`] for each at once.
    pub fn world_triangles<T: Send>(
        &self,
        select: impl Fn(Option<ShaderId>, &Shader) -> bool,
        map: impl Fn(&WorldTriangle) -> Option<T> + Sync + Send,
    ) -> Vec<T> {
        use rayon::prelude::*;
        /// Triangles one task maps: enough to make a task worth handing out.
        const CHUNK: u32 = 4096;
        // A task: an instance, the shaders picked among its object's, and a run of its triangles.
        type Chunk<'f, 'a> = (&'f FrameInstance<'a>, Vec<Option<ShaderId>>, Range<u32>);
        let mut work: Vec<Chunk<'_, 'a>> = Vec::new();
        for fi in &self.instances {
            let object = fi.object;
            let picked = |id: Option<ShaderId>| match id {
                Some(id) => self.scene.shader(id).is_ok_and(|s| select(Some(id), s)),
                None => select(None, self.scene.default_shader()),
            };
            let shaders = object.shaders_used.iter().map(|&id| Some(id)).chain(object.uses_default_shader.then_some(None));
            let chosen: Vec<Option<ShaderId>> = shaders.filter(|&id| picked(id)).collect();
            if chosen.is_empty() {
                continue;
            }
            // Only the runs of the chosen shaders, where the object keeps its runs: a mesh of a
            // million triangles with one small emitting part costs its part alone (the path
            // tracer gathers the emitters at every progressive pass).
            let runs: Option<Vec<Range<u32>>> = fi.object.shader_runs().map(|runs| runs.into_iter().filter(|(_, id)| chosen.contains(id)).map(|(r, _)| r).collect());
            let every = || std::iter::once(0..object.mesh.indices.len() as u32).collect();
            for run in runs.unwrap_or_else(every) {
                work.extend(run.clone().step_by(CHUNK as usize).map(|first| (fi, chosen.clone(), first..(first + CHUNK).min(run.end))));
            }
        }
        let map = &map;
        work.par_iter()
            .flat_map_iter(|(fi, chosen, prims)| {
                let mesh = &fi.object.mesh;
                prims.clone().filter_map(move |prim| {
                    let (_, shader_id) = self.shader_of(fi.object, prim);
                    if !chosen.contains(&shader_id) {
                        return None;
                    }
                    let local = mesh.triangle(prim);
                    let corners = local.map(|p| fi.placed.to_world.transform_point3(p));
                    let area = 0.5 * (corners[1] - corners[0]).cross(corners[2] - corners[0]).length();
                    let front = fi.placed.normal_to_world((local[1] - local[0]).cross(local[2] - local[0])).normalize_or_zero();
                    if !(area > 0.0 && area.is_finite() && front != Vec3::ZERO) {
                        return None;
                    }
                    let [a, b, c] = mesh.indices[prim as usize].map(|i| i as usize);
                    let uvs = [&mesh.uvs, &mesh.uvs1].map(|set| (!set.is_empty()).then(|| [set[a], set[b], set[c]]));
                    map(&WorldTriangle { corners, front, area, shader_id, local, uvs })
                })
            })
            .collect()
    }

    /// What camera rays that leave the scene show, as the scene sets it (`None`: the renderer
    /// decides).
    pub fn background(&self) -> Option<Background> {
        self.scene.background()
    }

    /// Every shader of the scene with its id (the scene's default shader is
    /// [`Frame::default_shader`]).
    pub fn shaders(&self) -> impl Iterator<Item = (ShaderId, &'a Shader)> + 'a {
        self.scene.shaders()
    }

    /// The shader of triangles that have none.
    pub fn default_shader(&self) -> &'a Shader {
        self.scene.default_shader()
    }

    /// The shading models of every instanced triangle, resolved through the shaders as they are
    /// now (the effect set is derived from them).
    pub fn shading_models(&self) -> Vec<ShadingModel> {
        let mut models: Vec<ShadingModel> = Vec::new();
        let mut seen_objects: HashSet<ObjectId> = HashSet::new();
        for fi in &self.instances {
            if !seen_objects.insert(fi.object_id) {
                continue;
            }
            let shaders = fi.object.shaders_used.iter().filter_map(|&s| self.scene.shader(s).ok());
            let default = fi.object.uses_default_shader.then(|| self.scene.default_shader());
            for shader in shaders.chain(default) {
                if !models.contains(&shader.class().model) {
                    models.push(shader.class().model);
                }
            }
        }
        models
    }

    /// Whether some instanced triangle's shader emits light (an `Emissive` shader, or a
    /// `PhysicallyBased` one with an emissive colour).
    pub fn has_emitters(&self) -> bool {
        self.any_instanced_shader(Shader::emits)
    }

    /// Whether some instanced triangle's shader lets light through (see [`Shader::transmits`]).
    pub fn has_transmitters(&self) -> bool {
        self.any_instanced_shader(Shader::transmits)
    }

    /// Whether `property` holds for the shader of some instanced triangle.
    fn any_instanced_shader(&self, property: fn(&Shader) -> bool) -> bool {
        self.instances.iter().any(|fi| {
            fi.object.shaders_used.iter().any(|&id| self.scene.shader(id).is_ok_and(property))
                || (fi.object.uses_default_shader && property(self.scene.default_shader()))
        })
    }

    /// Whether any instance moves during the shutter (has an end transform unlike its start).
    pub fn has_motion(&self) -> bool {
        self.instances.iter().any(|fi| fi.instance.end.is_some_and(|end| end != fi.instance.start))
    }

    /// A texture of the scene.
    pub fn texture(&self, id: crate::TextureId) -> Option<&'a crate::Texture> {
        self.scene.texture(id).ok()
    }

    /// The scene this is a frame of (what decides the integrator of a frame that names none).
    pub fn scene(&self) -> &'a Scene {
        self.scene
    }

    /// The lights, as they were when the frame started.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The camera, as it was when the frame started.
    pub fn camera(&self) -> &Camera {
        self.scene.camera()
    }

    /// The closest hit seen through pixel `(x, y)` of a `width × height` image.
    pub fn pick(&self, x: u32, y: u32, width: u32, height: u32) -> Option<SceneHit> {
        self.intersect(&self.camera().ray(x as f32 + 0.5, y as f32 + 0.5, width, height), 0.0)
    }

    /// Number of instances in the frame.
    pub fn instance_count(&self) -> usize {
        self.instances.len()
    }

    /// Seconds spent placing the instances and building the top level.
    pub fn top_level_seconds(&self) -> f64 {
        self.top_level_seconds
    }

    /// The object tree work done so far, and what was skipped.
    pub fn work(&self) -> FrameWork {
        use std::sync::atomic::Ordering::Relaxed;
        let pending: HashSet<ObjectId> =
            self.instances.iter().filter(|fi| !fi.object.is_built()).map(|fi| fi.object_id).collect();
        FrameWork {
            built: self.counters.built.load(Relaxed),
            refitted: self.counters.refitted.load(Relaxed),
            rebuilt: self.counters.rebuilt.load(Relaxed),
            skipped: pending.len() as u32,
            build_seconds: self.counters.wall_seconds(),
        }
    }
}

/// The unit shading normal at barycentrics `w` of the triangle with vertices `corners` of
/// `mesh`, on an instance placed by `placed`, turned to the side of `geometric_normal`: the
/// interpolated vertex normals, or the geometric normal if the mesh has none (or they
/// interpolate to zero).
#[inline(always)]
fn shading_normal(mesh: &crate::Mesh, placed: &Placed, corners: [usize; 3], w: [f32; 3], geometric_normal: Vec3) -> Vec3 {
    if mesh.normals.is_empty() {
        return geometric_normal;
    }
    let [a, b, c] = corners;
    let n = mesh.normals[a] * w[0] + mesh.normals[b] * w[1] + mesh.normals[c] * w[2];
    // A zero-length interpolated normal (zero normals in the file, or opposite ones cancelling)
    // shades with the triangle's own.
    let Some(n) = placed.normal_to_world(n).try_normalize() else { return geometric_normal };
    if n.dot(geometric_normal) < 0.0 { -n } else { n }
}

/// [`Frame::texture_density`] of triangle `prim` of `mesh` placed by `placed`.
fn texture_density(mesh: &crate::Mesh, prim: u32, placed: &Placed, set: usize) -> Option<f32> {
    let uvs = if set == 0 { &mesh.uvs } else { &mesh.uvs1 };
    if uvs.is_empty() {
        return None;
    }
    let [a, b, c] = mesh.indices[prim as usize].map(|i| i as usize);
    let (p, t) = ([a, b, c].map(|i| mesh.positions[i]), [a, b, c].map(|i| uvs[i]));
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let world = if placed.identity { e1.cross(e2) } else { placed.to_world.transform_vector3(e1).cross(placed.to_world.transform_vector3(e2)) }.length();
    let texture = (t[1] - t[0]).perp_dot(t[2] - t[0]).abs();
    let density = (texture / world).sqrt();
    (density.is_finite() && density > 0.0).then_some(density)
}

/// A per-vertex attribute at barycentrics `w` of the triangle with vertices `corners`, if the
/// mesh has it.
#[inline(always)]
fn interpolated(values: &[Vec2], corners: [usize; 3], w: [f32; 3]) -> Option<Vec2> {
    let [a, b, c] = corners;
    (!values.is_empty()).then(|| values[a] * w[0] + values[b] * w[1] + values[c] * w[2])
}

/// The barycentric weights of `hit`'s three vertices and their indices in `mesh`.
#[inline]
fn barycentrics(mesh: &crate::Mesh, hit: &SceneHit) -> ([f32; 3], [usize; 3]) {
    ([1.0 - hit.u - hit.v, hit.u, hit.v], mesh.indices[hit.prim as usize].map(|i| i as usize))
}

/// Merges the entries of [`Frame::intersect_many`]'s touched list that name the same instance
/// (each found by other rays): every ray that touches it, where each enters, the nearest entry.
fn merge_touched(touched: &mut Vec<Touched>) {
    touched.sort_unstable_by_key(|t| t.item);
    touched.dedup_by(|later, kept| {
        later.item == kept.item && {
            kept.nearest = kept.nearest.min(later.nearest);
            kept.entries.rays |= later.entries.rays;
            for (kept, later) in kept.entries.entry.iter_mut().zip(later.entries.entry) {
                *kept = kept.min(later);
            }
            true
        }
    });
}
