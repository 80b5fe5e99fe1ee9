//! The journal of a scene's edits: while it is on, every edit that succeeds is recorded as a
//! [`SceneEdit`] value, in order, and [`Scene::replay`] applies the values to another scene
//! that was equal to this one before them, which then becomes equal to it again. A cluster
//! keeps the replicas of an application's scene (the C ABI's) this way: the edits made between
//! two frames travel to every worker when the second starts, and each replays them, so every
//! rank holds the same scene (the same ids, the same trees refitted or rebuilt alike).

use glam::{Affine3A, Vec3};
use serde::{Deserialize, Serialize};

use crate::camera::Camera;
use crate::error::SceneError;
use crate::ids::{InstanceId, LightId, ObjectId, ShaderId, TextureId};
use crate::light::Light;
use crate::mesh::Mesh;
use crate::object::ObjectKind;
use crate::scene::{Background, Scene};
use crate::shader::ParamValue;
use crate::texture::Texture;

/// One edit of a scene, as the method that made it was called.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(missing_docs, reason = "each variant is the `Scene` method of the same name, its fields that method's arguments")]
pub enum SceneEdit {
    ReserveObjects { n: u32 },
    AddObject { kind: ObjectKind, mesh: Mesh },
    DefineObject { id: ObjectId, kind: ObjectKind, mesh: Mesh },
    SetPositions { id: ObjectId, positions: Vec<Vec3> },
    SetVertices { id: ObjectId, positions: Vec<Vec3>, normals: Option<Vec<Vec3>>, tangents: Option<Vec<glam::Vec4>> },
    DeleteObject { id: ObjectId },
    AddInstance { object: ObjectId, transform: Affine3A },
    SetMotion { id: InstanceId, start: Affine3A, end: Option<Affine3A> },
    RemoveInstance { id: InstanceId },
    ClearInstances,
    ReserveShaders { n: u32 },
    AddShader { class: String },
    DefineShader { id: ShaderId, class: String },
    SetParam { id: ShaderId, name: String, value: ParamValue },
    SetShaderName { id: ShaderId, name: Option<String> },
    RemoveShader { id: ShaderId },
    ReserveTextures { n: u32 },
    AddTexture { texture: Texture },
    DefineTexture { id: TextureId, texture: Texture },
    RemoveTexture { id: TextureId },
    AddLight { light: Light },
    SetLight { id: LightId, light: Light },
    RemoveLight { id: LightId },
    SetCamera { camera: Camera },
    SetBackground { background: Option<Background> },
}

/// A scene's journal: off (`None`), or the edits recorded since it was last taken. A clone of a
/// scene is a snapshot, which is not edited: it does not journal.
#[derive(Debug, Default)]
pub(crate) struct Journal(Option<Vec<SceneEdit>>);

impl Clone for Journal {
    fn clone(&self) -> Journal {
        Journal(None)
    }
}

impl Journal {
    /// Whether edits are recorded.
    pub(crate) fn is_on(&self) -> bool {
        self.0.is_some()
    }

    /// Records `edit` if the journal is on (`edit` is what [`Scene::recording`] made: `None`
    /// when it is off).
    pub(crate) fn record(&mut self, edit: Option<SceneEdit>) {
        if let (Some(edits), Some(edit)) = (&mut self.0, edit) {
            edits.push(edit);
        }
    }
}

impl Scene {
    /// Turns the journal on (recording from now on) or off (dropping what it holds).
    pub fn set_journal(&mut self, on: bool) {
        self.journal.0 = on.then(Vec::new);
    }

    /// The edits recorded since the journal was turned on or last taken, in order; empty when
    /// it is off.
    pub fn take_edits(&mut self) -> Vec<SceneEdit> {
        self.journal.0.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// `edit()` if the journal is on: what an edit method records once it has succeeded (made
    /// before, as the method consumes its arguments).
    pub(crate) fn recording(&self, edit: impl FnOnce() -> SceneEdit) -> Option<SceneEdit> {
        self.journal.is_on().then(edit)
    }

    /// Applies edits recorded on another scene, in order, by the methods that made them. The
    /// first that fails stops the replay with its error: this scene then differs from the one
    /// the edits came from (they succeeded there), which the caller must treat as a fault.
    pub fn replay(&mut self, edits: Vec<SceneEdit>) -> Result<(), SceneError> {
        for edit in edits {
            match edit {
                SceneEdit::ReserveObjects { n } => {
                    self.reserve_objects(n);
                }
                SceneEdit::AddObject { kind, mesh } => {
                    self.add_object(kind, mesh)?;
                }
                SceneEdit::DefineObject { id, kind, mesh } => self.define_object(id, kind, mesh)?,
                SceneEdit::SetPositions { id, positions } => self.set_positions(id, positions)?,
                SceneEdit::SetVertices { id, positions, normals, tangents } => self.set_vertices(id, positions, normals, tangents)?,
                SceneEdit::DeleteObject { id } => self.delete_object(id)?,
                SceneEdit::AddInstance { object, transform } => {
                    self.add_instance(object, transform)?;
                }
                SceneEdit::SetMotion { id, start, end } => self.set_motion(id, start, end)?,
                SceneEdit::RemoveInstance { id } => self.remove_instance(id)?,
                SceneEdit::ClearInstances => self.clear_instances(),
                SceneEdit::ReserveShaders { n } => {
                    self.reserve_shaders(n);
                }
                SceneEdit::AddShader { class } => {
                    self.add_shader(&class)?;
                }
                SceneEdit::DefineShader { id, class } => self.define_shader(id, &class)?,
                SceneEdit::SetParam { id, name, value } => {
                    self.set_param(id, &name, value)?;
                }
                SceneEdit::SetShaderName { id, name } => self.set_shader_name(id, name.as_deref())?,
                SceneEdit::RemoveShader { id } => self.remove_shader(id)?,
                SceneEdit::ReserveTextures { n } => {
                    self.reserve_textures(n);
                }
                SceneEdit::AddTexture { texture } => {
                    self.add_texture(texture)?;
                }
                SceneEdit::DefineTexture { id, texture } => self.define_texture(id, texture)?,
                SceneEdit::RemoveTexture { id } => self.remove_texture(id)?,
                SceneEdit::AddLight { light } => {
                    self.add_light(light)?;
                }
                SceneEdit::SetLight { id, light } => self.set_light(id, light)?,
                SceneEdit::RemoveLight { id } => self.remove_light(id)?,
                SceneEdit::SetCamera { camera } => self.set_camera(camera)?,
                SceneEdit::SetBackground { background } => self.set_background(background)?,
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::Image;

    fn square() -> Mesh {
        let positions = vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, 0.0)];
        Mesh::new(positions, vec![[0, 1, 2], [0, 2, 3]])
    }

    /// Every kind of edit, some failing (those are not recorded).
    fn edit(scene: &mut Scene) {
        let shader = scene.add_shader("Phong").unwrap();
        scene.set_param(shader, "diffuse", ParamValue::Color(Vec3::new(0.1, 0.5, 0.2))).unwrap();
        assert!(scene.set_param(shader, "no-such-parameter", ParamValue::Float(1.0)).is_ok());
        assert!(scene.add_shader("NoSuchClass").is_err());
        scene.set_shader_name(shader, Some("green")).unwrap();
        let mut mesh = square();
        mesh.shaders = vec![shader; 2];
        let object = scene.add_object(ObjectKind::Unstructured, mesh).unwrap();
        let reserved = scene.reserve_objects(2);
        scene.define_object(reserved, ObjectKind::Static, square()).unwrap();
        assert!(scene.define_object(ObjectId(99), ObjectKind::Static, square()).is_err());
        scene.set_positions(object, vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE]).unwrap();
        assert!(scene.set_positions(object, vec![Vec3::ZERO]).is_err());
        let instance = scene.add_instance(object, Affine3A::from_translation(Vec3::X)).unwrap();
        scene.add_instance(reserved, Affine3A::IDENTITY).unwrap();
        scene.set_motion(instance, Affine3A::IDENTITY, Some(Affine3A::from_translation(Vec3::Y))).unwrap();
        scene.set_transform(instance, Affine3A::from_scale(Vec3::splat(2.0))).unwrap();
        let image = Image::new(2, 1, vec![Vec3::ONE, Vec3::new(0.5, 0.0, 0.0)]).unwrap();
        let texture = scene.add_texture(Texture::Image(image.into())).unwrap();
        let first = scene.reserve_textures(1);
        scene.define_texture(first, Texture::Checker { a: Vec3::ZERO, b: Vec3::ONE, scale: 4.0 }).unwrap();
        scene.set_param(shader, "diffuse_texture", ParamValue::Texture(Some(texture))).unwrap();
        scene.remove_texture(first).unwrap();
        let light = scene.add_light(Light::Point { position: Vec3::Y, intensity: Vec3::ONE }).unwrap();
        scene.set_light(light, Light::Ambient { intensity: Vec3::splat(0.2) }).unwrap();
        let other = scene.add_light(Light::Ambient { intensity: Vec3::ONE }).unwrap();
        scene.remove_light(other).unwrap();
        let mut camera = *scene.camera();
        camera.fov_y_degrees = 30.0;
        scene.set_camera(camera).unwrap();
        scene.set_background(Some(Background::Sky)).unwrap();
        let spare = scene.add_shader("Diffuse").unwrap();
        scene.define_shader(spare, "Constant").unwrap();
        scene.remove_shader(spare).unwrap();
        scene.reserve_shaders(1);
        scene.remove_instance(instance).unwrap();
        scene.delete_object(reserved).unwrap();
    }

    #[test]
    fn replaying_the_journal_makes_an_equal_scene() {
        let mut original = Scene::new();
        original.add_object(ObjectKind::Static, square()).unwrap();
        let mut replica = original.clone();
        original.set_journal(true);
        edit(&mut original);
        let edits = original.take_edits();
        assert_eq!(edits.iter().filter(|e| matches!(e, SceneEdit::SetParam { .. })).count(), 3, "failed edits are not recorded: {edits:?}");
        assert!(!edits.iter().any(|e| matches!(e, SceneEdit::DefineObject { id: ObjectId(99), .. })));
        replica.replay(edits).unwrap();
        original.set_journal(false);
        assert_eq!(format!("{original:?}"), format!("{replica:?}"));
        assert!(original.take_edits().is_empty(), "taken, then off");
        // A clone (a snapshot) does not journal.
        let mut journalled = Scene::new();
        journalled.set_journal(true);
        let mut snapshot = journalled.clone();
        snapshot.clear_instances();
        assert!(snapshot.take_edits().is_empty());
        journalled.clear_instances();
        assert_eq!(journalled.take_edits(), vec![SceneEdit::ClearInstances]);
    }

    #[test]
    fn a_replay_that_cannot_be_applied_says_why() {
        let mut scene = Scene::new();
        let error = scene.replay(vec![SceneEdit::DeleteObject { id: ObjectId(3) }]).unwrap_err();
        assert!(matches!(error, SceneError::UnknownObject(ObjectId(3))), "{error:?}");
    }
}
