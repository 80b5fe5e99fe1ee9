//! Importing small glTF files written by hand in the tests: geometry, transforms, materials,
//! cameras and lights arrive in the scene; malformed files are refused with the offending part
//! named, and change nothing.

use base64::Engine;
use glam::{Affine3A, Vec3};
use raystage_gltf_import::{ImportError, Limits, read};
use raystage_scene::{Light, ParamValue, Scene, Texture};
use serde_json::{Value, json};

/// A unit quad in the xy plane (two triangles) as a buffer: four positions, then six u16
/// indices.
fn quad_buffer() -> Vec<u8> {
    let mut bytes = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]] {
        p.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bytes.extend(i.to_le_bytes());
    }
    bytes
}

/// A glTF document around [`quad_buffer`]: one mesh with material 0, nodes as given.
fn quad_gltf(buffer_uri: Option<String>, materials: Value, nodes: Value) -> Value {
    let len = quad_buffer().len();
    let mut buffer = json!({ "byteLength": len });
    if let Some(uri) = buffer_uri {
        buffer["uri"] = json!(uri);
    }
    json!({
        "asset": { "version": "2.0" },
        "buffers": [buffer],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 48 },
            { "buffer": 0, "byteOffset": 48, "byteLength": 12 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
            { "bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR" }
        ],
        "materials": materials,
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1, "material": 0 }] }],
        "nodes": nodes,
        "scenes": [{ "nodes": [0] }],
        "scene": 0
    })
}

fn data_uri(bytes: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

fn red() -> Value {
    json!([{ "pbrMetallicRoughness": { "baseColorFactor": [1, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 1 } }])
}

/// A binary glTF of `document` and `bin`.
fn glb(document: &Value, bin: &[u8]) -> Vec<u8> {
    raystage_gltf_import::glb(&serde_json::to_vec(document).unwrap(), bin)
}

fn import(document: &Value) -> Result<raystage_gltf_import::Import, ImportError> {
    read(&serde_json::to_vec(document).unwrap(), None, &Limits::default())
}

#[test]
fn a_node_hierarchy_becomes_instances_with_world_transforms() {
    let nodes = json!([
        { "translation": [10, 0, 0], "children": [1], "mesh": 0 },
        { "translation": [0, 5, 0], "scale": [2, 2, 2], "mesh": 0 }
    ]);
    let file = import(&quad_gltf(Some(data_uri(&quad_buffer())), red(), nodes)).unwrap();
    assert_eq!((file.object_count(), file.instance_count(), file.triangles()), (1, 2, 2));
    let mut scene = Scene::new();
    let added = file.add_to(&mut scene).unwrap();
    assert_eq!(added.objects.len(), 1);
    let transforms: Vec<Affine3A> = scene.instances().map(|(_, _, t)| t).collect();
    assert_eq!(transforms[0].transform_point3(Vec3::ZERO), Vec3::new(10.0, 0.0, 0.0));
    // The child is placed in its parent's space: translated, then scaled by 2.
    assert_eq!(transforms[1].transform_point3(Vec3::ONE), Vec3::new(12.0, 7.0, 2.0));
    let mesh = scene.mesh(added.objects[0]).unwrap();
    assert_eq!(mesh.indices, vec![[0, 1, 2], [0, 2, 3]]);
    let shader = scene.shader(mesh.shaders[0]).unwrap();
    assert_eq!((shader.class().name, shader.color("base_color")), ("PhysicallyBased", Vec3::new(1.0, 0.0, 0.0)));
}

#[test]
fn a_glb_reads_its_binary_chunk() {
    let nodes = json!([{ "mesh": 0 }]);
    let bytes = glb(&quad_gltf(None, red(), nodes), &quad_buffer());
    let file = read(&bytes, None, &Limits::default()).unwrap();
    assert_eq!((file.object_count(), file.instance_count(), file.triangles()), (1, 1, 2));
}

#[test]
fn materials_map_to_the_physically_based_class() {
    let cases = [
        // An emissive material is a light and still a surface: its emission is a parameter.
        (json!({ "emissiveFactor": [1, 0.5, 0], "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 4 } } }), "PhysicallyBased", "emissive", ParamValue::Color(Vec3::new(4.0, 2.0, 0.0))),
        (json!({ "pbrMetallicRoughness": { "baseColorFactor": [1, 0.8, 0.2, 1], "metallicFactor": 1, "roughnessFactor": 0.5 } }), "PhysicallyBased", "roughness", ParamValue::Float(0.5)),
        (json!({ "pbrMetallicRoughness": { "baseColorFactor": [1, 0.8, 0.2, 1], "metallicFactor": 0.25 } }), "PhysicallyBased", "metallic", ParamValue::Float(0.25)),
        // glTF's defaults: fully metallic, fully rough.
        (json!({ "pbrMetallicRoughness": {} }), "PhysicallyBased", "metallic", ParamValue::Float(1.0)),
        (json!({ "extensions": { "KHR_materials_ior": { "ior": 1.33 } } }), "PhysicallyBased", "ior", ParamValue::Float(1.33)),
        (json!({ "pbrMetallicRoughness": { "baseColorFactor": [0, 0, 1, 1] }, "extensions": { "KHR_materials_unlit": {} } }), "Constant", "color", ParamValue::Color(Vec3::Z)),
    ];
    for (material, class, param, value) in cases {
        let file = import(&quad_gltf(Some(data_uri(&quad_buffer())), json!([material]), json!([{ "mesh": 0 }]))).unwrap();
        let mut scene = Scene::new();
        let added = file.add_to(&mut scene).unwrap();
        let shader = scene.shader(added.shaders[0]).unwrap();
        assert_eq!(shader.class().name, class);
        assert_eq!(shader.get(param), Some(value), "{class}.{param}");
    }
}

#[test]
fn cameras_and_punctual_lights_come_along() {
    let mut document = quad_gltf(
        Some(data_uri(&quad_buffer())),
        red(),
        json!([
            { "mesh": 0, "children": [1, 2] },
            { "translation": [0, 0, 5], "camera": 0 },
            { "translation": [0, 3, 0], "extensions": { "KHR_lights_punctual": { "light": 0 } } }
        ]),
    );
    document["cameras"] = json!([{ "type": "perspective", "perspective": { "yfov": 0.5, "znear": 0.1 } }]);
    document["extensions"] = json!({ "KHR_lights_punctual": { "lights": [{ "type": "point", "color": [1, 1, 0.5], "intensity": 2 }] } });
    document["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    let file = import(&document).unwrap();
    let camera = file.camera().expect("the file's camera");
    assert_eq!((camera.eye, camera.target), (Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, 4.0)));
    assert!((camera.fov_y_degrees - 0.5f32.to_degrees()).abs() < 1e-4);
    assert_eq!(file.lights(), &[Light::Point { position: Vec3::new(0.0, 3.0, 0.0), intensity: Vec3::new(2.0, 2.0, 1.0) }]);
}

#[test]
fn a_new_scene_from_a_file_without_lights_gets_none_from_the_importer() {
    // The renderer lights a scene that nothing lights; the importer adds nothing the file
    // does not have (a default sun would shine into rooms lit by their own lamps).
    let file = import(&quad_gltf(Some(data_uri(&quad_buffer())), red(), json!([{ "mesh": 0 }]))).unwrap();
    let scene = file.into_scene().unwrap();
    assert_eq!(scene.lights().count(), 0);
    assert_eq!(scene.instances().count(), 1);
}

#[test]
fn the_framing_camera_sees_every_instance() {
    let nodes = json!([{ "mesh": 0, "children": [1] }, { "translation": [-30, 0, 0], "mesh": 0 }]);
    let file = import(&quad_gltf(Some(data_uri(&quad_buffer())), red(), nodes)).unwrap();
    assert!(file.camera().is_none());
    let camera = file.framing_camera();
    let mut scene = Scene::new();
    file.add_to(&mut scene).unwrap();
    scene.set_camera(camera).unwrap();
    let frame = scene.frame();
    // Both quads are in view: some pixel sees each instance.
    let seen: std::collections::HashSet<_> =
        (0..64).flat_map(|y| (0..64).map(move |x| (x, y))).filter_map(|(x, y)| frame.pick(x, y, 64, 64)).map(|h| h.instance).collect();
    assert_eq!(seen.len(), 2);
}

/// Imports a broken file: the error names the part at fault.
fn refused(document: &Value) -> ImportError {
    let err = import(document).unwrap_err();
    assert!(!matches!(err, ImportError::Internal), "{err}");
    err
}

#[test]
fn broken_files_are_refused_with_the_part_named() {
    let good = || quad_gltf(Some(data_uri(&quad_buffer())), red(), json!([{ "mesh": 0 }]));

    let mut past_the_end = good();
    past_the_end["accessors"][0]["count"] = json!(1000);
    assert_eq!(refused(&past_the_end).field(), Some("meshes[0].primitives[0].attributes.POSITION"));

    let mut huge_offset = good();
    huge_offset["accessors"][0]["byteOffset"] = json!(u32::MAX);
    assert_eq!(refused(&huge_offset).field(), Some("meshes[0].primitives[0].attributes.POSITION"));

    let mut wrong_type = good();
    wrong_type["accessors"][0]["type"] = json!("VEC2");
    assert_eq!(refused(&wrong_type).field(), Some("meshes[0].primitives[0].attributes.POSITION"));

    let mut bad_index = quad_buffer();
    bad_index[48..50].copy_from_slice(&9u16.to_le_bytes());
    let bad_index = quad_gltf(Some(data_uri(&bad_index)), red(), json!([{ "mesh": 0 }]));
    let err = refused(&bad_index);
    assert_eq!(err.field(), Some("meshes[0].primitives[0].indices"), "{err}");

    let mut nan = quad_buffer();
    nan[0..4].copy_from_slice(&f32::NAN.to_le_bytes());
    let nan = quad_gltf(Some(data_uri(&nan)), red(), json!([{ "mesh": 0 }]));
    assert!(refused(&nan).to_string().contains("not finite"));

    let short = quad_gltf(Some(data_uri(&quad_buffer()[..20])), red(), json!([{ "mesh": 0 }]));
    assert_eq!(refused(&short).field(), Some("buffers[0]"));

    let external = quad_gltf(Some("quad.bin".into()), red(), json!([{ "mesh": 0 }]));
    assert_eq!(refused(&external).field(), Some("buffers[0].uri"));

    assert!(matches!(read(b"not gltf at all", None, &Limits::default()), Err(ImportError::Syntax(_))));
    assert!(matches!(read(b"glTF\x02\0\0\0\xff\xff\xff\xff", None, &Limits::default()), Err(ImportError::Syntax(_))));
}

#[test]
fn limits_are_checked_before_reading() {
    let document = quad_gltf(Some(data_uri(&quad_buffer())), red(), json!([{ "mesh": 0 }]));
    let limits = Limits { max_triangles: 1, ..Limits::default() };
    let err = read(&serde_json::to_vec(&document).unwrap(), None, &limits).unwrap_err();
    assert!(matches!(err, ImportError::TooLarge { what: "triangles", count: 2, limit: 1 }), "{err}");
}

#[test]
fn node_cycles_are_refused_and_singular_nodes_left_out() {
    let nodes = json!([{ "mesh": 0, "children": [1] }, { "mesh": 0, "children": [0] }, { "mesh": 0, "scale": [0, 1, 1] }]);
    let mut document = quad_gltf(Some(data_uri(&quad_buffer())), red(), nodes);
    document["scenes"] = json!([{ "nodes": [0, 2] }]);
    // A cycle breaks the schema's rules: the validator or the walk refuses the file whole.
    match import(&document) {
        Err(ImportError::Syntax(_)) => {}
        Err(ImportError::Invalid { field, .. }) => assert_eq!(field, "nodes[0]"),
        other => panic!("a cycle is refused, not {other:?}"),
    }
    // A node with a second parent likewise.
    document["nodes"] = json!([{ "mesh": 0, "children": [2] }, { "mesh": 0, "children": [2] }, { "mesh": 0 }]);
    document["scenes"] = json!([{ "nodes": [0, 1] }]);
    assert!(matches!(import(&document), Err(ImportError::Syntax(_) | ImportError::Invalid { .. })));
    // A singular transform only hides its own mesh, with a note.
    document["nodes"] = json!([{ "mesh": 0 }, { "mesh": 0, "scale": [0, 1, 1] }]);
    let file = import(&document).unwrap();
    assert_eq!(file.instance_count(), 1);
    assert!(file.notes().iter().any(|n| n.contains("singular")), "{:?}", file.notes());
}

/// A hierarchy deeper than the importer follows is refused whole, naming the limit; one at the
/// limit is imported whole, its deepest mesh included.
#[test]
fn a_hierarchy_too_deep_is_refused_whole() {
    let chain = |levels: usize| {
        let nodes: Vec<Value> = (0..levels).map(|i| if i + 1 < levels { json!({ "children": [i + 1] }) } else { json!({ "mesh": 0 }) }).collect();
        let mut document = quad_gltf(Some(data_uri(&quad_buffer())), red(), json!(nodes));
        document["scenes"] = json!([{ "nodes": [0] }]);
        document
    };
    assert_eq!(import(&chain(256)).unwrap().instance_count(), 1, "the mesh at the 256th level");
    let err = import(&chain(257)).unwrap_err();
    assert!(matches!(err, ImportError::TooLarge { what: "levels of nodes", count: 257, limit: 256 }), "{err}");
    assert!(err.to_string().contains("more than the limit of 256"), "{err}");
}

/// A 2 × 1 PNG: a red texel, then a blue one.
fn red_blue_png() -> Vec<u8> {
    let image = image::RgbImage::from_fn(2, 1, |x, _| if x == 0 { image::Rgb([255, 0, 0]) } else { image::Rgb([0, 0, 255]) });
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
    bytes.into_inner()
}

/// [`quad_gltf`] with texture coordinates and a material whose base colour is texture 0, image
/// `image` (given by a URI or a buffer view), on texture coordinates `tex_coord`.
fn textured_quad(image: Value, tex_coord: u32, bin: &[u8]) -> Value {
    let uvs: Vec<u8> = [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]].iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let buffer = [quad_buffer(), uvs, bin.to_vec()].concat();
    let material = json!([{ "pbrMetallicRoughness": { "baseColorFactor": [1, 1, 0.5, 1], "metallicFactor": 0, "baseColorTexture": { "index": 0, "texCoord": tex_coord } } }]);
    let mut document = quad_gltf(Some(data_uri(&buffer)), material, json!([{ "mesh": 0 }]));
    document["buffers"][0]["byteLength"] = json!(buffer.len());
    document["bufferViews"].as_array_mut().unwrap().extend([
        json!({ "buffer": 0, "byteOffset": 60, "byteLength": 32 }),
        json!({ "buffer": 0, "byteOffset": 92, "byteLength": bin.len().max(1) }),
    ]);
    document["accessors"].as_array_mut().unwrap().push(json!({ "bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2" }));
    document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(2);
    document["images"] = json!([image]);
    document["textures"] = json!([{ "source": 0 }]);
    document
}

#[test]
fn a_base_colour_image_becomes_the_texture_of_a_physically_based_shader() {
    let png = red_blue_png();
    let by_uri = textured_quad(json!({ "uri": format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(&png)) }), 0, &[]);
    let in_buffer = textured_quad(json!({ "bufferView": 3, "mimeType": "image/png" }), 0, &png);
    for document in [by_uri, in_buffer] {
        let mut scene = Scene::new();
        let added = import(&document).unwrap().add_to(&mut scene).unwrap();
        assert_eq!(added.textures.len(), 1);
        let shader = scene.shader(added.shaders[0]).unwrap();
        assert_eq!(shader.class().name, "PhysicallyBased");
        assert_eq!(shader.get("base_color"), Some(ParamValue::Color(Vec3::new(1.0, 1.0, 0.5))), "the factor multiplies the texture");
        assert_eq!(shader.get("base_color_texture"), Some(ParamValue::Texture(Some(added.textures[0]))));
        let Texture::Image(image) = scene.texture(added.textures[0]).unwrap() else { panic!("an image texture") };
        assert_eq!((image.width(), image.height(), image.texel(0, 0), image.texel(1, 0)), (2, 1, Vec3::X, Vec3::Z));
        let mesh = scene.mesh(added.objects[0]).unwrap();
        assert_eq!(mesh.uvs.len(), 4, "texture coordinates come along");
    }
}

#[test]
fn textures_the_importer_cannot_use_are_left_out_or_refused() {
    let png = red_blue_png();
    // On a third set of texture coordinates, which raystage's meshes do not have: no texture.
    let mut scene = Scene::new();
    let file = import(&textured_quad(json!({ "bufferView": 3 }), 2, &png)).unwrap();
    assert!(file.notes().iter().any(|n| n.contains("third or later set of texture coordinates")), "{:?}", file.notes());
    let added = file.add_to(&mut scene).unwrap();
    assert!(added.textures.is_empty());
    assert_eq!(scene.shader(added.shaders[0]).unwrap().get("base_color_texture"), Some(ParamValue::Texture(None)));

    let broken = textured_quad(json!({ "bufferView": 3 }), 0, b"not a png");
    let err = refused(&broken);
    assert_eq!(err.field(), Some("images[0]"), "{err}");
    assert!(err.to_string().contains("the image cannot be read"), "{err}");

    let limits = Limits { max_image_side: 1, ..Limits::default() };
    let large = serde_json::to_vec(&textured_quad(json!({ "bufferView": 3 }), 0, &png)).unwrap();
    let err = read(&large, None, &limits).unwrap_err();
    assert!(matches!(err, ImportError::TooLarge { count: 2, limit: 1, .. }), "{err}");
    // 2 × 1 texels take 32 bytes decoded.
    let err = read(&large, None, &Limits { max_image_bytes: 31, ..Limits::default() }).unwrap_err();
    assert!(matches!(err, ImportError::TooLarge { count: 32, limit: 31, .. }), "{err}");
    assert!(read(&large, None, &Limits { max_image_bytes: 32, ..Limits::default() }).is_ok());

    let external = textured_quad(json!({ "uri": "wood.png" }), 0, &[]);
    assert_eq!(refused(&external).field(), Some("images[0].uri"));
}

/// A file's images together are bounded before any is decoded (the same image as colours and
/// as data is decoded twice, 32 bytes each here), and their decoding in time: a small file
/// naming many large images must not hold the reader for minutes.
#[test]
fn a_files_images_are_bounded_together_in_bytes_and_time() {
    let png = red_blue_png();
    let mut document = textured_quad(json!({ "bufferView": 3 }), 0, &png);
    document["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({ "index": 0 });
    let file = serde_json::to_vec(&document).unwrap();
    let err = read(&file, None, &Limits { max_images_bytes: 63, ..Limits::default() }).unwrap_err();
    assert!(matches!(err, ImportError::TooLarge { count: 64, limit: 63, .. }), "{err}");
    assert!(read(&file, None, &Limits { max_images_bytes: 64, ..Limits::default() }).is_ok());
    let err = read(&file, None, &Limits { max_decode_seconds: std::time::Duration::ZERO, ..Limits::default() }).unwrap_err();
    assert!(matches!(err, ImportError::TooSlow { .. }), "{err}");
    assert!(err.to_string().contains("decoding its images took longer than the limit of 0 s"), "{err}");
}

/// KHR_materials_transmission and KHR_materials_volume come through as the physically based
/// shader's transmission, thickness and attenuation, keeping the rest of the material (its
/// roughness and colour, which glass dropped); a volume's boundary is seen from both sides.
#[test]
fn transmission_and_volume_map_to_the_physically_based_class() {
    let glass = json!({
        "name": "bottle",
        "pbrMetallicRoughness": { "baseColorFactor": [0.9, 1, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.3 },
        "extensions": {
            "KHR_materials_transmission": { "transmissionFactor": 0.75 },
            "KHR_materials_ior": { "ior": 1.33 },
            "KHR_materials_volume": { "thicknessFactor": 0.2, "attenuationDistance": 4, "attenuationColor": [0.5, 0.8, 1] }
        }
    });
    // A thin wall: no volume (no extension, or thickness 0), and a volume without attenuation.
    let pane = json!({ "extensions": { "KHR_materials_transmission": { "transmissionFactor": 1 } } });
    let clear = json!({ "extensions": { "KHR_materials_transmission": { "transmissionFactor": 1 }, "KHR_materials_volume": { "thicknessFactor": 1 } } });
    let cases = [
        (
            glass,
            vec![
                ("transmission", ParamValue::Float(0.75)),
                ("ior", ParamValue::Float(1.33)),
                ("roughness", ParamValue::Float(0.3)),
                ("base_color", ParamValue::Color(Vec3::new(0.9, 1.0, 0.8))),
                ("thickness", ParamValue::Float(0.2)),
                ("attenuation_distance", ParamValue::Float(4.0)),
                ("attenuation_color", ParamValue::Color(Vec3::new(0.5, 0.8, 1.0))),
                ("double_sided", ParamValue::Float(1.0)),
            ],
        ),
        (pane, vec![("transmission", ParamValue::Float(1.0)), ("thickness", ParamValue::Float(0.0)), ("double_sided", ParamValue::Float(0.0))]),
        (clear, vec![("thickness", ParamValue::Float(1.0)), ("attenuation_color", ParamValue::Color(Vec3::ONE)), ("double_sided", ParamValue::Float(1.0))]),
    ];
    for (material, expected) in cases {
        let file = import(&quad_gltf(Some(data_uri(&quad_buffer())), json!([material]), json!([{ "mesh": 0 }]))).unwrap();
        assert!(file.notes().is_empty(), "{:?}", file.notes());
        let mut scene = Scene::new();
        let added = file.add_to(&mut scene).unwrap();
        let shader = scene.shader(added.shaders[0]).unwrap();
        assert_eq!(shader.class().name, "PhysicallyBased");
        assert!(shader.transmits());
        for (param, value) in expected {
            assert_eq!(shader.get(param), Some(value), "{param}");
        }
    }
}

/// KHR_materials_clearcoat (which the gltf crate does not parse) comes through as the coat's
/// weight and roughness; a texture whose index names no texture of the file (the file has none)
/// is left out with a note, and the factor stays.
#[test]
fn clearcoat_maps_to_the_coat_of_the_physically_based_class() {
    let paint = json!({
        "name": "paint",
        "pbrMetallicRoughness": { "baseColorFactor": [0.6, 0.05, 0.05, 1], "metallicFactor": 0.2 },
        "extensions": { "KHR_materials_clearcoat": { "clearcoatFactor": 0.8, "clearcoatRoughnessFactor": 0.1 } }
    });
    let textured = json!({ "extensions": { "KHR_materials_clearcoat": { "clearcoatFactor": 1, "clearcoatTexture": { "index": 0 } } } });
    let none = json!({});
    for (material, coat, roughness, noted) in [(paint, 0.8, 0.1, false), (textured, 1.0, 0.0, true), (none, 0.0, 0.0, false)] {
        let file = import(&quad_gltf(Some(data_uri(&quad_buffer())), json!([material]), json!([{ "mesh": 0 }]))).unwrap();
        assert_eq!(file.notes().iter().any(|n| n.contains("clearcoat texture is left out: index 0 names no texture of the file")), noted, "{:?}", file.notes());
        let mut scene = Scene::new();
        let added = file.add_to(&mut scene).unwrap();
        let shader = scene.shader(added.shaders[0]).unwrap();
        assert_eq!((shader.get("clearcoat"), shader.get("clearcoat_roughness")), (Some(ParamValue::Float(coat)), Some(ParamValue::Float(roughness))));
    }
}

/// What a material has that raystage does not render yet is said, once per material, by name;
/// the specular colour and the sheen factors it renders.
#[test]
fn what_a_material_leaves_out_is_a_note() {
    let extensions = json!({
        "KHR_materials_specular": { "specularColorFactor": [0.5, 0.25, 2.0] },
        "KHR_materials_sheen": { "sheenColorFactor": [0.9, 0.2, 0.1], "sheenRoughnessFactor": 0.4 },
        "KHR_materials_transmission": { "transmissionFactor": 0.5 },
        "KHR_materials_volume": { "thicknessFactor": 1, "thicknessTexture": { "index": 0 } },
    });
    let material = json!([{ "name": "leaves", "alphaMode": "MASK", "doubleSided": true, "extensions": extensions }]);
    let mut document = quad_gltf(Some(data_uri(&quad_buffer())), material, json!([{ "mesh": 0 }, { "mesh": 0 }]));
    document["textures"] = json!([{ "source": 0 }]);
    document["images"] = json!([{ "uri": "unused.png" }]);
    let file = import(&document).unwrap();
    let notes = file.notes().join("\n");
    assert!(notes.contains("material `leaves`: its thickness texture (the path length inside comes from the geometry) is not rendered yet"), "{notes}");
    assert!(!notes.contains("alpha mode") && !notes.contains("sheen") && !notes.contains("specular"), "a physically based material's alpha mode, specular and sheen factors are rendered: {notes}");
    assert_eq!(notes.matches("thickness").count(), 1, "{notes}");
    let mut scene = Scene::new();
    let added = file.add_to(&mut scene).unwrap();
    let shader = scene.shader(added.shaders[0]).unwrap();
    let param = |name: &str| shader.get(name);
    assert_eq!(param("specular_color"), Some(ParamValue::Color(Vec3::new(0.5, 0.25, 2.0))));
    assert_eq!(param("sheen_color"), Some(ParamValue::Color(Vec3::new(0.9, 0.2, 0.1))));
    assert_eq!(param("sheen_roughness"), Some(ParamValue::Float(0.4)));
}

/// The textures of KHR_materials_specular, _transmission, _clearcoat and _sheen fill their slots
/// of the physically based shader, each with its own sampler parameters: the specular and sheen
/// colours as colours (sRGB-decoded), the others as data, from the one image they all share.
/// They are no longer notes; the thickness texture and the clearcoat's normal texture still are.
#[test]
fn the_extensions_textures_fill_their_slots() {
    // One grey texel, half covered: 128 of 255 in every channel.
    let grey = image::RgbaImage::from_pixel(1, 1, image::Rgba([128, 128, 128, 128]));
    let mut png = std::io::Cursor::new(Vec::new());
    grey.write_to(&mut png, image::ImageFormat::Png).unwrap();
    let png = png.into_inner();
    let mut document = textured_quad(json!({ "bufferView": 3 }), 0, &png);
    document["materials"][0]["pbrMetallicRoughness"].as_object_mut().unwrap().remove("baseColorTexture");
    document["materials"][0]["extensions"] = json!({
        "KHR_materials_specular": { "specularFactor": 0.5, "specularTexture": { "index": 0 }, "specularColorTexture": { "index": 0 } },
        "KHR_materials_transmission": { "transmissionFactor": 0.8, "transmissionTexture": { "index": 0, "texCoord": 1 } },
        "KHR_materials_volume": { "thicknessFactor": 0.5, "thicknessTexture": { "index": 0 } },
        "KHR_materials_clearcoat": {
            "clearcoatFactor": 0.6,
            "clearcoatTexture": { "index": 0, "extensions": { "KHR_texture_transform": { "offset": [0.5, 0.25], "scale": [2, 2] } } },
            "clearcoatRoughnessFactor": 0.3,
            "clearcoatRoughnessTexture": { "index": 0, "texCoord": 1 },
            "clearcoatNormalTexture": { "index": 0 }
        },
        "KHR_materials_sheen": { "sheenColorFactor": [1, 0.5, 0.25], "sheenColorTexture": { "index": 0 }, "sheenRoughnessFactor": 0.4, "sheenRoughnessTexture": { "index": 0 } }
    });
    document["samplers"] = json!([{ "magFilter": 9728, "wrapS": 33071 }]);
    document["textures"][0]["sampler"] = json!(0);
    document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = json!(2);
    let file = import(&document).unwrap();
    let notes = file.notes().join("\n");
    for rendered in ["specular", "transmission", "sheen", "clearcoat texture", "clearcoat roughness", "left out"] {
        assert!(!notes.contains(rendered), "{rendered}: {notes}");
    }
    assert!(notes.contains("its thickness texture (the path length inside comes from the geometry) is not rendered yet"), "{notes}");
    assert!(notes.contains("its clearcoat normal texture (the coat takes the surface's normal) is not rendered yet"), "{notes}");
    let mut scene = Scene::new();
    let added = file.add_to(&mut scene).unwrap();
    assert_eq!(added.textures.len(), 2, "one image, read as colours and as data");
    let shader = scene.shader(added.shaders[0]).unwrap();
    let texel = |slot: &str| {
        let Some(ParamValue::Texture(Some(id))) = shader.get(&format!("{slot}_texture")) else { panic!("{slot}_texture is set") };
        let Texture::Image(image) = scene.texture(id).unwrap() else { panic!("an image texture") };
        image.texel(0, 0).x
    };
    for slot in ["specular_color", "sheen_color"] {
        assert!((texel(slot) - 0.2158).abs() < 1e-3, "{slot}: a colour, sRGB 128 is 0.216 in linear light");
    }
    for slot in ["specular", "transmission", "clearcoat", "clearcoat_roughness", "sheen_roughness"] {
        assert!((texel(slot) - 128.0 / 255.0).abs() < 1e-3, "{slot}: data, as stored");
    }
    let float = |name: &str| match shader.get(name) {
        Some(ParamValue::Float(f)) => f,
        other => panic!("{name}: {other:?}"),
    };
    // Every slot has the texture's sampler; each its own coordinates and transform.
    for slot in ["specular", "specular_color", "transmission", "clearcoat", "clearcoat_roughness", "sheen_color", "sheen_roughness"] {
        assert_eq!([float(&format!("{slot}_wrap_s")), float(&format!("{slot}_filter"))], [33071.0, 9728.0], "{slot}");
        let set = if matches!(slot, "transmission" | "clearcoat_roughness") { 1.0 } else { 0.0 };
        assert_eq!(float(&format!("{slot}_texcoord")), set, "{slot}");
    }
    assert_eq!(["offset_u", "offset_v", "scale_u", "scale_v"].map(|p| float(&format!("clearcoat_{p}"))), [0.5, 0.25, 2.0, 2.0]);
    assert_eq!(float("sheen_roughness_offset_u"), 0.0);
    // The factors stay: the textures multiply them.
    let factors = ["specular", "transmission", "clearcoat", "clearcoat_roughness", "sheen_roughness"].map(float);
    assert_eq!(factors, [0.5, 0.8, 0.6, 0.3, 0.4]);
    assert_eq!(shader.get("sheen_color"), Some(ParamValue::Color(Vec3::new(1.0, 0.5, 0.25))));
    assert_eq!(shader.get("thickness_texture"), None, "the class has no thickness slot");
}

/// A clearcoat or sheen texture (read from JSON the gltf crate does not check) whose index
/// names no texture of the file, or that has no index, is left out with a note: never a panic,
/// never a refused file.
#[test]
fn an_extension_texture_of_a_bad_index_is_a_note() {
    let png = red_blue_png();
    for (info, why) in [
        (json!({ "index": 7 }), "index 7 names no texture of the file"),
        (json!({ "index": -1 }), "index -1 names no texture of the file"),
        (json!({ "index": 1e300 }), "index 1e+300 names no texture of the file"),
        (json!({ "index": "0" }), "index \"0\" names no texture of the file"),
        (json!({ "texCoord": 0 }), "it has no index"),
    ] {
        let mut document = textured_quad(json!({ "bufferView": 3 }), 0, &png);
        document["materials"][0]["name"] = json!("paint");
        document["materials"][0]["extensions"] = json!({
            "KHR_materials_clearcoat": { "clearcoatFactor": 1, "clearcoatTexture": info },
            "KHR_materials_sheen": { "sheenColorFactor": [1, 1, 1], "sheenRoughnessTexture": info }
        });
        let file = import(&document).unwrap();
        let notes = file.notes().join("\n");
        assert!(notes.contains(&format!("material `paint`: its clearcoat texture is left out: {why}")), "{notes}");
        assert!(notes.contains(&format!("material `paint`: its sheen roughness texture is left out: {why}")), "{notes}");
        let mut scene = Scene::new();
        let added = file.add_to(&mut scene).unwrap();
        let shader = scene.shader(added.shaders[0]).unwrap();
        assert_eq!([shader.get("clearcoat_texture"), shader.get("sheen_roughness_texture")], [Some(ParamValue::Texture(None)); 2]);
        assert_eq!(shader.get("clearcoat"), Some(ParamValue::Float(1.0)), "the factor stays");
        assert!(matches!(shader.get("base_color_texture"), Some(ParamValue::Texture(Some(_)))), "the rest of the material is imported");
    }
}

/// The metallic-roughness texture is data: its values are read as stored, not sRGB-decoded,
/// even from the very image the base colour reads as colours.
#[test]
fn a_metallic_roughness_image_is_read_as_data() {
    let grey = image::RgbImage::from_pixel(1, 1, image::Rgb([128, 128, 128]));
    let mut png = std::io::Cursor::new(Vec::new());
    grey.write_to(&mut png, image::ImageFormat::Png).unwrap();
    let png = png.into_inner();
    let mut document = textured_quad(json!({ "uri": format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(&png)) }), 0, &[]);
    document["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({ "index": 0 });
    let mut scene = Scene::new();
    let added = import(&document).unwrap().add_to(&mut scene).unwrap();
    assert_eq!(added.textures.len(), 2, "one image, read as colours and as data");
    let shader = scene.shader(added.shaders[0]).unwrap();
    let texel = |param: &str| {
        let Some(ParamValue::Texture(Some(id))) = shader.get(param) else { panic!("{param} is set") };
        let Texture::Image(image) = scene.texture(id).unwrap() else { panic!("an image texture") };
        image.texel(0, 0).x
    };
    assert!((texel("metallic_roughness_texture") - 128.0 / 255.0).abs() < 1e-3);
    assert!((texel("base_color_texture") - 0.2158).abs() < 1e-3, "sRGB 128 is 0.216 in linear light");
}

/// A texture's sampler (wrap modes, magnification filter), its texture coordinate set and its
/// `KHR_texture_transform` become the parameters of its slot; a texture without them gets
/// glTF's defaults.
#[test]
fn samplers_coordinate_sets_and_texture_transforms_become_slot_parameters() {
    let png = red_blue_png();
    let mut document = textured_quad(json!({ "bufferView": 3 }), 0, &png);
    document["samplers"] = json!([{ "magFilter": 9728, "wrapS": 33071, "wrapT": 33648 }]);
    document["textures"] = json!([{ "source": 0, "sampler": 0 }, { "source": 0 }]);
    document["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = json!({
        "KHR_texture_transform": { "offset": [0.25, -0.5], "rotation": 0.5, "scale": [2, 3], "texCoord": 1 }
    });
    document["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({ "index": 1 });
    // The second coordinates: the first ones again.
    document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = json!(2);
    let mut scene = Scene::new();
    let added = import(&document).unwrap().add_to(&mut scene).unwrap();
    let shader = scene.shader(added.shaders[0]).unwrap();
    let float = |name: &str| match shader.get(name) {
        Some(ParamValue::Float(f)) => f,
        other => panic!("{name}: {other:?}"),
    };
    let base = ["wrap_s", "wrap_t", "filter", "texcoord", "offset_u", "offset_v", "rotation", "scale_u", "scale_v"].map(|p| float(&format!("base_color_{p}")));
    assert_eq!(base, [33071.0, 33648.0, 9728.0, 1.0, 0.25, -0.5, 0.5, 2.0, 3.0]);
    let defaults = ["wrap_s", "wrap_t", "filter", "texcoord", "offset_u", "offset_v", "rotation", "scale_u", "scale_v"].map(|p| float(&format!("metallic_roughness_{p}")));
    assert_eq!(defaults, [10497.0, 10497.0, 9729.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0]);
    let mesh = scene.mesh(added.objects[0]).unwrap();
    assert_eq!((mesh.uvs1.len(), mesh.uvs1[2]), (4, mesh.uvs[2]), "the second coordinates come along");
}

/// A normal texture becomes the `normal` slot with its scale; the mesh keeps the file's tangents
/// or, without them, gets tangents generated from its texture coordinates.
#[test]
fn normal_textures_come_with_tangents() {
    let png = red_blue_png();
    let mut document = textured_quad(json!({ "bufferView": 3 }), 0, &png);
    document["materials"][0]["normalTexture"] = json!({ "index": 0, "scale": 0.5 });
    let mut scene = Scene::new();
    let added = import(&document).unwrap().add_to(&mut scene).unwrap();
    let shader = scene.shader(added.shaders[0]).unwrap();
    assert_eq!(shader.get("normal_scale"), Some(ParamValue::Float(0.5)));
    let Some(ParamValue::Texture(Some(map))) = shader.get("normal_texture") else { panic!("a normal texture") };
    let Texture::Image(image) = scene.texture(map).unwrap() else { panic!("an image texture") };
    assert_eq!(image.texel(0, 0), Vec3::X, "data, not sRGB-decoded");
    // u along +x, v down the quad: the tangent is +x, right-handed.
    let mesh = scene.mesh(added.objects[0]).unwrap();
    assert_eq!(mesh.tangents, vec![glam::Vec4::new(1.0, 0.0, 0.0, 1.0); 4]);

    // The file's own tangents are kept.
    let file_tangents: Vec<u8> = [[0.0f32, 1.0, 0.0, -1.0]; 4].iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let buffer = [quad_buffer(), [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]].iter().flatten().flat_map(|c| c.to_le_bytes()).collect(), png.clone(), file_tangents].concat();
    document["buffers"][0] = json!({ "uri": data_uri(&buffer), "byteLength": buffer.len() });
    document["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 0, "byteOffset": 92 + png.len(), "byteLength": 64 }));
    document["accessors"].as_array_mut().unwrap().push(json!({ "bufferView": 4, "componentType": 5126, "count": 4, "type": "VEC4" }));
    document["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = json!(3);
    let mut scene = Scene::new();
    let added = import(&document).unwrap().add_to(&mut scene).unwrap();
    assert_eq!(scene.mesh(added.objects[0]).unwrap().tangents, vec![glam::Vec4::new(0.0, 1.0, 0.0, -1.0); 4]);
}

/// Emissive and occlusion textures come with their slots: the emissive one as colours, the
/// occlusion one as data with its strength.
#[test]
fn emissive_and_occlusion_textures_are_imported() {
    let png = red_blue_png();
    let mut document = textured_quad(json!({ "bufferView": 3 }), 0, &png);
    document["materials"][0]["emissiveTexture"] = json!({ "index": 0 });
    document["materials"][0]["emissiveFactor"] = json!([1.0, 0.5, 0.25]);
    document["materials"][0]["occlusionTexture"] = json!({ "index": 0, "strength": 0.75 });
    let mut scene = Scene::new();
    let file = import(&document).unwrap();
    assert!(!file.notes().iter().any(|n| n.contains("emissive") || n.contains("occlusion")), "{:?}", file.notes());
    let added = file.add_to(&mut scene).unwrap();
    let shader = scene.shader(added.shaders[0]).unwrap();
    assert_eq!(shader.get("emissive"), Some(ParamValue::Color(Vec3::new(1.0, 0.5, 0.25))));
    assert_eq!(shader.get("occlusion_strength"), Some(ParamValue::Float(0.75)));
    for param in ["emissive_texture", "occlusion_texture"] {
        assert!(matches!(shader.get(param), Some(ParamValue::Texture(Some(_)))), "{param}");
    }
}

/// Alpha mode, cut-off, the base colour's alpha and sidedness round-trip; a cut-off outside
/// [0, 1] is refused with the field named.
#[test]
fn alpha_modes_and_sidedness_are_imported() {
    let material = json!([{ "pbrMetallicRoughness": { "baseColorFactor": [1, 1, 1, 0.25] }, "alphaMode": "MASK", "alphaCutoff": 0.3 }]);
    let document = quad_gltf(Some(data_uri(&quad_buffer())), material, json!([{ "mesh": 0 }]));
    let mut scene = Scene::new();
    let added = import(&document).unwrap().add_to(&mut scene).unwrap();
    let shader = scene.shader(added.shaders[0]).unwrap();
    let floats = ["opacity", "alpha_mode", "alpha_cutoff", "double_sided"].map(|p| shader.get(p));
    assert_eq!(floats, [0.25, 1.0, 0.3, 0.0].map(|f| Some(ParamValue::Float(f))), "single-sided is glTF's default");

    let blend = json!([{ "alphaMode": "BLEND", "doubleSided": true }]);
    let mut scene = Scene::new();
    let added = import(&quad_gltf(Some(data_uri(&quad_buffer())), blend, json!([{ "mesh": 0 }]))).unwrap().add_to(&mut scene).unwrap();
    let shader = scene.shader(added.shaders[0]).unwrap();
    assert_eq!([shader.get("alpha_mode"), shader.get("double_sided")], [Some(ParamValue::Float(2.0)), Some(ParamValue::Float(1.0))]);

    for cutoff in [-0.5, 1.5] {
        let bad = json!([{ "alphaMode": "MASK", "alphaCutoff": cutoff }]);
        let err = refused(&quad_gltf(Some(data_uri(&quad_buffer())), bad, json!([{ "mesh": 0 }])));
        assert_eq!(err.field(), Some("materials[0].alphaCutoff"), "{err}");
        assert!(err.to_string().contains("not within [0, 1]"), "{err}");
    }
}

/// Each shader is named after its glTF material; a material without a name gives none.
#[test]
fn shaders_are_named_after_their_materials() {
    let materials = json!([{ "name": "brass" }, {}]);
    let mut document = quad_gltf(Some(data_uri(&quad_buffer())), materials, json!([{ "mesh": 0 }, { "mesh": 1 }]));
    let primitive = document["meshes"][0]["primitives"][0].clone();
    document["meshes"].as_array_mut().unwrap().push(json!({ "primitives": [primitive] }));
    document["meshes"][1]["primitives"][0]["material"] = json!(1);
    document["scenes"][0]["nodes"] = json!([0, 1]);
    let mut scene = Scene::new();
    let added = import(&document).unwrap().add_to(&mut scene).unwrap();
    let names: Vec<Option<&str>> = added.shaders.iter().map(|&id| scene.shader(id).unwrap().name()).collect();
    assert_eq!(names, [Some("brass"), None]);
}

/// From the file to the pixels: a quad whose base colour PNG is cut out on its left half
/// (alpha 0 there, blue and opaque on the right), alpha mode MASK, sampled nearest; then the same
/// with `KHR_texture_transform` moving the texture by half its width, which swaps the halves.
#[test]
fn alpha_cut_outs_and_texture_transforms_reach_the_pixels() {
    let rgba = image::RgbaImage::from_fn(2, 1, |x, _| if x == 0 { image::Rgba([255, 0, 0, 0]) } else { image::Rgba([0, 0, 255, 255]) });
    let mut png = std::io::Cursor::new(Vec::new());
    rgba.write_to(&mut png, image::ImageFormat::Png).unwrap();
    let png = png.into_inner();
    let render = |transform: Option<Value>| {
        let mut document = textured_quad(json!({ "bufferView": 3 }), 0, &png);
        document["materials"][0]["alphaMode"] = json!("MASK");
        document["samplers"] = json!([{ "magFilter": 9728 }]);
        document["textures"][0]["sampler"] = json!(0);
        if let Some(t) = transform {
            document["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = json!({ "KHR_texture_transform": t });
        }
        let mut scene = import(&document).unwrap().into_scene().unwrap();
        scene.set_background(Some(raystage_scene::Background::Color(Vec3::Y))).unwrap();
        scene.set_camera(raystage_scene::Camera::look_at(Vec3::new(0.5, 0.5, 3.0), Vec3::new(0.5, 0.5, 0.0), Vec3::Y, 30.0).unwrap()).unwrap();
        let settings = raystage_render::RenderSettings { width: 32, height: 32, ..Default::default() };
        let (film, _) = raystage_render::render(&scene.frame(), &settings).unwrap();
        // The quad spans pixels 6 to 26 across.
        (film.pixel(10, 16), film.pixel(22, 16))
    };
    let (left, right) = render(None);
    assert_eq!(left, Vec3::Y, "cut out: the background shows");
    // (The material's factor halves blue.)
    assert!(right.z > 0.4 && right.x == 0.0 && right.y == 0.0, "the opaque blue half: {right}");
    let (left, right) = render(Some(json!({ "offset": [0.5, 0.0] })));
    assert!(left.z > 0.4 && left.x == 0.0, "moved by half the texture: {left}");
    assert_eq!(right, Vec3::Y);
}

/// From the file to the pixels: a black quad that reflects nothing itself, under a clear coat
/// whose texture is black on its left half and white on its right, lit by a point light at the
/// camera, shows the coat's highlight on its right half only.
#[test]
fn a_clearcoat_texture_reaches_the_pixels() {
    let mask = image::RgbImage::from_fn(2, 1, |x, _| image::Rgb([if x == 0 { 0 } else { 255 }; 3]));
    let mut png = std::io::Cursor::new(Vec::new());
    mask.write_to(&mut png, image::ImageFormat::Png).unwrap();
    let png = png.into_inner();
    let mut document = textured_quad(json!({ "bufferView": 3 }), 0, &png);
    document["materials"][0] = json!({
        "pbrMetallicRoughness": { "baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0 },
        "extensions": {
            "KHR_materials_specular": { "specularFactor": 0 },
            "KHR_materials_clearcoat": { "clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.5, "clearcoatTexture": { "index": 0 } }
        }
    });
    document["samplers"] = json!([{ "magFilter": 9728 }]);
    document["textures"][0]["sampler"] = json!(0);
    let mut scene = import(&document).unwrap().into_scene().unwrap();
    let eye = Vec3::new(0.5, 0.5, 3.0);
    scene.add_light(Light::Point { position: eye, intensity: Vec3::splat(100.0) }).unwrap();
    scene.set_camera(raystage_scene::Camera::look_at(eye, Vec3::new(0.5, 0.5, 0.0), Vec3::Y, 30.0).unwrap()).unwrap();
    let settings = raystage_render::RenderSettings { width: 32, height: 32, integrator: raystage_render::Integrator::Whitted, ..Default::default() };
    let (film, _) = raystage_render::render(&scene.frame(), &settings).unwrap();
    // The quad spans pixels 6 to 26 across: u ≈ 0.2 at pixel 10, 0.8 at 22.
    let (left, right) = (film.pixel(10, 16), film.pixel(22, 16));
    assert_eq!(left, Vec3::ZERO, "no coat on the left");
    assert!(right.min_element() > 0.1, "the coat's highlight on the right: {right}");
}

/// The quad of [`quad_gltf`] as `KHR_mesh_quantization` stores it: positions as plain shorts
/// 1000 times the float ones, normals as normalised bytes, texture coordinates as normalised
/// unsigned shorts, undone by the node's scale.
fn quantised_quad(extensions: &[&str]) -> Value {
    let mut bytes = Vec::new();
    for p in [[0i16, 0, 0], [1000, 0, 0], [1000, 1000, 0], [0, 1000, 0]] {
        p.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
        bytes.extend([0, 0]); // each element padded to 4 bytes, as glTF asks
    }
    for _ in 0..4 {
        bytes.extend([0u8, 0, 127, 0]); // +z, normalised
    }
    for uv in [[0u16, 65535], [65535, 65535], [65535, 0], [0, 0]] {
        uv.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bytes.extend(i.to_le_bytes());
    }
    json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": extensions,
        "extensionsRequired": extensions,
        "buffers": [{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 32, "byteStride": 8 },
            { "buffer": 0, "byteOffset": 32, "byteLength": 16, "byteStride": 4 },
            { "buffer": 0, "byteOffset": 48, "byteLength": 16 },
            { "buffer": 0, "byteOffset": 64, "byteLength": 12 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5122, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1000, 1000, 0] },
            { "bufferView": 1, "componentType": 5120, "normalized": true, "count": 4, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5123, "normalized": true, "count": 4, "type": "VEC2" },
            { "bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR" }
        ],
        "materials": red(),
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2 }, "indices": 3, "material": 0 }] }],
        "nodes": [{ "mesh": 0, "scale": [0.001, 0.001, 0.001] }],
        "scenes": [{ "nodes": [0] }],
        "scene": 0
    })
}

#[test]
fn quantised_vertices_are_read_as_the_whole_numbers_they_are() {
    let file = import(&quantised_quad(&["KHR_mesh_quantization"])).unwrap();
    let mut scene = Scene::new();
    let added = file.add_to(&mut scene).unwrap();
    let mesh = scene.mesh(added.objects[0]).unwrap();
    assert_eq!(mesh.positions[2], Vec3::new(1000.0, 1000.0, 0.0));
    assert_eq!(mesh.normals[0], Vec3::Z);
    assert_eq!((mesh.uvs[0].to_array(), mesh.uvs[2].to_array()), ([0.0, 1.0], [1.0, 0.0]));
    let placed = scene.transform(added.instances[0]).unwrap().transform_point3(mesh.positions[2]);
    assert!(placed.abs_diff_eq(Vec3::new(1.0, 1.0, 0.0), 1e-6), "{placed}");

    // Without the extension, glTF allows floats (and normalised integers for texture
    // coordinates) only: the file is refused, naming the attribute.
    let err = import(&quantised_quad(&[])).unwrap_err();
    assert_eq!(err.field(), Some("meshes[0].primitives[0].attributes.POSITION"), "{err}");
}

#[test]
fn files_may_require_the_extensions_that_are_read_and_no_others() {
    let mut document = quad_gltf(Some(data_uri(&quad_buffer())), red(), json!([{ "mesh": 0 }]));
    document["extensionsUsed"] = json!(["KHR_texture_transform", "KHR_materials_clearcoat"]);
    document["extensionsRequired"] = json!(["KHR_texture_transform", "KHR_materials_clearcoat"]);
    assert_eq!(import(&document).unwrap().triangles(), 2);

    document["extensionsUsed"] = json!(["KHR_texture_transform", "KHR_draco_mesh_compression"]);
    document["extensionsRequired"] = json!(["KHR_texture_transform", "KHR_draco_mesh_compression"]);
    let err = refused(&document);
    assert_eq!(err.field(), Some("extensionsRequired[1]"), "{err}");
    assert!(err.to_string().contains("KHR_draco_mesh_compression is not supported"), "{err}");

    // The rest of the document is still held to glTF's schema.
    document["extensionsRequired"] = json!(["KHR_texture_transform"]);
    document["meshes"][0]["primitives"][0]["material"] = json!(7);
    assert!(matches!(refused(&document), ImportError::Syntax(_)));
}

/// The animated samples as `gltfpack` writes them (`scripts/references/gltfpack.sh`), quantised
/// and quantised and compressed, each name with both files.
fn gltfpack_files() -> [(&'static str, &'static [u8], &'static [u8]); 3] {
    macro_rules! pair {
        ($name:literal) => {
            (
                $name,
                include_bytes!(concat!("../../demo/assets/animated/gltfpack/", $name, ".glb")).as_slice(),
                include_bytes!(concat!("../../demo/assets/animated/gltfpack/", $name, ".cc.glb")).as_slice(),
            )
        };
    }
    [pair!("BoxAnimated"), pair!("RiggedSimple"), pair!("AnimatedMorphCube")]
}

/// Every mesh of a file once imported into a scene, in the order of the scene's objects.
fn meshes(bytes: &[u8]) -> Vec<raystage_scene::Mesh> {
    let mut scene = Scene::new();
    let added = read(bytes, None, &Limits::default()).unwrap().add_to(&mut scene).unwrap();
    added.objects.iter().map(|&o| scene.mesh(o).unwrap().clone()).collect()
}

#[test]
fn compressed_buffers_decode_to_the_vertices_they_hold() {
    for (name, quantised, compressed) in gltfpack_files() {
        let (plain, decoded) = (meshes(quantised), meshes(compressed));
        assert_eq!(plain.len(), decoded.len(), "{name}");
        // The same file under the extension's Khronos name reads alike.
        let khr = edited_glb(compressed, |d| *d = serde_json::from_str(&d.to_string().replace("EXT_meshopt_compression", "KHR_meshopt_compression")).unwrap());
        assert_eq!(meshes(&khr), decoded, "{name}, KHR_meshopt_compression");
        for (p, d) in plain.iter().zip(&decoded) {
            // gltfpack orders vertices and triangles for the codec when it compresses, and its
            // filters are lossy: each vertex must have a twin in the other mesh, its position
            // within a ten-thousandth of the mesh's size, its normal (octahedral filter) within
            // a few degrees.
            assert_eq!(p.indices.len(), d.indices.len(), "{name}");
            let size = p.positions.iter().fold(Vec3::ZERO, |m, q| m.max(q.abs())).max_element();
            let twin = |a: &raystage_scene::Mesh, b: &raystage_scene::Mesh| {
                a.positions.iter().zip(&a.normals).all(|(q, n)| {
                    b.positions.iter().zip(&b.normals).any(|(r, m)| q.distance(*r) <= 1e-4 * size && n.normalize().dot(m.normalize()) > 0.998)
                })
            };
            assert!(twin(p, d) && twin(d, p), "{name}");
        }
    }
}

/// `bytes`, a binary glTF, with its JSON changed by `edit`.
fn edited_glb(bytes: &[u8], edit: impl FnOnce(&mut Value)) -> Vec<u8> {
    let file = gltf::binary::Glb::from_slice(bytes).unwrap();
    let mut document: Value = serde_json::from_slice(&file.json).unwrap();
    edit(&mut document);
    glb(&document, &file.bin.unwrap())
}

#[test]
fn broken_compressed_buffers_are_refused_with_the_part_named() {
    let (_, _, compressed) = gltfpack_files()[0];
    let refused_glb = |edit: &dyn Fn(&mut Value)| read(&edited_glb(compressed, |d| edit(d)), None, &Limits::default()).unwrap_err();
    let extension = "bufferViews[0].extensions.EXT_meshopt_compression";

    // Arguments meshoptimizer's decoder would assert on are checked first.
    let err = refused_glb(&|d| d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteStride"] = json!(6));
    assert_eq!(err.field(), Some(format!("{extension}.byteStride").as_str()), "{err}");
    let err = refused_glb(&|d| d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["filter"] = json!("QUATERNION"));
    assert_eq!(err.field(), Some(format!("{extension}.filter").as_str()), "{err}");
    let err = refused_glb(&|d| d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["mode"] = json!("ZIP"));
    assert_eq!(err.field(), Some(format!("{extension}.mode").as_str()), "{err}");
    // Compressed bytes that are not there, or that decode to more than the view holds.
    let err = refused_glb(&|d| d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteOffset"] = json!(1u64 << 40));
    assert_eq!(err.field(), Some("bufferViews[0]"), "{err}");
    let err = refused_glb(&|d| d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = json!(100_000));
    assert_eq!(err.field(), Some("bufferViews[0]"), "{err}");
    // A fallback buffer larger than the limit is refused before it is made.
    let err = refused_glb(&|d| d["buffers"][1]["byteLength"] = json!(1u64 << 40));
    assert!(matches!(err, ImportError::TooLarge { what: "bytes of decompressed buffers", .. }), "{err}");
}

#[test]
fn damaged_compressed_bytes_are_an_error_or_a_checked_mesh_never_a_crash() {
    for (name, _, compressed) in gltfpack_files() {
        let file = gltf::binary::Glb::from_slice(compressed).unwrap();
        let document: Value = serde_json::from_slice(&file.json).unwrap();
        let bin = file.bin.unwrap().into_owned();
        // Every eighth byte of the compressed data in turn, flipped: each file is either
        // refused or read with every index and number checked as any file's are.
        for at in (0..bin.len()).step_by(8) {
            let mut damaged = bin.clone();
            damaged[at] ^= 0x5a;
            match read(&glb(&document, &damaged), None, &Limits::default()) {
                Ok(_) => {}
                Err(ImportError::Internal) => panic!("{name}: byte {at} broke the reader"),
                Err(_) => {}
            }
        }
    }
}

/// The quad placed three times by one node's `EXT_mesh_gpu_instancing` (moved, turned,
/// scaled), under a parent that moves them all; and the same placements as three child nodes.
fn instanced_quads(instancing: bool) -> Value {
    let translations = [[0.0f32, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 3.0, -1.0]];
    let half = std::f32::consts::FRAC_1_SQRT_2;
    let rotations = [[0.0f32, 0.0, 0.0, 1.0], [0.0, half, 0.0, half], [0.0, 0.0, 0.0, 1.0]];
    let scales = [[1.0f32, 1.0, 1.0], [1.0, 1.0, 1.0], [2.0, 0.5, 1.0]];
    let mut bytes = quad_buffer();
    for values in [translations.concat(), rotations.concat(), scales.concat()] {
        values.iter().for_each(|v| bytes.extend(v.to_le_bytes()));
    }
    let mut document = quad_gltf(Some(data_uri(&bytes)), red(), json!([]));
    document["buffers"][0]["byteLength"] = json!(bytes.len());
    if instancing {
        let views = document["bufferViews"].as_array_mut().unwrap();
        views.extend([json!({ "buffer": 0, "byteOffset": 60, "byteLength": 36 }), json!({ "buffer": 0, "byteOffset": 96, "byteLength": 48 }), json!({ "buffer": 0, "byteOffset": 144, "byteLength": 36 })]);
        let accessors = document["accessors"].as_array_mut().unwrap();
        accessors.extend([
            json!({ "bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3" }),
            json!({ "bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC4" }),
            json!({ "bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC3" }),
        ]);
        document["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing"]);
        document["nodes"] = json!([
            { "translation": [10, 0, 0], "children": [1] },
            { "mesh": 0, "extensions": { "EXT_mesh_gpu_instancing": { "attributes": { "TRANSLATION": 2, "ROTATION": 3, "SCALE": 4 } } } }
        ]);
    } else {
        let children: Vec<Value> =
            (0..3).map(|k| json!({ "mesh": 0, "translation": translations[k], "rotation": rotations[k], "scale": scales[k] })).collect();
        let mut nodes = vec![json!({ "translation": [10, 0, 0], "children": [1, 2, 3] })];
        nodes.extend(children);
        document["nodes"] = json!(nodes);
    }
    document
}

/// The world transforms of a scene's instances.
fn transforms(scene: &Scene) -> Vec<Affine3A> {
    scene.instances().map(|(_, _, t)| t).collect()
}

#[test]
fn a_mesh_repeated_by_gpu_instancing_is_placed_as_child_nodes_would_place_it() {
    let (mut instanced, mut nodes) = (Scene::new(), Scene::new());
    import(&instanced_quads(true)).unwrap().add_to(&mut instanced).unwrap();
    import(&instanced_quads(false)).unwrap().add_to(&mut nodes).unwrap();
    let (instanced, nodes) = (transforms(&instanced), transforms(&nodes));
    assert_eq!(instanced.len(), 3);
    for (a, b) in instanced.iter().zip(&nodes) {
        assert!(a.abs_diff_eq(*b, 1e-6), "{a:?} against {b:?}");
    }
    // The second instance is turned a quarter about y and moved, under the parent's move.
    assert!(instanced[1].transform_point3(Vec3::X).abs_diff_eq(Vec3::new(12.0, 0.0, -1.0), 1e-6));

    // Attributes of different lengths, or none at all, are refused naming the part.
    let mut document = instanced_quads(true);
    document["accessors"][3]["count"] = json!(2);
    assert_eq!(refused(&document).field(), Some("nodes[1].extensions.EXT_mesh_gpu_instancing.attributes.ROTATION"));
    document["nodes"][1]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = json!({});
    assert_eq!(refused(&document).field(), Some("nodes[1].extensions.EXT_mesh_gpu_instancing.attributes"));
    // The instances count against the limit before their transforms are read.
    let limits = Limits { max_instances: 2, ..Limits::default() };
    let err = read(&serde_json::to_vec(&instanced_quads(true)).unwrap(), None, &limits).unwrap_err();
    assert!(matches!(err, ImportError::TooLarge { what: "instances", count: 3, limit: 2 }), "{err}");
}

/// The grove (`scripts/references/grove.py`: one tree placed by 24 nodes on a ground quad)
/// rendered from its camera with the eye-light shading, the file as written or as `gltfpack -mi`
/// gathers its trees into one node that `EXT_mesh_gpu_instancing` repeats.
fn grove(bytes: &[u8]) -> Vec<Vec3> {
    let scene = read(bytes, None, &Limits::default()).unwrap().into_scene().unwrap();
    let settings = raystage_render::RenderSettings { width: 96, height: 64, integrator: raystage_render::Integrator::EyeLight, ..Default::default() };
    let (film, _) = raystage_render::render(&scene.frame(), &settings).unwrap();
    film.pixels().to_vec()
}

#[test]
fn the_grove_that_gltfpack_instances_renders_as_its_nodes() {
    let nodes = grove(include_bytes!("../../demo/assets/instanced/grove.gltf"));
    let packed = include_bytes!("../../demo/assets/instanced/grove.instanced.glb");
    let instanced = grove(packed);
    let differ = |a: &[Vec3]| nodes.iter().zip(a).filter(|(p, q)| (**p - **q).abs().max_element() > 0.02).count();
    // gltfpack quantises the tree (14-bit positions, 8-bit normals): a few pixels on the trees'
    // outlines may change sides.
    assert!(differ(&instanced) <= 20, "{} of {} pixels differ", differ(&instanced), nodes.len());
    // Read as if the extension were not there (the one node's mesh once, where the
    // extension's first element is not), the grove is gone.
    let without = edited_glb(packed, |d| {
        d["nodes"].as_array_mut().unwrap().iter_mut().for_each(|n| drop(n.as_object_mut().unwrap().remove("extensions")));
        d["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    });
    assert!(differ(&grove(&without)) > 500, "{} pixels differ without the extension", differ(&grove(&without)));
}

#[test]
fn a_webp_image_is_preferred_to_its_fallback_and_decoded_texel_for_texel() {
    // scripts/references/webp.py: libwebp's lossless encoding of these sRGB colours.
    let palette: [[[u8; 3]; 4]; 2] =
        [[[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]], [[0, 0, 0], [128, 64, 32], [17, 200, 99], [250, 128, 7]]];
    let webp = include_bytes!("data/palette.webp");
    let uri = |mime: &str, bytes: &[u8]| json!({ "uri": format!("data:{mime};base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes)) });
    let mut document = textured_quad(uri("image/png", &red_blue_png()), 0, &[]);
    document["images"].as_array_mut().unwrap().push(uri("image/webp", webp));
    document["extensionsUsed"] = json!(["EXT_texture_webp"]);
    document["textures"][0]["extensions"] = json!({ "EXT_texture_webp": { "source": 1 } });
    let texels = |document: &Value| {
        let mut scene = Scene::new();
        let added = import(document).unwrap().add_to(&mut scene).unwrap();
        let Texture::Image(image) = scene.texture(added.textures[0]).unwrap() else { panic!("an image texture") };
        (0..image.height()).flat_map(|y| (0..image.width()).map(move |x| (x, y))).map(|(x, y)| image.texel(i64::from(x), i64::from(y))).collect::<Vec<Vec3>>()
    };
    // The base colour is sRGB: each texel is its colour in linear light.
    let expected: Vec<Vec3> = palette.iter().flatten().map(|c| Vec3::from_array(c.map(|v| srgb_to_linear(v as f32 / 255.0)))).collect();
    let decoded = texels(&document);
    assert_eq!(decoded.len(), 8, "the WebP image, not the 2 x 1 fallback");
    for (d, e) in decoded.iter().zip(&expected) {
        assert!(d.abs_diff_eq(*e, 1e-5), "{d} against {e}");
    }
    // A texture whose only image is the WebP one (glTF then allows no `source`).
    document["extensionsRequired"] = json!(["EXT_texture_webp"]);
    document["textures"][0].as_object_mut().unwrap().remove("source");
    assert_eq!(texels(&document), decoded);
    // An extension that names no image is refused, naming it.
    document["textures"][0]["extensions"]["EXT_texture_webp"]["source"] = json!(2);
    assert_eq!(refused(&document).field(), Some("textures[0].extensions.EXT_texture_webp.source"));
}

/// The sRGB transfer function's inverse.
fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}
