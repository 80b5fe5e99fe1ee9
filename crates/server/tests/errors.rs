//! Every class of bad request gets its status and a JSON error naming the field at fault, and
//! none changes a scene or takes the server down.

mod common;

use axum::body::Body;
use axum::http::StatusCode;
use common::*;
use raystage_server::{AppState, Config, Limits, router};
use serde_json::{Value, json};

async fn scene_with_square(app: &axum::Router) -> u64 {
    let s = new_scene(app).await;
    let object = ok(app, "POST", &format!("/scenes/{s}/objects"), json!({ "mesh": square(1.0) }), StatusCode::CREATED).await;
    ok(app, "POST", &format!("/scenes/{s}/instances"), json!({ "object": object["id"] }), StatusCode::CREATED).await;
    s
}

#[tokio::test]
async fn malformed_json_is_400_naming_the_field() {
    let app = app();
    let s = new_scene(&app).await;
    let objects = format!("/scenes/{s}/objects");
    let bad_number = json!({ "mesh": { "positions": [[0, 0, "zero"]] } });
    assert_eq!(fails(&app, "POST", &objects, bad_number, StatusCode::BAD_REQUEST).await, "mesh.positions[0][2]");
    let misspelt = json!({ "mesh": square(1.0), "knid": "static" });
    assert_eq!(fails(&app, "POST", &objects, misspelt, StatusCode::BAD_REQUEST).await, "knid");
    let missing = json!({ "kind": "static" });
    fails(&app, "POST", &objects, missing, StatusCode::BAD_REQUEST).await;
    let bad_kind = json!({ "kind": "wobbly", "mesh": square(1.0) });
    assert_eq!(fails(&app, "POST", &objects, bad_kind, StatusCode::BAD_REQUEST).await, "kind");
    let batch = json!({ "commands": [{ "add_light": { "class": "PointLight" } }, { "add_instance": { "object": 0, "transform": { "translate": [1, 2] } } }] });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/commands"), batch, StatusCode::BAD_REQUEST).await, "commands[1].add_instance.transform.translate");
    let (status, _, body) = send(&app, "POST", &objects, Body::from("{\"mesh\": "), &[]).await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{}", String::from_utf8_lossy(&body));
    let (status, _, _) = send(&app, "GET", &format!("/scenes/{s}/frame.png?width=ten"), Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    let (status, _, body) = send(&app, "GET", &format!("/scenes/{s}/frame.png?widht=10"), Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "unknown query parameters are refused: {}", String::from_utf8_lossy(&body));
}

#[tokio::test]
async fn nan_and_infinity_are_422() {
    let app = app();
    let s = scene_with_square(&app).await;
    let (status, _, body) = send(&app, "PUT", &format!("/scenes/{s}/camera"), Body::from(r#"{"eye": [0, NaN, 5]}"#), &[]).await;
    let body: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!((status, body["error"]["field"].as_str()), (StatusCode::UNPROCESSABLE_ENTITY, Some("eye[1]")), "{body}");
    let (status, _, _) = send(&app, "POST", &format!("/scenes/{s}/lights"), Body::from(r#"{"class": "PointLight", "intensity": Infinity}"#), &[]).await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    // A number too large for 32 bits becomes infinite: refused as well.
    let huge = json!({ "object": 0, "transform": { "translate": [1e39, 0, 0] } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/instances"), huge, StatusCode::UNPROCESSABLE_ENTITY).await, "transform");
    let huge_vertex = json!({ "mesh": { "positions": [[0, 0, 0], [1, 0, 0], [0, 1e39, 0]] } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/objects"), huge_vertex, StatusCode::UNPROCESSABLE_ENTITY).await, "mesh.positions");
    let param = json!({ "params": { "diffuse": [0.5, 1e39, 0.5] } });
    let shader = ok(&app, "POST", &format!("/scenes/{s}/shaders"), json!({ "class": "Diffuse" }), StatusCode::CREATED).await;
    assert_eq!(fails(&app, "PATCH", &format!("/scenes/{s}/shaders/{}", shader["id"]), param, StatusCode::UNPROCESSABLE_ENTITY).await, "params.diffuse");
}

#[tokio::test]
async fn unacceptable_values_are_422_naming_the_field() {
    let app = app();
    let s = scene_with_square(&app).await;
    let frame = |q: &str| format!("/scenes/{s}/frame.png?{q}");
    assert_eq!(fails(&app, "GET", &frame("width=100000"), json!(null), StatusCode::UNPROCESSABLE_ENTITY).await, "width");
    assert_eq!(fails(&app, "GET", &frame("spp=0"), json!(null), StatusCode::UNPROCESSABLE_ENTITY).await, "spp");
    assert_eq!(fails(&app, "GET", &frame("width=4000&height=4000&spp=1000"), json!(null), StatusCode::UNPROCESSABLE_ENTITY).await, "spp");
    assert_eq!(fails(&app, "GET", &frame("integrator=magic"), json!(null), StatusCode::UNPROCESSABLE_ENTITY).await, "integrator");
    let singular = json!({ "object": 0, "transform": { "scale": [1, 0, 1] } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/instances"), singular, StatusCode::UNPROCESSABLE_ENTITY).await, "transform");
    let spot = json!({ "class": "SpotLight", "cone": 95 });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/lights"), spot, StatusCode::UNPROCESSABLE_ENTITY).await, "cone");
    let class = json!({ "class": "Velvet" });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/shaders"), class, StatusCode::UNPROCESSABLE_ENTITY).await, "class");
    let range = json!({ "class": "Glass", "params": { "ior": 9 } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/shaders"), range, StatusCode::UNPROCESSABLE_ENTITY).await, "params.ior");
    let index = json!({ "mesh": { "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 3]] } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/objects"), index, StatusCode::UNPROCESSABLE_ENTITY).await, "mesh.indices");
    let camera = json!({ "target": [0, 0, 5], "eye": [0, 0, 5] });
    assert_eq!(fails(&app, "PUT", &format!("/scenes/{s}/camera"), camera, StatusCode::UNPROCESSABLE_ENTITY).await, "target");
    let positions = json!({ "positions": [[0, 0, 0]] });
    assert_eq!(fails(&app, "PATCH", &format!("/scenes/{s}/objects/0"), positions, StatusCode::UNPROCESSABLE_ENTITY).await, "positions");
    let pick = format!("/scenes/{s}/pick?x=700&y=0");
    assert_eq!(fails(&app, "GET", &pick, json!(null), StatusCode::UNPROCESSABLE_ENTITY).await, "x");
}

#[tokio::test]
async fn unknown_ids_and_routes_are_404() {
    let app = app();
    let s = scene_with_square(&app).await;
    assert_eq!(fails(&app, "GET", "/scenes/99", json!(null), StatusCode::NOT_FOUND).await, "scene");
    assert_eq!(fails(&app, "GET", "/scenes/one", json!(null), StatusCode::NOT_FOUND).await, "scene");
    assert_eq!(fails(&app, "PUT", &format!("/scenes/{s}/objects/7"), json!({ "mesh": square(1.0) }), StatusCode::NOT_FOUND).await, "id");
    assert_eq!(fails(&app, "DELETE", &format!("/scenes/{s}/instances/7"), json!(null), StatusCode::NOT_FOUND).await, "id");
    assert_eq!(fails(&app, "GET", &format!("/scenes/{s}/shaders/7"), json!(null), StatusCode::NOT_FOUND).await, "shader");
    assert_eq!(fails(&app, "GET", &format!("/scenes/{s}/lights/7"), json!(null), StatusCode::NOT_FOUND).await, "id");
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/instances"), json!({ "object": 7 }), StatusCode::NOT_FOUND).await, "object");
    let bound = json!({ "mesh": { "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "shader": 3 } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/objects"), bound, StatusCode::NOT_FOUND).await, "mesh.shader");
    let label = json!({ "commands": [{ "add_instance": { "object": "cube" } }] });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/commands"), label, StatusCode::NOT_FOUND).await, "commands[0].add_instance.object");
    fails(&app, "GET", "/nowhere", json!(null), StatusCode::NOT_FOUND).await;
    fails(&app, "PATCH", "/scenes", json!({}), StatusCode::METHOD_NOT_ALLOWED).await;
}

#[tokio::test]
async fn oversized_requests_are_413() {
    let limits = Limits { max_body_bytes: 4096, max_triangles: 4, max_commands: 3, max_dimension: 16, ..Limits::default() };
    let app = router(AppState::new(Config { limits, ..Config::default() }));
    let s = new_scene(&app).await;
    let big = json!({ "mesh": { "positions": vec![[0.0, 0.0, 0.0]; 400] } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/objects"), big, StatusCode::PAYLOAD_TOO_LARGE).await, "");
    let many = json!({ "mesh": { "positions": vec![[0.0, 0.0, 0.0]; 15] } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/objects"), many, StatusCode::PAYLOAD_TOO_LARGE).await, "mesh.positions");
    let batch = json!({ "commands": vec![json!({ "set_camera": {} }); 4] });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/commands"), batch, StatusCode::PAYLOAD_TOO_LARGE).await, "commands");
    let (status, _, _) = send(&app, "POST", &format!("/scenes/{s}/gltf"), Body::from(vec![b' '; 5000]), &[]).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE);
    let (status, _, _) = send(&app, "POST", &format!("/scenes/{s}/textures"), Body::from(vec![0u8; 5000]), &[("content-type", "image/png")]).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE, "an image body over the body limit");
    // A few hundred bytes of PNG that would decode to an image wider than the limit.
    let mut wide = std::io::Cursor::new(Vec::new());
    image::RgbImage::new(64, 2).write_to(&mut wide, image::ImageFormat::Png).unwrap();
    let (status, _, body) = send(&app, "POST", &format!("/scenes/{s}/textures"), Body::from(wide.into_inner()), &[("content-type", "image/png")]).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE, "{}", String::from_utf8_lossy(&body));
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["textures"], 0);
}

#[tokio::test]
async fn a_failed_batch_changes_nothing() {
    let app = app();
    let s = scene_with_square(&app).await;
    let before = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await;
    let batch = json!({ "commands": [
        { "add_object": { "label": "tri", "mesh": { "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]] } } },
        { "add_instance": { "object": "tri" } },
        { "delete_object": { "id": 0 } },
        { "set_camera": { "fov_y_degrees": 10 } },
        { "add_light": { "class": "PointLight", "position": [0, 3, 0] } },
        { "add_instance": { "object": 0 } }
    ] });
    let field = fails(&app, "POST", &format!("/scenes/{s}/commands"), batch, StatusCode::NOT_FOUND).await;
    assert_eq!(field, "commands[5].add_instance.object", "object 0 was deleted by command 2");
    let after = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await;
    assert_eq!(before, after);
    // Deleting an object deletes its instances within the batch too.
    let cascade = json!({ "commands": [{ "delete_object": { "id": 0 } }, { "delete_instance": { "id": 0 } }] });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/commands"), cascade, StatusCode::NOT_FOUND).await, "commands[1].delete_instance.id");
    let relabel = json!({ "commands": [{ "add_shader": { "label": "a", "class": "Diffuse" } }, { "add_light": { "label": "a", "class": "AmbientLight" } }] });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/commands"), relabel, StatusCode::UNPROCESSABLE_ENTITY).await, "commands[1].add_light.label");
    let wrong_kind = json!({ "commands": [{ "add_shader": { "label": "a", "class": "Diffuse" } }, { "add_instance": { "object": "a" } }] });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/commands"), wrong_kind, StatusCode::UNPROCESSABLE_ENTITY).await, "commands[1].add_instance.object");
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await, before);
}

#[tokio::test]
async fn a_token_guards_every_route() {
    let app = router(AppState::new(Config { token: Some("s3cret".into()), ..Config::default() }));
    let (status, _, body) = send(&app, "GET", "/scenes", Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    assert_eq!(serde_json::from_slice::<Value>(&body).unwrap()["error"]["code"], "unauthorized");
    let (status, _, _) = send(&app, "GET", "/scenes", Body::empty(), &[("authorization", "Bearer wrong!")]).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    let (status, _, _) = send(&app, "GET", "/openapi.json", Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    let (status, _, _) = send(&app, "GET", "/scenes?token=s3cret", Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED, "the query token is for streams only");
    let (status, _, _) = send(&app, "GET", "/scenes", Body::empty(), &[("authorization", "Bearer s3cret")]).await;
    assert_eq!(status, StatusCode::OK);
    // The scheme's case does not matter (RFC 9110); the token's does.
    let (status, _, _) = send(&app, "GET", "/scenes", Body::empty(), &[("authorization", "bearer s3cret")]).await;
    assert_eq!(status, StatusCode::OK);
    let (status, _, _) = send(&app, "GET", "/scenes", Body::empty(), &[("authorization", "Bearer S3CRET")]).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
}

#[tokio::test]
async fn a_blank_token_is_refused_at_start_up() {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let state = AppState::new(Config { token: Some("  ".into()), ..Config::default() });
    let error = raystage_server::serve(listener, state, std::future::pending()).await.unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::PermissionDenied);
    assert!(error.to_string().contains("blank token"), "{error}");
}

/// A small deterministic generator for the fuzz test.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        self.0 >> 33
    }
}

#[tokio::test]
async fn mangled_requests_never_fail_on_the_server_side() {
    let app = app();
    let s = scene_with_square(&app).await;
    let seeds = [
        (format!("/scenes/{s}/objects"), json!({ "kind": "unstructured", "mesh": { "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]], "shader": 0 } })),
        (format!("/scenes/{s}/instances"), json!({ "object": 0, "transform": { "translate": [1, 2, 3], "rotate": { "axis": [0, 1, 0], "degrees": 30 }, "scale": 2 } })),
        (format!("/scenes/{s}/lights"), json!({ "class": "SpotLight", "position": [0, 5, 0], "direction": [0, -1, 0], "cone": 40, "falloff": 30 })),
        (format!("/scenes/{s}/commands"), json!({ "commands": [{ "add_shader": { "label": "x", "class": "Phong", "params": { "shininess": 10 } } }, { "set_camera": { "eye": [1, 2, 3] } }] })),
        (format!("/scenes/{s}/textures"), json!({ "kind": "checker", "a": [1, 0, 0.5], "b": 0.25, "scale": 4 })),
        (format!("/scenes/{s}/commands"), json!({ "commands": [{ "add_texture": { "label": "t", "kind": "noise" } }, { "add_shader": { "class": "Diffuse", "params": { "diffuse_texture": { "texture": "t" } } } }, { "add_light": { "class": "EnvironmentLight", "map": "t" } }] })),
    ];
    let mut rng = Lcg(7);
    for _ in 0..300 {
        let (uri, seed) = &seeds[rng.next() as usize % seeds.len()];
        let mut bytes = seed.to_string().into_bytes();
        for _ in 0..1 + rng.next() % 4 {
            let at = rng.next() as usize % bytes.len();
            bytes[at] = b"0123456789-.e,[]{}\":nN aZ"[rng.next() as usize % 25];
        }
        let (status, _, body) = send(&app, "POST", uri, Body::from(bytes.clone()), &[]).await;
        assert!(status.is_success() || status.is_client_error(), "{status} for {}: {}", String::from_utf8_lossy(&bytes), String::from_utf8_lossy(&body));
    }
    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=16&height=16&integrator=eyelight")).await;
    assert_eq!(image.dimensions(), (16, 16), "the scene still renders");
}
