//! The node hierarchy: world transforms, and what the nodes hold (meshes become instances,
//! `KHR_lights_punctual` lights become lights, the first perspective camera becomes the camera).
//! The hierarchy itself is kept too, each node after its parent, for animations to move. A node
//! whose mesh `EXT_mesh_gpu_instancing` repeats places one instance per element of its
//! attributes, each as a child of the node that animations move with it.

use gltf::camera::Projection;
use gltf::khr_lights_punctual::Kind;
use gltf::scene::Transform;
use glam::{Affine3A, Mat4, Quat, Vec3, Vec4};
use raystage_scene::{Camera, Light, Local};

use crate::accessor::{Encoding, read_floats};
use crate::error::ImportError;
use crate::mesh::Encodings;
use crate::Limits;

/// Most levels a node hierarchy may have: a file with more is refused whole, never imported
/// with its deepest meshes left out.
pub(crate) const MAX_LEVELS: usize = 256;

/// A node of the default scene, as animations see it.
#[derive(Debug)]
pub(crate) struct Placed {
    /// Its index in the file (for one of the instances `EXT_mesh_gpu_instancing` places, the
    /// index of the node that holds the extension, its parent).
    pub index: usize,
    /// Its parent (an index into [`Placements::nodes`], before its own).
    pub parent: Option<usize>,
    /// Its transform relative to its parent.
    pub local: Local,
    /// Whether it holds the camera or a light (which animations do not move).
    pub holds_view_or_light: bool,
}

/// What the nodes place in the world.
#[derive(Debug, Default)]
pub(crate) struct Placements {
    /// Mesh index, object-to-world transform and node (an index into `nodes`) of each
    /// instance.
    pub instances: Vec<(usize, Affine3A, usize)>,
    /// The nodes reached from the roots, each after its parent.
    pub nodes: Vec<Placed>,
    /// For each node of the file, its index in `nodes` if it was reached.
    pub placed: Vec<Option<usize>>,
    /// Lights in world space.
    pub lights: Vec<Light>,
    /// The first perspective camera.
    pub camera: Option<Camera>,
    /// The width-to-height ratio that camera was authored for, if the file says.
    pub aspect_ratio: Option<f32>,
    /// What was left out, for the user.
    pub notes: Vec<String>,
}

/// Walks the default scene (or the first, or every root node if the file has no scenes).
pub(crate) fn place(document: &gltf::Document, buffers: &[Vec<u8>], encodings: Encodings, limits: &Limits) -> Result<Placements, ImportError> {
    let roots: Vec<gltf::Node<'_>> = match document.default_scene().or_else(|| document.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; document.nodes().len()];
            document.nodes().flat_map(|n| n.children()).for_each(|c| is_child[c.index()] = true);
            document.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let out = Placements { placed: vec![None; document.nodes().len()], ..Placements::default() };
    let mut walk = Walk { out, document, buffers, encodings, limits };
    for root in roots {
        walk.node(&root, None, Mat4::IDENTITY, 0)?;
    }
    Ok(walk.out)
}

struct Walk<'l> {
    /// Its `placed` are the nodes already placed: glTF gives a node one parent, so a node
    /// reached twice (a cycle, or a second parent) makes the file invalid.
    out: Placements,
    document: &'l gltf::Document,
    buffers: &'l [Vec<u8>],
    encodings: Encodings,
    limits: &'l Limits,
}

impl Walk<'_> {
    fn node(&mut self, node: &gltf::Node<'_>, parent_node: Option<usize>, parent: Mat4, depth: usize) -> Result<(), ImportError> {
        let field = format!("nodes[{}]", node.index());
        if self.out.placed[node.index()].is_some() {
            return Err(ImportError::invalid(field, "is reached twice (a cycle, or a second parent): glTF gives a node one parent"));
        }
        if depth >= MAX_LEVELS {
            return Err(ImportError::TooLarge { what: "levels of nodes", count: depth + 1, limit: MAX_LEVELS });
        }
        let this = self.out.nodes.len();
        self.out.placed[node.index()] = Some(this);
        let local = match node.transform() {
            Transform::Matrix { matrix } => Local::Matrix(Mat4::from_cols_array_2d(&matrix)),
            Transform::Decomposed { translation, rotation, scale } => {
                Local::Trs { translation: Vec3::from(translation), rotation: Quat::from_vec4(Vec4::from(rotation).normalize_or(Vec4::W)), scale: Vec3::from(scale) }
            }
        };
        let holds_view_or_light = node.light().is_some() || (self.out.camera.is_none() && node.camera().is_some());
        self.out.nodes.push(Placed { index: node.index(), parent: parent_node, local, holds_view_or_light });
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let affine = Affine3A::from_mat4(world);
        if let Some(mesh) = node.mesh() {
            match self.instancing(node, &field)? {
                None => self.instance(mesh.index(), affine, this, &field)?,
                Some(locals) => {
                    for (k, local) in locals.into_iter().enumerate() {
                        let child = self.out.nodes.len();
                        self.out.nodes.push(Placed { index: node.index(), parent: Some(this), local, holds_view_or_light: false });
                        let affine = Affine3A::from_mat4(world * local.matrix());
                        self.instance(mesh.index(), affine, child, &format!("{field}.extensions.EXT_mesh_gpu_instancing, instance {k}"))?;
                    }
                }
            }
        }
        if let Some(light) = node.light() {
            let light = punctual(&light, &affine);
            light.validate().map_err(|e| ImportError::invalid(format!("{field}.extensions.KHR_lights_punctual"), e.to_string()))?;
            self.out.lights.push(light);
        }
        if let (None, Some(camera)) = (self.out.camera, node.camera()) {
            self.camera(&camera, &affine, &field);
        }
        for child in node.children() {
            self.node(&child, Some(this), world, depth + 1)?;
        }
        Ok(())
    }

    /// Places `mesh` where `affine` says, for the node `node` (an index into `nodes`); a
    /// singular transform hides it, with a note.
    fn instance(&mut self, mesh: usize, affine: Affine3A, node: usize, field: &str) -> Result<(), ImportError> {
        if !is_invertible(&affine) {
            self.out.notes.push(format!("{field}: a singular transform hides its mesh; left out"));
            return Ok(());
        }
        if self.out.instances.len() >= self.limits.max_instances {
            return Err(ImportError::TooLarge { what: "instances", count: self.out.instances.len() + 1, limit: self.limits.max_instances });
        }
        self.out.instances.push((mesh, affine, node));
        Ok(())
    }

    /// The transforms, relative to `node`, of the instances its `EXT_mesh_gpu_instancing`
    /// places (`TRANSLATION`, `ROTATION` and `SCALE`, each absent one the identity's), if it
    /// has the extension; their number is checked against the instance limit before any is
    /// read.
    fn instancing(&self, node: &gltf::Node<'_>, field: &str) -> Result<Option<Vec<Local>>, ImportError> {
        let Some(extension) = node.extensions().and_then(|e| e.get("EXT_mesh_gpu_instancing")) else { return Ok(None) };
        let field = format!("{field}.extensions.EXT_mesh_gpu_instancing.attributes");
        let document = self.document;
        let mut count = None;
        let mut attribute = |name: &str| -> Result<Option<gltf::Accessor<'_>>, ImportError> {
            let Some(index) = extension.get("attributes").and_then(|a| a.get(name)) else { return Ok(None) };
            let accessor = index
                .as_u64()
                .and_then(|i| document.accessors().nth(usize::try_from(i).ok()?))
                .ok_or_else(|| ImportError::invalid(format!("{field}.{name}"), "names no accessor"))?;
            match count {
                Some(n) if n != accessor.count() => {
                    return Err(ImportError::invalid(format!("{field}.{name}"), format!("has {} elements, the other attributes {n}", accessor.count())));
                }
                _ => count = Some(accessor.count()),
            }
            Ok(Some(accessor))
        };
        let (translation, rotation, scale) = (attribute("TRANSLATION")?, attribute("ROTATION")?, attribute("SCALE")?);
        let count = count.ok_or_else(|| ImportError::invalid(&field, "has none of TRANSLATION, ROTATION and SCALE"))?;
        if self.out.instances.len().saturating_add(count) > self.limits.max_instances {
            return Err(ImportError::TooLarge { what: "instances", count: self.out.instances.len().saturating_add(count), limit: self.limits.max_instances });
        }
        let read = |accessor: Option<gltf::Accessor<'_>>, encoding: Encoding, name: &str, default: [f32; 4]| -> Result<Vec<[f32; 4]>, ImportError> {
            let f = format!("{field}.{name}");
            Ok(match accessor {
                None => vec![default; count],
                Some(a) if name == "ROTATION" => read_floats::<4>(&a, self.buffers, encoding, &f)?,
                Some(a) => read_floats::<3>(&a, self.buffers, encoding, &f)?.into_iter().map(|[x, y, z]| [x, y, z, 0.0]).collect(),
            })
        };
        let translations = read(translation, self.encodings.positions, "TRANSLATION", [0.0; 4])?;
        let rotations = read(rotation, Encoding::NORMALISED, "ROTATION", [0.0, 0.0, 0.0, 1.0])?;
        let scales = read(scale, self.encodings.positions, "SCALE", [1.0; 4])?;
        Ok(Some(
            (0..count)
                .map(|i| Local::Trs {
                    translation: Vec4::from(translations[i]).truncate(),
                    rotation: Quat::from_vec4(Vec4::from(rotations[i]).normalize_or(Vec4::W)),
                    scale: Vec4::from(scales[i]).truncate(),
                })
                .collect(),
        ))
    }

    /// The camera looks down the node's −z axis with its +y up.
    fn camera(&mut self, camera: &gltf::Camera<'_>, world: &Affine3A, field: &str) {
        let Projection::Perspective(p) = camera.projection() else {
            self.out.notes.push(format!("{field}: orthographic cameras are not supported; left out"));
            return;
        };
        let eye = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        match Camera::look_at(eye, eye + forward, world.transform_vector3(Vec3::Y), p.yfov().to_degrees()) {
            Ok(c) => {
                self.out.camera = Some(c);
                self.out.aspect_ratio = p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0);
            }
            Err(e) => self.out.notes.push(format!("{field}: camera left out: {e}")),
        }
    }
}

/// Whether a transform can place an instance: finite and invertible (as the scene requires).
fn is_invertible(t: &Affine3A) -> bool {
    t.is_finite() && t.matrix3.determinant().is_normal() && t.inverse().is_finite()
}

/// A punctual light in world space; its colour times its intensity is the light's intensity
/// (candela and lux taken as raystage's units, with no photometric conversion).
fn punctual(light: &gltf::khr_lights_punctual::Light<'_>, world: &Affine3A) -> Light {
    let intensity = Vec3::from(light.color()) * light.intensity();
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(Vec3::NEG_Z);
    match light.kind() {
        Kind::Directional => Light::Directional { direction, intensity },
        Kind::Point => Light::Point { position, intensity },
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            let cone_degrees = outer_cone_angle.to_degrees().clamp(1e-3, 90.0);
            Light::Spot { position, direction, intensity, cone_degrees, falloff_degrees: inner_cone_angle.to_degrees().clamp(0.0, cone_degrees) }
        }
    }
}
