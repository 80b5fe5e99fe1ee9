//! The client's network layer against a real server started in-process: the scene arrives over
//! HTTP, frames over the WebSocket (decoded, refining), a camera change shows in a later
//! frame, and a glTF scene's animation is listed, posed and played by the scene's clock.

use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration, Instant};

use raystage_client::net::{Event, Link, StreamConfig, connect};
use raystage_client::protocol::{CameraPatch, Request, Settings};
use raystage_client::{Frame, Server};

mod common;
use common::server;

fn next(link: &Link, deadline: Instant) -> Event {
    match link.events.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
        Ok(Event::Closed(reason)) => panic!("the connection closed: {reason}"),
        Ok(event) => event,
        Err(RecvTimeoutError::Timeout) => panic!("nothing from the server in time"),
        Err(RecvTimeoutError::Disconnected) => panic!("the network thread ended"),
    }
}

fn next_frame(link: &Link, deadline: Instant) -> Frame {
    loop {
        match next(link, deadline) {
            Event::Frame(frame) => return frame,
            Event::Problem(problem) => panic!("{problem}"),
            _ => {}
        }
    }
}

#[test]
fn frames_arrive_refine_and_follow_the_camera() {
    let (_runtime, url) = server();
    let settings = Settings { width: Some(64), height: Some(48), integrator: Some("eyelight".into()), max_samples: Some(4096), ..Settings::default() };
    let link = connect(StreamConfig { server: Server::parse(&url, None).unwrap(), scene: None, settings }, || {});
    let deadline = Instant::now() + Duration::from_secs(30);

    let Event::Scene(scene) = next(&link, deadline) else { panic!("the scene comes first") };
    assert_eq!((scene.info.id, scene.info.origin.as_str()), (1, "demo:cornell"));
    assert!(!scene.objects.is_empty() && !scene.instances.is_empty(), "{scene:?}");
    let Event::Connected(hello) = next(&link, deadline) else { panic!("then the stream opens") };
    assert_eq!((hello.width, hello.height, hello.integrator.as_deref()), (64, 48, Some("eyelight")));

    let first = next_frame(&link, deadline);
    let second = next_frame(&link, deadline);
    for frame in [&first, &second] {
        assert_eq!((frame.image.size, frame.stats.width, frame.stats.integrator.as_str()), ([64, 48], 64, "eyelight"));
        assert!(frame.stats.mrays_per_second > 0.0 && frame.stats.rays.primary > 0, "{:?}", frame.stats);
    }
    assert!(second.stats.seq > first.stats.seq && second.stats.samples > first.stats.samples, "frames refine");
    // The Cornell room has a red and a green wall: the decoded pixels are the rendered image.
    let red = first.image.pixels.iter().filter(|c| i32::from(c.r()) > i32::from(c.g()) + 50).count();
    let green = first.image.pixels.iter().filter(|c| i32::from(c.g()) > i32::from(c.r()) + 30).count();
    assert!(red > 64 && green > 64, "red {red}, green {green} of {} pixels", first.image.pixels.len());

    // A camera change is an edit of the scene: a later frame shows its version, from scratch.
    // (Made once the image has many samples: frames are skipped while the viewer is busy, so a
    // fresh accumulation is told from a continued one by being well behind it.)
    let settled = loop {
        let frame = next_frame(&link, deadline);
        if frame.stats.samples >= 2048 {
            break frame;
        }
    };
    let version = settled.stats.scene_version;
    let eye = scene.info.camera.eye;
    link.requests.send(Request::Camera(CameraPatch { eye: [eye[0] + 0.5, eye[1], eye[2]], target: scene.info.camera.target })).unwrap();
    let moved = loop {
        let frame = next_frame(&link, deadline);
        if frame.stats.scene_version > version {
            break frame;
        }
    };
    assert!(moved.stats.samples < settled.stats.samples, "the image started over: {:?} after {:?}", moved.stats, settled.stats);

    // Dropping the link ends the connection.
    let Link { events, requests } = link;
    drop(requests);
    let end = Instant::now() + Duration::from_secs(10);
    while events.recv_timeout(end.saturating_duration_since(Instant::now())).is_ok() {}
    assert!(Instant::now() < end, "the network thread stops when the viewer goes");
}

/// A GLB file: a unit quad that its animation `slide` moves from x = 0 at 0 s to x = 2 at 1 s.
fn sliding_quad() -> Vec<u8> {
    let floats = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0];
    let mut bin: Vec<u8> = floats[..12].iter().flat_map(|f| f.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    bin.extend(floats[12..].iter().flat_map(|f| f.to_le_bytes()));
    let document = serde_json::json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": [
            { "buffer": 0, "byteLength": 48 }, { "buffer": 0, "byteOffset": 48, "byteLength": 12 },
            { "buffer": 0, "byteOffset": 60, "byteLength": 8 }, { "buffer": 0, "byteOffset": 68, "byteLength": 24 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
            { "bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR" },
            { "bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1] },
            { "bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3" }
        ],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "nodes": [{ "mesh": 0 }],
        "animations": [{ "name": "slide", "channels": [{ "sampler": 0, "target": { "node": 0, "path": "translation" } }],
            "samplers": [{ "input": 2, "output": 3, "interpolation": "LINEAR" }] }],
        "scenes": [{ "nodes": [0] }]
    });
    raystage_gltf_import::glb(&serde_json::to_vec(&document).unwrap(), &bin)
}

/// The timeline's requests reach the scene's clock: a glTF scene's snapshot lists its
/// animation, setting the clock's time makes a new version of the image and comes back as the
/// clock's state, the scene fetched again has the quad where the animation puts it, and a
/// playing clock brings frames of later and later times with nothing more sent.
#[test]
fn the_clock_poses_and_plays_the_scene_the_stream_shows() {
    let (runtime, url) = server();
    let server = Server::parse(&url, None).unwrap();
    let created: serde_json::Value = runtime.block_on(server.post("/scenes", "model/gltf-binary", &sliding_quad())).unwrap();
    let scene = created["id"].as_u64().unwrap() as u32;
    let settings = Settings { width: Some(32), height: Some(24), integrator: Some("eyelight".into()), max_samples: Some(1), ..Settings::default() };
    let link = connect(StreamConfig { server, scene: Some(scene), settings }, || {});
    let deadline = Instant::now() + Duration::from_secs(30);
    let Event::Scene(snapshot) = next(&link, deadline) else { panic!("the scene comes first") };
    let [animation] = snapshot.animations.as_slice() else { panic!("one animation: {:?}", snapshot.animations) };
    assert_eq!((animation.index, animation.name.as_str(), animation.duration), (0, "slide", 1.0));
    let version = next_frame(&link, deadline).stats.scene_version;

    link.requests.send(Request::Clock(serde_json::json!({ "time": 0.25, "animation": 0 }))).unwrap();
    let clock = loop {
        match next(&link, deadline) {
            Event::Clock(clock) => break clock,
            Event::Problem(problem) => panic!("{problem}"),
            _ => {}
        }
    };
    assert_eq!((clock.time, clock.playing), (0.25, false));
    while next_frame(&link, deadline).stats.scene_version == version {}
    link.requests.send(Request::RefreshScene).unwrap();
    let posed = loop {
        match next(&link, deadline) {
            Event::Scene(scene) => break scene,
            Event::Problem(problem) => panic!("{problem}"),
            _ => {}
        }
    };
    assert_eq!(posed.instances[0].matrix[0][3], 0.5, "{:?}", posed.instances);
    assert_eq!(posed.clock, Some(clock), "the scene comes with its clock");

    link.requests.send(Request::Clock(serde_json::json!({ "playing": true, "rate": 0.1 }))).unwrap();
    let mut times = Vec::new();
    while times.len() < 4 {
        if let Some(time) = next_frame(&link, deadline).stats.scene_time.filter(|&t| t > 0.25) {
            times.push(time);
        }
    }
    assert!(times.windows(2).all(|w| w[1] > w[0]), "{times:?}");
}

/// An image file on the viewer's machine lights the scene: uploaded as a texture and made the
/// map of a new environment light, the scene fetched again shows it; a file that cannot be read
/// is a problem named by its path, and the stream goes on.
#[test]
fn an_image_file_becomes_the_environment() {
    let (_runtime, url) = server();
    let settings = Settings { width: Some(32), height: Some(24), integrator: Some("eyelight".into()), max_samples: Some(1), ..Settings::default() };
    let link = connect(StreamConfig { server: Server::parse(&url, None).unwrap(), scene: None, settings }, || {});
    let deadline = Instant::now() + Duration::from_secs(30);
    let Event::Scene(scene) = next(&link, deadline) else { panic!("the scene comes first") };
    assert!(scene.lights.iter().all(|l| l.class != "EnvironmentLight"), "{:?}", scene.lights);

    let dir = std::env::temp_dir().join(format!("raystage-client-environment-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sky = dir.join("sky.png");
    image::RgbImage::from_fn(8, 4, |_, y| if y < 2 { image::Rgb([120, 160, 255]) } else { image::Rgb([90, 80, 60]) }).save(&sky).unwrap();
    let light = serde_json::json!({ "class": "EnvironmentLight", "radiance": [2.0, 2.0, 2.0], "map": null, "rotate": 90.0 });
    link.requests.send(Request::EnvironmentImage { path: sky, id: None, light: light.clone() }).unwrap();
    let lit = loop {
        match next(&link, deadline) {
            Event::Scene(scene) => break scene,
            Event::Problem(problem) => panic!("{problem}"),
            _ => {}
        }
    };
    let environment = lit.lights.iter().find(|l| l.class == "EnvironmentLight").expect("an environment light was added");
    assert!(environment.map.is_some(), "{environment:?}");
    assert_eq!((environment.radiance, environment.rotate), (Some([2.0; 3]), Some(90.0)));

    let missing = dir.join("missing.hdr");
    link.requests.send(Request::EnvironmentImage { path: missing.clone(), id: Some(environment.id), light }).unwrap();
    let problem = loop {
        if let Event::Problem(problem) = next(&link, deadline) {
            break problem;
        }
    };
    assert!(problem.contains("missing.hdr"), "{problem}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The viewer writes its own `settings` message (it speaks the published protocol, not the
/// server's types): every field it can send is one of the stream's settings, as the server's one
/// list of a frame's settings names them, or the stream's own `max_samples`. A field renamed or
/// dropped there fails here, before a viewer sends what the server refuses.
#[test]
fn every_setting_the_viewer_sends_is_one_the_stream_takes() {
    let all = Settings {
        width: Some(1),
        height: Some(1),
        integrator: Some("path".into()),
        max_samples: Some(1),
        exposure: Some(0.0),
        tonemap: Some("clamp".into()),
        default_lights: Some(true),
    };
    let sent = serde_json::to_value(&all).unwrap();
    let fields: Vec<&String> = sent.as_object().unwrap().keys().collect();
    assert_eq!(fields.len(), 7, "a field left out of the test: {fields:?}");
    for field in fields {
        assert!(field == "max_samples" || raystage_render::SettingsPatch::NAMES.contains(&field.as_str()), "the viewer sends `{field}`, which is no stream setting");
    }
}
