//! A server rendering with a cluster's workers, its ranks as threads of this process joined by
//! channels (the command line joins them by MPI: `tests/serve_mpi.rs` at the root): every edit
//! reaches the workers' replicas and every frame, one-shot or streamed, is byte for byte the one
//! a single process renders; a worker that refuses an edit has it refused everywhere; a worker
//! that stops answering is given up and the server goes on alone.

mod common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use axum::Router;
use axum::body::Body;
use axum::http::StatusCode;
use common::*;
use futures_util::StreamExt;
use raystage_cluster::{Cluster, Transport, work};
use raystage_server::{AppState, Config, Limits, router};
use serde_json::{Value, json};
use tokio_tungstenite::tungstenite::Message;

/// One rank's ends of the channels between every two ranks.
struct Link {
    rank: u32,
    ranks: u32,
    /// To each rank.
    to: Vec<Sender<Vec<u8>>>,
    /// From each rank.
    from: Vec<Mutex<Receiver<Vec<u8>>>>,
    /// While set, this rank answers nothing (a hung worker).
    hung: Arc<AtomicBool>,
}

impl Transport for Link {
    fn rank(&self) -> u32 {
        self.rank
    }

    fn ranks(&self) -> u32 {
        self.ranks
    }

    fn send(&self, rank: u32, message: &[u8], _deadline: Option<Instant>) -> Result<bool, String> {
        while self.hung.load(Ordering::Acquire) {
            std::thread::sleep(Duration::from_millis(10));
        }
        self.to[rank as usize].send(message.to_vec()).map_err(|e| e.to_string())?;
        Ok(true)
    }

    fn receive(&self, rank: u32, deadline: Option<Instant>) -> Result<Option<Vec<u8>>, String> {
        let from = self.from[rank as usize].lock().unwrap();
        match deadline {
            None => from.recv().map(Some).map_err(|e| e.to_string()),
            Some(deadline) => match from.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
                Ok(message) => Ok(Some(message)),
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => Ok(None),
                Err(e) => Err(e.to_string()),
            },
        }
    }
}

/// A cluster of `ranks` ranks: rank 0's server (its state, to listen with) and the switches
/// that hang each rank. Worker `r` checks edits against `limits(r)`; rank 0 gives a
/// worker up after `timeout`.
fn cluster(ranks: u32, limits: impl Fn(u32) -> Limits, timeout: Duration) -> (AppState, Vec<Arc<AtomicBool>>) {
    let n = ranks as usize;
    let mut senders: Vec<Vec<Option<Sender<Vec<u8>>>>> = (0..n).map(|_| (0..n).map(|_| None).collect()).collect();
    let mut receivers: Vec<Vec<Option<Receiver<Vec<u8>>>>> = (0..n).map(|_| (0..n).map(|_| None).collect()).collect();
    for from in 0..n {
        for to in 0..n {
            let (tx, rx) = channel();
            senders[from][to] = Some(tx);
            receivers[to][from] = Some(rx);
        }
    }
    let mut links: Vec<Link> = (0..n)
        .map(|r| Link {
            rank: r as u32,
            ranks,
            to: senders[r].iter_mut().map(|s| s.take().unwrap()).collect(),
            from: receivers[r].iter_mut().map(|rx| Mutex::new(rx.take().unwrap())).collect(),
            hung: Arc::default(),
        })
        .collect();
    let hung = links.iter().map(|l| Arc::clone(&l.hung)).collect();
    for link in links.drain(1..) {
        let config = Config { token: None, limits: limits(link.rank) };
        std::thread::spawn(move || work(&link, config, Vec::new()));
    }
    let root = links.pop().unwrap();
    (AppState::clustered(Config::default(), Cluster::new(Box::new(root), timeout)), hung)
}

/// The PNG bytes of `uri`.
async fn png(app: &Router, uri: &str) -> Vec<u8> {
    let (status, content_type, bytes) = send(app, "GET", uri, Body::empty(), &[]).await;
    assert_eq!((status, content_type.as_str()), (StatusCode::OK, "image/png"), "{uri}: {}", String::from_utf8_lossy(&bytes));
    bytes
}

/// Sends the same request to both servers; both must answer `expected`, with the same body.
async fn both(apps: &[&Router; 2], method: &str, uri: &str, body: Value, expected: StatusCode) -> Value {
    let one = ok(apps[0], method, uri, body.clone(), expected).await;
    let many = ok(apps[1], method, uri, body, expected).await;
    assert_eq!(one, many, "{method} {uri}: the cluster answered otherwise");
    one
}

/// Frames of scene `s` by every integrator: the same bytes from both servers, the second's
/// rendered by all its `ranks` (not by rank 0 alone, which a pass falls back to when a worker
/// lacks the scene's version).
async fn same_frames(apps: &[&Router; 2], ranks: u32, s: u64, what: &str) {
    for integrator in ["eyelight", "whitted", "distribution", "path"] {
        let uri = format!("/scenes/{s}/frame.png?width=48&height=32&spp=3&integrator={integrator}");
        assert!(png(apps[0], &uri).await == png(apps[1], &uri).await, "{what}, {integrator}: the cluster rendered other bytes");
        let stats = ok(apps[1], "GET", &format!("/scenes/{s}/stats"), Value::Null, StatusCode::OK).await;
        assert_eq!(stats["last_frame"]["cluster"]["ranks"], ranks, "{what}, {integrator}: every rank renders: {stats}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_edit_reaches_the_workers_and_frames_are_the_same_bytes() {
    for ranks in [2, 3] {
        let alone = router(AppState::new(Config::default()));
        let (state, _) = cluster(ranks, |_| Limits::default(), Duration::from_secs(60));
        let clustered = router(state);
        let apps = [&alone, &clustered];

        let s = both(&apps, "POST", "/scenes", json!({ "demo": "cornell" }), StatusCode::CREATED).await["id"].as_u64().unwrap();
        same_frames(&apps, ranks, s, "the Cornell room").await;
        let stats = ok(&clustered, "GET", &format!("/scenes/{s}/stats"), Value::Null, StatusCode::OK).await;
        let gathered = stats["last_frame"]["cluster"]["gathered_bytes"].as_u64().unwrap();
        let own = raystage_render::Share { index: 0, count: ranks }.pixel_count(48, 32) as u64;
        assert_eq!(gathered, (48 * 32 - own) * 12, "the workers' pixels, as floats: {stats}");

        // Commands: the camera, a batch, new geometry, moved vertices.
        both(&apps, "PUT", &format!("/scenes/{s}/camera"), json!({ "fov_y_degrees": 50 }), StatusCode::OK).await;
        let batch = json!({ "commands": [
            { "add_shader": { "label": "green", "class": "Phong", "params": { "diffuse": [0, 0.8, 0] } } },
            { "add_object": { "label": "square", "kind": "unstructured", "mesh": { "positions": [[-0.2, -0.2, 0.5], [0.2, -0.2, 0.5], [0.2, 0.2, 0.5], [-0.2, 0.2, 0.5]], "indices": [[0, 1, 2], [0, 2, 3]], "shader": "green" } } },
            { "add_instance": { "object": "square", "transform": { "translate": [0, 0.5, 0] } } }
        ] });
        let result = both(&apps, "POST", &format!("/scenes/{s}/commands"), batch, StatusCode::OK).await;
        let object = result["results"][1]["id"].as_u64().unwrap();
        let moved = json!({ "positions": [[-0.3, -0.1, 0.4], [0.2, -0.2, 0.5], [0.2, 0.3, 0.5], [-0.2, 0.2, 0.6]] });
        both(&apps, "PATCH", &format!("/scenes/{s}/objects/{object}"), moved, StatusCode::OK).await;
        same_frames(&apps, ranks, s, "the room after edits").await;

        // An image texture (the file goes to the workers) on the new square.
        let mut file = Vec::new();
        let checker = image::RgbImage::from_fn(4, 4, |x, y| if (x + y) % 2 == 0 { image::Rgb([250, 20, 20]) } else { image::Rgb([20, 20, 250]) });
        checker.write_to(&mut std::io::Cursor::new(&mut file), image::ImageFormat::Png).unwrap();
        let mut texture = None;
        for app in apps {
            let (status, _, body) = send(app, "POST", &format!("/scenes/{s}/textures"), Body::from(file.clone()), &[("content-type", "image/png")]).await;
            assert_eq!(status, StatusCode::CREATED, "{}", String::from_utf8_lossy(&body));
            texture = Some(serde_json::from_slice::<Value>(&body).unwrap()["id"].clone());
        }
        let shader = result["results"][0]["id"].as_u64().unwrap();
        let textured = json!({ "params": { "diffuse": 1, "diffuse_texture": { "texture": texture.unwrap() } } });
        both(&apps, "PATCH", &format!("/scenes/{s}/shaders/{shader}"), textured, StatusCode::OK).await;
        same_frames(&apps, ranks, s, "a textured square").await;

        // A glTF file added to the scene, and a scene made of one; a deleted scene.
        for app in apps {
            let (status, _, body) = send(app, "POST", &format!("/scenes/{s}/gltf?camera=keep"), Body::from(glb()), &[("content-type", "model/gltf-binary")]).await;
            assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
        }
        same_frames(&apps, ranks, s, "the room with a glTF file").await;
        let mut file_scene = 0;
        for app in apps {
            let (status, _, body) = send(app, "POST", "/scenes?environment=0.3", Body::from(glb()), &[("content-type", "model/gltf-binary")]).await;
            assert_eq!(status, StatusCode::CREATED, "{}", String::from_utf8_lossy(&body));
            file_scene = serde_json::from_slice::<Value>(&body).unwrap()["id"].as_u64().unwrap();
        }
        same_frames(&apps, ranks, file_scene, "a glTF scene").await;
        for app in apps {
            assert_eq!(send(app, "DELETE", &format!("/scenes/{file_scene}"), Body::empty(), &[]).await.0, StatusCode::NO_CONTENT);
        }

        // An animated demo over several frames: a new scene per frame.
        for frame in [0, 7] {
            let r = both(&apps, "POST", "/scenes", json!({ "demo": "robots", "frame": frame }), StatusCode::CREATED).await["id"].as_u64().unwrap();
            same_frames(&apps, ranks, r, &format!("robots at frame {frame}")).await;
        }
    }
}

/// The converged frame of a stream of `s` with `query` on `state`'s server.
async fn converged_stream_frame(state: AppState, s: u64, query: &str) -> Vec<u8> {
    let addr = listen(state).await;
    let (mut socket, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/scenes/{s}/stream?{query}")).await.unwrap();
    loop {
        let Some(Ok(Message::Text(text))) = socket.next().await else { continue };
        let message: Value = serde_json::from_str(text.as_str()).unwrap();
        if message["type"] != "frame" {
            continue;
        }
        let Some(Ok(Message::Binary(png))) = socket.next().await else { panic!("a frame's PNG follows its statistics") };
        if message["converged"] == true {
            return png.to_vec();
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stream_accumulates_across_the_ranks_to_the_same_image() {
    let alone = AppState::new(Config::default());
    let (clustered, _) = cluster(3, |_| Limits::default(), Duration::from_secs(60));
    for state in [&alone, &clustered] {
        ok(&router(state.clone()), "POST", "/scenes", json!({ "demo": "cornell" }), StatusCode::CREATED).await;
    }
    // Passes of growing size, split as each server's timing says: each pixel's samples go on
    // where the last pass left them, so the split does not change the image. (Adaptive
    // sampling decides at pass boundaries, so it is left out: its image depends on the split.)
    let query = "width=40&height=40&integrator=path&max_samples=24";
    let one = converged_stream_frame(alone, 1, query).await;
    let many = converged_stream_frame(clustered, 1, query).await;
    assert!(one == many, "the stream's converged frame differs across ranks");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_edit_a_worker_refuses_is_refused_everywhere() {
    // Worker 2 allows scenes of 1 MB; rank 0 and worker 1 the default.
    let small = |rank| if rank == 2 { Limits { max_scene_bytes: 1 << 20, ..Limits::default() } } else { Limits::default() };
    let (state, _) = cluster(3, small, Duration::from_secs(60));
    let app = router(state);
    let (status, error) = call(&app, "POST", "/scenes", json!({ "demo": "museum-200000" })).await;
    assert_eq!(status, StatusCode::INTERNAL_SERVER_ERROR, "{error}");
    assert!(error["error"]["message"].as_str().unwrap().contains("rank 2 could not apply"), "{error}");
    assert_eq!(ok(&app, "GET", "/scenes", Value::Null, StatusCode::OK).await, json!([]), "the scene is not kept on rank 0");
    // An edit: refused, the scene left as it was on rank 0.
    let s = new_scene(&app).await;
    let big: Vec<[f32; 3]> = (0..60_000).map(|i| [i as f32, 0.0, (i % 7) as f32]).collect();
    let indices: Vec<[u32; 3]> = (0..59_998).map(|i| [i, i + 1, i + 2]).collect();
    let add = json!({ "mesh": { "positions": big, "indices": indices } });
    let (status, error) = call(&app, "POST", &format!("/scenes/{s}/objects"), add).await;
    assert_eq!(status, StatusCode::INTERNAL_SERVER_ERROR, "{error}");
    assert!(error["error"]["message"].as_str().unwrap().contains("refused on every rank"), "{error}");
    let info = ok(&app, "GET", &format!("/scenes/{s}"), Value::Null, StatusCode::OK).await;
    assert_eq!((info["version"].as_u64(), info["objects"].as_u64()), (Some(0), Some(0)), "{info}");
    // The cluster goes on: a small edit stands everywhere and renders.
    let square = json!({ "mesh": { "positions": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], "indices": [[0, 1, 2], [0, 2, 3]] } });
    ok(&app, "POST", &format!("/scenes/{s}/objects"), square, StatusCode::CREATED).await;
    png(&app, &format!("/scenes/{s}/frame.png?width=16&height=16")).await;
    let stats = ok(&app, "GET", &format!("/scenes/{s}/stats"), Value::Null, StatusCode::OK).await;
    assert_eq!(stats["last_frame"]["cluster"]["ranks"], 3, "{stats}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_worker_that_stops_answering_is_given_up_and_rank_0_serves_alone() {
    let (state, hung) = cluster(2, |_| Limits::default(), Duration::from_secs(1));
    let app = router(state);
    let alone = router(AppState::new(Config::default()));
    for app in [&app, &alone] {
        ok(app, "POST", "/scenes", json!({ "demo": "cornell" }), StatusCode::CREATED).await;
    }
    let uri = "/scenes/1/frame.png?width=32&height=24&spp=2&integrator=path";
    let expected = png(&alone, uri).await;
    assert!(png(&app, uri).await == expected);
    hung[1].store(true, Ordering::Release);
    let start = Instant::now();
    // The frame after the worker stopped answering: rendered alone, within the timeout and the
    // render's own time.
    assert!(png(&app, uri).await == expected, "rank 0 renders the same image alone");
    assert!(start.elapsed() < Duration::from_secs(20), "no hang: {:?}", start.elapsed());
    let stats = ok(&app, "GET", "/scenes/1/stats", Value::Null, StatusCode::OK).await;
    assert!(stats["last_frame"]["cluster"].is_null(), "one process rendered it: {stats}");
    // Edits go on, on rank 0 alone.
    ok(&app, "PUT", "/scenes/1/camera", json!({ "fov_y_degrees": 30 }), StatusCode::OK).await;
    ok(&alone, "PUT", "/scenes/1/camera", json!({ "fov_y_degrees": 30 }), StatusCode::OK).await;
    assert!(png(&app, uri).await == png(&alone, uri).await);
}
