//! Animated scenes after the BART benchmark (Lext, Assarsson and Möller 2000, described in the
//! seeds, docs/design/seeds.md §5): robots walking through a city (hierarchical motion), a museum
//! of triangles morphing from a cloud into a sphere (unstructured motion), and a terrain covered
//! with hundreds of instanced trees. Each is procedural, deterministic, and described independently
//! of any renderer, so that the benchmark can drive raystage and Embree with the same frames.

mod museum;
mod parts;
mod robots;
mod terrain;

use glam::{Affine3A, Vec3};
use raystage_scene::{Background, Camera, InstanceId, Light, Mesh as SceneMesh, ObjectId, ObjectKind, Scene, SceneError};

pub use museum::Museum;
pub use robots::Robots;
pub use terrain::Terrain;

use crate::Mesh;

/// An object of an animated scene: how it changes, and its geometry at frame 0.
pub struct AnimatedObject {
    /// Static, animated (moved by instances only) or unstructured (its vertices move).
    pub kind: ObjectKind,
    /// The geometry at frame 0.
    pub mesh: Mesh,
}

/// The view of an animated scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
    /// Direction the sunlight travels in.
    pub sun: Vec3,
}

/// An animated scene: objects defined once, instances placed every frame, and for unstructured
/// objects new vertex positions every frame.
pub trait Animation: Sync {
    /// Short name, as on the command line.
    fn name(&self) -> String;
    /// The objects (their index is their id in [`Animation::instances`]).
    fn objects(&self) -> Vec<AnimatedObject>;
    /// The instances at frame `frame`: object index and object-to-world transform. The same
    /// number of instances, in the same order, every frame.
    fn instances(&self, frame: u32) -> Vec<(usize, Affine3A)>;
    /// New vertex positions of the unstructured objects at frame `frame` (same vertex count).
    fn deform(&self, frame: u32) -> Vec<(usize, Vec<Vec3>)>;
    /// Camera and sun.
    fn view(&self) -> View;
}

/// An animation loaded into a retained scene, ready to be advanced frame by frame.
pub struct Staged {
    /// The scene: objects coloured by index (the first one grey), the view's camera and sun.
    pub scene: Scene,
    objects: Vec<ObjectId>,
    instances: Vec<InstanceId>,
}

impl Staged {
    /// Loads `animation` at frame 0.
    pub fn new(animation: &dyn Animation) -> Result<Staged, SceneError> {
        let mut scene = Scene::new();
        let mut objects = Vec::new();
        for (k, object) in animation.objects().into_iter().enumerate() {
            let albedo = if k == 0 { Vec3::splat(0.6) } else { crate::scenes::palette(k as f32 * crate::scenes::HUE_STEP) };
            let shader = crate::scenes::diffuse(&mut scene, albedo)?;
            let mesh = SceneMesh { positions: object.mesh.vertices, indices: object.mesh.indices, ..SceneMesh::default() };
            objects.push(scene.add_object(object.kind, mesh.with_shader(shader))?);
        }
        let instances = animation
            .instances(0)
            .into_iter()
            .map(|(object, t)| scene.add_instance(objects[object], t))
            .collect::<Result<Vec<_>, _>>()?;
        let view = animation.view();
        scene.set_camera(Camera::look_at(view.eye, view.target, Vec3::Y, view.fov_y_degrees)?)?;
        // Outdoors: the sky behind, as a backdrop (the sun and fill light it).
        scene.set_background(Some(Background::Sky))?;
        scene.add_light(Light::Directional { direction: view.sun, intensity: Vec3::splat(0.9 * std::f32::consts::PI) })?;
        scene.add_light(Light::Directional { direction: Vec3::new(0.4, -0.5, 1.0), intensity: Vec3::splat(0.25 * std::f32::consts::PI) })?;
        Ok(Staged { scene, objects, instances })
    }

    /// Moves the scene to a frame of the animation: `instances` and `deformed` as returned by
    /// [`Animation::instances`] and [`Animation::deform`] for that frame.
    pub fn advance(&mut self, instances: &[(usize, Affine3A)], deformed: Vec<(usize, Vec<Vec3>)>) -> Result<(), SceneError> {
        for (&id, &(_, t)) in self.instances.iter().zip(instances) {
            self.scene.set_transform(id, t)?;
        }
        for (object, positions) in deformed {
            self.scene.set_positions(self.objects[object], positions)?;
        }
        Ok(())
    }
}

/// Every built-in demo, by name: the two standard scenes, the three animated ones and the two
/// shading showcases.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Demo {
    /// A standard benchmark scene.
    Standard(crate::StandardScene),
    /// [`crate::shading::cornell_room`].
    Cornell,
    /// [`crate::shading::materials`].
    Materials,
    /// [`Robots`].
    Robots,
    /// [`Museum`] with this many moving triangles.
    Museum(usize),
    /// [`Terrain`].
    Terrain,
}

impl Demo {
    /// The names [`Demo::from_name`] accepts.
    pub const NAMES: &'static str = "spheres, sphere, soup, cornell, materials, robots, museum, museum-<triangles>, terrain";

    /// Parses a demo name (see [`Demo::NAMES`]); `museum` has 16,384 triangles.
    pub fn from_name(name: &str) -> Option<Demo> {
        if let Some(standard) = crate::StandardScene::from_name(name) {
            return Some(Demo::Standard(standard));
        }
        match name {
            "cornell" => Some(Demo::Cornell),
            "materials" => Some(Demo::Materials),
            "robots" => Some(Demo::Robots),
            "museum" => Some(Demo::Museum(16_384)),
            "terrain" => Some(Demo::Terrain),
            _ => name.strip_prefix("museum-").and_then(|n| n.parse().ok()).filter(|&n| (1..=4_000_000).contains(&n)).map(Demo::Museum),
        }
    }

    /// The demo's name.
    pub fn name(&self) -> String {
        match self {
            Demo::Standard(s) => s.name().into(),
            Demo::Cornell => "cornell".into(),
            Demo::Materials => "materials".into(),
            Demo::Robots => "robots".into(),
            Demo::Museum(n) => format!("museum-{n}"),
            Demo::Terrain => "terrain".into(),
        }
    }

    /// The animation, for the animated demos.
    pub fn animation(&self) -> Option<Box<dyn Animation>> {
        match *self {
            Demo::Standard(_) | Demo::Cornell | Demo::Materials => None,
            Demo::Robots => Some(Box::new(Robots)),
            Demo::Museum(n) => Some(Box::new(Museum::new(n))),
            Demo::Terrain => Some(Box::new(Terrain)),
        }
    }

    /// The demo as a retained scene at frame `frame` (still scenes ignore the frame).
    pub fn scene(&self, frame: u32) -> Result<Scene, SceneError> {
        let Some(animation) = self.animation() else {
            return match self {
                Demo::Standard(standard) => standard.scene(),
                Demo::Cornell => crate::shading::cornell_room(),
                _ => crate::shading::materials(),
            };
        };
        let mut staged = Staged::new(animation.as_ref())?;
        if frame > 0 {
            staged.advance(&animation.instances(frame), animation.deform(frame))?;
        }
        Ok(staged.scene)
    }
}

/// A standard scene as an animation that never moves: one static object, one instance, the
/// probe's camera. Lets still and animated scenes be measured by the same harness.
#[derive(Clone, Copy, Debug)]
pub struct Still(pub crate::StandardScene);

impl Animation for Still {
    fn name(&self) -> String {
        self.0.name().into()
    }

    fn objects(&self) -> Vec<AnimatedObject> {
        vec![AnimatedObject { kind: ObjectKind::Static, mesh: self.0.mesh() }]
    }

    fn instances(&self, _frame: u32) -> Vec<(usize, Affine3A)> {
        vec![(0, Affine3A::IDENTITY)]
    }

    fn deform(&self, _frame: u32) -> Vec<(usize, Vec<Vec3>)> {
        Vec::new()
    }

    fn view(&self) -> View {
        let (eye, target) = match self.0 {
            crate::StandardScene::Spheres => (Vec3::new(0.0, 8.0, 8.0), Vec3::new(0.0, 0.0, -10.0)),
            crate::StandardScene::Soup => (Vec3::new(0.5, 0.5, 2.5), Vec3::new(0.5, 0.5, 0.5)),
        };
        View { eye, target, fov_y_degrees: 60.0, sun: Vec3::new(-0.5, -1.0, -0.4) }
    }
}

/// An animation's first frame baked into world space: every instance's triangles copied into one
/// static object under one identity instance. The same geometry as the animation without the
/// instancing, so that a benchmark can tell what instancing costs from what the geometry does.
pub struct Baked {
    name: String,
    mesh: Mesh,
    view: View,
}

impl Baked {
    /// Bakes frame 0 of `animation`.
    pub fn new(animation: &dyn Animation) -> Baked {
        let objects = animation.objects();
        let mut mesh = Mesh::default();
        for (object, t) in animation.instances(0) {
            mesh.append(&objects[object].mesh, t);
        }
        Baked { name: format!("{}-baked", animation.name()), mesh, view: animation.view() }
    }
}

impl Animation for Baked {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn objects(&self) -> Vec<AnimatedObject> {
        vec![AnimatedObject { kind: ObjectKind::Static, mesh: self.mesh.clone() }]
    }

    fn instances(&self, _frame: u32) -> Vec<(usize, Affine3A)> {
        vec![(0, Affine3A::IDENTITY)]
    }

    fn deform(&self, _frame: u32) -> Vec<(usize, Vec<Vec3>)> {
        Vec::new()
    }

    fn view(&self) -> View {
        self.view
    }
}
