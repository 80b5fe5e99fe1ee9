//! An import: everything read from a glTF file and checked, ready to add to a scene.

use std::path::Path;

use glam::{Affine3A, Vec3};
use raystage_scene::{Camera, Image, InstanceId, Light, LightId, Mesh, ObjectId, ObjectKind, ParamValue, Scene, Shader, ShaderId, Texture, TextureId};

use crate::error::ImportError;
use crate::material::{MaterialShaders, ShaderSpec};
use crate::mesh::{Budget, read_mesh};
use crate::{Limits, buffers, images, nodes};

/// A glTF file read and checked: shaders, objects, instances, lights and camera, not yet in any
/// scene. See the crate documentation.
#[derive(Debug)]
pub struct Import {
    shaders: Vec<ShaderSpec>,
    /// The images the shaders' textures use, each with its index in the file and whether it
    /// was decoded as colours or as data.
    images: Vec<((usize, bool), Image)>,
    /// One per glTF mesh (`None` for a mesh without triangles); `Mesh::shaders` hold indices
    /// into `shaders`.
    objects: Vec<Option<Mesh>>,
    instances: Vec<(usize, Affine3A)>,
    lights: Vec<Light>,
    camera: Option<Camera>,
    aspect_ratio: Option<f32>,
    notes: Vec<String>,
}

/// The ids an import was given in a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Added {
    /// One shader per material (and vertex-colour use) of the file.
    pub shaders: Vec<ShaderId>,
    /// One texture per image that a material's textures use (two if one image is used both as
    /// colours and as data, as the base colour and the metallic-roughness texture may share it).
    pub textures: Vec<TextureId>,
    /// One object per glTF mesh that has triangles.
    pub objects: Vec<ObjectId>,
    /// One instance per node that holds such a mesh.
    pub instances: Vec<InstanceId>,
    /// The file's punctual lights.
    pub lights: Vec<LightId>,
}

pub(crate) fn read(bytes: &[u8], base: Option<&Path>, limits: &Limits) -> Result<Import, ImportError> {
    let gltf = gltf::Gltf::from_slice(bytes)?;
    for (i, m) in gltf.document.materials().enumerate() {
        if let Some(cutoff) = m.alpha_cutoff().filter(|c| !(0.0..=1.0).contains(c)) {
            return Err(ImportError::invalid(format!("materials[{i}].alphaCutoff"), format!("{cutoff} is not within [0, 1]")));
        }
    }
    let buffers = buffers::load(&gltf.document, gltf.blob.as_deref(), base)?;
    let mut shaders = MaterialShaders::new(&gltf.document);
    let mut budget = Budget::default();
    let objects =
        gltf.document.meshes().map(|mesh| read_mesh(&mesh, &buffers, &mut shaders, &mut budget, limits)).collect::<Result<Vec<_>, _>>()?;
    for (k, spec) in shaders.specs.iter().enumerate() {
        check_shader(spec).map_err(|e| ImportError::invalid(format!("materials (shader {k})"), e.to_string()))?;
    }
    let mut used: Vec<(usize, bool)> = shaders.specs.iter().flat_map(|s| s.textures.iter().map(|t| (t.image, t.colour))).collect();
    used.sort_unstable();
    used.dedup();
    let images = images::load_all(&gltf.document, used, &buffers, base, limits)?;
    for (k, mesh) in objects.iter().enumerate() {
        if let Some(mesh) = mesh {
            mesh.validate().map_err(|e| ImportError::invalid(format!("meshes[{k}]"), e.to_string()))?;
        }
    }
    let placed = nodes::place(&gltf.document, limits)?;
    let mut notes = shaders.notes.clone();
    notes.extend(placed.notes);
    let instances: Vec<(usize, Affine3A)> = placed.instances.into_iter().filter(|&(mesh, _)| objects[mesh].is_some()).collect();
    let skipped = objects.iter().filter(|o| o.is_none()).count();
    if skipped > 0 {
        notes.push(format!("{skipped} meshes without triangles (points or lines) left out"));
    }
    Ok(Import { shaders: shaders.specs, images, objects, instances, lights: placed.lights, camera: placed.camera, aspect_ratio: placed.aspect_ratio, notes })
}

/// Checks a shader's class and parameters the way the scene will.
fn check_shader(spec: &ShaderSpec) -> Result<(), raystage_scene::SceneError> {
    let mut shader = Shader::new(spec.class)?;
    for &(name, value) in &spec.params {
        shader.set(name, value)?;
    }
    Ok(())
}

impl Import {
    /// Triangles over all objects (each counted once however often it is instanced).
    pub fn triangles(&self) -> usize {
        self.objects.iter().flatten().map(|m| m.indices.len()).sum()
    }

    /// Number of objects that will be added.
    pub fn object_count(&self) -> usize {
        self.objects.iter().flatten().count()
    }

    /// Number of instances that will be added.
    pub fn instance_count(&self) -> usize {
        self.instances.len()
    }

    /// The lights that will be added.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The file's first perspective camera, if it has one.
    pub fn camera(&self) -> Option<Camera> {
        self.camera
    }

    /// The width-to-height ratio the file's camera was authored for (glTF's optional
    /// `aspectRatio`), so that a render can keep the framing its author saw.
    pub fn aspect_ratio(&self) -> Option<f32> {
        self.aspect_ratio
    }

    /// A camera that sees every instance: from the front (+z) and a little above, 45° field of
    /// view, at the distance where the bounding sphere fills the view.
    pub fn framing_camera(&self) -> Camera {
        let (lo, hi) = self.bounds();
        if lo.cmpgt(hi).any() {
            return Camera::default();
        }
        let centre = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-3);
        let fov = 45.0f32;
        let distance = radius / (0.5 * fov.to_radians()).sin() * 1.05;
        let eye = centre + Vec3::new(0.0, 0.3, 1.0).normalize() * distance;
        Camera::look_at(eye, centre, Vec3::Y, fov).unwrap_or_default()
    }

    /// What the file had that was left out (one line each).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// World bounds of every instance: the boxes of their objects' vertices, transformed.
    fn bounds(&self) -> (Vec3, Vec3) {
        let empty = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let boxes: Vec<(Vec3, Vec3)> = self
            .objects
            .iter()
            .map(|m| m.as_ref().map_or(empty, |m| m.positions.iter().fold(empty, |(lo, hi), &p| (lo.min(p), hi.max(p)))))
            .collect();
        let mut out = empty;
        for &(mesh, t) in &self.instances {
            let (lo, hi) = boxes[mesh];
            for corner in 0..8 {
                let pick = |bit: u32, l: f32, h: f32| if corner >> bit & 1 == 0 { l } else { h };
                let p = t.transform_point3(Vec3::new(pick(0, lo.x, hi.x), pick(1, lo.y, hi.y), pick(2, lo.z, hi.z)));
                out = (out.0.min(p), out.1.max(p));
            }
        }
        out
    }

    /// A new scene holding everything, seen through the file's camera or, if it has none, a
    /// camera that frames every instance. A file with neither lights nor emitting materials is
    /// lit by the renderer's default (the sky as an environment light), not by the importer.
    pub fn into_scene(self) -> Result<Scene, ImportError> {
        let camera = self.camera.unwrap_or_else(|| self.framing_camera());
        let mut scene = Scene::new();
        self.add_to(&mut scene)?;
        scene.set_camera(camera)?;
        Ok(scene)
    }

    /// Adds everything to `scene` under new ids (the camera is left alone: set
    /// [`Import::camera`] or [`Import::framing_camera`] if wanted). Everything was checked by
    /// [`crate::read`], so this cannot fail half-way except through a bug.
    pub fn add_to(self, scene: &mut Scene) -> Result<Added, ImportError> {
        let mut added = Added::default();
        let mut textures = std::collections::HashMap::new();
        for (index, image) in self.images {
            let id = scene.add_texture(Texture::Image(image.into()))?;
            textures.insert(index, id);
            added.textures.push(id);
        }
        for spec in &self.shaders {
            let id = scene.add_shader(spec.class)?;
            scene.set_shader_name(id, spec.name.as_deref())?;
            for &(name, value) in &spec.params {
                scene.set_param(id, name, value)?;
            }
            for t in &spec.textures {
                scene.set_param(id, t.param, ParamValue::Texture(Some(textures[&(t.image, t.colour)])))?;
            }
            added.shaders.push(id);
        }
        let mut objects = Vec::with_capacity(self.objects.len());
        for mesh in self.objects {
            objects.push(match mesh {
                Some(mut mesh) => {
                    mesh.shaders.iter_mut().for_each(|s| *s = added.shaders[s.0 as usize]);
                    let id = scene.add_object(ObjectKind::Static, mesh)?;
                    added.objects.push(id);
                    Some(id)
                }
                None => None,
            });
        }
        for (mesh, transform) in self.instances {
            let object = objects[mesh].expect("instances of meshes without triangles were left out");
            added.instances.push(scene.add_instance(object, transform)?);
        }
        for light in self.lights {
            added.lights.push(scene.add_light(light)?);
        }
        Ok(added)
    }
}
