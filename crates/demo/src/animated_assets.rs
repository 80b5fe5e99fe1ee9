//! Animated glTF assets as Blender's Cycles and raystage both render them: three Khronos sample
//! assets (a node-animated hierarchy, a skin, morph targets; `assets/animated/`, licences in its
//! `LICENSES.md`), each wrapped in a binary glTF with a perspective camera and the scene
//! `extras` that `scripts/references/cycles_gltf.py` reads (`environment`: the radiance of a
//! uniform environment, the only light; `image_size`: the size the scene is compared at). The
//! assets' own nodes, meshes, skins and animations are kept as they are, so that Blender's glTF
//! importer and raystage's read the very same arrays; `tests/cycles_reference.rs` compares the
//! two at [`AnimatedAsset::times`].

use std::borrow::Cow;

use glam::Vec3;
use gltf::binary::Glb;
use serde_json::{Value, json};

use crate::material_scenes::look_at;

/// Radiance of the uniform environment that lights every asset (none has lights of its own).
pub const ENVIRONMENT: [f32; 3] = [1.0, 1.0, 1.0];
/// The size every asset is compared at, width and height: small, so that its references are
/// small files.
pub const SIZE: (u32, u32) = (160, 120);

/// One of the animated assets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnimatedAsset {
    /// `BoxAnimated.glb`: node animation. An inner box, inside an outer one in the rest pose,
    /// rises out of it (a translation of its grandparent) and turns half a turn about x.
    BoxAnimated,
    /// `RiggedSimple.glb`: a skin. A cylinder of two joints bends by up to 34° and back.
    RiggedSimple,
    /// `AnimatedMorphCube.glb`: morph targets. A cube's two targets (one thins it, one bevels
    /// it) blend in and out.
    AnimatedMorphCube,
}

impl AnimatedAsset {
    /// Every asset.
    pub const ALL: [AnimatedAsset; 3] = [AnimatedAsset::BoxAnimated, AnimatedAsset::RiggedSimple, AnimatedAsset::AnimatedMorphCube];

    /// The name of the asset's files (`NAME.glb`; its references `NAME_TIMEs.pfm`, see
    /// [`AnimatedAsset::reference_name`]).
    pub fn name(self) -> &'static str {
        match self {
            AnimatedAsset::BoxAnimated => "box_animated",
            AnimatedAsset::RiggedSimple => "rigged_simple",
            AnimatedAsset::AnimatedMorphCube => "animated_morph_cube",
        }
    }

    /// The two times (seconds of the asset's only animation) it is compared at, each far from
    /// the rest pose. Blender interpolates a LINEAR rotation component by component where glTF
    /// (and raystage) slerp: the box's half turn, whose keys are 180° apart, is shown only
    /// where the two agree (before its keys, and halfway between them); the skin's keys are 34°
    /// apart, where they differ by less than a tenth of a degree.
    pub fn times(self) -> [f32; 2] {
        match self {
            // Rising with no turn yet; fully up, a quarter turn.
            AnimatedAsset::BoxAnimated => [0.625, 1.875],
            // Bending; nearly fully bent.
            AnimatedAsset::RiggedSimple => [0.5, 1.0],
            // Thinned; mostly bevelled.
            AnimatedAsset::AnimatedMorphCube => [1.0, 3.0],
        }
    }

    /// The name of the reference image of the asset at `time` (without its prefix and
    /// extension): `NAME_TIMEs`, the time as `cycles_gltf.py` writes it (`0.625`, `1`).
    pub fn reference_name(self, time: f32) -> String {
        format!("{}_{time}s", self.name())
    }

    /// The asset wrapped with its camera and scene extras, as a binary glTF.
    pub fn glb(self) -> Vec<u8> {
        self.wrapped(true)
    }

    /// The same without its animations: what an importer that ignores them shows (the rest
    /// pose), which the comparison must tell apart from the animation.
    pub fn rest_pose_glb(self) -> Vec<u8> {
        self.wrapped(false)
    }

    /// The asset as `gltfpack` re-encodes it (`scripts/references/gltfpack.sh`): its vertices
    /// quantised to bytes and shorts (`KHR_mesh_quantization`), its nodes and meshes merged
    /// where they can be, and if `compressed`, its buffers compressed as well
    /// (`EXT_meshopt_compression`, with its filters); wrapped with the same camera, it shows what
    /// [`AnimatedAsset::glb`] shows.
    pub fn gltfpack_glb(self, compressed: bool) -> Vec<u8> {
        wrap(self.gltfpack_asset(compressed), self.view(), true)
    }

    /// The asset as published.
    fn asset(self) -> &'static [u8] {
        match self {
            AnimatedAsset::BoxAnimated => include_bytes!("../assets/animated/BoxAnimated.glb"),
            AnimatedAsset::RiggedSimple => include_bytes!("../assets/animated/RiggedSimple.glb"),
            AnimatedAsset::AnimatedMorphCube => include_bytes!("../assets/animated/AnimatedMorphCube.glb"),
        }
    }

    /// The asset as `gltfpack` writes it, compressed or not.
    fn gltfpack_asset(self, compressed: bool) -> &'static [u8] {
        match (self, compressed) {
            (AnimatedAsset::BoxAnimated, false) => include_bytes!("../assets/animated/gltfpack/BoxAnimated.glb"),
            (AnimatedAsset::BoxAnimated, true) => include_bytes!("../assets/animated/gltfpack/BoxAnimated.cc.glb"),
            (AnimatedAsset::RiggedSimple, false) => include_bytes!("../assets/animated/gltfpack/RiggedSimple.glb"),
            (AnimatedAsset::RiggedSimple, true) => include_bytes!("../assets/animated/gltfpack/RiggedSimple.cc.glb"),
            (AnimatedAsset::AnimatedMorphCube, false) => include_bytes!("../assets/animated/gltfpack/AnimatedMorphCube.glb"),
            (AnimatedAsset::AnimatedMorphCube, true) => include_bytes!("../assets/animated/gltfpack/AnimatedMorphCube.cc.glb"),
        }
    }

    /// The camera: its position, the point it looks at (+y up) and its vertical field of view
    /// (radians), framing the asset at both [`AnimatedAsset::times`] and in its rest pose.
    fn view(self) -> (Vec3, Vec3, f32) {
        match self {
            // The boxes span y from −0.5 to 3.02 as the inner one rises.
            AnimatedAsset::BoxAnimated => (Vec3::new(3.5, 2.5, 6.0), Vec3::new(0.0, 1.25, 0.0), 0.55),
            // The cylinder stands 9.15 tall about the origin and bends towards +z: seen from the side.
            AnimatedAsset::RiggedSimple => (Vec3::new(13.0, 2.0, 5.0), Vec3::new(0.0, 0.0, 1.0), 0.75),
            // A cube of side 2 about the origin, seen from behind the face that the second
            // target tilts up: the file leaves that face's normal as it was (its NORMAL delta
            // is 0, which glTF, and raystage, apply: 41° from the face at 3 s), where Blender
            // takes a shape key's normals from its positions.
            AnimatedAsset::AnimatedMorphCube => (Vec3::new(3.0, 2.2, -4.0), Vec3::ZERO, 0.7),
        }
    }

    fn wrapped(self, animated: bool) -> Vec<u8> {
        wrap(self.asset(), self.view(), animated)
    }
}

/// `asset` (a binary glTF) with a camera at `view` (see [`AnimatedAsset::view`]) and the scene
/// extras, without its animations unless `animated`.
fn wrap(asset: &[u8], (eye, target, yfov): (Vec3, Vec3, f32), animated: bool) -> Vec<u8> {
    let glb = Glb::from_slice(asset).expect("the checked-in assets are binary glTF");
    let mut doc: Value = serde_json::from_slice(&glb.json).expect("the checked-in assets hold JSON");
    let (width, height) = SIZE;
    let cameras = doc.as_object_mut().expect("a glTF document is an object").entry("cameras").or_insert_with(|| json!([]));
    let cameras = cameras.as_array_mut().expect("glTF's cameras are an array");
    cameras.push(json!({ "type": "perspective", "perspective": { "yfov": yfov, "aspectRatio": width as f32 / height as f32, "znear": 0.01 } }));
    let camera = cameras.len() - 1;
    let nodes = doc["nodes"].as_array_mut().expect("the assets have nodes");
    nodes.push(json!({ "name": "camera", "camera": camera, "translation": eye.to_array(), "rotation": look_at(eye, target).to_array() }));
    let node = nodes.len() - 1;
    let scene = doc["scene"].as_u64().unwrap_or(0) as usize;
    let scene = &mut doc["scenes"][scene];
    scene["nodes"].as_array_mut().expect("the assets' scenes have nodes").push(json!(node));
    scene["extras"] = json!({ "environment": ENVIRONMENT, "image_size": [width, height] });
    if !animated {
        doc.as_object_mut().expect("a glTF document is an object").remove("animations");
    }
    let json = serde_json::to_vec(&doc).expect("JSON values serialise");
    Glb { header: glb.header, json: Cow::Owned(json), bin: glb.bin }.to_vec().expect("a binary glTF writes to memory")
}

/// Joints of [`skinned_tube`], evenly spaced up its axis.
const TUBE_JOINTS: usize = 8;
/// Height and radius of [`skinned_tube`].
const TUBE_SIZE: (f32, f32) = (4.0, 0.4);

/// A skinned tube, generated to any size for the animation benchmark: `rings` rings of `sides`
/// vertices up the y axis (2 × (`rings` − 1) × `sides` triangles; 196 × 256 is 99,840), bound to a
/// chain of [`TUBE_JOINTS`] joints, each vertex to the two nearest joints by its height; one
/// LINEAR animation of two seconds sways every joint about z by ±15° in turn. A binary glTF
/// with a camera looking at it, as [`AnimatedAsset::glb`] has.
pub fn skinned_tube(rings: usize, sides: usize) -> Vec<u8> {
    let (height, radius) = TUBE_SIZE;
    let spacing = height / (TUBE_JOINTS - 1) as f32;
    let (mut positions, mut normals, mut joints, mut weights) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for ring in 0..rings {
        let y = height * ring as f32 / (rings - 1) as f32;
        let below = ((y / spacing) as usize).min(TUBE_JOINTS - 2);
        let up = y / spacing - below as f32;
        for side in 0..sides {
            let angle = std::f32::consts::TAU * side as f32 / sides as f32;
            let normal = Vec3::new(angle.cos(), 0.0, angle.sin());
            positions.push(normal * radius + Vec3::Y * y);
            normals.push(normal);
            joints.push([below as u16, below as u16 + 1, 0, 0]);
            weights.push([1.0 - up, up, 0.0, 0.0]);
        }
    }
    let mut indices: Vec<u32> = Vec::new();
    for ring in 0..rings - 1 {
        for side in 0..sides {
            let at = |r: usize, s: usize| (r * sides + s % sides) as u32;
            // Counter-clockwise seen from outside.
            indices.extend([at(ring, side), at(ring + 1, side), at(ring, side + 1)]);
            indices.extend([at(ring, side + 1), at(ring + 1, side), at(ring + 1, side + 1)]);
        }
    }
    let inverse_bind: Vec<[f32; 16]> = (0..TUBE_JOINTS).map(|k| glam::Mat4::from_translation(-Vec3::Y * spacing * k as f32).to_cols_array()).collect();
    let times = [0.0f32, 0.5, 1.0, 1.5, 2.0];
    let sway = 15f32.to_radians();
    let rotations: Vec<[f32; 4]> = [0.0, sway, 0.0, -sway, 0.0].iter().map(|&a| glam::Quat::from_rotation_z(a).to_array()).collect();

    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors) = (Vec::new(), Vec::new());
    let mut add = |bytes: &[u8], count: usize, kind: &str, component: u32, bounds: Option<(Vec3, Vec3)>| {
        views.push(json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len() }));
        bin.extend_from_slice(bytes);
        bin.resize(bin.len().next_multiple_of(4), 0);
        let mut accessor = json!({ "bufferView": views.len() - 1, "count": count, "type": kind, "componentType": component });
        if let Some((min, max)) = bounds {
            accessor["min"] = json!(min.to_array());
            accessor["max"] = json!(max.to_array());
        }
        accessors.push(accessor);
        accessors.len() - 1
    };
    let floats = |values: &[f32]| values.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>();
    let flat: Vec<f32> = positions.iter().flat_map(|p| p.to_array()).collect();
    let bounds = (Vec3::new(-radius, 0.0, -radius), Vec3::new(radius, height, radius));
    let position = add(&floats(&flat), positions.len(), "VEC3", 5126, Some(bounds));
    let flat: Vec<f32> = normals.iter().flat_map(|p| p.to_array()).collect();
    let normal = add(&floats(&flat), normals.len(), "VEC3", 5126, None);
    let joint = add(&joints.iter().flatten().flat_map(|j| j.to_le_bytes()).collect::<Vec<u8>>(), joints.len(), "VEC4", 5123, None);
    let weight = add(&floats(&weights.concat()), weights.len(), "VEC4", 5126, None);
    let index = add(&indices.iter().flat_map(|i| i.to_le_bytes()).collect::<Vec<u8>>(), indices.len(), "SCALAR", 5125, None);
    let inverse = add(&floats(&inverse_bind.concat()), TUBE_JOINTS, "MAT4", 5126, None);
    let input = add(&floats(&times), times.len(), "SCALAR", 5126, None);
    let output = add(&floats(&rotations.concat()), rotations.len(), "VEC4", 5126, None);
    // glTF asks for the bounds of an animation's times.
    accessors[input]["min"] = json!([times[0]]);
    accessors[input]["max"] = json!([times[times.len() - 1]]);

    // Node 0 holds the mesh, nodes 1.. the joint chain, the last the camera.
    let mut nodes = vec![json!({ "name": "tube", "mesh": 0, "skin": 0 })];
    for k in 0..TUBE_JOINTS {
        let child = if k + 1 < TUBE_JOINTS { json!([k + 2]) } else { json!([]) };
        nodes.push(json!({ "name": format!("joint {k}"), "translation": [0.0, if k == 0 { 0.0 } else { spacing }, 0.0], "children": child }));
    }
    let (eye, target) = (Vec3::new(0.0, 2.0, 9.0), Vec3::new(0.0, 2.0, 0.0));
    nodes.push(json!({ "name": "camera", "camera": 0, "translation": eye.to_array(), "rotation": look_at(eye, target).to_array() }));
    let (width, height_px) = SIZE;
    let document = json!({
        "asset": { "version": "2.0", "generator": "raystage-demo animated_assets skinned_tube" },
        "scene": 0,
        "scenes": [{ "nodes": [0, 1, TUBE_JOINTS + 1], "extras": { "environment": ENVIRONMENT, "image_size": [width, height_px] } }],
        "nodes": nodes,
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.6, "aspectRatio": width as f32 / height_px as f32, "znear": 0.01 } }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": position, "NORMAL": normal, "JOINTS_0": joint, "WEIGHTS_0": weight }, "indices": index }] }],
        "skins": [{ "joints": (1..=TUBE_JOINTS).collect::<Vec<_>>(), "inverseBindMatrices": inverse, "skeleton": 1 }],
        "animations": [{ "name": "sway", "samplers": (0..TUBE_JOINTS - 1).map(|_| json!({ "input": input, "output": output, "interpolation": "LINEAR" })).collect::<Vec<_>>(),
            "channels": (0..TUBE_JOINTS - 1).map(|k| json!({ "sampler": k, "target": { "node": k + 2, "path": "rotation" } })).collect::<Vec<_>>() }],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{ "byteLength": bin.len() }],
    });
    let json = serde_json::to_vec(&document).expect("JSON values serialise");
    Glb { header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 }, json: Cow::Owned(json), bin: Some(Cow::Owned(bin)) }.to_vec().expect("a binary glTF writes to memory")
}
