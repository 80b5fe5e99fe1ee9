//! The scene: the retained description every API edits. Objects, instances, shaders and lights
//! refer to each other by id only; [`Scene::frame`] resolves the ids for rendering.

use std::sync::Arc;

use glam::{Affine3A, Vec3};

use crate::camera::Camera;
use crate::error::SceneError;
use crate::animation::Rig;
use crate::frame::Frame;
use crate::ids::{InstanceId, LightId, ObjectId, ShaderId, Table, TextureId};
use crate::instance::{Instance, validate_transform};
use crate::journal::{Journal, SceneEdit};
use crate::light::Light;
use crate::mesh::Mesh;
use crate::object::{Object, ObjectKind};
use crate::shader::{ParamValue, Shader};
use crate::texture::{Image, Texture};

/// A retained two-level scene. Every edit is checked first and either happens entirely or
/// returns an error and changes nothing.
///
/// A clone is a snapshot, and a cheap one: objects (with their trees), shaders and textures are
/// shared, and an edit copies only what it changes. A renderer that must not hold up edits
/// renders a clone (OpenRT's frame semantics: the frame sees the scene as it was when it
/// started); trees that frame builds are kept by the scene too.
#[derive(Clone, Debug)]
pub struct Scene {
    objects: Table<Arc<Object>>,
    instances: Table<Instance>,
    shaders: Table<Arc<Shader>>,
    lights: Table<Light>,
    textures: Table<Arc<Texture>>,
    camera: Camera,
    /// Shades triangles that have no shader of their own.
    default_shader: Shader,
    /// What camera rays that leave the scene show, if the scene says.
    background: Option<Background>,
    /// The edits made since the journal was last taken, if it is on (see [`crate::journal`]).
    pub(crate) journal: Journal,
    /// Its animations, if it has any (shared with its snapshots: posing edits the scene, never
    /// the rig).
    pub(crate) rig: Option<Arc<Rig>>,
    /// The animations and time the scene was last posed at (see [`Scene::posed`]).
    pub(crate) posed: Option<(crate::animation::Play, f32)>,
}

/// What camera rays that hit nothing show: a backdrop, which lights nothing (OpenGL's clear
/// colour). Light from around the scene is an environment light.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Background {
    /// A soft gradient from a pale horizon to a blue zenith.
    Sky,
    /// One colour, linear RGB.
    Color(glam::Vec3),
}

/// A colour written `R,G,B`, or one number for grey, as the command line and query strings
/// take them; `None` for anything else. The numbers are not checked: callers say which they
/// accept.
pub fn parse_color(text: &str) -> Option<glam::Vec3> {
    let numbers: Vec<f32> = text.split(',').map(|n| n.trim().parse().ok()).collect::<Option<_>>()?;
    match numbers[..] {
        [v] => Some(glam::Vec3::splat(v)),
        [r, g, b] => Some(glam::Vec3::new(r, g, b)),
        _ => None,
    }
}

impl std::str::FromStr for Background {
    type Err = SceneError;

    /// `sky`, `black`, or a linear colour: `R,G,B` or one number for grey.
    fn from_str(text: &str) -> Result<Background, SceneError> {
        let bad = || SceneError::OutOfRange { field: "background", message: format!("`{text}` is not sky, black or a colour R,G,B") };
        let background = match text {
            "sky" => Background::Sky,
            "black" => Background::Color(glam::Vec3::ZERO),
            _ => Background::Color(parse_color(text).ok_or_else(bad)?),
        };
        background.validate()?;
        Ok(background)
    }
}

impl Background {
    /// Checks a colour is finite and not negative.
    pub fn validate(&self) -> Result<(), SceneError> {
        match self {
            Background::Sky => Ok(()),
            Background::Color(c) if !c.is_finite() => Err(SceneError::NotFinite { field: "background", index: 0 }),
            Background::Color(c) if c.min_element() < 0.0 => Err(SceneError::OutOfRange { field: "background", message: "is negative".into() }),
            Background::Color(_) => Ok(()),
        }
    }
}

impl Default for Scene {
    fn default() -> Self {
        Scene::new()
    }
}

/// What an object's tree takes per triangle, for [`Scene::memory_bytes`]: an 8-wide tree's
/// triangle blocks (40 bytes a triangle when full) and nodes, rounded up for partly filled
/// blocks (measured: 50 to 70 bytes a triangle on the standard scenes).
pub const TREE_BYTES_PER_TRIANGLE: u64 = 80;

impl Scene {
    /// An empty scene with the default camera.
    pub fn new() -> Scene {
        Scene {
            objects: Table::default(),
            instances: Table::default(),
            shaders: Table::default(),
            lights: Table::default(),
            textures: Table::default(),
            camera: Camera::default(),
            default_shader: Shader::new("Diffuse").expect("Diffuse is built in"),
            background: None,
            journal: Journal::default(),
            rig: None,
            posed: None,
        }
    }

    // ----- objects -----

    /// Reserves `n` consecutive object ids (`rtGenObjects`) without defining them; returns the
    /// first.
    pub fn reserve_objects(&mut self, n: u32) -> ObjectId {
        self.journal.record(self.recording(|| SceneEdit::ReserveObjects { n }));
        ObjectId(self.objects.reserve(n))
    }

    /// Adds an object under a new id.
    pub fn add_object(&mut self, kind: ObjectKind, mesh: Mesh) -> Result<ObjectId, SceneError> {
        self.check_mesh(&mesh)?;
        self.journal.record(self.recording(|| SceneEdit::AddObject { kind, mesh: mesh.clone() }));
        Ok(ObjectId(self.objects.insert(Arc::new(Object::new(kind, mesh)))))
    }

    /// Defines a reserved object id, or redefines an existing object: every instance of it
    /// follows. For an unstructured object with the same number of triangles, the next frame
    /// refits its tree instead of rebuilding it. `kind` replaces the object's kind.
    pub fn define_object(&mut self, id: ObjectId, kind: ObjectKind, mesh: Mesh) -> Result<(), SceneError> {
        if !self.objects.is_reserved(id.0) {
            return Err(SceneError::UnknownObject(id));
        }
        self.check_mesh(&mesh)?;
        self.journal.record(self.recording(|| SceneEdit::DefineObject { id, kind, mesh: mesh.clone() }));
        match self.objects.get_mut(id.0) {
            Some(object) if object.kind == kind => Arc::make_mut(object).redefine(mesh),
            _ => {
                self.objects.set(id.0, Arc::new(Object::new(kind, mesh)));
            }
        }
        Ok(())
    }

    /// Moves an object's vertices: `positions` replaces the mesh's positions, one per vertex, and
    /// everything else stays. This is the cheap way to animate an unstructured object: its tree
    /// is refitted by the next frame that needs it.
    pub fn set_positions(&mut self, id: ObjectId, positions: Vec<glam::Vec3>) -> Result<(), SceneError> {
        self.check_vertices(id, &positions, None, None)?;
        self.journal.record(self.recording(|| SceneEdit::SetPositions { id, positions: positions.clone() }));
        let object = self.objects.get_mut(id.0).expect("checked above");
        Arc::make_mut(object).move_vertices(positions, None, None);
        Ok(())
    }

    /// Moves an object's vertices and turns its normals and tangents with them (as a skinned
    /// mesh's are): [`Scene::set_positions`] that also replaces the normals and the tangents
    /// where given (each one per vertex, as the mesh has them).
    pub fn set_vertices(&mut self, id: ObjectId, positions: Vec<Vec3>, normals: Option<Vec<Vec3>>, tangents: Option<Vec<glam::Vec4>>) -> Result<(), SceneError> {
        self.check_vertices(id, &positions, normals.as_deref(), tangents.as_deref())?;
        self.journal.record(self.recording(|| SceneEdit::SetVertices { id, positions: positions.clone(), normals: normals.clone(), tangents: tangents.clone() }));
        let object = self.objects.get_mut(id.0).expect("checked above");
        Arc::make_mut(object).move_vertices(positions, normals, tangents);
        Ok(())
    }

    fn check_vertices(&self, id: ObjectId, positions: &[Vec3], normals: Option<&[Vec3]>, tangents: Option<&[glam::Vec4]>) -> Result<(), SceneError> {
        let mesh = &self.objects.get(id.0).ok_or(SceneError::UnknownObject(id))?.mesh;
        let expected = mesh.positions.len();
        if positions.len() != expected {
            return Err(SceneError::WrongLength { field: "positions", got: positions.len(), expected });
        }
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(SceneError::NotFinite { field: "positions", index });
        }
        for (field, given, has) in [("normals", normals.map(|n| (n.len(), n.iter().all(|v| v.is_finite()))), mesh.normals.len()), ("tangents", tangents.map(|t| (t.len(), t.iter().all(|v| v.is_finite()))), mesh.tangents.len())] {
            match given {
                Some((got, _)) if got != has => return Err(SceneError::WrongLength { field, got, expected: has }),
                Some((_, false)) => return Err(SceneError::NotFinite { field, index: 0 }),
                _ => {}
            }
        }
        Ok(())
    }

    /// Deletes an object and every instance of it.
    pub fn delete_object(&mut self, id: ObjectId) -> Result<(), SceneError> {
        self.objects.take(id.0).ok_or(SceneError::UnknownObject(id))?;
        self.journal.record(self.recording(|| SceneEdit::DeleteObject { id }));
        let doomed: Vec<u32> = self.instances.iter().filter(|(_, i)| i.object == id).map(|(k, _)| k).collect();
        for k in doomed {
            self.instances.take(k);
        }
        Ok(())
    }

    /// The object's mesh.
    pub fn mesh(&self, id: ObjectId) -> Result<&Mesh, SceneError> {
        Ok(&self.object_record(id).ok_or(SceneError::UnknownObject(id))?.mesh)
    }

    /// The object's kind.
    pub fn object_kind(&self, id: ObjectId) -> Result<ObjectKind, SceneError> {
        Ok(self.object_record(id).ok_or(SceneError::UnknownObject(id))?.kind)
    }

    /// The defined objects' ids.
    pub fn object_ids(&self) -> impl Iterator<Item = ObjectId> + '_ {
        self.objects.iter().map(|(id, _)| ObjectId(id))
    }

    /// Whether the object's tree for its current geometry exists (built by an earlier frame).
    pub fn is_built(&self, id: ObjectId) -> Result<bool, SceneError> {
        Ok(self.object_record(id).ok_or(SceneError::UnknownObject(id))?.is_built())
    }

    fn check_mesh(&self, mesh: &Mesh) -> Result<(), SceneError> {
        mesh.validate()?;
        match mesh.shaders.iter().find(|s| self.shaders.get(s.0).is_none()) {
            Some(&unknown) => Err(SceneError::UnknownShader(unknown)),
            None => Ok(()),
        }
    }

    // ----- instances -----

    /// Places an instance of `object` with the object-to-world `transform`.
    pub fn add_instance(&mut self, object: ObjectId, transform: Affine3A) -> Result<InstanceId, SceneError> {
        self.object_record(object).ok_or(SceneError::UnknownObject(object))?;
        let start = validate_transform("transform", transform)?;
        self.journal.record(self.recording(|| SceneEdit::AddInstance { object, transform }));
        Ok(InstanceId(self.instances.insert(Instance { object, start, end: None })))
    }

    /// Moves an instance: its transform from now on, with no motion blur.
    pub fn set_transform(&mut self, id: InstanceId, transform: Affine3A) -> Result<(), SceneError> {
        self.set_motion(id, transform, None)
    }

    /// An instance's transform at the shutter's opening.
    pub fn transform(&self, id: InstanceId) -> Result<Affine3A, SceneError> {
        self.instances.get(id.0).map(|i| i.start).ok_or(SceneError::UnknownInstance(id))
    }

    /// The object an instance places.
    pub fn instance_object(&self, id: InstanceId) -> Result<ObjectId, SceneError> {
        self.instances.get(id.0).map(|i| i.object).ok_or(SceneError::UnknownInstance(id))
    }

    /// Moves an instance and sets its motion during the shutter: `start` at its opening, `end`
    /// (if any) at its close.
    pub fn set_motion(&mut self, id: InstanceId, start: Affine3A, end: Option<Affine3A>) -> Result<(), SceneError> {
        let start = validate_transform("transform", start)?;
        let end = end.map(|e| validate_transform("end_transform", e)).transpose()?;
        let edit = self.recording(|| SceneEdit::SetMotion { id, start, end });
        let instance = self.instances.get_mut(id.0).ok_or(SceneError::UnknownInstance(id))?;
        instance.start = start;
        instance.end = end;
        self.journal.record(edit);
        Ok(())
    }

    /// Removes an instance.
    pub fn remove_instance(&mut self, id: InstanceId) -> Result<(), SceneError> {
        self.instances.take(id.0).ok_or(SceneError::UnknownInstance(id))?;
        self.journal.record(self.recording(|| SceneEdit::RemoveInstance { id }));
        Ok(())
    }

    /// Removes every instance (`rtDeleteAllInstances`); objects stay.
    pub fn clear_instances(&mut self) {
        self.journal.record(self.recording(|| SceneEdit::ClearInstances));
        self.instances = Table::default();
    }

    /// Every instance: id, object, transform.
    pub fn instances(&self) -> impl Iterator<Item = (InstanceId, ObjectId, Affine3A)> + '_ {
        self.instances.iter().map(|(id, i)| (InstanceId(id), i.object, i.start))
    }

    // ----- shaders -----

    /// Reserves `n` consecutive shader ids (`rtGenShaders`); returns the first.
    pub fn reserve_shaders(&mut self, n: u32) -> ShaderId {
        self.journal.record(self.recording(|| SceneEdit::ReserveShaders { n }));
        ShaderId(self.shaders.reserve(n))
    }

    /// Adds a shader of class `class` under a new id.
    pub fn add_shader(&mut self, class: &str) -> Result<ShaderId, SceneError> {
        let shader = Arc::new(Shader::new(class)?);
        self.journal.record(self.recording(|| SceneEdit::AddShader { class: class.to_string() }));
        Ok(ShaderId(self.shaders.insert(shader)))
    }

    /// Defines a reserved shader id as a shader of class `class` (parameters at their defaults),
    /// or replaces an existing shader: every triangle bound to the id changes with it.
    pub fn define_shader(&mut self, id: ShaderId, class: &str) -> Result<(), SceneError> {
        if !self.shaders.is_reserved(id.0) {
            return Err(SceneError::UnknownShader(id));
        }
        self.shaders.set(id.0, Arc::new(Shader::new(class)?));
        self.journal.record(self.recording(|| SceneEdit::DefineShader { id, class: class.to_string() }));
        Ok(())
    }

    /// Writes parameter `name` of a shader. `Ok(false)`: the shader's class does not export it,
    /// and the write was ignored.
    pub fn set_param(&mut self, id: ShaderId, name: &str, value: ParamValue) -> Result<bool, SceneError> {
        if let ParamValue::Texture(Some(texture)) = value {
            self.texture(texture)?;
        }
        let exported = Arc::make_mut(self.shaders.get_mut(id.0).ok_or(SceneError::UnknownShader(id))?).set(name, value)?;
        self.journal.record(self.recording(|| SceneEdit::SetParam { id, name: name.to_string(), value }));
        Ok(exported)
    }

    /// Names a shader (see [`Shader::set_name`]).
    pub fn set_shader_name(&mut self, id: ShaderId, name: Option<&str>) -> Result<(), SceneError> {
        Arc::make_mut(self.shaders.get_mut(id.0).ok_or(SceneError::UnknownShader(id))?).set_name(name)?;
        self.journal.record(self.recording(|| SceneEdit::SetShaderName { id, name: name.map(str::to_string) }));
        Ok(())
    }

    // ----- textures -----

    /// Reserves `n` consecutive texture ids (`rtGenTextures`); returns the first.
    pub fn reserve_textures(&mut self, n: u32) -> TextureId {
        self.journal.record(self.recording(|| SceneEdit::ReserveTextures { n }));
        TextureId(self.textures.reserve(n))
    }

    /// Adds a texture.
    pub fn add_texture(&mut self, texture: Texture) -> Result<TextureId, SceneError> {
        texture.validate()?;
        self.journal.record(self.recording(|| SceneEdit::AddTexture { texture: texture.clone() }));
        Ok(TextureId(self.textures.insert(Arc::new(texture))))
    }

    /// Defines a reserved texture id, or replaces a texture: every shader and environment light
    /// using it changes with it.
    pub fn define_texture(&mut self, id: TextureId, texture: Texture) -> Result<(), SceneError> {
        if !self.textures.is_reserved(id.0) {
            return Err(SceneError::UnknownTexture(id));
        }
        texture.validate()?;
        self.journal.record(self.recording(|| SceneEdit::DefineTexture { id, texture: texture.clone() }));
        self.textures.set(id.0, Arc::new(texture));
        Ok(())
    }

    /// Replaces an existing texture: every shader and environment light using it changes with
    /// it.
    pub fn set_texture(&mut self, id: TextureId, texture: Texture) -> Result<(), SceneError> {
        self.texture(id)?;
        self.define_texture(id, texture)
    }

    /// A texture.
    pub fn texture(&self, id: TextureId) -> Result<&Texture, SceneError> {
        self.textures.get(id.0).map(|t| &**t).ok_or(SceneError::UnknownTexture(id))
    }

    /// The memory the scene takes, with every object's tree counted as built
    /// ([`TREE_BYTES_PER_TRIANGLE`] a triangle, whether a frame has built it yet or not) and
    /// every instance and light with what a frame builds for it: geometry, images, instances,
    /// the tables of lights, shaders and textures, and the rig that animates it (its node hierarchy,
    /// keyframes and deformed meshes). What a server budgets scenes by. Objects, images and the
    /// rig that snapshots share count once.
    pub fn memory_bytes(&self) -> u64 {
        let objects: u64 = self
            .objects
            .iter()
            .map(|(_, o)| {
                o.mesh.memory_bytes() + (o.cover.len() * size_of::<raystage_kernel::Aabb>()) as u64 + o.shader_runs_bytes() + o.mesh.indices.len() as u64 * TREE_BYTES_PER_TRIANGLE
            })
            .sum();
        let images: u64 = self.textures.iter().map(|(_, t)| if let Texture::Image(image) = &**t { image.memory_bytes() } else { 0 }).sum();
        // Instances are small but may be millions (a glTF file of a million nodes): their
        // records, and what each frame builds for them.
        let instances = self.instances.slot_bytes() + self.instances.count() as u64 * crate::frame::FRAME_BYTES_PER_INSTANCE as u64;
        let lights = self.lights.slot_bytes() + self.lights.count() as u64 * crate::frame::FRAME_BYTES_PER_LIGHT as u64;
        let rig = self.rig.as_ref().map_or(0, |rig| rig.memory_bytes());
        objects + images + instances + lights + rig + self.shaders.slot_bytes() + self.textures.slot_bytes()
    }

    /// Every texture with its id, in id order.
    pub fn textures(&self) -> impl Iterator<Item = (TextureId, &Texture)> + '_ {
        self.textures.iter().map(|(id, t)| (TextureId(id), &**t))
    }

    /// Removes a texture (`rtDeleteTextures`). Shaders and environment lights refer to it by id
    /// only: from the next frame on they look as if they had none. The id stays reserved:
    /// [`Scene::define_texture`] can define it again.
    pub fn remove_texture(&mut self, id: TextureId) -> Result<(), SceneError> {
        self.textures.take(id.0).ok_or(SceneError::UnknownTexture(id))?;
        self.journal.record(self.recording(|| SceneEdit::RemoveTexture { id }));
        Ok(())
    }

    /// Removes a shader (`rtDeleteShaders`). Triangles bound to it are shaded with the default
    /// shader from the next frame on, since they refer to it by id only; new geometry can no
    /// longer bind it. The id stays reserved: [`Scene::define_shader`] can define it again.
    pub fn remove_shader(&mut self, id: ShaderId) -> Result<(), SceneError> {
        self.shaders.take(id.0).ok_or(SceneError::UnknownShader(id))?;
        self.journal.record(self.recording(|| SceneEdit::RemoveShader { id }));
        Ok(())
    }

    /// A shader.
    pub fn shader(&self, id: ShaderId) -> Result<&Shader, SceneError> {
        self.shaders.get(id.0).map(|s| &**s).ok_or(SceneError::UnknownShader(id))
    }

    /// Every shader with its id, in id order.
    pub fn shaders(&self) -> impl Iterator<Item = (ShaderId, &Shader)> + '_ {
        self.shaders.iter().map(|(id, s)| (ShaderId(id), &**s))
    }

    /// The shader of triangles that have none.
    pub fn default_shader(&self) -> &Shader {
        &self.default_shader
    }

    // ----- lights and camera -----

    /// Adds a light.
    pub fn add_light(&mut self, light: Light) -> Result<LightId, SceneError> {
        self.check_light(&light)?;
        self.journal.record(self.recording(|| SceneEdit::AddLight { light }));
        Ok(LightId(self.lights.insert(light)))
    }

    /// Adds an environment light of `image`, a latitude-longitude map added as a texture, scaled
    /// by `radiance` and turned `rotate_degrees` about +y: the one way the command line and the
    /// server add an image environment (an HDR sky, the studio). The light is checked before the
    /// texture is added, so a refused one leaves no texture behind.
    pub fn add_environment_map(&mut self, image: Image, radiance: Vec3, rotate_degrees: f32) -> Result<LightId, SceneError> {
        Light::Environment { radiance, map: None, rotate_degrees }.validate()?;
        let map = self.add_texture(Texture::Image(image.into()))?;
        self.add_light(Light::Environment { radiance, map: Some(map), rotate_degrees })
    }

    /// Replaces a light.
    pub fn set_light(&mut self, id: LightId, light: Light) -> Result<(), SceneError> {
        self.check_light(&light)?;
        *self.lights.get_mut(id.0).ok_or(SceneError::UnknownLight(id))? = light;
        self.journal.record(self.recording(|| SceneEdit::SetLight { id, light }));
        Ok(())
    }

    fn check_light(&self, light: &Light) -> Result<(), SceneError> {
        light.validate()?;
        if let Light::Environment { map: Some(texture), .. } = light {
            self.texture(*texture)?;
        }
        Ok(())
    }

    /// Removes a light.
    pub fn remove_light(&mut self, id: LightId) -> Result<(), SceneError> {
        self.lights.take(id.0).ok_or(SceneError::UnknownLight(id))?;
        self.journal.record(self.recording(|| SceneEdit::RemoveLight { id }));
        Ok(())
    }

    /// Every light with its id.
    pub fn lights(&self) -> impl Iterator<Item = (LightId, &Light)> + '_ {
        self.light_records().map(|(id, l)| (LightId(id), l))
    }

    /// Sets the camera.
    pub fn set_camera(&mut self, camera: Camera) -> Result<(), SceneError> {
        camera.validate()?;
        self.camera = camera;
        self.journal.record(self.recording(|| SceneEdit::SetCamera { camera }));
        Ok(())
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Sets what camera rays that hit nothing show; `None` leaves it to the renderer (the
    /// environment if there is one, else black).
    pub fn set_background(&mut self, background: Option<Background>) -> Result<(), SceneError> {
        if let Some(b) = &background {
            b.validate()?;
        }
        self.background = background;
        self.journal.record(self.recording(|| SceneEdit::SetBackground { background }));
        Ok(())
    }

    /// What camera rays that hit nothing show, if the scene says.
    pub fn background(&self) -> Option<Background> {
        self.background
    }

    // ----- frames -----

    /// Freezes the scene for rendering: resolves every id, places the instances and builds the
    /// top level. Object trees are built (or refitted) lazily, by the first ray that needs them.
    pub fn frame(&self) -> Frame<'_> {
        Frame::new(self)
    }

    pub(crate) fn object_record(&self, id: ObjectId) -> Option<&Arc<Object>> {
        self.objects.get(id.0)
    }

    pub(crate) fn instance_records(&self) -> impl Iterator<Item = (InstanceId, &Instance)> + '_ {
        self.instances.iter().map(|(id, i)| (InstanceId(id), i))
    }

    pub(crate) fn light_records(&self) -> impl Iterator<Item = (u32, &Light)> + '_ {
        self.lights.iter()
    }
}
