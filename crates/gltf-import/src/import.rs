//! An import: everything read from a glTF file and checked, ready to add to a scene.

use std::path::Path;

use glam::{Affine3A, Vec3};
use raystage_scene::{
    AnimationInfo, Binding, Camera, Deformer, Image, InstanceId, Light, LightId, Mesh, Node, ObjectId, ObjectKind, ParamValue, Play, Rig, Scene, Shader, ShaderId,
    Target, Texture, TextureId,
};

use crate::error::ImportError;
use crate::material::{MaterialShaders, ShaderSpec};
use crate::mesh::{Budget, Deformation, Encodings, read_mesh};
use crate::nodes::Placements;
use crate::{Limits, animation, buffers, images, nodes};

/// A glTF file read and checked: shaders, objects, instances, lights, camera and animations,
/// not yet in any scene. See the crate documentation.
#[derive(Debug)]
pub struct Import {
    shaders: Vec<ShaderSpec>,
    /// The images the shaders' textures use, each with its index in the file and whether it
    /// was decoded as colours or as data.
    images: Vec<((usize, bool), Image)>,
    /// One per glTF mesh (`None` for a mesh without triangles); `Mesh::shaders` hold indices
    /// into `shaders`.
    objects: Vec<Option<Mesh>>,
    /// Mesh, transform and node (an index into the rig's nodes) of each instance.
    instances: Vec<(usize, Affine3A, usize)>,
    /// What animates the file, if anything does. Checked by [`Rig::new`] when the file is
    /// read, with the ids it names standing for what is not in a scene yet: its nodes'
    /// instances are indices into `instances`, its deformers' objects placeholders;
    /// [`Import::add_to`] gives them their ids.
    rig: Option<Rig>,
    /// Whether the scene opens at time 0 of its first animation (else at rest: see
    /// [`read_rig`]).
    opens_posed: bool,
    /// For each instance, the deformer (an index into the rig's) that gives it an unstructured
    /// object of its own, if it is skinned or morphed.
    deformed: Vec<Option<usize>>,
    /// For each node of the rig, whether an animation moves it (or a node above it).
    moving: Vec<bool>,
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
    /// One object per glTF mesh that has triangles, but for a mesh that every node holding it
    /// skins or morphs; then one per skinned or morphed instance.
    pub objects: Vec<ObjectId>,
    /// One instance per node that holds such a mesh.
    pub instances: Vec<InstanceId>,
    /// The file's punctual lights.
    pub lights: Vec<LightId>,
}

pub(crate) fn read(bytes: &[u8], base: Option<&Path>, limits: &Limits) -> Result<Import, ImportError> {
    let gltf = parse(bytes)?;
    for (i, m) in gltf.document.materials().enumerate() {
        if let Some(cutoff) = m.alpha_cutoff().filter(|c| !(0.0..=1.0).contains(c)) {
            return Err(ImportError::invalid(format!("materials[{i}].alphaCutoff"), format!("{cutoff} is not within [0, 1]")));
        }
    }
    let buffers = buffers::load(&gltf.document, gltf.blob.as_deref(), base, limits)?;
    let mut shaders = MaterialShaders::new(&gltf.document);
    let mut budget = Budget::default();
    let encodings = Encodings::of(&gltf.document);
    let read_meshes =
        gltf.document.meshes().map(|mesh| read_mesh(&mesh, &buffers, encodings, &mut shaders, &mut budget, limits)).collect::<Result<Vec<_>, _>>()?;
    let (objects, deformations): (Vec<Option<Mesh>>, Vec<Deformation>) =
        read_meshes.into_iter().map(|m| m.map_or((None, Deformation::default()), |(mesh, d)| (Some(mesh), d))).unzip();
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
    let mut placed = nodes::place(&gltf.document, &buffers, encodings, limits)?;
    let mut notes = shaders.notes.clone();
    notes.append(&mut placed.notes);
    let instances: Vec<(usize, Affine3A, usize)> = std::mem::take(&mut placed.instances).into_iter().filter(|&(mesh, ..)| objects[mesh].is_some()).collect();
    let skipped = objects.iter().filter(|o| o.is_none()).count();
    if skipped > 0 {
        notes.push(format!("{skipped} meshes without triangles (points or lines) left out"));
    }
    let animated = read_rig(&gltf.document, &buffers, &placed, &objects, &deformations, &instances, &mut budget, limits, &mut notes)?;
    let (rig, deformed, moving, opens_posed) =
        animated.map_or((None, vec![None; instances.len()], Vec::new(), false), |a| (Some(a.rig), a.deformed, a.moving, a.opens_posed));
    Ok(Import {
        shaders: shaders.specs,
        images,
        objects,
        instances,
        rig,
        opens_posed,
        deformed,
        moving,
        lights: placed.lights,
        camera: placed.camera,
        aspect_ratio: placed.aspect_ratio,
        notes,
    })
}

/// The extensions a file may require: those the importer reads. `KHR_animation_pointer` is
/// read in part (its channels that move nodes and morph weights play; the rest is a note), which
/// shows the file as its author posed it rather than not at all.
const READ_EXTENSIONS: &[&str] = &[
    "EXT_mesh_gpu_instancing",
    "EXT_meshopt_compression",
    "EXT_texture_webp",
    "KHR_animation_pointer",
    "KHR_lights_punctual",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_materials_volume",
    "KHR_mesh_quantization",
    "KHR_meshopt_compression",
    "KHR_texture_transform",
];

/// The file parsed and checked against glTF's schema, refused if it requires an extension that
/// the importer does not read (a compressed mesh, say, which it could not decode). The gltf
/// crate's own check of `extensionsRequired` knows only the extensions that crate parses, and
/// would refuse files that require ones read here (`KHR_texture_transform`, and
/// `KHR_mesh_quantization`, which every file `gltfpack` writes requires), so the list is
/// checked here and the rest of the document validated by the crate.
fn parse(bytes: &[u8]) -> Result<gltf::Gltf, ImportError> {
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice_without_validation(bytes)?;
    let mut json = document.into_json();
    if let Some((i, name)) = json.extensions_required.iter().enumerate().find(|(_, e)| !READ_EXTENSIONS.contains(&e.as_str())) {
        return Err(ImportError::invalid(
            format!("extensionsRequired[{i}]"),
            format!("{name} is not supported: the file cannot be read without it (the extensions read are {})", READ_EXTENSIONS.join(", ")),
        ));
    }
    json.extensions_required.clear();
    prefer_webp(&mut json)?;
    Ok(gltf::Gltf { document: gltf::Document::from_json(json)?, blob })
}

/// Points every texture that has a WebP image (`EXT_texture_webp`) at it: the importer decodes
/// WebP, and the file's `source`, where it has one, is a fallback for viewers that cannot (and
/// may be absent, which glTF's schema then allows).
fn prefer_webp(json: &mut gltf::json::Root) -> Result<(), ImportError> {
    let images = json.images.len();
    for (i, texture) in json.textures.iter_mut().enumerate() {
        let Some(webp) = texture.extensions.as_ref().and_then(|e| e.others.get("EXT_texture_webp")) else { continue };
        let field = format!("textures[{i}].extensions.EXT_texture_webp.source");
        let source = webp
            .get("source")
            .and_then(serde_json::Value::as_u64)
            .and_then(|s| u32::try_from(s).ok())
            .filter(|&s| (s as usize) < images)
            .ok_or_else(|| ImportError::invalid(&field, format!("must name one of the file's {images} images")))?;
        texture.source = gltf::json::Index::new(source);
    }
    Ok(())
}

/// What animates a file (see [`Import`] for each part).
struct Animated {
    rig: Rig,
    opens_posed: bool,
    deformed: Vec<Option<usize>>,
    moving: Vec<bool>,
}

/// The file's animations, skins and morph targets as a rig, with each instance's deformer and
/// each node's motion; `None` for a file where nothing moves. Each deformed instance's copy of
/// its mesh counts against the limits, as the meshes did. The scene opens at time 0 of the
/// first animation, as a viewer opens the file (skins and morph weights apply in a file
/// without animations too); where that pose cannot place a mesh (a node scaled to zero), it
/// opens at rest, with a note, so that [`Import::add_to`] cannot fail.
#[allow(clippy::too_many_arguments, reason = "the parts of the file read so far, each read once in `read`")]
fn read_rig(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    placed: &Placements,
    objects: &[Option<Mesh>],
    deformations: &[Deformation],
    instances: &[(usize, Affine3A, usize)],
    budget: &mut Budget,
    limits: &Limits,
    notes: &mut Vec<String>,
) -> Result<Option<Animated>, ImportError> {
    if document.extensions_used().any(|e| e == "KHR_animation_pointer") {
        notes.push("KHR_animation_pointer is not supported: only channels that move nodes and morph target weights play".into());
    }
    let file_nodes: Vec<gltf::Node<'_>> = document.nodes().collect();
    let mesh_of = |k: usize| file_nodes[placed.nodes[k].index].mesh().map(|m| m.index()).filter(|&m| objects[m].is_some());
    let morph_targets: Vec<usize> = (0..placed.nodes.len()).map(|k| mesh_of(k).map_or(0, |m| deformations[m].targets.len())).collect();
    let clips = animation::read_clips(document, buffers, placed, &morph_targets, notes)?;
    let mut nodes = Vec::with_capacity(placed.nodes.len());
    for (k, p) in placed.nodes.iter().enumerate() {
        let file_node = &file_nodes[p.index];
        let targets = morph_targets[k];
        let weights = match file_node.weights().or_else(|| file_node.mesh().and_then(|m| m.weights())) {
            _ if targets == 0 => Vec::new(),
            Some(w) if w.len() == targets && w.iter().all(|w| w.is_finite()) => w.to_vec(),
            Some(w) => return Err(ImportError::invalid(format!("nodes[{}].weights", p.index), format!("has {} finite weights for {targets} morph targets", w.len()))),
            None => vec![0.0; targets],
        };
        nodes.push(Node { parent: p.parent, local: p.local, weights, instances: Vec::new() });
    }
    let mut skins = Vec::new();
    let mut skin_of_file = std::collections::HashMap::new();
    let mut deformers = Vec::new();
    let mut deformed = Vec::with_capacity(instances.len());
    for &(mesh, _, node) in instances {
        let d = &deformations[mesh];
        let file_node = &file_nodes[placed.nodes[node].index];
        let skin = match (file_node.skin(), d.per_vertex) {
            (Some(_), 0) => {
                notes.push(format!("nodes[{}]: has a skin, but meshes[{mesh}] has no JOINTS_0 and WEIGHTS_0; not skinned", placed.nodes[node].index));
                None
            }
            (Some(skin), _) => Some(match skin_of_file.get(&skin.index()) {
                Some(&s) => s,
                None => {
                    skins.push(animation::read_skin(document, skin.index(), buffers, placed)?);
                    skin_of_file.insert(skin.index(), skins.len() - 1);
                    skins.len() - 1
                }
            }),
            (None, _) => None,
        };
        if skin.is_none() && d.targets.is_empty() {
            deformed.push(None);
            continue;
        }
        if let Some(s) = skin {
            let count = skins[s].joints.len();
            if let Some(&j) = d.joints.iter().find(|&&j| j as usize >= count) {
                return Err(ImportError::invalid(format!("meshes[{mesh}]"), format!("a vertex names joint {j}, and the skin of nodes[{}] has {count} joints", placed.nodes[node].index)));
            }
        }
        let base = objects[mesh].as_ref().expect("instances of meshes without triangles were left out");
        budget.take(base.indices.len(), base.positions.len(), limits)?;
        deformed.push(Some(deformers.len()));
        deformers.push(Deformer {
            object: ObjectId(u32::MAX),
            node,
            positions: base.positions.clone(),
            normals: base.normals.clone(),
            tangents: base.tangents.clone(),
            targets: d.targets.clone(),
            binding: skin.map(|skin| Binding { skin, per_vertex: d.per_vertex, joints: d.joints.clone(), weights: d.weights.clone() }),
        });
    }
    if clips.is_empty() && deformers.is_empty() {
        return Ok(None);
    }
    let mut moving = vec![false; nodes.len()];
    for channel in clips.iter().flat_map(|c| &c.channels).filter(|c| c.target != Target::Weights) {
        moving[channel.node] = true;
    }
    for k in 0..nodes.len() {
        moving[k] |= nodes[k].parent.is_some_and(|p| moving[p]);
    }
    for (i, (&(_, _, node), d)) in instances.iter().zip(&deformed).enumerate() {
        if d.is_some() || moving[node] {
            nodes[node].instances.push(InstanceId(i as u32));
        }
    }
    let rig = Rig::new(nodes, clips, skins, deformers).map_err(|e| ImportError::invalid("animations", e.to_string()))?;
    let opens_posed = match rig.pose(opening(&rig), 0.0) {
        Ok(_) => true,
        Err(e) => {
            notes.push(format!("the scene opens in its rest pose: {e}"));
            false
        }
    };
    Ok(Some(Animated { rig, opens_posed, deformed, moving }))
}

/// What the scene opens with: the first animation, or the rest pose's skins and weights.
fn opening(rig: &Rig) -> Play {
    if rig.clips.is_empty() { Play::All } else { Play::Clip(0) }
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
    /// Triangles over all objects (each counted once however often it is instanced; a skinned
    /// or morphed instance's object of its own counts too).
    pub fn triangles(&self) -> usize {
        let triangles = |mesh: usize| self.objects[mesh].as_ref().map_or(0, |m| m.indices.len());
        let shared: usize = self.shared_objects().iter().enumerate().filter(|(_, s)| **s).map(|(k, _)| triangles(k)).sum();
        shared + self.instances.iter().zip(&self.deformed).filter(|(_, d)| d.is_some()).map(|(&(mesh, ..), _)| triangles(mesh)).sum::<usize>()
    }

    /// Number of objects that will be added.
    pub fn object_count(&self) -> usize {
        self.shared_objects().iter().filter(|&&shared| shared).count() + self.deformed.iter().flatten().count()
    }

    /// For each mesh, whether it becomes an object that its instances share: it has triangles
    /// and is not deformed in every instance it has (a deformed instance gets an object of its
    /// own; a mesh no node holds is still an object, as in a file without animations).
    fn shared_objects(&self) -> Vec<bool> {
        let mut deformed_somewhere = vec![false; self.objects.len()];
        let mut undeformed = vec![false; self.objects.len()];
        for (&(mesh, ..), deformed) in self.instances.iter().zip(&self.deformed) {
            deformed_somewhere[mesh] |= deformed.is_some();
            undeformed[mesh] |= deformed.is_none();
        }
        self.objects.iter().enumerate().map(|(k, m)| m.is_some() && (undeformed[k] || !deformed_somewhere[k])).collect()
    }

    /// The file's animations: name, duration in seconds, channels.
    pub fn animations(&self) -> Vec<AnimationInfo> {
        self.rig.as_ref().map(Rig::animations).unwrap_or_default()
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
        for &(mesh, t, _) in &self.instances {
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
        let shared = self.shared_objects();
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
        // A mesh moved by an animation is an animated object: built once, only its instances'
        // transforms change.
        let mut kinds = vec![ObjectKind::Static; self.objects.len()];
        for (&(mesh, _, node), deformed) in self.instances.iter().zip(&self.deformed) {
            if deformed.is_none() && self.moving.get(node).copied().unwrap_or(false) {
                kinds[mesh] = ObjectKind::Animated;
            }
        }
        let remap = |mesh: &Mesh| {
            let mut mesh = mesh.clone();
            mesh.shaders.iter_mut().for_each(|s| *s = added.shaders[s.0 as usize]);
            mesh
        };
        let mut objects = Vec::with_capacity(self.objects.len());
        for (k, mesh) in self.objects.iter().enumerate() {
            objects.push(match mesh {
                Some(mesh) if shared[k] => Some(scene.add_object(kinds[k], remap(mesh))?),
                _ => None,
            });
        }
        added.objects.extend(objects.iter().flatten());
        let mut rig = self.rig;
        for (&(mesh, transform, _), deformed) in self.instances.iter().zip(&self.deformed) {
            let object = match (deformed, &mut rig) {
                (Some(d), Some(rig)) => {
                    let id = scene.add_object(ObjectKind::Unstructured, remap(self.objects[mesh].as_ref().expect("instances of meshes without triangles were left out")))?;
                    rig.deformers[*d].object = id;
                    added.objects.push(id);
                    id
                }
                _ => objects[mesh].expect("an instance that is not deformed shares its mesh's object"),
            };
            added.instances.push(scene.add_instance(object, transform)?);
        }
        for light in self.lights {
            added.lights.push(scene.add_light(light)?);
        }
        if let Some(mut rig) = rig {
            for id in rig.nodes.iter_mut().flat_map(|n| &mut n.instances) {
                *id = added.instances[id.0 as usize];
            }
            let play = opening(&rig);
            scene.set_rig(rig)?;
            if self.opens_posed {
                scene.pose(play, 0.0)?;
            }
        }
        Ok(added)
    }
}
