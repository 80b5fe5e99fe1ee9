//! glTF uploads: a file written in the test (JSON with an embedded base64 buffer, and the same
//! as GLB) becomes a scene that renders; broken files are refused and change nothing.

mod common;

use axum::body::Body;
use axum::http::StatusCode;
use base64::Engine;
use common::*;
use serde_json::{Value, json};

fn embedded() -> Vec<u8> {
    let uri = format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(square_buffer()));
    serde_json::to_vec(&document(Some(uri))).unwrap()
}


async fn upload(app: &axum::Router, uri: &str, body: Vec<u8>, content_type: &str) -> (StatusCode, Value) {
    let (status, _, bytes) = send(app, "POST", uri, Body::from(body), &[("content-type", content_type)]).await;
    (status, serde_json::from_slice(&bytes).unwrap())
}

#[tokio::test]
async fn a_gltf_file_becomes_a_scene_seen_through_its_camera() {
    let app = app();
    for (body, content_type) in [(embedded(), "model/gltf+json"), (glb(), "model/gltf-binary")] {
        let (status, info) = upload(&app, "/scenes", body, content_type).await;
        assert_eq!(status, StatusCode::CREATED, "{info}");
        assert_eq!((info["origin"].as_str(), info["objects"].as_u64(), info["instances"].as_u64()), (Some("gltf"), Some(1), Some(2)));
        assert_eq!(info["camera"]["eye"], json!([0.0, 0.0, 3.0]));
        let s = info["id"].as_u64().unwrap();
        let image = frame(&app, &format!("/scenes/{s}/frame.png?width=80&height=40&integrator=eyelight")).await;
        let orange = [255, 188, 0, 255];
        assert_eq!(image.get_pixel(27, 20).0, orange, "the left square");
        assert_eq!(image.get_pixel(53, 20).0, orange, "the right square");
        assert_ne!(image.get_pixel(40, 20).0, orange, "the gap between them");
    }
}

#[tokio::test]
async fn an_upload_adds_to_a_scene_and_a_broken_one_changes_nothing() {
    let app = app();
    let s = new_scene(&app).await;
    let (status, added) = upload(&app, &format!("/scenes/{s}/gltf?camera=keep"), glb(), "model/gltf-binary").await;
    assert_eq!(status, StatusCode::OK, "{added}");
    assert_eq!((added["objects"].as_array().unwrap().len(), added["instances"].as_array().unwrap().len()), (1, 2));
    assert_eq!((added["triangles"].as_u64(), added["camera_changed"].as_bool()), (Some(2), Some(false)));
    let shader = ok(&app, "GET", &format!("/scenes/{s}/shaders/{}", added["shaders"][0]), json!(null), StatusCode::OK).await;
    assert_eq!((&shader["class"], &shader["name"]), (&json!("Constant"), &json!("orange")), "named after its material");
    // The scene's shaders, listed: id, class and name.
    let shaders = ok(&app, "GET", &format!("/scenes/{s}/shaders"), json!(null), StatusCode::OK).await;
    assert_eq!(shaders, json!([{ "id": added["shaders"][0], "class": "Constant", "name": "orange" }]));
    let before = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await;
    let (status, error) = upload(&app, &format!("/scenes/{s}/gltf"), b"{ not gltf".to_vec(), "model/gltf+json").await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{error}");
    let mut lying = document(Some(format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(square_buffer()))));
    lying["accessors"][0]["count"] = json!(4000);
    let (status, error) = upload(&app, &format!("/scenes/{s}/gltf"), serde_json::to_vec(&lying).unwrap(), "model/gltf+json").await;
    assert_eq!((status, error["error"]["field"].as_str()), (StatusCode::UNPROCESSABLE_ENTITY, Some("meshes[0].primitives[0].attributes.POSITION")));
    let external = document(Some("square.bin".into()));
    let (status, error) = upload(&app, &format!("/scenes/{s}/gltf"), serde_json::to_vec(&external).unwrap(), "model/gltf+json").await;
    assert_eq!((status, error["error"]["field"].as_str()), (StatusCode::UNPROCESSABLE_ENTITY, Some("buffers[0].uri")));
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await, before);
    // Every byte of the GLB flipped in turn: refused or imported, never a server error.
    let good = glb();
    for at in (0..good.len()).step_by(3) {
        let mut bad = good.clone();
        bad[at] ^= 0xa5;
        let (status, body) = upload(&app, "/scenes/999/gltf", bad.clone(), "model/gltf-binary").await;
        assert_eq!(status, StatusCode::NOT_FOUND, "{body}");
        let version = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"].clone();
        let (status, body) = upload(&app, &format!("/scenes/{s}/gltf?camera=keep"), bad, "model/gltf-binary").await;
        assert!(status.is_success() || status.is_client_error(), "byte {at}: {status} {body}");
        if !status.is_success() {
            assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"], version);
        }
    }
}

#[tokio::test]
async fn an_import_may_light_the_scene_with_a_uniform_environment() {
    let app = app();
    let (status, info) = upload(&app, "/scenes?environment=0.25,0.5,1", glb(), "model/gltf-binary").await;
    assert_eq!((status, info["lights"].as_u64()), (StatusCode::CREATED, Some(1)), "{info}");
    let s = info["id"].as_u64().unwrap();
    let lights = ok(&app, "GET", &format!("/scenes/{s}/lights"), Value::Null, StatusCode::OK).await;
    assert_eq!((lights[0]["class"].as_str(), &lights[0]["radiance"]), (Some("EnvironmentLight"), &json!([0.25, 0.5, 1.0])), "{lights}");

    let s = new_scene(&app).await;
    let (status, added) = upload(&app, &format!("/scenes/{s}/gltf?environment=2"), glb(), "model/gltf-binary").await;
    assert_eq!((status, added["lights"].as_array().map(Vec::len)), (StatusCode::OK, Some(1)), "{added}");
    let lights = ok(&app, "GET", &format!("/scenes/{s}/lights"), Value::Null, StatusCode::OK).await;
    assert_eq!(lights[0]["radiance"], json!([2.0, 2.0, 2.0]));

    for bad in ["-1", "1,2", "sky", "1,nan,1"] {
        for uri in [format!("/scenes?environment={bad}"), format!("/scenes/{s}/gltf?environment={bad}")] {
            let (status, error) = upload(&app, &uri, glb(), "model/gltf-binary").await;
            assert_eq!((status, error["error"]["field"].as_str()), (StatusCode::UNPROCESSABLE_ENTITY, Some("environment")), "{uri}: {error}");
        }
    }
    let scenes = ok(&app, "GET", "/scenes", Value::Null, StatusCode::OK).await;
    assert_eq!(scenes.as_array().unwrap().len(), 2, "refused imports add no scene");
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), Value::Null, StatusCode::OK).await["lights"], 1, "nor change one");
}

/// A file without lights of its own is lit by the studio environment by default, as glTF
/// viewers light it (and path traced where no integrator is named); `environment=none` leaves it
/// unlit, `environment=studio` asks for the studio in any case, a file with a lamp or a scene
/// with lights gets none by default.
#[tokio::test]
async fn a_file_without_lights_is_lit_by_the_studio_by_default() {
    let app = app();
    let studio = |lights: &Value| lights.as_array().unwrap().iter().filter(|l| l["class"] == "EnvironmentLight" && !l["map"].is_null()).count();
    let (status, info) = upload(&app, "/scenes", glb(), "model/gltf-binary").await;
    assert_eq!((status, info["lights"].as_u64()), (StatusCode::CREATED, Some(1)), "{info}");
    let s = info["id"].as_u64().unwrap();
    let lights = ok(&app, "GET", &format!("/scenes/{s}/lights"), Value::Null, StatusCode::OK).await;
    assert_eq!(studio(&lights), 1, "{lights}");
    frame(&app, &format!("/scenes/{s}/frame.png?width=16&height=16")).await;
    let stats = ok(&app, "GET", &format!("/scenes/{s}/stats"), Value::Null, StatusCode::OK).await;
    assert_eq!(stats["last_frame"]["integrator"], "path", "an image environment is path traced by default: {stats}");

    // Added to a scene that has lights: none by default, the studio when asked for.
    let (status, added) = upload(&app, &format!("/scenes/{s}/gltf?camera=keep"), glb(), "model/gltf-binary").await;
    assert_eq!((status, added["lights"].as_array().map(Vec::len)), (StatusCode::OK, Some(0)), "{added}");
    let (status, added) = upload(&app, &format!("/scenes/{s}/gltf?camera=keep&environment=studio"), glb(), "model/gltf-binary").await;
    assert_eq!((status, added["lights"].as_array().map(Vec::len)), (StatusCode::OK, Some(1)), "{added}");

    let (status, info) = upload(&app, "/scenes?environment=none", glb(), "model/gltf-binary").await;
    assert_eq!((status, info["lights"].as_u64()), (StatusCode::CREATED, Some(0)), "{info}");
    let mut lamp = document(Some(format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(square_buffer()))));
    lamp["extensionsUsed"] = json!(["KHR_materials_unlit", "KHR_lights_punctual"]);
    lamp["extensions"] = json!({ "KHR_lights_punctual": { "lights": [{ "type": "point", "intensity": 5 }] } });
    lamp["nodes"].as_array_mut().unwrap().push(json!({ "translation": [0, 0, 2], "extensions": { "KHR_lights_punctual": { "light": 0 } } }));
    let last = lamp["nodes"].as_array().unwrap().len() - 1;
    lamp["scenes"][0]["nodes"].as_array_mut().unwrap().push(json!(last));
    let (status, info) = upload(&app, "/scenes", serde_json::to_vec(&lamp).unwrap(), "model/gltf+json").await;
    assert_eq!((status, info["lights"].as_u64()), (StatusCode::CREATED, Some(1)), "the file's lamp alone: {info}");
    let lights = ok(&app, "GET", &format!("/scenes/{}/lights", info["id"]), Value::Null, StatusCode::OK).await;
    assert_eq!(studio(&lights), 0, "{lights}");
}

/// A file whose images take longer to decode than a render may run is refused (413 naming
/// `max_render_seconds`) and changes nothing; the images are decoded only once the file is
/// within the limits (issue 38: a small file naming many large images held a core for minutes).
#[tokio::test]
async fn an_upload_whose_images_take_too_long_is_refused() {
    let mut png = std::io::Cursor::new(Vec::new());
    image::RgbImage::from_pixel(4, 4, image::Rgb([200, 100, 50])).write_to(&mut png, image::ImageFormat::Png).unwrap();
    let png = png.into_inner();
    let mut document = document(None);
    let uvs: Vec<u8> = [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]].iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let bin = [square_buffer(), uvs, png.clone()].concat();
    document["buffers"][0]["byteLength"] = json!(bin.len());
    document["bufferViews"].as_array_mut().unwrap().extend([
        json!({ "buffer": 0, "byteOffset": 60, "byteLength": 32 }),
        json!({ "buffer": 0, "byteOffset": 92, "byteLength": png.len() }),
    ]);
    document["accessors"].as_array_mut().unwrap().push(json!({ "bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2" }));
    document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(2);
    document["images"] = json!([{ "bufferView": 3, "mimeType": "image/png" }]);
    document["textures"] = json!([{ "source": 0 }]);
    // A lit material, whose base colour texture the importer decodes.
    document["materials"][0] = json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } });
    let file = raystage_gltf_import::glb(&serde_json::to_vec(&document).unwrap(), &bin);

    let state = raystage_server::AppState::new(raystage_server::Config {
        limits: raystage_server::Limits { max_render_seconds: 0, ..raystage_server::Limits::default() },
        ..raystage_server::Config::default()
    });
    let app = raystage_server::router(state);
    let s = new_scene(&app).await;
    let (status, error) = upload(&app, &format!("/scenes/{s}/gltf"), file.clone(), "model/gltf-binary").await;
    assert_eq!((status, error["error"]["limit"].as_str()), (StatusCode::PAYLOAD_TOO_LARGE, Some("max_render_seconds")), "{error}");
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), Value::Null, StatusCode::OK).await["instances"], 0);
    let (status, added) = upload(&app_with_defaults().await, "/scenes/1/gltf", file, "model/gltf-binary").await;
    assert_eq!(status, StatusCode::OK, "{added}");
}

/// A fresh server with one empty scene (id 1).
async fn app_with_defaults() -> axum::Router {
    let app = app();
    new_scene(&app).await;
    app
}
