//! The server under careless and hostile clients: renders nobody waits for stop and give their
//! turn back, renders have a time budget, slow clients are cut off, and limits on memory are
//! checked before the memory is taken. Errors name the limit (`Limits`' field) they ran into.

mod common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use axum::body::Body;
use axum::http::StatusCode;
use common::*;
use raystage_server::{AppState, Config, Limits, router};
use serde_json::{Value, json};

/// A frame the path tracer takes many seconds over even on many cores (a diffuse square that
/// fills a 1920×1080 image, 256 samples per pixel: within the default limits).
const SLOW_FRAME: &str = "frame.png?width=1920&height=1080&spp=256&integrator=path";

/// A scene holding a diffuse square that fills the default camera's view; its id.
async fn filled_scene(app: &axum::Router) -> u64 {
    grey_square_scene(app, 50.0).await
}

/// Reads from a raw connection until the server closes it (or `deadline`); what it sent.
fn read_until_closed(stream: &mut TcpStream, deadline: Duration) -> (Vec<u8>, bool) {
    stream.set_read_timeout(Some(Duration::from_millis(100))).unwrap();
    let start = Instant::now();
    let mut got = Vec::new();
    let mut buf = [0; 4096];
    while start.elapsed() < deadline {
        match stream.read(&mut buf) {
            Ok(0) => return (got, true),
            Ok(n) => got.extend_from_slice(&buf[..n]),
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {}
            Err(_) => return (got, true),
        }
    }
    (got, false)
}

/// The JSON body of a raw HTTP/1.1 response.
fn json_body(response: &[u8]) -> Value {
    let text = String::from_utf8_lossy(response);
    let body = text.split_once("\r\n\r\n").map(|(_, b)| b).unwrap_or("");
    serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {text}"))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn renders_whose_clients_hang_up_stop_and_give_their_turn_back() {
    let state = AppState::new(Config::default());
    let app = router(state.clone());
    let s = filled_scene(&app).await;
    let addr = listen(state.clone()).await;
    let permits = Limits::default().concurrent_renders;

    // Twenty clients ask for a slow frame at once and hang up half a second later, one after
    // the other.
    let abandoned = 20;
    let mut clients = Vec::new();
    for _ in 0..abandoned {
        let mut client = tokio::net::TcpStream::connect(addr).await.unwrap();
        let request = format!("GET /scenes/{s}/{SLOW_FRAME} HTTP/1.1\r\nhost: test\r\n\r\n");
        tokio::io::AsyncWriteExt::write_all(&mut client, request.as_bytes()).await.unwrap();
        clients.push(client);
    }
    let mut most = 0;
    for client in clients {
        for _ in 0..5 {
            tokio::time::sleep(Duration::from_millis(20)).await;
            most = most.max(state.active_renders());
        }
        drop(client);
    }
    let last_drop = Instant::now();
    assert!(most == permits, "{most} renders ran at once; the server allows {permits}, and had {abandoned} waiting");
    let idle = eventually(Duration::from_secs(20), || state.active_renders() == 0).await;
    let to_idle = last_drop.elapsed();
    assert!(idle, "{} renders still run {to_idle:?} after the last client hung up", state.active_renders());
    eprintln!("{abandoned} abandoned renders: at most {most} ran at once; idle {to_idle:?} after the last hang-up");

    // A new client's small frame gets a turn at once.
    let asked = Instant::now();
    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=32&height=32&integrator=eyelight")).await;
    assert_eq!(image.dimensions(), (32, 32));
    eprintln!("a fresh 32×32 frame then took {:?}", asked.elapsed());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_render_past_its_time_budget_is_stopped_with_503_naming_the_limit() {
    let state = AppState::new(Config { limits: Limits { max_render_seconds: 1, ..Limits::default() }, ..Config::default() });
    let app = router(state.clone());
    let s = filled_scene(&app).await;
    let start = Instant::now();
    let (status, value) = call(&app, "GET", &format!("/scenes/{s}/{SLOW_FRAME}"), Value::Null).await;
    assert_eq!(status, StatusCode::SERVICE_UNAVAILABLE, "{value}");
    assert_eq!((value["error"]["code"].as_str(), value["error"]["limit"].as_str()), (Some("timeout"), Some("max_render_seconds")), "{value}");
    assert!(start.elapsed() >= Duration::from_secs(1));
    // The render itself stopped, not only the wait for it.
    assert!(eventually(Duration::from_secs(10), || state.active_renders() == 0).await, "the render still runs");
}

#[tokio::test]
async fn a_client_that_trickles_its_headers_is_cut_off() {
    let state = AppState::new(Config { limits: Limits { header_read_seconds: 1, ..Limits::default() }, ..Config::default() });
    let addr = listen(state).await;
    let closed = tokio::task::spawn_blocking(move || {
        let mut stream = TcpStream::connect(addr).unwrap();
        stream.write_all(b"GET / HTTP/1.1\r\n").unwrap();
        let start = Instant::now();
        // A header line every 200 ms, never the blank line that ends them.
        while start.elapsed() < Duration::from_secs(10) {
            if stream.write_all(b"x-slow: 1\r\n").is_err() {
                return Some(start.elapsed());
            }
            let (_, closed) = read_until_closed(&mut stream, Duration::from_millis(200));
            if closed {
                return Some(start.elapsed());
            }
        }
        None
    })
    .await
    .unwrap();
    let after = closed.expect("the connection is still open after 10 s of trickled headers");
    assert!(after >= Duration::from_millis(900), "closed after {after:?}, before the limit");
}

#[tokio::test]
async fn a_client_that_trickles_its_body_gets_408_naming_the_limit_and_is_cut_off() {
    let state = AppState::new(Config { limits: Limits { body_read_seconds: 1, ..Limits::default() }, ..Config::default() });
    let addr = listen(state).await;
    let (response, closed) = tokio::task::spawn_blocking(move || {
        let mut stream = TcpStream::connect(addr).unwrap();
        stream.write_all(b"POST /scenes HTTP/1.1\r\nhost: test\r\ncontent-type: application/json\r\ncontent-length: 1000\r\n\r\n{").unwrap();
        let start = Instant::now();
        let mut response = Vec::new();
        while start.elapsed() < Duration::from_secs(10) {
            // A byte every 200 ms: the body would take 200 s.
            let _ = stream.write_all(b" ");
            let (got, closed) = read_until_closed(&mut stream, Duration::from_millis(200));
            response.extend(got);
            if closed {
                return (response, true);
            }
        }
        (response, false)
    })
    .await
    .unwrap();
    assert!(closed, "the connection is still open after 10 s of a trickled body");
    assert!(response.starts_with(b"HTTP/1.1 408"), "{}", String::from_utf8_lossy(&response));
    let value = json_body(&response);
    assert_eq!((value["error"]["code"].as_str(), value["error"]["limit"].as_str()), (Some("timeout"), Some("body_read_seconds")), "{value}");
}

#[tokio::test]
async fn a_client_that_sends_in_time_is_served() {
    let addr = listen(AppState::new(Config::default())).await;
    let (response, _) = tokio::task::spawn_blocking(move || {
        let mut stream = TcpStream::connect(addr).unwrap();
        stream.write_all(b"POST /scenes HTTP/1.1\r\nhost: test\r\nconnection: close\r\ncontent-length: 2\r\n\r\n{}").unwrap();
        read_until_closed(&mut stream, Duration::from_secs(10))
    })
    .await
    .unwrap();
    assert!(response.starts_with(b"HTTP/1.1 201"), "{}", String::from_utf8_lossy(&response));
    assert_eq!(json_body(&response)["id"], json!(1));
}

/// A request that must fail with `status` naming `limit`; returns the error.
async fn fails_on_limit(app: &axum::Router, uri: &str, body: Body, content_type: &str, status: StatusCode, limit: &str) -> Value {
    let (got, _, bytes) = send(app, "POST", uri, body, &[("content-type", content_type)]).await;
    let value: Value = serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&bytes)));
    assert_eq!((got, value["error"]["limit"].as_str()), (status, Some(limit)), "{value}");
    value
}

#[tokio::test]
async fn a_batch_past_the_command_limit_fails_at_the_first_command_too_many() {
    let limits = Limits { max_commands: 3, ..Limits::default() };
    let app = router(AppState::new(Config { limits, ..Config::default() }));
    let s = new_scene(&app).await;
    // Four commands, then bytes that are not JSON at all: parsing stops at the fourth command,
    // so they are never read (else the answer would be 400 for them).
    let body = format!("{{\"commands\": [{}, this is not JSON", [r#"{"set_camera": {}}"#; 4].join(", "));
    let error = fails_on_limit(&app, &format!("/scenes/{s}/commands"), Body::from(body), "application/json", StatusCode::PAYLOAD_TOO_LARGE, "max_commands").await;
    assert_eq!(error["error"]["field"], "commands");
    // Within the limit, a batch still runs, and its errors still name the field.
    let three = json!({ "commands": vec![json!({ "set_camera": {} }); 3] });
    ok(&app, "POST", &format!("/scenes/{s}/commands"), three, StatusCode::OK).await;
    let bad = json!({ "commands": [{ "set_camera": { "eye": [0, 0, "far"] } }] });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/commands"), bad, StatusCode::BAD_REQUEST).await, "commands[0].set_camera.eye[2]");
}

#[tokio::test]
async fn an_image_larger_decoded_than_the_texture_budget_is_refused_before_decoding() {
    // 1024 × 1024 texels of black: 4 KB of PNG, 16 MiB decoded.
    let mut png = std::io::Cursor::new(Vec::new());
    image::RgbImage::new(1024, 1024).write_to(&mut png, image::ImageFormat::Png).unwrap();
    let png = png.into_inner();
    let limits = Limits { max_texture_bytes: 8 << 20, ..Limits::default() };
    let app = router(AppState::new(Config { limits, ..Config::default() }));
    let s = new_scene(&app).await;
    let uri = format!("/scenes/{s}/textures");
    fails_on_limit(&app, &uri, Body::from(png.clone()), "image/png", StatusCode::PAYLOAD_TOO_LARGE, "max_texture_bytes").await;
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["textures"], 0);
    // Within the budget it is a texture.
    let roomy = router(AppState::new(Config::default()));
    let s = new_scene(&roomy).await;
    let (status, _, body) = send(&roomy, "POST", &format!("/scenes/{s}/textures"), Body::from(png), &[("content-type", "image/png")]).await;
    assert_eq!(status, StatusCode::CREATED, "{}", String::from_utf8_lossy(&body));
}

#[tokio::test]
async fn demos_past_the_size_limit_and_scenes_past_the_scene_limit_are_refused_before_they_are_built() {
    let app = router(AppState::new(Config { limits: Limits { max_scenes: 2, ..Limits::default() }, ..Config::default() }));
    let huge = Body::from(json!({ "demo": "museum-4000000" }).to_string());
    let error = fails_on_limit(&app, "/scenes", huge, "application/json", StatusCode::UNPROCESSABLE_ENTITY, "max_demo_triangles").await;
    assert_eq!(error["error"]["field"], "demo");
    ok(&app, "POST", "/scenes", json!({ "demo": "museum-1024" }), StatusCode::CREATED).await;
    ok(&app, "POST", "/scenes", json!({}), StatusCode::CREATED).await;
    // The sphere grid would take seconds and a hundred megabytes to build: the limit comes first.
    let third = Body::from(json!({ "demo": "spheres" }).to_string());
    fails_on_limit(&app, "/scenes", third, "application/json", StatusCode::PAYLOAD_TOO_LARGE, "max_scenes").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn frames_share_the_memory_for_images_and_one_larger_than_all_of_it_is_refused() {
    // Room for one 1080p frame (33 MB) but not two.
    let state = AppState::new(Config { limits: Limits { max_render_bytes: 48 << 20, ..Limits::default() }, ..Config::default() });
    let app = router(state.clone());
    let s = filled_scene(&app).await;
    let (status, value) = call(&app, "GET", &format!("/scenes/{s}/frame.png?width=4096&height=4096"), Value::Null).await;
    assert_eq!((status, value["error"]["limit"].as_str()), (StatusCode::PAYLOAD_TOO_LARGE, Some("max_render_bytes")), "{value}");
    // A slow frame holds its share while it renders ...
    let slow = tokio::spawn({
        let app = app.clone();
        async move { call(&app, "GET", &format!("/scenes/{s}/{SLOW_FRAME}"), Value::Null).await }
    });
    assert!(eventually(Duration::from_secs(10), || state.active_renders() == 1).await);
    let (status, value) = call(&app, "GET", &format!("/scenes/{s}/frame.png?width=1920&height=1080"), Value::Null).await;
    assert_eq!((status, value["error"]["limit"].as_str()), (StatusCode::SERVICE_UNAVAILABLE, Some("max_render_bytes")), "{value}");
    // ... and gives it back once its render has stopped. (Stopped now: until then, the slow
    // frame's tiles keep the render threads, and so every other test's renders, waiting.)
    slow.abort();
    assert!(eventually(Duration::from_secs(10), || state.active_renders() == 0).await);
    frame(&app, &format!("/scenes/{s}/frame.png?width=1920&height=1080&integrator=eyelight")).await;
}

#[tokio::test]
async fn shutting_down_closes_idle_connections_and_returns() {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(raystage_server::serve(listener, AppState::new(Config::default()), async {
        let _ = stopped.await;
    }));
    // A kept-alive connection, idle after its request.
    let mut client = tokio::task::spawn_blocking(move || {
        let mut stream = TcpStream::connect(addr).unwrap();
        stream.write_all(b"GET / HTTP/1.1\r\nhost: test\r\n\r\n").unwrap();
        let mut buf = [0; 4096];
        assert!(stream.read(&mut buf).unwrap() > 0);
        stream
    })
    .await
    .unwrap();
    stop.send(()).unwrap();
    let served = tokio::time::timeout(Duration::from_secs(10), server).await.expect("serve returns once its connections close");
    served.unwrap().unwrap();
    let (_, closed) = tokio::task::spawn_blocking(move || read_until_closed(&mut client, Duration::from_secs(5))).await.unwrap();
    assert!(closed, "the idle connection was closed");
}

/// A mesh of `n` separate triangles: 36 bytes of positions, 12 of indices and
/// `TREE_BYTES_PER_TRIANGLE` of tree each (128 bytes a triangle).
fn triangles(n: usize) -> Value {
    let positions: Vec<[f32; 3]> = (0..n).flat_map(|i| [[i as f32, 0.0, 0.0], [i as f32 + 1.0, 0.0, 0.0], [i as f32, 1.0, 0.0]]).collect();
    let indices: Vec<[usize; 3]> = (0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    json!({ "mesh": { "positions": positions, "indices": indices } })
}

#[tokio::test]
async fn scenes_have_a_memory_budget_each_and_together_and_an_edit_past_it_changes_nothing() {
    // 5,000 triangles take 640,000 bytes: one fits a scene, two do not; two scenes of one each
    // do not fit the server.
    let limits = Limits { max_scene_bytes: 1_000_000, max_total_scene_bytes: 1_200_000, ..Limits::default() };
    let app = router(AppState::new(Config { limits, ..Config::default() }));
    let a = new_scene(&app).await;
    ok(&app, "POST", &format!("/scenes/{a}/objects"), triangles(5000), StatusCode::CREATED).await;
    let info = ok(&app, "GET", &format!("/scenes/{a}"), json!(null), StatusCode::OK).await;
    let bytes = info["memory_bytes"].as_u64().unwrap();
    assert!((5000 * 128..5000 * 128 + 1024).contains(&bytes), "triangles and a few bounding boxes: {info}");
    let uri = format!("/scenes/{a}/objects");
    fails_on_limit(&app, &uri, Body::from(triangles(5000).to_string()), "application/json", StatusCode::PAYLOAD_TOO_LARGE, "max_scene_bytes").await;
    let after = ok(&app, "GET", &format!("/scenes/{a}"), json!(null), StatusCode::OK).await;
    assert_eq!((after["objects"].as_u64(), &after["version"]), (Some(1), &info["version"]), "the refused edit changed nothing");

    let b = new_scene(&app).await;
    let uri = format!("/scenes/{b}/objects");
    fails_on_limit(&app, &uri, Body::from(triangles(5000).to_string()), "application/json", StatusCode::PAYLOAD_TOO_LARGE, "max_total_scene_bytes").await;
    // The same as a batch, or as a glTF-sized upload: the budget is the edit's, however it came.
    let batch = json!({ "commands": [{ "add_object": triangles(2500) }, { "add_object": triangles(2500) }] });
    let (status, error) = call(&app, "POST", &format!("/scenes/{b}/commands"), batch).await;
    assert_eq!((status, error["error"]["limit"].as_str()), (StatusCode::PAYLOAD_TOO_LARGE, Some("max_total_scene_bytes")), "{error}");
    // Deleting the first scene gives its share back.
    let (status, _, _) = send(&app, "DELETE", &format!("/scenes/{a}"), Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    ok(&app, "POST", &uri, triangles(5000), StatusCode::CREATED).await;
}
