//! Helpers for driving the API in-process: requests through `tower::ServiceExt::oneshot`,
//! JSON in and out, PNG bodies decoded.

#![allow(dead_code, reason = "each test file uses some of the helpers")]

use axum::Router;
use axum::body::Body;
use axum::http::{Request, StatusCode};
use http_body_util::BodyExt;
use raystage_server::{AppState, Config, router};
use serde_json::{Value, json};
use tower::ServiceExt;

/// A fresh server with the default configuration.
pub fn app() -> Router {
    router(AppState::new(Config::default()))
}

/// Sends a request; returns the status, the content type and the body.
pub async fn send(app: &Router, method: &str, uri: &str, body: Body, headers: &[(&str, &str)]) -> (StatusCode, String, Vec<u8>) {
    let mut request = Request::builder().method(method).uri(uri);
    for (name, value) in headers {
        request = request.header(*name, *value);
    }
    let response = app.clone().oneshot(request.body(body).unwrap()).await.unwrap();
    let status = response.status();
    let content_type = response.headers().get("content-type").map(|v| v.to_str().unwrap().to_string()).unwrap_or_default();
    let bytes = response.into_body().collect().await.unwrap().to_bytes().to_vec();
    (status, content_type, bytes)
}

/// Sends JSON (or nothing, for `Value::Null`); returns the status and the JSON body.
pub async fn call(app: &Router, method: &str, uri: &str, body: Value) -> (StatusCode, Value) {
    let body = if body.is_null() { Body::empty() } else { Body::from(body.to_string()) };
    let (status, content_type, bytes) = send(app, method, uri, body, &[("content-type", "application/json")]).await;
    assert!(content_type.starts_with("application/json"), "{method} {uri}: {status} with content type `{content_type}`");
    (status, serde_json::from_slice(&bytes).unwrap())
}

/// Sends JSON that must succeed with `expected`; returns the body.
pub async fn ok(app: &Router, method: &str, uri: &str, body: Value, expected: StatusCode) -> Value {
    let (status, value) = call(app, method, uri, body).await;
    assert_eq!(status, expected, "{method} {uri}: {value}");
    value
}

/// A request that must fail with `status`; returns the error's `field` (or "" for none) and
/// checks the body has the documented shape.
pub async fn fails(app: &Router, method: &str, uri: &str, body: Value, status: StatusCode) -> String {
    let (got, value) = call(app, method, uri, body).await;
    assert_eq!(got, status, "{method} {uri}: {value}");
    let error = &value["error"];
    assert!(error["code"].is_string() && error["message"].is_string(), "{value}");
    error["field"].as_str().unwrap_or("").to_string()
}

/// A new empty scene; returns its id.
pub async fn new_scene(app: &Router) -> u64 {
    ok(app, "POST", "/scenes", json!({}), StatusCode::CREATED).await["id"].as_u64().unwrap()
}

/// A frame, decoded.
pub async fn frame(app: &Router, uri: &str) -> image::RgbaImage {
    let (status, content_type, bytes) = send(app, "GET", uri, Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&bytes));
    assert_eq!(content_type, "image/png");
    image::load_from_memory(&bytes).unwrap().to_rgba8()
}

/// A square in the z = 0 plane from (-s, -s) to (s, s), facing +z (the default camera).
pub fn square(s: f32) -> Value {
    json!({ "positions": [[-s, -s, 0], [s, -s, 0], [s, s, 0], [-s, s, 0]], "indices": [[0, 1, 2], [0, 2, 3]] })
}

/// A new scene holding a red `Constant` square (±1, facing the default camera) placed once;
/// the scene's id, the shader and the instance as the API answered them.
pub async fn red_square_scene(app: &Router) -> (u64, Value, Value) {
    let s = new_scene(app).await;
    let red = ok(app, "POST", &format!("/scenes/{s}/shaders"), json!({ "class": "Constant", "params": { "color": [1, 0, 0] } }), StatusCode::CREATED).await;
    let mut mesh = square(1.0);
    mesh["shader"] = red["id"].clone();
    let object = ok(app, "POST", &format!("/scenes/{s}/objects"), json!({ "mesh": mesh }), StatusCode::CREATED).await;
    let instance = ok(app, "POST", &format!("/scenes/{s}/instances"), json!({ "object": object["id"] }), StatusCode::CREATED).await;
    (s, red, instance)
}

/// A new scene holding a grey diffuse square (albedo 0.5), `size` from its centre to each edge,
/// facing the default camera; its id.
pub async fn grey_square_scene(app: &Router, size: f32) -> u64 {
    let s = new_scene(app).await;
    let grey = ok(app, "POST", &format!("/scenes/{s}/shaders"), json!({ "class": "Diffuse", "params": { "diffuse": 0.5 } }), StatusCode::CREATED).await;
    let mut mesh = square(size);
    mesh["shader"] = grey["id"].clone();
    let object = ok(app, "POST", &format!("/scenes/{s}/objects"), json!({ "mesh": mesh }), StatusCode::CREATED).await;
    ok(app, "POST", &format!("/scenes/{s}/instances"), json!({ "object": object["id"] }), StatusCode::CREATED).await;
    s
}

/// Serves `state` on a free loopback port until the test ends; returns the address.
pub async fn listen(state: AppState) -> std::net::SocketAddr {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(raystage_server::serve(listener, state, std::future::pending()));
    addr
}

/// Polls `done` every 20 ms until it holds or `deadline` passes; whether it held.
pub async fn eventually(deadline: std::time::Duration, mut done: impl FnMut() -> bool) -> bool {
    let start = std::time::Instant::now();
    while start.elapsed() < deadline {
        if done() {
            return true;
        }
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    done()
}

/// Two triangles forming a unit square in the xy plane, centred on the origin.
pub fn square_buffer() -> Vec<u8> {
    let mut bytes = Vec::new();
    for p in [[-0.5f32, -0.5, 0.0], [0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [-0.5, 0.5, 0.0]] {
        p.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bytes.extend(i.to_le_bytes());
    }
    bytes
}

/// A glTF document: the square as one mesh with an unlit orange material, placed by two nodes
/// side by side, and a camera looking at them; buffer 0 as `uri` (or the GLB chunk).
pub fn document(uri: Option<String>) -> Value {
    let mut buffer = json!({ "byteLength": 60 });
    if let Some(uri) = uri {
        buffer["uri"] = json!(uri);
    }
    json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_materials_unlit"],
        "buffers": [buffer],
        "bufferViews": [{ "buffer": 0, "byteLength": 48 }, { "buffer": 0, "byteOffset": 48, "byteLength": 12 }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0] },
            { "bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR" }
        ],
        "materials": [{ "name": "orange", "pbrMetallicRoughness": { "baseColorFactor": [1, 0.5, 0, 1] }, "extensions": { "KHR_materials_unlit": {} } }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1, "material": 0 }] }],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1 } }],
        "nodes": [
            { "mesh": 0, "translation": [-0.6, 0, 0] },
            { "mesh": 0, "translation": [0.6, 0, 0] },
            { "camera": 0, "translation": [0, 0, 3] }
        ],
        "scenes": [{ "nodes": [0, 1, 2] }]
    })
}

/// [`document`] as GLB, the square's buffer in its binary chunk.
pub fn glb() -> Vec<u8> {
    raystage_gltf_import::glb(&serde_json::to_vec(&document(None)).unwrap(), &square_buffer())
}

/// [`document`] with an animation `slide` that moves the left square (node 0) from x = −0.6
/// at 0 s to x = 0.4 at 1 s, linearly: keyframe times and values follow the square's buffer.
pub fn animated_glb() -> Vec<u8> {
    let mut bin = square_buffer();
    [0.0f32, 1.0, -0.6, 0.0, 0.0, 0.4, 0.0, 0.0].iter().for_each(|f| bin.extend(f.to_le_bytes()));
    let mut doc = document(None);
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    let views = doc["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 0, "byteOffset": 60, "byteLength": 8 }));
    views.push(json!({ "buffer": 0, "byteOffset": 68, "byteLength": 24 }));
    let accessors = doc["accessors"].as_array_mut().unwrap();
    accessors.push(json!({ "bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1] }));
    accessors.push(json!({ "bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3" }));
    doc["animations"] = json!([{ "name": "slide", "channels": [{ "sampler": 0, "target": { "node": 0, "path": "translation" } }],
        "samplers": [{ "input": 2, "output": 3, "interpolation": "LINEAR" }] }]);
    raystage_gltf_import::glb(&serde_json::to_vec(&doc).unwrap(), &bin)
}
