//! Importing animated glTF files: node animation, morph targets and skins arrive as the scene's
//! rig, and posing the scene moves what the file animates; malformed animations are refused
//! with the offending part named. Small files are written here; the Khronos sample assets in
//! `../shared/assets/animated/` are read where that directory exists.

use std::f32::consts::FRAC_1_SQRT_2;
use std::path::Path;

use glam::{Affine3A, Vec3};
use raystage_gltf_import::{ImportError, Limits, read, read_file};
use raystage_scene::{AnimationInfo, ObjectKind, Play, Scene};
use serde_json::{Value, json};

/// Little-endian bytes of floats.
fn floats(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A unit quad (four positions, six u16 indices) followed by `extra` floats, and a document
/// with views 0 (positions), 1 (indices) and one view per `(offset in floats, count, type)` of
/// `accessors` into the extra floats, as accessors 2, 3, ...
fn document(extra: &[f32], accessors: &[(usize, usize, &str)], mesh: Value, nodes: Value, animations: Value) -> Vec<u8> {
    let mut bin = floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0]);
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    let base = bin.len();
    bin.extend(floats(extra));
    let mut views = vec![json!({ "buffer": 0, "byteOffset": 0, "byteLength": 48 }), json!({ "buffer": 0, "byteOffset": 48, "byteLength": 12 })];
    let mut list = vec![
        json!({ "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] }),
        json!({ "bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR" }),
    ];
    for &(offset, count, ty) in accessors {
        let width = match ty {
            "SCALAR" => 1,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 16,
        };
        views.push(json!({ "buffer": 0, "byteOffset": base + 4 * offset, "byteLength": 4 * width * count }));
        let mut accessor = json!({ "bufferView": views.len() - 1, "componentType": 5126, "count": count, "type": ty });
        if views.len() == 3 && ty == "SCALAR" {
            // The first extra accessor holds keyframe times, which need their bounds.
            let times = &extra[offset..offset + count];
            accessor["min"] = json!([times[0]]);
            accessor["max"] = json!([times[count - 1]]);
        }
        list.push(accessor);
    }
    let doc = json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": views,
        "accessors": list,
        "meshes": [mesh],
        "nodes": nodes,
        "animations": animations,
        "scenes": [{ "nodes": [0] }],
        "scene": 0
    });
    raystage_gltf_import::glb(&serde_json::to_vec(&doc).unwrap(), &bin)
}

fn quad_mesh() -> Value {
    json!({ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] })
}

fn scene_of(bytes: &[u8]) -> (Scene, raystage_gltf_import::Added) {
    let import = read(bytes, None, &Limits::default()).unwrap();
    let mut scene = Scene::new();
    let added = import.add_to(&mut scene).unwrap();
    (scene, added)
}

/// A root that an animation moves (its `path`: translation or scale), with a child 1 above it;
/// both hold the quad.
fn moving_box(interpolation: &str, path: &str, times: &[f32], values: &[f32]) -> Vec<u8> {
    let mut extra = times.to_vec();
    extra.extend(values);
    let nodes = json!([{ "mesh": 0, "children": [1] }, { "mesh": 0, "translation": [0, 1, 0] }]);
    let animations = json!([{ "name": "slide", "channels": [{ "sampler": 0, "target": { "node": 0, "path": path } }],
        "samplers": [{ "input": 2, "output": 3, "interpolation": interpolation }] }]);
    document(&extra, &[(0, times.len(), "SCALAR"), (times.len(), values.len() / 3, "VEC3")], quad_mesh(), nodes, animations)
}

#[test]
fn node_animation_moves_the_instances_of_the_node_and_its_children() {
    let (mut scene, added) = scene_of(&moving_box("LINEAR", "translation", &[0.0, 1.0], &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]));
    assert_eq!(scene.animations(), [AnimationInfo { name: "slide".into(), duration: 1.0, channels: 1 }]);
    assert_eq!(added.objects.len(), 1, "the moving mesh is still one object");
    assert_eq!(scene.object_kind(added.objects[0]).unwrap(), ObjectKind::Animated);
    scene.pose(Play::Clip(0), 0.25).unwrap();
    assert_eq!(scene.transform(added.instances[0]).unwrap(), Affine3A::from_translation(Vec3::new(0.5, 0.0, 0.0)));
    assert_eq!(scene.transform(added.instances[1]).unwrap(), Affine3A::from_translation(Vec3::new(0.5, 1.0, 0.0)));
    // Past the last key the animation holds its last value.
    scene.pose(Play::All, 5.0).unwrap();
    assert_eq!(scene.transform(added.instances[0]).unwrap(), Affine3A::from_translation(Vec3::new(2.0, 0.0, 0.0)));
    assert!(scene.pose(Play::Clip(1), 0.0).is_err(), "there is one animation");
}

#[test]
fn a_file_whose_first_pose_hides_a_mesh_opens_at_rest() {
    // Scaled from 0 to 1 over 1 s: at time 0 the instances cannot be placed.
    let bytes = moving_box("LINEAR", "scale", &[0.0, 1.0], &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    let import = read(&bytes, None, &Limits::default()).unwrap();
    assert!(import.notes().iter().any(|n| n.starts_with("the scene opens in its rest pose: ")), "{:?}", import.notes());
    let mut scene = Scene::new();
    let added = import.add_to(&mut scene).unwrap();
    assert_eq!(scene.transform(added.instances[0]).unwrap(), Affine3A::IDENTITY, "at rest");
    scene.pose(Play::Clip(0), 0.5).unwrap();
    assert_eq!(scene.transform(added.instances[0]).unwrap(), Affine3A::from_scale(Vec3::splat(0.5)));
    let error = scene.pose(Play::Clip(0), 0.0).unwrap_err().to_string();
    assert!(error.contains("cannot place its meshes at time 0"), "{error}");
}

#[test]
fn step_and_cubic_spline_samplers_are_read() {
    let (mut scene, added) = scene_of(&moving_box("STEP", "translation", &[0.0, 1.0], &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]));
    scene.pose(Play::Clip(0), 0.9).unwrap();
    assert_eq!(scene.transform(added.instances[0]).unwrap().translation.x, 0.0);
    // In-tangent, value, out-tangent per key; out-tangent 3 at key 0, in-tangent 0 at key 1, over
    // 1 s: at s = 0.5, 0.5·0 + 0.125·3 + 0.5·2 − 0.125·0 = 1.375.
    let values = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let (mut scene, added) = scene_of(&moving_box("CUBICSPLINE", "translation", &[0.0, 1.0], &values));
    scene.pose(Play::Clip(0), 0.5).unwrap();
    assert!((scene.transform(added.instances[0]).unwrap().translation.x - 1.375).abs() < 1e-6);
}

#[test]
fn an_animated_node_moves_every_instance_its_gpu_instancing_places() {
    // The node slides 2 along x over a second; it places the quad twice, 5 apart.
    let extra = [0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 5.0, 0.0, 0.0];
    let nodes = json!([{ "mesh": 0, "extensions": { "EXT_mesh_gpu_instancing": { "attributes": { "TRANSLATION": 4 } } } }]);
    let animations = json!([{ "channels": [{ "sampler": 0, "target": { "node": 0, "path": "translation" } }], "samplers": [{ "input": 2, "output": 3 }] }]);
    let bytes = document(&extra, &[(0, 2, "SCALAR"), (2, 2, "VEC3"), (8, 2, "VEC3")], quad_mesh(), nodes, animations);
    let (mut scene, added) = scene_of(&bytes);
    assert_eq!(added.instances.len(), 2);
    scene.pose(Play::Clip(0), 0.5).unwrap();
    let at = |scene: &Scene, k: usize| scene.transform(added.instances[k]).unwrap().translation;
    assert_eq!((at(&scene, 0), at(&scene, 1)), (Vec3::new(1.0, 0.0, 0.0).into(), Vec3::new(6.0, 0.0, 0.0).into()));
}

#[test]
fn a_morph_target_moves_the_vertices_by_its_weight() {
    // Target 0 lifts vertex 2 by 1 in z; its weight goes from 0 to 1 over 2 s.
    let mut extra = vec![0.0, 2.0, 0.0, 1.0];
    extra.extend([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    let mesh = json!({ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1, "targets": [{ "POSITION": 4 }] }], "weights": [0.0] });
    let animations = json!([{ "channels": [{ "sampler": 0, "target": { "node": 0, "path": "weights" } }], "samplers": [{ "input": 2, "output": 3 }] }]);
    let bytes = document(&extra, &[(0, 2, "SCALAR"), (2, 2, "SCALAR"), (4, 4, "VEC3")], mesh, json!([{ "mesh": 0 }]), animations);
    let (mut scene, added) = scene_of(&bytes);
    assert_eq!(scene.object_kind(added.objects[0]).unwrap(), ObjectKind::Unstructured);
    scene.pose(Play::Clip(0), 1.0).unwrap();
    assert_eq!(scene.mesh(added.objects[0]).unwrap().positions[2], Vec3::new(1.0, 1.0, 0.5));
    scene.pose(Play::Clip(0), 0.0).unwrap();
    assert_eq!(scene.mesh(added.objects[0]).unwrap().positions[2], Vec3::new(1.0, 1.0, 0.0));
}

/// A quad skinned to two joints: vertices 0 and 1 (y = 0) to joint 0, vertices 2 and 3 (y = 1)
/// to joint 1 with the given weights; joint 1 sits at y = 1 under joint 0.
fn skinned_quad(joints: [u32; 4], top_weights: [f32; 2]) -> Vec<u8> {
    let mut extra = Vec::new();
    // Inverse bind matrices: identity, and a translation by −1 in y.
    extra.extend([1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    extra.extend([1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 1.0]);
    // Weights, VEC4 per vertex: first component for JOINTS_0's first joint.
    extra.extend([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    extra.extend([top_weights[0], 0.0, 0.0, 0.0, top_weights[1], 0.0, 0.0, 0.0]);
    // JOINTS_0 as unsigned bytes, four per vertex: each vertex's four take one float's room
    // (the accessor is retyped below).
    let joint_bytes: Vec<u8> = [[0u8, 0, 0, 0], [0, 0, 0, 0], [joints[2] as u8, 0, 0, 0], [joints[3] as u8, 0, 0, 0]].concat();
    extra.extend(joint_bytes.chunks(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])));
    let mesh = json!({ "primitives": [{ "attributes": { "POSITION": 0, "WEIGHTS_0": 3, "JOINTS_0": 4 }, "indices": 1 }] });
    let nodes = json!([{ "children": [1, 2] }, { "mesh": 0, "skin": 0 }, { "children": [3] }, { "translation": [0, 1, 0], "rotation": [0, 0, FRAC_1_SQRT_2, FRAC_1_SQRT_2] }]);
    let mut bytes = document(&extra, &[(0, 2, "MAT4"), (32, 4, "VEC4"), (48, 4, "SCALAR")], mesh, nodes, json!([]));
    // Retype accessor 4 (the joints) as unsigned bytes: patch the JSON in place.
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut doc: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    doc["accessors"][4] = json!({ "bufferView": 4, "componentType": 5121, "count": 4, "type": "VEC4" });
    doc["skins"] = json!([{ "joints": [2, 3], "inverseBindMatrices": 2 }]);
    doc.as_object_mut().unwrap().remove("animations");
    let bin = bytes.split_off(20 + json_len + 8);
    raystage_gltf_import::glb(&serde_json::to_vec(&doc).unwrap(), &bin)
}

#[test]
fn a_skin_bends_its_mesh_as_its_joints_are_posed() {
    // Joint 1 is turned 90° about z at rest: the top vertices swing about (0, 1).
    let (scene, added) = scene_of(&skinned_quad([0, 0, 1, 1], [1.0, 1.0]));
    assert_eq!(scene.object_kind(added.objects[0]).unwrap(), ObjectKind::Unstructured);
    let positions = &scene.mesh(added.objects[0]).unwrap().positions;
    // Vertex 2 (1, 1): 1 to the right of the joint, turned to 1 above it: (0, 2).
    // Vertex 3 (0, 1): at the joint, stays.
    let expected = [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 2.0, 0.0), Vec3::Y];
    for (p, e) in positions.iter().zip(expected) {
        assert!(p.abs_diff_eq(e, 1e-5), "{p} != {e}");
    }
    // Weights that sum to 2 are normalised: the same pose.
    let (scene, added) = scene_of(&skinned_quad([0, 0, 1, 1], [2.0, 2.0]));
    assert!(scene.mesh(added.objects[0]).unwrap().positions[2].abs_diff_eq(Vec3::new(0.0, 2.0, 0.0), 1e-5));
}

fn refused(bytes: &[u8]) -> ImportError {
    read(bytes, None, &Limits::default()).expect_err("refused")
}

#[test]
fn broken_animations_are_refused_with_the_part_named() {
    let joints = refused(&skinned_quad([0, 0, 1, 7], [1.0, 1.0]));
    assert!(joints.to_string().contains("joint 7"), "{joints}");
    let mismatched = refused(&moving_box("LINEAR", "translation", &[0.0, 1.0, 2.0], &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]));
    assert_eq!(mismatched.field(), Some("animations[0].samplers[0]"), "{mismatched}");
    let nan = refused(&moving_box("LINEAR", "translation", &[0.0, f32::NAN], &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]));
    assert!(nan.to_string().contains("not finite"), "{nan}");
    let backwards = refused(&moving_box("LINEAR", "translation", &[1.0, 0.0], &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]));
    assert!(backwards.to_string().contains("increase"), "{backwards}");
}

#[test]
fn what_animations_leave_out_is_a_note() {
    let bytes = moving_box("LINEAR", "translation", &[0.0, 1.0], &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]);
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut doc: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    doc["extensionsUsed"] = json!(["KHR_animation_pointer"]);
    doc["cameras"] = json!([{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1 } }]);
    doc["nodes"][1]["camera"] = json!(0);
    let import = read(&raystage_gltf_import::glb(&serde_json::to_vec(&doc).unwrap(), &bytes[20 + json_len + 8..]), None, &Limits::default()).unwrap();
    let notes = import.notes().join("\n");
    assert!(notes.contains("KHR_animation_pointer is not supported"), "{notes}");
    assert!(notes.contains("nodes[1]: animations move its camera"), "{notes}");
}

/// The Khronos sample assets, where they are.
fn asset(name: &str) -> Option<std::path::PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/animated").join(name);
    if path.exists() {
        Some(path)
    } else {
        eprintln!("skipped: {} is not there", path.display());
        None
    }
}

#[test]
fn the_khronos_samples_play() {
    for (name, kind) in [
        ("BoxAnimated.glb", ObjectKind::Animated),
        ("AnimatedMorphCube.glb", ObjectKind::Unstructured),
        ("RiggedSimple.glb", ObjectKind::Unstructured),
        ("SimpleSkin.gltf", ObjectKind::Unstructured),
        ("CesiumMan.glb", ObjectKind::Unstructured),
        ("InterpolationCubes.glb", ObjectKind::Animated),
    ] {
        let Some(path) = asset(name) else { continue };
        let import = read_file(&path, &Limits::default()).unwrap();
        assert!(!import.animations().is_empty(), "{name}");
        let mut scene = import.into_scene().unwrap();
        assert!(scene.object_ids().any(|o| scene.object_kind(o).unwrap() == kind), "{name} has an {kind:?} object");
        let snapshot = |scene: &Scene| -> Vec<(Vec<Vec3>, Affine3A)> {
            scene.instances().map(|(_, o, t)| (scene.mesh(o).unwrap().positions.clone(), t)).collect()
        };
        let start = snapshot(&scene);
        let duration = scene.animations()[0].duration;
        scene.pose(Play::Clip(0), duration * 0.37).unwrap();
        assert_ne!(snapshot(&scene), start, "{name} moves");
        scene.pose(Play::All, duration * 0.37).unwrap();
    }
}
