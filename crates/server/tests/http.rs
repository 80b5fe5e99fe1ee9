//! The API end to end, in-process: build scenes through JSON, render them, decode the PNGs and
//! look at their pixels.

mod common;

use axum::http::StatusCode;
use common::*;
use serde_json::json;

#[tokio::test]
async fn a_scene_built_from_json_renders_as_described() {
    let app = app();
    let (s, red, instance) = red_square_scene(&app).await;

    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=64&height=48&integrator=eyelight")).await;
    assert_eq!(image.dimensions(), (64, 48));
    assert_eq!(image.get_pixel(32, 24).0, [255, 0, 0, 255], "the square fills the centre");
    assert_ne!(image.get_pixel(1, 1).0, [255, 0, 0, 255], "but not the corner");

    // Move the instance right: the left of the centre is uncovered.
    let uri = format!("/scenes/{s}/instances/{}", instance["id"]);
    ok(&app, "PUT", &uri, json!({ "transform": { "translate": [1.5, 0, 0] } }), StatusCode::OK).await;
    let moved = frame(&app, &format!("/scenes/{s}/frame.png?width=64&height=48&integrator=eyelight")).await;
    assert_ne!(moved.get_pixel(24, 24).0, [255, 0, 0, 255]);
    assert_eq!(moved.get_pixel(50, 24).0, [255, 0, 0, 255]);

    // A parameter write changes every triangle bound to the shader.
    ok(&app, "PATCH", &format!("/scenes/{s}/shaders/{}", red["id"]), json!({ "params": { "color": [0, 0, 1] } }), StatusCode::OK).await;
    let blue = frame(&app, &format!("/scenes/{s}/frame.png?width=64&height=48&integrator=eyelight")).await;
    assert_eq!(blue.get_pixel(50, 24).0, [0, 0, 255, 255]);
}


#[tokio::test]
async fn lights_make_whitted_the_default_and_shade_diffuse_surfaces() {
    let app = app();
    let s = grey_square_scene(&app, 1.0).await;
    // Nothing lights it: the renderer's default sky does, and the statistics say so.
    let sky_lit = frame(&app, &format!("/scenes/{s}/frame.png?width=32&height=32&integrator=whitted")).await;
    assert!(sky_lit.get_pixel(16, 16).0[2] > 100, "the sky lights the square: {:?}", sky_lit.get_pixel(16, 16));
    let stats = ok(&app, "GET", &format!("/scenes/{s}/stats"), json!(null), StatusCode::OK).await;
    assert_eq!((&stats["last_frame"]["default_lights"], &stats["last_frame"]["non_finite_samples"]), (&json!(true), &json!(0)));

    let light = ok(&app, "POST", &format!("/scenes/{s}/lights"), json!({ "class": "DirectionalLight", "direction": [0, 0, -1], "intensity": 2.5 }), StatusCode::CREATED).await;
    let lit = frame(&app, &format!("/scenes/{s}/frame.png?width=32&height=32")).await;
    let value = lit.get_pixel(16, 16).0[0];
    // Albedo 0.5 under irradiance 2.5: radiance 0.5 × 2.5 / π = 0.398, sRGB 170.
    assert!((168..=172).contains(&value), "{value}");
    let stats = ok(&app, "GET", &format!("/scenes/{s}/stats"), json!(null), StatusCode::OK).await;
    assert_eq!(stats["last_frame"]["integrator"], "whitted");
    assert_eq!(stats["last_frame"]["default_lights"], json!(false));
    assert!(stats["last_frame"]["rays"]["shadow"].as_u64().unwrap() > 0);

    let lights = ok(&app, "GET", &format!("/scenes/{s}/lights"), json!(null), StatusCode::OK).await;
    assert_eq!(lights[0]["class"], "DirectionalLight");
    assert_eq!(lights[0]["intensity"], json!([2.5, 2.5, 2.5]));
    ok(&app, "DELETE", &format!("/scenes/{s}/lights/{}", light["id"]), json!(null), StatusCode::OK).await;
    let info = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await;
    assert_eq!((info["lights"].as_u64(), info["objects"].as_u64(), info["triangles"].as_u64()), (Some(0), Some(1), Some(2)));
}

#[tokio::test]
async fn a_batch_builds_a_scene_with_labels_and_reports_each_command() {
    let app = app();
    let s = new_scene(&app).await;
    let batch = json!({ "commands": [
        { "add_shader": { "label": "green", "class": "Constant", "params": { "color": [0, 1, 0], "shininess": 3 } } },
        { "add_object": { "label": "square", "mesh": { "positions": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], "indices": [[0, 1, 2], [0, 2, 3]], "shader": "green" } } },
        { "add_instance": { "label": "left", "object": "square", "transform": { "translate": [-1, 0, 0], "scale": 0.5 } } },
        { "add_instance": { "object": "square", "transform": { "matrix": [[0.5, 0, 0, 1], [0, 0.5, 0, 0], [0, 0, 0.5, 0], [0, 0, 0, 1]] } } },
        { "set_camera": { "eye": [0, 0, 4] } }
    ] });
    let result = ok(&app, "POST", &format!("/scenes/{s}/commands"), batch, StatusCode::OK).await;
    let results = result["results"].as_array().unwrap();
    assert_eq!(results.len(), 5);
    assert_eq!(results[0]["ignored"], json!(["shininess"]), "Constant has no shininess: ignored, as in the C ABI");
    assert!(results[1]["id"].is_u64() && results[2]["id"].is_u64() && results[3]["id"].is_u64());
    assert_eq!(result["version"], 1, "one batch, one version");

    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=64&height=32&integrator=eyelight")).await;
    assert_eq!(image.get_pixel(22, 16).0, [0, 255, 0, 255], "left square");
    assert_eq!(image.get_pixel(42, 16).0, [0, 255, 0, 255], "right square");
    assert_ne!(image.get_pixel(32, 16).0, [0, 255, 0, 255], "a gap between them");
    let instances = ok(&app, "GET", &format!("/scenes/{s}/instances"), json!(null), StatusCode::OK).await;
    assert_eq!(instances[1]["matrix"][0], json!([0.5, 0.0, 0.0, 1.0]));
}

#[tokio::test]
async fn put_redefines_and_patch_moves_vertices_of_an_object_and_its_instances() {
    let app = app();
    let s = new_scene(&app).await;
    let object = ok(&app, "POST", &format!("/scenes/{s}/objects"), json!({ "kind": "unstructured", "mesh": square(0.2) }), StatusCode::CREATED).await;
    let o = object["id"].as_u64().unwrap();
    ok(&app, "POST", &format!("/scenes/{s}/instances"), json!({ "object": o }), StatusCode::CREATED).await;
    let pick = |x: u32| format!("/scenes/{s}/pick?x={x}&y=24&width=64&height=48");
    assert!(ok(&app, "GET", &pick(32), json!(null), StatusCode::OK).await["hit"].is_object());
    assert!(ok(&app, "GET", &pick(10), json!(null), StatusCode::OK).await["hit"].is_null());

    // PUT: a bigger square, as base64; the instance follows.
    let positions: Vec<u8> = [[-2.0f32, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]].iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
    let indices: Vec<u8> = [0u32, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()).collect();
    use base64::Engine;
    let b64 = |b: &[u8]| base64::engine::general_purpose::STANDARD.encode(b);
    let mesh = json!({ "positions_base64": b64(&positions), "indices_base64": b64(&indices) });
    ok(&app, "PUT", &format!("/scenes/{s}/objects/{o}"), json!({ "mesh": mesh }), StatusCode::OK).await;
    let hit = ok(&app, "GET", &pick(10), json!(null), StatusCode::OK).await;
    assert_eq!(hit["hit"]["object"], o);
    let info = ok(&app, "GET", &format!("/scenes/{s}/objects/{o}"), json!(null), StatusCode::OK).await;
    assert_eq!((info["kind"].as_str(), info["triangles"].as_u64()), (Some("unstructured"), Some(2)));

    // PATCH: the same vertices moved far away.
    let far = json!({ "positions": [[10, 10, 0], [11, 10, 0], [11, 11, 0], [10, 11, 0]] });
    ok(&app, "PATCH", &format!("/scenes/{s}/objects/{o}"), far, StatusCode::OK).await;
    assert!(ok(&app, "GET", &pick(32), json!(null), StatusCode::OK).await["hit"].is_null());

    // DELETE takes the instances with it.
    ok(&app, "DELETE", &format!("/scenes/{s}/objects/{o}"), json!(null), StatusCode::OK).await;
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}/instances"), json!(null), StatusCode::OK).await, json!([]));
}

#[tokio::test]
async fn built_in_demos_load_by_name_and_everything_is_listed() {
    let app = app();
    let created = ok(&app, "POST", "/scenes", json!({ "demo": "cornell" }), StatusCode::CREATED).await;
    assert_eq!(created["origin"], "demo:cornell");
    assert!(created["triangles"].as_u64().unwrap() > 10);
    let s = created["id"].as_u64().unwrap();
    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=40&height=30&spp=2&integrator=path")).await;
    assert!(image.pixels().any(|p| p.0[0] > 20), "the room is lit");
    let scenes = ok(&app, "GET", "/scenes", json!(null), StatusCode::OK).await;
    assert_eq!(scenes.as_array().unwrap().len(), 1);
    let classes = ok(&app, "GET", "/shader-classes", json!(null), StatusCode::OK).await;
    let names: Vec<&str> = classes.as_array().unwrap().iter().map(|c| c["name"].as_str().unwrap()).collect();
    assert!(names.contains(&"Glass") && names.contains(&"SpotLight"), "{names:?}");
    let shader = ok(&app, "GET", &format!("/scenes/{s}/shaders/0"), json!(null), StatusCode::OK).await;
    assert!(shader["class"].is_string() && shader["params"].is_object(), "{shader}");
    let camera = ok(&app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
    ok(&app, "PUT", &format!("/scenes/{s}/camera"), json!({ "fov_y_degrees": 30 }), StatusCode::OK).await;
    let narrower = ok(&app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
    assert_eq!((narrower["fov_y_degrees"].as_f64(), &narrower["eye"]), (Some(30.0), &camera["eye"]), "fields left out stay");
    let (status, _, _) = send(&app, "DELETE", &format!("/scenes/{s}"), axum::body::Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    fails(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::NOT_FOUND).await;
}

/// The frame route takes the settings that set a render up like another renderer's, and the
/// PNG's grading: each reaches the image, and a bad value is a 422 naming its parameter.
#[tokio::test]
async fn frame_settings_reach_the_image_and_bad_ones_are_named() {
    let app = app();
    let s = grey_square_scene(&app, 1.0).await;
    let base = format!("/scenes/{s}/frame.png?width=32&height=32&integrator=path&spp=4");
    let plain = frame(&app, &base).await;
    let darker = frame(&app, &format!("{base}&exposure=-2&tonemap=neutral&max_depth=3&russian_roulette=false&filter=gaussian&seed=3")).await;
    assert!(darker.get_pixel(16, 16).0[0] + 40 < plain.get_pixel(16, 16).0[0], "{:?} vs {:?}", darker.get_pixel(16, 16), plain.get_pixel(16, 16));
    let red = frame(&app, &format!("{base}&background=1,0,0")).await;
    assert_eq!(red.get_pixel(0, 0).0, [255, 0, 0, 255], "the backdrop behind the square");
    for (query, field) in [
        ("tonemap=aces", "tonemap"),
        ("exposure=inf", "exposure"),
        ("background=blue", "background"),
        ("filter=tent", "filter"),
        ("max_depth=0", "max_depth"),
        ("noise_threshold=2", "noise_threshold"),
    ] {
        assert_eq!(fails(&app, "GET", &format!("{base}&{query}"), json!(null), StatusCode::UNPROCESSABLE_ENTITY).await, field, "{query}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_edit_is_applied_while_a_frame_renders() {
    let app = app();
    let created = ok(&app, "POST", "/scenes", json!({ "demo": "cornell" }), StatusCode::CREATED).await;
    let s = created["id"].as_u64().unwrap();
    // Seconds of path tracing, even on many cores in release.
    let slow = tokio::spawn({
        let app = app.clone();
        async move { frame(&app, &format!("/scenes/{s}/frame.png?width=96&height=96&spp=512&integrator=path")).await }
    });
    tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    ok(&app, "PUT", &format!("/scenes/{s}/camera"), json!({ "fov_y_degrees": 30 }), StatusCode::OK).await;
    let camera = ok(&app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
    assert_eq!(camera["fov_y_degrees"].as_f64(), Some(30.0));
    // The edit did not wait for the frame: a render holds no lock on the scene.
    assert!(!slow.is_finished(), "the frame finished before the edit: the test proves nothing");
    slow.abort();
}

#[tokio::test]
async fn an_orthographic_camera_set_over_http_renders_its_window() {
    let app = app();
    let (s, _, _) = red_square_scene(&app).await;
    let camera = ok(&app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
    assert_eq!(camera["projection"], json!({ "kind": "perspective" }));

    // The window [-2, 2] × [-1, 1]: the square (±1) covers exactly the middle half of the
    // columns and every row, whatever the distance.
    let window = json!({ "kind": "orthographic", "left": -2, "right": 2, "bottom": -1, "top": 1, "near": 0 });
    ok(&app, "PUT", &format!("/scenes/{s}/camera"), json!({ "projection": window, "eye": [0, 0, 40] }), StatusCode::OK).await;
    let camera = ok(&app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
    assert_eq!(camera["projection"]["kind"], "orthographic");
    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=64&height=32&integrator=eyelight")).await;
    let red_px = [255, 0, 0, 255];
    for y in [0, 16, 31] {
        assert_eq!(image.get_pixel(17, y).0, red_px, "row {y} inside");
        assert_eq!(image.get_pixel(46, y).0, red_px, "row {y} inside");
        assert_ne!(image.get_pixel(14, y).0, red_px, "row {y} left of the square");
        assert_ne!(image.get_pixel(49, y).0, red_px, "row {y} right of the square");
    }

    // Back to perspective; a window without width is refused naming the field, changing nothing.
    let flat = json!({ "kind": "orthographic", "left": 1, "right": 1, "bottom": -1, "top": 1, "near": 0 });
    let error = fails(&app, "PUT", &format!("/scenes/{s}/camera"), json!({ "projection": flat }), StatusCode::UNPROCESSABLE_ENTITY).await;
    assert!(error.to_string().contains("projection"), "{error}");
    let unchanged = ok(&app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
    assert_eq!(unchanged["projection"]["kind"], "orthographic");
    ok(&app, "PUT", &format!("/scenes/{s}/camera"), json!({ "projection": { "kind": "perspective" } }), StatusCode::OK).await;
    let camera = ok(&app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
    assert_eq!(camera["projection"], json!({ "kind": "perspective" }));
    let field = fails(&app, "PUT", &format!("/scenes/{s}/camera"), json!({ "projection": { "kind": "fisheye" } }), StatusCode::BAD_REQUEST).await;
    assert_eq!(field, "projection.kind");
}

#[tokio::test]
async fn channels_say_what_each_pixel_sees() {
    let app = app();
    let (s, _, instance) = red_square_scene(&app).await;
    let get = async |uri: String| send(&app, "GET", &uri, axum::body::Body::empty(), &[]).await;

    let (status, content_type, png) = get(format!("/scenes/{s}/channels/instance?width=32&height=24")).await;
    assert_eq!((status, content_type.as_str()), (StatusCode::OK, "image/png"));
    let ids = image::load_from_memory(&png).unwrap().to_rgb8();
    let id = instance["id"].as_u64().unwrap() as u8;
    assert_eq!((ids.get_pixel(16, 12).0, ids.get_pixel(0, 0).0), ([id, 0, 0], [255, 255, 255]), "the square's instance, and none");

    // Depths are floats: the square is straight ahead of the default camera, the corner empty.
    let (status, content_type, pfm) = get(format!("/scenes/{s}/channels/depth?width=32&height=24")).await;
    assert_eq!((status, content_type.as_str()), (StatusCode::OK, "image/x-portable-floatmap"));
    let header = b"Pf\n32 24\n-1.0\n".len();
    let depth = |x: usize, y: usize| {
        let at = header + ((23 - y) * 32 + x) * 4;
        f32::from_le_bytes(pfm[at..at + 4].try_into().unwrap())
    };
    assert!(depth(16, 12).is_finite() && depth(16, 12) > 0.0 && depth(0, 0) == f32::INFINITY, "{} {}", depth(16, 12), depth(0, 0));

    for (uri, status, field) in [
        (format!("/scenes/{s}/channels/colour"), StatusCode::NOT_FOUND, "channel"),
        (format!("/scenes/{s}/channels/depth?format=png"), StatusCode::UNPROCESSABLE_ENTITY, "format"),
        (format!("/scenes/{s}/channels/normal?format=gif"), StatusCode::UNPROCESSABLE_ENTITY, "format"),
        (format!("/scenes/{s}/channels/normal?width=0"), StatusCode::UNPROCESSABLE_ENTITY, "width"),
    ] {
        let (got, error) = call(&app, "GET", &uri, serde_json::Value::Null).await;
        assert_eq!((got, error["error"]["field"].as_str()), (status, Some(field)), "{uri}: {error}");
    }
}

#[tokio::test]
async fn the_root_is_the_viewer_page_for_browsers_and_the_index_for_everyone_else() {
    let app = raystage_server::router(raystage_server::AppState::new(raystage_server::Config { token: Some("s3cret".into()), ..Default::default() }));
    let get = async |uri: &str, headers: &[(&str, &str)]| {
        let mut request = axum::http::Request::get(uri);
        for (name, value) in headers {
            request = request.header(*name, *value);
        }
        let response = tower::ServiceExt::oneshot(app.clone(), request.body(axum::body::Body::empty()).unwrap()).await.unwrap();
        let (status, headers) = (response.status(), response.headers().clone());
        let body = http_body_util::BodyExt::collect(response.into_body()).await.unwrap().to_bytes();
        (status, headers, String::from_utf8_lossy(&body).into_owned())
    };
    // A browser gets the page and its files without the token (they hold no data), under a
    // policy that allows the server's own files and connections only.
    let browser = [("accept", "text/html,application/xhtml+xml,*/*;q=0.8")];
    let (status, headers, page) = get("/", &browser).await;
    assert_eq!(status, StatusCode::OK);
    assert!(headers["content-type"].to_str().unwrap().starts_with("text/html"));
    assert!(page.contains(r#"<script src="/web/viewer.js" defer></script>"#), "{page}");
    let policy = headers["content-security-policy"].to_str().unwrap();
    assert!(policy.contains("default-src 'none'") && policy.contains("script-src 'self'") && policy.contains("connect-src 'self'"), "{policy}");
    assert_eq!(headers["vary"], "accept");
    for (path, content_type) in [("/web/viewer.js", "text/javascript"), ("/web/viewer.css", "text/css")] {
        let (status, headers, body) = get(path, &[]).await;
        assert_eq!(status, StatusCode::OK, "{path}");
        assert!(headers["content-type"].to_str().unwrap().starts_with(content_type) && !body.is_empty(), "{path}");
        assert_eq!(headers["x-content-type-options"], "nosniff");
    }
    // Anyone else gets the JSON index, which needs the token like the rest of the API.
    let (status, _, _) = get("/", &[("accept", "*/*")]).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    let (status, headers, body) = get("/", &[("authorization", "Bearer s3cret")]).await;
    assert_eq!((status, headers["vary"].to_str().unwrap()), (StatusCode::OK, "accept"));
    let index: serde_json::Value = serde_json::from_str(&body).unwrap();
    assert_eq!((index["name"].as_str(), index["openapi"].as_str()), (Some("raystage"), Some("/openapi.json")));
    // The exemption is for the page only: the API stays closed to a browser without the token.
    let (status, _, _) = get("/scenes", &browser).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
}
