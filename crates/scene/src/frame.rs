//! A frame: the scene frozen for rendering. Starting one resolves every reference by id (frame
//! semantics), places the instances and rebuilds the top level over their world boxes; tracing
//! then builds or refits each object's tree the first time a ray reaches it.

use std::collections::HashSet;
use std::time::Instant;

use glam::{Vec2, Vec3};
use raystage_kernel::{BoxTree, PreparedRay, Ray};

use crate::camera::Camera;
use crate::ids::{InstanceId, ObjectId};
use crate::instance::{Instance, Placed, world_bounds};
use crate::light::Light;
use crate::object::{BuildCounters, Object};
use crate::scene::Scene;
use crate::shader::{Shader, ShadingModel};

/// An instance as a frame sees it.
struct FrameInstance<'a> {
    id: InstanceId,
    object_id: ObjectId,
    object: &'a Object,
    instance: Instance,
    /// The placement at shutter time 0, used by every ray of a still instance.
    placed: Placed,
}

impl FrameInstance<'_> {
    /// The placement at shutter time `time`.
    fn placed_at(&self, time: f32) -> Placed {
        if self.instance.end.is_some() && time != 0.0 { Placed::at(&self.instance, time) } else { self.placed }
    }
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
    /// The instance's position in the frame's list.
    item: u32,
}

/// What a shader needs to know about a hit point, in world space.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint<'a> {
    /// The hit point.
    pub position: Vec3,
    /// The hit point in the object's own space (where solid textures are evaluated, so that
    /// they move with the object).
    pub local_position: Vec3,
    /// Unit geometric normal, facing the side the ray came from.
    pub geometric_normal: Vec3,
    /// Whether the ray hit the triangle's front (the side its counter-clockwise winding faces,
    /// the outside of a consistently wound closed mesh).
    pub front_face: bool,
    /// Unit shading normal (interpolated vertex normals if the mesh has them), on the same side.
    pub shading_normal: Vec3,
    /// Interpolated vertex colour, if the mesh has colours.
    pub color: Option<Vec3>,
    /// Interpolated texture coordinates, if the mesh has them.
    pub uv: Option<Vec2>,
    /// The triangle's shader.
    pub shader: &'a Shader,
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
    /// Seconds spent building and refitting object trees (summed over threads).
    pub build_seconds: f64,
}

/// The scene frozen for rendering: see the module documentation.
pub struct Frame<'a> {
    scene: &'a Scene,
    instances: Vec<FrameInstance<'a>>,
    top: BoxTree,
    counters: BuildCounters,
    lights: Vec<Light>,
    top_level_seconds: f64,
}

impl<'a> Frame<'a> {
    pub(crate) fn new(scene: &'a Scene) -> Frame<'a> {
        let start = Instant::now();
        let instances: Vec<FrameInstance<'a>> = scene
            .instance_records()
            .filter_map(|(id, instance)| {
                let object = scene.object_record(instance.object)?;
                let placed = Placed::at(instance, 0.0);
                Some(FrameInstance { id, object_id: instance.object, object, instance: *instance, placed })
            })
            .collect();
        let boxes: Vec<_> = instances
            .iter()
            .map(|fi| {
                let b = world_bounds(&fi.object.bounds, &fi.instance.start);
                match fi.instance.end {
                    Some(end) => b.union(world_bounds(&fi.object.bounds, &end)),
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
            counters: BuildCounters::default(),
            lights,
            top_level_seconds: start.elapsed().as_secs_f64(),
        }
    }

    /// The closest hit of `ray` at shutter time `time` in `[0, 1]` (0 for a still frame). Ties
    /// between instances at exactly the same distance go to the earlier instance.
    pub fn intersect(&self, ray: &Ray, time: f32) -> Option<SceneHit> {
        // Prepared once: instances placed by the identity trace the world ray as it is.
        let world = PreparedRay::new(ray);
        let mut best: Option<SceneHit> = None;
        self.top.closest(&world, |item, tfar| {
            let fi = &self.instances[item as usize];
            let placed = fi.placed_at(time);
            let bvh = fi.object.accel(&self.counters);
            let found = if placed.identity {
                bvh.intersect_prepared(&world.with_tfar(tfar))
            } else {
                bvh.intersect(&Ray { tfar, ..placed.ray_to_object(ray) })
            };
            let Some(h) = found else {
                return tfar;
            };
            if best.is_none_or(|b| h.t < b.t || (h.t == b.t && item < b.item)) {
                let hit = SceneHit { t: h.t, instance: fi.id, object: fi.object_id, prim: h.prim, u: h.u, v: h.v, item };
                best = Some(hit);
            }
            best.map_or(tfar, |b| b.t)
        });
        best
    }

    /// The closest hits of many rays, `hits[i]` for `rays[i]`, at shutter time `time`: exactly
    /// what [`Frame::intersect`] returns for each.
    ///
    /// # Panics
    /// If `rays` and `hits` differ in length.
    pub fn intersect_many(&self, rays: &[Ray], hits: &mut [Option<SceneHit>], time: f32) {
        assert_eq!(rays.len(), hits.len(), "one hit slot per ray");
        for (ray, hit) in rays.iter().zip(hits) {
            *hit = self.intersect(ray, time);
        }
    }

    /// Whether anything is hit in `(tnear, tfar]` at shutter time `time`.
    pub fn occluded(&self, ray: &Ray, time: f32) -> bool {
        let world = PreparedRay::new(ray);
        self.top.any(&world, |item| {
            let fi = &self.instances[item as usize];
            let placed = fi.placed_at(time);
            let bvh = fi.object.accel(&self.counters);
            if placed.identity { bvh.occluded_prepared(&world) } else { bvh.occluded(&placed.ray_to_object(ray)) }
        })
    }

    /// Everything a shader needs to know about `hit` of `ray` (at shutter time `time`).
    pub fn surface(&self, ray: &Ray, hit: &SceneHit, time: f32) -> SurfacePoint<'a> {
        let fi = &self.instances[hit.item as usize];
        let placed = fi.placed_at(time);
        let mesh = &fi.object.mesh;
        let [a, b, c] = mesh.indices[hit.prim as usize].map(|i| i as usize);
        let w = [1.0 - hit.u - hit.v, hit.u, hit.v];
        let lerp3 = |v: &[Vec3]| v[a] * w[0] + v[b] * w[1] + v[c] * w[2];
        let [p0, p1, p2] = [a, b, c].map(|i| mesh.positions[i]);
        let outward = placed.normal_to_world((p1 - p0).cross(p2 - p0)).normalize_or_zero();
        let front_face = outward.dot(ray.dir) < 0.0;
        let geometric_normal = if front_face { outward } else { -outward };
        let shading_normal = if mesh.normals.is_empty() {
            geometric_normal
        } else {
            let n = placed.normal_to_world(lerp3(&mesh.normals)).normalize_or_zero();
            if n.dot(geometric_normal) < 0.0 { -n } else { n }
        };
        let shader = mesh.shaders.get(hit.prim as usize).and_then(|&s| self.scene.shader(s).ok()).unwrap_or(self.scene.default_shader());
        SurfacePoint {
            position: ray.at(hit.t),
            local_position: p0 * w[0] + p1 * w[1] + p2 * w[2],
            geometric_normal,
            front_face,
            shading_normal,
            color: (!mesh.colors.is_empty()).then(|| lerp3(&mesh.colors)),
            uv: (!mesh.uvs.is_empty()).then(|| mesh.uvs[a] * w[0] + mesh.uvs[b] * w[1] + mesh.uvs[c] * w[2]),
            shader,
        }
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

    /// Whether any instance moves during the shutter (has an end transform unlike its start).
    pub fn has_motion(&self) -> bool {
        self.instances.iter().any(|fi| fi.instance.end.is_some_and(|end| end != fi.instance.start))
    }

    /// A texture of the scene.
    pub fn texture(&self, id: crate::TextureId) -> Option<&'a crate::Texture> {
        self.scene.texture(id).ok()
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
            build_seconds: self.counters.nanos.load(Relaxed) as f64 * 1e-9,
        }
    }
}
