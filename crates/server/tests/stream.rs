//! The WebSocket stream over a real socket: progressive frames arrive, a camera change
//! restarts the image, settings and bad messages get replies.

mod common;

use axum::http::StatusCode;
use common::*;
use futures_util::{SinkExt, StreamExt};
use raystage_server::{AppState, Config};
use serde_json::{Value, json};
use tokio_tungstenite::tungstenite::Message;

type Socket = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

/// A server with a new empty scene and a stream of it with `query`: the API, the scene's id and
/// the socket.
async fn stream_of_a_new_scene(query: &str) -> (axum::Router, u64, Socket) {
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let s = new_scene(&app).await;
    let addr = listen(state).await;
    let (socket, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/scenes/{s}/stream?{query}")).await.unwrap();
    (app, s, socket)
}

/// The next text message, as JSON.
async fn next_json(socket: &mut Socket) -> Value {
    loop {
        match socket.next().await.expect("the stream stays open").expect("no socket error") {
            Message::Text(text) => return serde_json::from_str(text.as_str()).unwrap(),
            Message::Ping(_) | Message::Pong(_) => continue,
            other => panic!("expected a JSON text message, got {other:?}"),
        }
    }
}

/// The next frame: its statistics and its image.
async fn next_frame(socket: &mut Socket) -> (Value, image::RgbaImage) {
    loop {
        let message = next_json(socket).await;
        if message["type"] != "frame" {
            continue;
        }
        let Some(Ok(Message::Binary(png))) = socket.next().await else { panic!("a frame's PNG follows its statistics") };
        return (message, image::load_from_memory(&png).unwrap().to_rgba8());
    }
}

/// A server with the red square scene (`red_square_scene`) and a stream of it with `query`: the
/// server's address, the scene's id and the socket.
async fn stream_of_the_red_square(query: &str) -> (std::net::SocketAddr, u64, Socket) {
    let state = AppState::new(Config::default());
    let (s, _, _) = red_square_scene(&raystage_server::router(state.clone())).await;
    let addr = listen(state).await;
    let (socket, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/scenes/{s}/stream?{query}")).await.unwrap();
    (addr, s, socket)
}

/// The next `error` message.
async fn next_error(socket: &mut Socket) -> Value {
    loop {
        let message = next_json(socket).await;
        if message["type"] == "error" {
            return message;
        }
    }
}

/// The status that opening a stream at `path` is refused with.
async fn refusal(addr: std::net::SocketAddr, path: &str) -> u16 {
    let refused = tokio_tungstenite::connect_async(format!("ws://{addr}{path}")).await.unwrap_err();
    let tokio_tungstenite::tungstenite::Error::Http(response) = refused else { panic!("{path}: {refused}") };
    response.status().as_u16()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn frames_refine_and_a_camera_change_restarts_them() {
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let (s, _, _) = red_square_scene(&app).await;

    let addr = listen(state).await;
    let url = format!("ws://{addr}/scenes/{s}/stream?width=48&height=32&integrator=eyelight&max_samples=4096");
    let (mut socket, _) = tokio_tungstenite::connect_async(url).await.unwrap();

    let hello = next_json(&mut socket).await;
    assert_eq!((hello["type"].as_str(), hello["protocol"].as_u64(), hello["width"].as_u64()), (Some("hello"), Some(1), Some(48)));
    let mut samples = 0;
    for _ in 0..3 {
        let (stats, image) = next_frame(&mut socket).await;
        assert_eq!(image.dimensions(), (48, 32));
        assert_eq!(image.get_pixel(24, 16).0, [255, 0, 0, 255]);
        let now = stats["samples"].as_u64().unwrap();
        assert!(now > samples, "each frame has more samples: {stats}");
        samples = now;
        assert_eq!(stats["scene_version"], 3);
    }

    let camera = json!({ "type": "camera", "request": 7, "camera": { "eye": [4, 0, 5], "target": [4, 0, 0] } });
    socket.send(Message::text(camera.to_string())).await.unwrap();
    let (stats, image) = loop {
        let (stats, image) = next_frame(&mut socket).await;
        if stats["scene_version"] == 4 {
            break (stats, image);
        }
    };
    assert_ne!(image.get_pixel(24, 16).0, [255, 0, 0, 255], "the square is out of the centre now");
    assert!(stats["samples"].as_u64().unwrap() < samples + 64, "the image started over: {stats}");

    // Replies come in between frames.
    let reply = async |socket: &mut Socket| loop {
        let message = next_json(socket).await;
        if message["type"] != "frame" {
            return message;
        }
        socket.next().await; // its PNG
    };
    socket.send(Message::text(r#"{"type": "settings", "request": 8, "width": 0}"#)).await.unwrap();
    let error = reply(&mut socket).await;
    assert_eq!((error["type"].as_str(), error["request"].as_u64(), error["error"]["field"].as_str()), (Some("error"), Some(8), Some("width")));
    socket.send(Message::text(r#"{"type": "dance"}"#)).await.unwrap();
    assert_eq!(reply(&mut socket).await["type"], "error");
    socket.send(Message::text(r#"{"type": "settings", "request": 9, "width": 24, "height": 16, "max_samples": 8}"#)).await.unwrap();
    let result = reply(&mut socket).await;
    assert_eq!((result["type"].as_str(), result["request"].as_u64()), (Some("result"), Some(9)));
    let (stats, image) = loop {
        let (stats, image) = next_frame(&mut socket).await;
        if image.width() == 24 && stats["converged"] == true {
            break (stats, image);
        }
    };
    assert_eq!((image.dimensions(), stats["samples"].as_u64()), ((24, 16), Some(8)));
    socket.close(None).await.unwrap();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stream_is_set_up_as_frames_are_and_regraded_without_rendering_again() {
    let query = "width=32&height=32&integrator=eyelight&max_samples=4&background=0.2,0.2,0.2&exposure=1&tonemap=neutral";
    let (addr, s, mut socket) = stream_of_the_red_square(query).await;
    let converged = async |socket: &mut Socket| loop {
        let (stats, image) = next_frame(socket).await;
        if stats["converged"] == true {
            return (stats, image);
        }
    };
    let (first, image) = converged(&mut socket).await;
    // The background exposed by one stop (0.4) less the neutral curve's offset (0.04): 0.36,
    // sRGB 162; the square's red exposed to 2, compressed under 1 and desaturated.
    assert_eq!(image.get_pixel(0, 0).0, [162, 162, 162, 255]);
    let red = image.get_pixel(16, 16).0;
    assert!(red[0] > 240 && red[1] > 0 && red[1] == red[2], "{red:?}");

    // Only the grading changes: the same samples come back, graded anew, at once.
    socket.send(Message::text(r#"{"type": "settings", "request": 1, "exposure": -1, "tonemap": "clamp"}"#)).await.unwrap();
    let (second, image) = converged(&mut socket).await;
    assert_eq!(second["samples"], first["samples"]);
    assert_eq!(second["pass_seconds"], first["pass_seconds"], "the image was not rendered again: {second}");
    assert!(second["seq"].as_u64() > first["seq"].as_u64());
    assert_eq!(image.get_pixel(0, 0).0, [89, 89, 89, 255], "0.1 in sRGB");
    assert_eq!(image.get_pixel(16, 16).0, [188, 0, 0, 255], "0.5 in sRGB");

    // A change of the image renders it again; bad values are refused, naming the field.
    socket.send(Message::text(r#"{"type": "settings", "request": 2, "background": "black"}"#)).await.unwrap();
    let (_, image) = converged(&mut socket).await;
    assert_eq!((image.get_pixel(0, 0).0, image.get_pixel(16, 16).0), ([0, 0, 0, 255], [188, 0, 0, 255]));
    for (change, field) in [(r#""max_depth": 0"#, "max_depth"), (r#""tonemap": "fancy""#, "tonemap"), (r#""background": "blue""#, "background")] {
        socket.send(Message::text(format!(r#"{{"type": "settings", "request": 3, {change}}}"#))).await.unwrap();
        let error = next_error(&mut socket).await;
        assert_eq!(error["error"]["field"], field, "{error}");
    }
    socket.close(None).await.unwrap();
    assert_eq!(refusal(addr, &format!("/scenes/{s}/stream?filter=sinc")).await, 422);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn frames_come_as_jpeg_when_asked_and_a_new_encoding_needs_no_new_samples() {
    let (addr, s, mut socket) = stream_of_the_red_square("width=64&height=48&integrator=eyelight&max_samples=4&encoding=jpeg&quality=90").await;
    // The raw bytes of the next converged frame, and its statistics.
    let converged = async |socket: &mut Socket| loop {
        let message = next_json(socket).await;
        if message["type"] != "frame" {
            continue;
        }
        let Some(Ok(Message::Binary(bytes))) = socket.next().await else { panic!("a frame's image follows its statistics") };
        if message["converged"] == true {
            return (message, bytes.to_vec());
        }
    };
    let (first, jpeg) = converged(&mut socket).await;
    assert_eq!(first["encoding"], "jpeg");
    assert_eq!(jpeg[..3], [0xff, 0xd8, 0xff], "a JPEG's start of image");
    let jpeg = image::load_from_memory_with_format(&jpeg, image::ImageFormat::Jpeg).unwrap().to_rgb8();

    // A new encoding re-encodes the samples the image has, as a new grading does.
    socket.send(Message::text(r#"{"type": "settings", "request": 1, "encoding": "png"}"#)).await.unwrap();
    let (second, png) = converged(&mut socket).await;
    assert_eq!((second["encoding"].as_str(), second["samples"].as_u64()), (Some("png"), first["samples"].as_u64()));
    assert_eq!(second["pass_seconds"], first["pass_seconds"], "the image was not rendered again: {second}");
    let png = image::load_from_memory_with_format(&png, image::ImageFormat::Png).unwrap().to_rgb8();
    assert_eq!(png.get_pixel(32, 24).0, [255, 0, 0]);
    // The same image, lossy: at quality 90, within a few levels on average (measured 1.3),
    // farther only where ringing follows the square's hard edges (measured 52).
    let errors: Vec<u32> = jpeg.as_raw().iter().zip(png.as_raw()).map(|(&a, &b)| a.abs_diff(b) as u32).collect();
    let mean = errors.iter().sum::<u32>() as f64 / errors.len() as f64;
    let max = errors.iter().max().unwrap();
    eprintln!("JPEG at quality 90 against the PNG: mean error {mean:.2} levels, largest {max}");
    assert!(mean < 2.0 && *max < 64, "mean {mean}, largest {max}");

    for (change, field) in [(r#""quality": 0"#, "quality"), (r#""quality": 101"#, "quality"), (r#""encoding": "webp""#, "encoding")] {
        socket.send(Message::text(format!(r#"{{"type": "settings", "request": 2, {change}}}"#))).await.unwrap();
        let error = next_error(&mut socket).await;
        assert_eq!(error["error"]["field"], field, "{error}");
    }
    socket.close(None).await.unwrap();
    for query in ["quality=101", "encoding=gif"] {
        assert_eq!(refusal(addr, &format!("/scenes/{s}/stream?{query}")).await, 422, "{query}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn deleting_the_scene_ends_its_streams() {
    let (app, s, mut socket) = stream_of_a_new_scene("width=16&height=16&max_samples=4").await;
    next_frame(&mut socket).await;
    let (status, _, _) = send(&app, "DELETE", &format!("/scenes/{s}"), axum::body::Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    let error = loop {
        if let Some(Ok(Message::Text(text))) = socket.next().await {
            let message: Value = serde_json::from_str(text.as_str()).unwrap();
            if message["type"] == "error" {
                break message;
            }
        }
    };
    assert_eq!(error["error"]["field"], "scene");
    // A frame already on its way may still arrive; then the server closes the stream.
    for _ in 0..4 {
        match socket.next().await {
            None | Some(Ok(Message::Close(_))) | Some(Err(_)) => return,
            Some(Ok(_)) => continue,
        }
    }
    panic!("the stream of a deleted scene stays open");
}

#[tokio::test]
async fn a_stream_of_an_unknown_scene_or_with_bad_settings_is_refused() {
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let s = new_scene(&app).await;
    let addr = listen(state).await;
    for (path, status) in [("/scenes/99/stream", 404), (&format!("/scenes/{s}/stream?width=0") as &str, 422), (&format!("/scenes/{s}/stream?max_samples=0"), 422),
        // 2.3 GB of accumulation, more than all the server's memory for images.
        (&format!("/scenes/{s}/stream?width=8192&height=8192&max_samples=1"), 413),
    ] {
        assert_eq!(refusal(addr, path).await, status, "{path}");
        // The same request without the upgrade gets the same error, for browsers, whose
        // WebSocket does not show it.
        assert_eq!(call(&app, "GET", path, Value::Null).await.0.as_u16(), status, "{path} without the upgrade");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_closed_stream_stops_its_render() {
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let s = grey_square_scene(&app, 50.0).await;
    let addr = listen(state.clone()).await;
    // Path-traced 1080p passes: long enough to be running when the client goes.
    let url = format!("ws://{addr}/scenes/{s}/stream?width=1920&height=1080&integrator=path&max_samples=256");
    let (mut socket, _) = tokio_tungstenite::connect_async(url).await.unwrap();
    next_frame(&mut socket).await;
    assert!(eventually(std::time::Duration::from_secs(10), || state.active_renders() == 1).await, "the next pass runs");
    drop(socket);
    assert!(eventually(std::time::Duration::from_secs(10), || state.active_renders() == 0).await, "the pass still runs after the stream closed");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_message_within_the_body_limit_gets_an_answer_however_large_its_frame() {
    let (_, _, mut socket) = stream_of_a_new_scene("width=16&height=16&max_samples=1").await;
    // 20 MiB in one frame: over tungstenite's default frame limit, within the server's 256 MiB.
    let padding = "x".repeat(20 << 20);
    let message = json!({ "type": "camera", "request": 7, "camera": { "fov_y_degrees": 50 }, "padding": padding }).to_string();
    socket.send(Message::text(message)).await.unwrap();
    let reply = loop {
        match socket.next().await.expect("the stream stays open").expect("no socket error") {
            Message::Text(text) => {
                let message: Value = serde_json::from_str(text.as_str()).unwrap();
                if message["type"] == "error" || message["type"] == "result" {
                    break message;
                }
            }
            // Frames' PNGs.
            _ => continue,
        }
    };
    // Read, and refused for what it says rather than for its size.
    assert_eq!(reply["type"], "error", "{reply}");
    assert!(reply["error"]["message"].as_str().unwrap().contains("unknown field `padding`"), "{reply}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_commands_message_is_counted_as_it_is_parsed() {
    let state = AppState::new(Config { limits: raystage_server::Limits { max_commands: 3, ..Default::default() }, ..Config::default() });
    let app = raystage_server::router(state.clone());
    let s = new_scene(&app).await;
    let addr = listen(state).await;
    let (mut socket, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/scenes/{s}/stream?width=8&height=8&max_samples=1")).await.unwrap();
    // The next reply (frames and their PNGs skipped).
    let reply = async |socket: &mut Socket| loop {
        if let Some(Ok(Message::Text(text))) = socket.next().await {
            let message: Value = serde_json::from_str(text.as_str()).unwrap();
            if message["type"] == "result" || message["type"] == "error" {
                return message;
            }
        }
    };
    // Within the limit, the edits apply and the reply echoes the request.
    let three = json!({ "type": "commands", "request": 5, "commands": vec![json!({ "set_camera": {} }); 3] });
    socket.send(Message::text(three.to_string())).await.unwrap();
    let result = reply(&mut socket).await;
    assert_eq!((result["type"].as_str(), result["request"].as_u64(), result["results"].as_array().map(Vec::len)), (Some("result"), Some(5), Some(3)), "{result}");
    // The fourth command ends parsing: the bytes after it, not even JSON, are never read.
    let four = format!(r#"{{"type": "commands", "request": 6, "commands": [{}, this is not JSON"#, [r#"{"set_camera": {}}"#; 4].join(", "));
    socket.send(Message::text(four)).await.unwrap();
    let error = reply(&mut socket).await;
    assert_eq!((error["type"].as_str(), error["error"]["limit"].as_str(), error["error"]["field"].as_str()), (Some("error"), Some("max_commands"), Some("commands")), "{error}");
    // Errors inside a command still name it; unknown keys are refused as before.
    socket.send(Message::text(r#"{"type": "commands", "commands": [{"set_camera": {"eye": [0, 0, "far"]}}]}"#)).await.unwrap();
    assert_eq!(reply(&mut socket).await["error"]["field"], "commands[0].set_camera.eye[2]");
    socket.send(Message::text(r#"{"type": "commands", "commands": [], "also": 1}"#)).await.unwrap();
    assert_eq!(reply(&mut socket).await["type"], "error");
    socket.close(None).await.unwrap();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stream_follows_a_playing_clock_and_tags_each_frame_with_its_time() {
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let s = animated_scene(&app).await;
    let addr = listen(state).await;
    // Few samples: the image is finished at once, and only the clock brings new frames.
    let url = format!("ws://{addr}/scenes/{s}/stream?width=40&height=20&integrator=eyelight&max_samples=1");
    let (mut socket, _) = tokio_tungstenite::connect_async(url).await.unwrap();
    let (still, _) = next_frame(&mut socket).await;
    assert_eq!(still["converged"], true);
    ok(&app, "PUT", &format!("/scenes/{s}/clock"), json!({ "playing": true, "rate": 0.1 }), StatusCode::OK).await;
    // Bounded, so that a clock the stream ignores fails the test instead of hanging it.
    let within = std::time::Duration::from_secs(60);
    let mut times = Vec::new();
    while times.len() < 5 {
        let (stats, _) = tokio::time::timeout(within, next_frame(&mut socket)).await.expect("frames keep coming while the clock plays");
        if let Some(time) = stats["scene_time"].as_f64() {
            times.push((time, stats["scene_version"].as_u64().unwrap()));
        }
    }
    assert!(times.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 > w[0].1), "each frame a later time and version: {times:?}");
    // Paused, the frames stop coming once the last pose is finished.
    ok(&app, "PUT", &format!("/scenes/{s}/clock"), json!({ "playing": false }), StatusCode::OK).await;
    let paused = ok(&app, "GET", &format!("/scenes/{s}/clock"), json!(null), StatusCode::OK).await["time"].as_f64().unwrap();
    let last = loop {
        let (stats, _) = tokio::time::timeout(within, next_frame(&mut socket)).await.expect("the paused pose is shown");
        if stats["scene_time"].as_f64() == Some(paused) {
            break stats;
        }
    };
    assert_eq!(last["converged"], true);
    let quiet = tokio::time::timeout(std::time::Duration::from_millis(300), next_frame(&mut socket)).await;
    assert!(quiet.is_err(), "no frames while nothing changes: {:?}", quiet.map(|f| f.0));
}

/// How long the tests of render turns wait for what must come.
const PATIENCE: std::time::Duration = std::time::Duration::from_secs(60);

/// A server with one turn to render, the Cornell box as scene `s`, a stream of it set up by
/// `query`, and the scene version of each of the stream's frames as it arrives, once the first
/// has. The stream is read all along, so that every pass's frame is delivered and the next one
/// encoded.
async fn stream_with_one_turn(query: &str) -> (AppState, axum::Router, Value, tokio::sync::mpsc::UnboundedReceiver<u64>) {
    let state = AppState::new(Config { limits: raystage_server::Limits { concurrent_renders: 1, ..raystage_server::Limits::default() }, ..Config::default() });
    let app = raystage_server::router(state.clone());
    let s = ok(&app, "POST", "/scenes", json!({ "demo": "cornell" }), StatusCode::CREATED).await["id"].clone();
    let addr = listen(state.clone()).await;
    let (mut socket, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/scenes/{s}/stream?{query}")).await.unwrap();
    let (versions_tx, mut versions) = tokio::sync::mpsc::unbounded_channel();
    tokio::spawn(async move {
        while let Some(Ok(message)) = socket.next().await {
            if let Message::Text(text) = message {
                let message: Value = serde_json::from_str(text.as_str()).unwrap();
                if message["type"] == "frame" {
                    let _ = versions_tx.send(message["scene_version"].as_u64().unwrap());
                }
            }
        }
    });
    tokio::time::timeout(PATIENCE, versions.recv()).await.expect("a first frame").unwrap();
    (state, app, s, versions)
}

/// Whether a frame of scene version `version` or later arrives within [`PATIENCE`].
async fn shows(versions: &mut tokio::sync::mpsc::UnboundedReceiver<u64>, version: u64) -> bool {
    let shown = async {
        while let Some(shown) = versions.recv().await {
            if shown >= version {
                return;
            }
        }
    };
    tokio::time::timeout(PATIENCE, shown).await.is_ok()
}

/// A pass yields to an edit: it is stopped, and its turn goes to the pass that starts over, not
/// to a render another client queued meanwhile, so that the edit is on screen one pass later
/// rather than one round of the turns later. With one turn to render: the stream's pass (a
/// path-traced 1920×1080 image, far longer than an edit takes) holds it, another client waits
/// for it, and the camera moves; the frame showing the move must come while the other client
/// still waits (here: for ever, as it never gives its turn back once it has it).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_edit_takes_the_turn_of_the_pass_it_cut_short() {
    use futures_util::FutureExt;

    let (state, app, s, mut versions) = stream_with_one_turn("width=1920&height=1080&integrator=path&max_samples=256").await;

    // The other client asks for the turn while a pass of the stream holds it.
    let other = loop {
        assert!(eventually(PATIENCE, || state.active_renders() == 1).await, "the stream renders");
        let waiting = state.clone();
        let mut other = Box::pin(async move { waiting.render_permit(raystage_service::Client(1_000_000), raystage_service::Urgency::InTurn).await });
        if (&mut other).now_or_never().is_none() {
            break other;
        }
        // Taken between two passes: given back, and tried again.
    };
    let moved = ok(&app, "PUT", &format!("/scenes/{s}/camera"), json!({ "eye": [0.5, 1, 4] }), StatusCode::OK).await;
    let version = moved["version"].as_u64().unwrap();
    assert!(shows(&mut versions, version).await, "the moved camera's frame waited for the other client's render, which never ends");
    drop(other);
}

/// An edit that comes while the stream waits for a turn puts it ahead of the renders other
/// clients queued: the frame showing it comes one render later, not one round of the turns
/// later. With one turn to render: a render of this test's holds it while the stream waits for
/// its next refining pass, another client queues (and would never give the turn back), and the
/// camera moves. The other client is next in the round (its number follows the holder's), so
/// the moved camera's frame comes only if the stream's edit goes first.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_edit_goes_before_renders_queued_earlier() {
    use futures_util::FutureExt;
    use raystage_service::{Client, Urgency};

    let (state, app, s, mut versions) = stream_with_one_turn("width=320&height=180&integrator=path&max_samples=4096").await;

    // The holder takes the turn between two refining passes; the stream then waits for it.
    let held = tokio::time::timeout(PATIENCE, state.render_permit(Client(999_999), Urgency::InTurn)).await.expect("the holder's turn");
    let waiting = state.clone();
    let mut other = Box::pin(async move { waiting.render_permit(Client(1_000_000), Urgency::InTurn).await });
    assert!((&mut other).now_or_never().is_none(), "the other client waits");
    let moved = ok(&app, "PUT", &format!("/scenes/{s}/camera"), json!({ "eye": [0.5, 1, 4] }), StatusCode::OK).await;
    let version = moved["version"].as_u64().unwrap();
    // The stream has seen the change (it re-queues as an edit) before the turn comes free.
    tokio::time::sleep(std::time::Duration::from_millis(200)).await;
    drop(held);
    assert!(shows(&mut versions, version).await, "the moved camera's frame waited for the other client's render, which never ends");
    drop(other);
}

/// The pass that starts a stream over after an edit runs to its end whatever changes
/// meanwhile: a scene that changes faster than a pass renders (a drag's camera moves, a playing
/// clock) still shows frames, each at most a pass old, rather than none until the changes
/// stop. Here the camera moves back to back, many times during each path-traced pass.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn frames_keep_coming_while_the_camera_moves_faster_than_a_pass() {
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let s = ok(&app, "POST", "/scenes", json!({ "demo": "cornell" }), StatusCode::CREATED).await["id"].clone();
    let addr = listen(state).await;
    let url = format!("ws://{addr}/scenes/{s}/stream?width=640&height=360&integrator=path&max_samples=256");
    let (mut socket, _) = tokio_tungstenite::connect_async(url).await.unwrap();
    let (first, _) = next_frame(&mut socket).await;
    let moving = tokio::spawn({
        let (app, camera) = (app.clone(), format!("/scenes/{s}/camera"));
        async move {
            for k in 0u32.. {
                ok(&app, "PUT", &camera, json!({ "eye": [(k as f32 * 0.1).sin(), 1, 4] }), StatusCode::OK).await;
            }
        }
    });
    let patience = std::time::Duration::from_secs(60);
    let shown = tokio::time::timeout(patience, async {
        let mut version = first["scene_version"].as_u64().unwrap();
        for _ in 0..3 {
            loop {
                let (frame, _) = next_frame(&mut socket).await;
                if frame["scene_version"].as_u64().unwrap() > version {
                    version = frame["scene_version"].as_u64().unwrap();
                    break;
                }
            }
        }
    })
    .await;
    moving.abort();
    assert!(shown.is_ok(), "no frame came while the camera kept moving");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_clock_set_playing_wakes_a_stream_that_waits_on_it_paused() {
    // Setting the clock poses the scene (an edit, which wakes the stream) before it plays: a
    // stream that finished that pose first waited on the paused clock it had seen, for good.
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let s = animated_scene(&app).await;
    ok(&app, "PUT", &format!("/scenes/{s}/clock"), json!({ "playing": false }), StatusCode::OK).await;
    let slot = state.scene(s as u32).unwrap();
    let waiting = tokio::spawn(async move { slot.clock_due().await });
    // Long enough for the wait to start while the clock is paused.
    tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    assert!(!waiting.is_finished(), "a paused clock is not due");
    ok(&app, "PUT", &format!("/scenes/{s}/clock"), json!({ "playing": true }), StatusCode::OK).await;
    tokio::time::timeout(std::time::Duration::from_secs(10), waiting).await.expect("setting the clock wakes the wait").unwrap();
}
