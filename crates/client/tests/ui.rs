//! The viewer's UI state, with the test playing the server on the other end of the viewer's
//! channels (egui_kittest, no window, no rendering): statistics show up in the side panel,
//! choosing an integrator sends a `settings` message, a drag sends the orbited camera, and the
//! first frame of a scene version refreshes objects the panel shows as not built; the lighting
//! controls edit the scene's environment light with `commands` messages, and the timeline of a
//! scene with animations sets the scene's clock (a time from the slider at most ten times a
//! second, play and pause once each) and follows the time of the frames while it plays.

use std::time::{Duration, Instant};

use eframe::egui::{self, Color32, ColorImage};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raystage_client::net::{Event, Frame, Link, Remote, SceneSnapshot};
use raystage_client::protocol::{AnimationInfo, CameraJson, Clock, FrameStats, Hello, LightInfo, ObjectInfo, Rays, Request, SceneInfo, Settings};
use raystage_client::{Viewer, ViewerOptions};
use serde_json::json;

fn scene() -> SceneSnapshot {
    let camera = CameraJson { eye: [0.0, 0.0, 5.0], target: [0.0; 3], up: [0.0, 1.0, 0.0], fov_y_degrees: 60.0 };
    let info = SceneInfo { id: 1, origin: "demo:test".into(), version: 0, objects: 0, instances: 0, lights: 0, triangles: 0, camera };
    SceneSnapshot { info, objects: Vec::new(), instances: Vec::new(), lights: Vec::new(), animations: Vec::new(), clock: None }
}

fn frame(seq: u64, samples: u32, received: Instant) -> Event {
    let stats = FrameStats {
        seq,
        scene_version: 0,
        scene_time: None,
        width: 8,
        height: 4,
        integrator: "eyelight".into(),
        samples,
        pass_samples: 4,
        pass_seconds: 0.021,
        encode_seconds: 0.004,
        rays: Rays { primary: 128, total: 128, ..Rays::default() },
        mrays_per_second: 11.2,
        effects: vec!["multisampling".into()],
        converged: false,
    };
    Event::Frame(Frame { stats, image: ColorImage::new([8, 4], vec![Color32::RED; 32]), received })
}

fn viewer() -> (Harness<'static, Viewer>, Remote) {
    let (link, remote) = Link::pair();
    let viewer = Viewer::new(link, ViewerOptions { integrator: None, max_samples: 256, ..ViewerOptions::default() });
    let harness = Harness::builder().with_size([1000.0, 600.0]).build_ui_state(|ui, viewer: &mut Viewer| viewer.ui(ui), viewer);
    (harness, remote)
}

fn requests(remote: &mut Remote) -> Vec<Request> {
    std::iter::from_fn(|| remote.requests.try_recv().ok()).collect()
}

fn hello() -> Event {
    Event::Connected(Hello { protocol: 1, scene: 1, width: 640, height: 360, integrator: None, max_samples: 256 })
}

#[test]
fn the_side_panel_shows_the_stream_statistics() {
    let (mut harness, remote) = viewer();
    let start = Instant::now();
    remote.events.send(Event::Scene(Box::new(scene()))).unwrap();
    remote.events.send(hello()).unwrap();
    remote.events.send(frame(1, 4, start)).unwrap();
    remote.events.send(frame(2, 16, start + Duration::from_millis(500))).unwrap();
    harness.run();

    for shown in ["11.2 Mrays/s", "16 / 256", "21.0 ms for 4 spp", "effects: multisampling", "2.0 frames/s", "8 × 4, eyelight", "scene 1 (demo:test)"] {
        assert!(harness.query_by_label(shown).is_some(), "the side panel shows `{shown}`");
    }
    assert_eq!(harness.state().stats().map(|s| s.samples), Some(16));
}

#[test]
fn the_stream_follows_the_view_and_choosing_an_integrator_sends_settings() {
    let (mut harness, mut remote) = viewer();
    remote.events.send(Event::Scene(Box::new(scene()))).unwrap();
    remote.events.send(hello()).unwrap();
    harness.run();
    // The first size goes out at once: the view's pixels (the window less the side panel and
    // the status line).
    let first = requests(&mut remote);
    let [Request::Settings(Settings { width: Some(w), height: Some(h), max_samples: Some(256), integrator: None, .. })] = first.as_slice() else {
        panic!("one settings message with the view's size, got {first:?}")
    };
    assert!((600..1000).contains(w) && (500..600).contains(h), "{w} × {h}");

    harness.get_by_label("path").click();
    harness.run();
    let sent = requests(&mut remote);
    assert_eq!(sent, [Request::Settings(Settings { integrator: Some("path".into()), ..Settings::default() })]);
    assert_eq!(sent[0].message(9), Some(json!({ "type": "settings", "request": 9, "integrator": "path" })));

    // Grading: the tone curve and the exposure.
    harness.get_by_label("neutral tone map").click();
    harness.run();
    assert_eq!(requests(&mut remote), [Request::Settings(Settings { tonemap: Some("neutral".into()), ..Settings::default() })]);

    // A resize is sent once it has held still.
    harness.set_size(egui::vec2(900.0, 600.0));
    harness.step();
    assert!(requests(&mut remote).is_empty(), "not while the window may still be moving");
    harness.run_steps(30);
    let sent = requests(&mut remote);
    assert!(matches!(sent.as_slice(), [Request::Settings(Settings { width: Some(n), .. })] if *n == w - 100), "{sent:?}");
}

#[test]
fn dragging_orbits_the_camera_around_its_target() {
    let (mut harness, mut remote) = viewer();
    remote.events.send(Event::Scene(Box::new(scene()))).unwrap();
    remote.events.send(hello()).unwrap();
    remote.events.send(frame(1, 1, Instant::now())).unwrap();
    harness.run();
    requests(&mut remote);

    // 100 points to the right, over a few frames, on the view (left of the side panel).
    let start = egui::pos2(300.0, 300.0);
    harness.hover_at(start);
    harness.drag_at(start);
    harness.run();
    for x in [20.0, 60.0, 100.0] {
        harness.hover_at(start + egui::vec2(x, 0.0));
        harness.run();
    }
    harness.drop_at(start + egui::vec2(100.0, 0.0));
    harness.run();

    let cameras: Vec<_> = requests(&mut remote).into_iter().filter_map(|r| if let Request::Camera(c) = r { Some(c) } else { None }).collect();
    let last = cameras.last().expect("the drag sent camera messages");
    // One radian (0.01 per point) about the up axis: the eye goes left around the target.
    let expected = [-5.0 * 1f32.sin(), 0.0, 5.0 * 1f32.cos()];
    assert!(last.eye.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-3), "eye {:?}, expected {expected:?}", last.eye);
    assert_eq!(last.target, [0.0; 3]);
    let message = Request::Camera(*last).message(3).unwrap();
    assert_eq!((message["type"].as_str(), message["camera"]["target"].clone()), (Some("camera"), json!([0.0, 0.0, 0.0])));

    // A scroll over the view zooms in: same direction, closer.
    harness.hover_at(start);
    harness.event(egui::Event::MouseWheel { unit: egui::MouseWheelUnit::Point, delta: egui::vec2(0.0, 50.0), phase: egui::TouchPhase::Move, source: egui::MouseWheelSource::Unknown, modifiers: egui::Modifiers::NONE });
    harness.run();
    let orbit = harness.state().orbit().unwrap();
    assert!(orbit.eye.length() < 4.99, "{orbit:?}");
}

#[test]
fn the_first_frame_of_a_version_refreshes_objects_shown_as_not_built() {
    let (mut harness, mut remote) = viewer();
    let object = |built| ObjectInfo { id: 0, kind: "static".into(), triangles: 12, vertices: 8, built };
    let mut unbuilt = scene();
    unbuilt.objects = vec![object(false)];
    remote.events.send(Event::Scene(Box::new(unbuilt))).unwrap();
    remote.events.send(hello()).unwrap();
    harness.run();
    requests(&mut remote);
    remote.events.send(frame(1, 1, Instant::now())).unwrap();
    remote.events.send(frame(2, 2, Instant::now())).unwrap();
    harness.run();
    let refreshes = |sent: Vec<Request>| sent.iter().filter(|r| matches!(r, Request::RefreshScene)).count();
    assert_eq!(refreshes(requests(&mut remote)), 1, "once for the version, not for every frame");
    assert!(harness.query_by_label("#0 static: 12 triangles, not built").is_some());

    let mut built = scene();
    built.objects = vec![object(true)];
    remote.events.send(Event::Scene(Box::new(built))).unwrap();
    remote.events.send(frame(3, 4, Instant::now())).unwrap();
    harness.run();
    assert!(harness.query_by_label("#0 static: 12 triangles, built").is_some());
    assert_eq!(refreshes(requests(&mut remote)), 0, "everything is built: nothing to refresh");
}

/// The scene's environment light: switched off (deleted) and on again (added with the same
/// parameters, its id fetched anew), its intensity and turn sent as `set_light` commands.
#[test]
fn the_lighting_controls_edit_the_environment_light() {
    let (mut harness, mut remote) = viewer();
    // The edits sent, not the stream's size (the panel's width may change with its contents).
    let requests = |remote: &mut Remote| requests(remote).into_iter().filter(|r| !matches!(r, Request::Settings(_))).collect::<Vec<_>>();
    let studio = |id| LightInfo { id, class: "EnvironmentLight".into(), radiance: Some([1.0; 3]), map: Some(1), rotate: Some(0.0) };
    let with_lights = |lights: Vec<LightInfo>| SceneSnapshot { lights, ..scene() };
    remote.events.send(Event::Scene(Box::new(with_lights(vec![studio(3)])))).unwrap();
    remote.events.send(hello()).unwrap();
    harness.run();
    requests(&mut remote);
    assert!(harness.query_by_label("environment: image (a studio or a sky)").is_some());

    harness.get_by_label("environment on").click();
    harness.run();
    assert_eq!(requests(&mut remote), [Request::Commands(json!([{ "delete_light": { "id": 3 } }]))]);
    // A fetch of the scene (it has no environment light now) keeps the switched-off one.
    remote.events.send(Event::Scene(Box::new(with_lights(Vec::new())))).unwrap();
    harness.run();
    harness.get_by_label("environment on").click();
    harness.run();
    let spec = json!({ "class": "EnvironmentLight", "radiance": [1.0, 1.0, 1.0], "map": 1, "rotate": 0.0 });
    assert_eq!(requests(&mut remote), [Request::Commands(json!([{ "add_light": spec }])), Request::RefreshScene]);
    remote.events.send(Event::Scene(Box::new(with_lights(vec![studio(4)])))).unwrap();
    harness.run();

    // A slider moved by a key sends its value once.
    harness.get_by_role_and_label(egui::accesskit::Role::Slider, "intensity").focus();
    harness.run();
    harness.key_press(egui::Key::ArrowRight);
    harness.run();
    let sent = requests(&mut remote);
    let [Request::Commands(commands)] = sent.as_slice() else { panic!("one batch, got {sent:?}") };
    assert_eq!(commands[0]["set_light"]["id"], 4, "{commands}");
    let radiance = commands[0]["set_light"]["light"]["radiance"][0].as_f64().unwrap();
    assert!((radiance - 1.05).abs() < 1e-6, "{commands}");
    assert_eq!(Request::Commands(commands.clone()).message(5).unwrap()["type"], "commands");
}

/// A studio can be made uniform and back (`set_light` with and without its map); a scene with
/// no environment light gets a uniform one from a button; a file named in the panel is handed
/// to the connection to upload, with the light it becomes the map of.
#[test]
fn the_lighting_controls_choose_uniform_image_or_a_file() {
    let (mut harness, mut remote) = viewer();
    let requests = |remote: &mut Remote| requests(remote).into_iter().filter(|r| !matches!(r, Request::Settings(_))).collect::<Vec<_>>();
    let studio = LightInfo { id: 3, class: "EnvironmentLight".into(), radiance: Some([1.0; 3]), map: Some(1), rotate: Some(30.0) };
    remote.events.send(Event::Scene(Box::new(SceneSnapshot { lights: vec![studio.clone()], ..scene() }))).unwrap();
    remote.events.send(hello()).unwrap();
    harness.run();
    requests(&mut remote);

    harness.get_by_label("uniform").click();
    harness.run();
    let uniform = json!({ "class": "EnvironmentLight", "radiance": [1.0, 1.0, 1.0], "map": null, "rotate": 30.0 });
    assert_eq!(requests(&mut remote), [Request::Commands(json!([{ "set_light": { "id": 3, "light": uniform } }]))]);
    // The scene fetched again shows the light without its map: the image can still be chosen.
    let without_map = LightInfo { map: None, ..studio.clone() };
    remote.events.send(Event::Scene(Box::new(SceneSnapshot { lights: vec![without_map], ..scene() }))).unwrap();
    harness.run();
    assert!(harness.query_by_label("environment: uniform").is_some());
    harness.get_by_label("image").click();
    harness.run();
    let image = json!({ "class": "EnvironmentLight", "radiance": [1.0, 1.0, 1.0], "map": 1, "rotate": 30.0 });
    assert_eq!(requests(&mut remote), [Request::Commands(json!([{ "set_light": { "id": 3, "light": image } }]))]);

    harness.get_by_role(egui::accesskit::Role::TextInput).click();
    harness.run();
    harness.get_by_role(egui::accesskit::Role::TextInput).type_text("/skies/dusk.hdr");
    harness.run();
    harness.get_by_label("load").click();
    harness.run();
    assert_eq!(requests(&mut remote), [Request::EnvironmentImage { path: "/skies/dusk.hdr".into(), id: Some(3), light: image }]);

    // No environment light at all: a button adds a uniform one.
    let (mut harness, mut remote) = viewer();
    remote.events.send(Event::Scene(Box::new(scene()))).unwrap();
    harness.run();
    assert!(harness.query_by_label("no environment light").is_some());
    harness.get_by_label("add a uniform environment").click();
    harness.run();
    let white = json!({ "class": "EnvironmentLight", "radiance": [1.0, 1.0, 1.0], "map": null, "rotate": 0.0 });
    assert_eq!(requests(&mut remote), [Request::Commands(json!([{ "add_light": white }])), Request::RefreshScene]);
}

/// The clock times set among `requests`: (seconds, animation).
fn times(requests: Vec<Request>) -> Vec<(f64, u64)> {
    requests
        .into_iter()
        .filter_map(|r| match r {
            Request::Clock(c) => Some((c["time"].as_f64()?, c["animation"].as_u64().unwrap())),
            _ => None,
        })
        .collect()
}

/// A frame showing the scene at `time` seconds of its animation.
fn frame_at(time: f64) -> Event {
    let Event::Frame(mut frame) = frame(1, 1, Instant::now()) else { unreachable!("frame makes frames") };
    frame.stats.scene_time = Some(time);
    Event::Frame(frame)
}

/// A scene with two animations, one second and four seconds long.
fn animated() -> Event {
    let animations = vec![
        AnimationInfo { index: 0, name: "slide".into(), duration: 1.0 },
        AnimationInfo { index: 1, name: "spin".into(), duration: 4.0 },
    ];
    Event::Scene(Box::new(SceneSnapshot { animations, ..scene() }))
}

#[test]
fn the_timeline_sends_the_time_the_slider_is_moved_to() {
    let (mut harness, mut remote) = viewer();
    remote.events.send(Event::Scene(Box::new(scene()))).unwrap();
    harness.run();
    assert!(harness.query_by_label("Timeline").is_none(), "a scene without animations has no timeline");
    remote.events.send(animated()).unwrap();
    harness.run();
    assert!(harness.query_by_label("play").is_some() && harness.query_by_label("animation").is_some());
    assert_eq!(times(requests(&mut remote)), [], "opening the viewer poses nothing");

    harness.get_by_role_and_label(egui::accesskit::Role::Slider, "seconds").focus();
    harness.run();
    harness.key_press(egui::Key::ArrowRight);
    harness.run();
    let sent = times(requests(&mut remote));
    let [(seconds, 0)] = sent.as_slice() else { panic!("one set_time of animation 0, got {sent:?}") };
    assert!(*seconds > 0.0 && *seconds <= 1.0, "{seconds}");
}

#[test]
fn the_slider_sends_at_most_ten_times_a_second() {
    let (link, mut remote) = Link::pair();
    let viewer = Viewer::new(link, ViewerOptions { max_samples: 256, ..ViewerOptions::default() });
    // Steps of 40 ms: faster than the timeline may send.
    let mut harness = Harness::builder().with_size([1000.0, 600.0]).with_step_dt(0.04).build_ui_state(|ui, viewer: &mut Viewer| viewer.ui(ui), viewer);
    remote.events.send(animated()).unwrap();
    harness.run();
    requests(&mut remote);
    harness.get_by_role_and_label(egui::accesskit::Role::Slider, "seconds").focus();
    harness.run();
    // 20 presses of →, each with two steps of 40 ms (the press's and one more): 1.6 s, so at
    // most 16 sends at ten a second, and the last time is sent once the slider rests.
    for _ in 0..20 {
        harness.key_press(egui::Key::ArrowRight);
        harness.step();
    }
    for _ in 0..5 {
        harness.step();
    }
    let sent = times(requests(&mut remote));
    assert!((8..=16).contains(&sent.len()), "{} sends: {sent:?}", sent.len());
    assert!(sent.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 == 0), "{sent:?}");
    assert!((sent.last().unwrap().0 - 0.2).abs() < 1e-6, "the time the slider rests at goes last: {sent:?}");
}

#[test]
fn playing_starts_the_scene_clock_once_and_the_slider_follows_the_frames() {
    let (mut harness, mut remote) = viewer();
    remote.events.send(animated()).unwrap();
    harness.run();
    requests(&mut remote);
    harness.get_by_label("play").click();
    harness.run();
    assert_eq!(requests(&mut remote), [Request::Clock(json!({ "playing": true, "animation": 0, "time": 0.0 }))]);
    // The clock plays on the server: frames bring its time, and the viewer sends nothing.
    remote.events.send(frame_at(0.6)).unwrap();
    for _ in 0..10 {
        harness.step();
    }
    assert_eq!(requests(&mut remote), []);
    harness.get_by_label("pause").click();
    harness.run();
    assert_eq!(requests(&mut remote), [Request::Clock(json!({ "playing": false, "animation": 0 }))]);
    harness.get_by_label("play").click();
    harness.run();
    let sent = times(requests(&mut remote));
    let [(seconds, 0)] = sent.as_slice() else { panic!("one clock change of animation 0, got {sent:?}") };
    assert!((seconds - 0.6).abs() < 1e-6, "playing again starts where the frames showed it: {seconds}");
    // Another client paused the clock: the server's word stands.
    remote.events.send(Event::Clock(Clock { animation: json!(0), time: 0.3, playing: false })).unwrap();
    harness.run();
    assert!(harness.query_by_label("play").is_some() && harness.query_by_label("pause").is_none());
}
