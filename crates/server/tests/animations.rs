//! Animations over HTTP: a glTF file's animation is listed, `set_time` poses the scene (in a
//! batch, so in the stream's `commands` too), and times or animations it cannot play are
//! refused with the field named and nothing changed.

mod common;

use axum::body::Body;
use axum::http::StatusCode;
use common::*;
use serde_json::json;

/// The x of every instance's translation, by id.
async fn xs(app: &axum::Router, s: u64) -> Vec<f64> {
    let instances = ok(app, "GET", &format!("/scenes/{s}/instances"), json!(null), StatusCode::OK).await;
    instances.as_array().unwrap().iter().map(|i| i["matrix"][0][3].as_f64().unwrap()).collect()
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5)
}

#[tokio::test]
async fn the_animation_is_listed_and_set_time_moves_what_it_animates() {
    let app = app();
    let s = animated_scene(&app).await;
    let animations = ok(&app, "GET", &format!("/scenes/{s}/animations"), json!(null), StatusCode::OK).await;
    assert_eq!(animations, json!([{ "index": 0, "name": "slide", "duration": 1.0, "channels": 1 }]));
    assert!(close(&xs(&app, s).await, &[-0.6, 0.6]), "it opens at 0 s");
    let version = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"].as_u64().unwrap();
    let done = ok(&app, "POST", &format!("/scenes/{s}/commands"), json!({ "commands": [{ "set_time": { "seconds": 0.5 } }] }), StatusCode::OK).await;
    assert_eq!(done, json!({ "version": version + 1, "results": [{}] }), "a pose is an edit");
    assert!(close(&xs(&app, s).await, &[-0.1, 0.6]), "{:?}", xs(&app, s).await);
    // By name, all together, and past the end, where the last keyframe holds.
    for (animation, seconds, x) in [(json!("slide"), 0.25, -0.35), (json!("all"), 7.0, 0.4), (json!(0), 0.0, -0.6)] {
        let body = json!({ "commands": [{ "set_time": { "seconds": seconds, "animation": animation } }] });
        ok(&app, "POST", &format!("/scenes/{s}/commands"), body, StatusCode::OK).await;
        assert!(close(&xs(&app, s).await, &[x, 0.6]), "{animation} at {seconds}: {:?}", xs(&app, s).await);
    }
    // The frame follows: the left square leaves its place.
    let url = format!("/scenes/{s}/frame.png?width=80&height=40&integrator=eyelight");
    let orange = [255, 188, 0, 255];
    assert_eq!(frame(&app, &url).await.get_pixel(27, 20).0, orange);
    ok(&app, "POST", &format!("/scenes/{s}/commands"), json!({ "commands": [{ "set_time": { "seconds": 1.0 } }] }), StatusCode::OK).await;
    assert_ne!(frame(&app, &url).await.get_pixel(27, 20).0, orange, "the square moved away");
}

#[tokio::test]
async fn times_and_animations_that_cannot_play_are_refused_and_change_nothing() {
    let app = app();
    let s = animated_scene(&app).await;
    let before = ok(&app, "GET", &format!("/scenes/{s}/instances"), json!(null), StatusCode::OK).await;
    let info = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await;
    let instance = before[1]["id"].clone();
    for (set_time, field) in [
        (json!({ "seconds": -1.0 }), "seconds"),
        (json!({ "seconds": 1e39 }), "seconds"),
        (json!({ "seconds": 0.5, "animation": 1 }), "animation"),
        (json!({ "seconds": 0.5, "animation": "walk" }), "animation"),
    ] {
        // After a command that would move the other square: all or nothing.
        let commands = json!([{ "set_instance": { "id": instance, "transform": { "translate": [5, 0, 0] } } }, { "set_time": set_time }]);
        let error = fails(&app, "POST", &format!("/scenes/{s}/commands"), json!({ "commands": commands }), StatusCode::UNPROCESSABLE_ENTITY).await;
        assert_eq!(error, format!("commands[1].set_time.{field}"), "{set_time}");
    }
    for malformed in [json!({}), json!({ "seconds": "1" }), json!({ "seconds": 1, "animation": [0] }), json!({ "seconds": 1, "speed": 2 })] {
        let (status, body) = call(&app, "POST", &format!("/scenes/{s}/commands"), json!({ "commands": [{ "set_time": malformed }] })).await;
        assert!(status == StatusCode::BAD_REQUEST || status == StatusCode::UNPROCESSABLE_ENTITY, "{malformed}: {status} {body}");
    }
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}/instances"), json!(null), StatusCode::OK).await, before);
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await, info);
    // A scene without animations has nothing to play.
    let empty = new_scene(&app).await;
    assert_eq!(ok(&app, "GET", &format!("/scenes/{empty}/animations"), json!(null), StatusCode::OK).await, json!([]));
    let error = fails(&app, "POST", &format!("/scenes/{empty}/commands"), json!({ "commands": [{ "set_time": { "seconds": 0 } }] }), StatusCode::UNPROCESSABLE_ENTITY).await;
    assert_eq!(error, "commands[0].set_time.animation");
}

/// A frame of scene `s` and the animation time it shows (its `x-scene-time` header).
async fn frame_time(app: &axum::Router, s: u64) -> f64 {
    let response = tower::ServiceExt::oneshot(app.clone(), axum::http::Request::get(format!("/scenes/{s}/frame.png?width=8&height=8&integrator=eyelight")).body(Body::empty()).unwrap()).await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    response.headers()["x-scene-time"].to_str().unwrap().parse().unwrap()
}

#[tokio::test]
async fn the_clock_is_set_played_paused_and_stops_at_the_end_and_frames_say_their_time() {
    let app = app();
    let s = animated_scene(&app).await;
    let clock = format!("/scenes/{s}/clock");
    let opened = ok(&app, "GET", &clock, json!(null), StatusCode::OK).await;
    assert_eq!(opened, json!({ "animation": 0, "time": 0.0, "duration": 1.0, "playing": false, "rate": 1.0, "loop": true }), "a glTF scene opens posed at 0 s: its clock is there, paused");
    // Set: the scene is posed at once.
    let set = ok(&app, "PUT", &clock, json!({ "time": 0.5 }), StatusCode::OK).await;
    assert_eq!(set, json!({ "animation": 0, "time": 0.5, "duration": 1.0, "playing": false, "rate": 1.0, "loop": true }));
    assert!(close(&xs(&app, s).await, &[-0.1, 0.6]), "{:?}", xs(&app, s).await);
    assert_eq!(frame_time(&app, s).await, 0.5);
    // Played: each frame moves the scene to the clock's time, and says which.
    ok(&app, "PUT", &clock, json!({ "playing": true, "rate": 0.1 }), StatusCode::OK).await;
    tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    let first = frame_time(&app, s).await;
    assert!(first > 0.5 && first < 1.0, "{first}");
    let x = xs(&app, s).await[0];
    assert!((x - (-0.6 + first)).abs() < 1e-5, "the square is where the frame's time puts it: {x} at {first}");
    tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    let later = frame_time(&app, s).await;
    assert!(later > first, "{later} after {first}");
    // Paused: the time stands.
    let paused = ok(&app, "PUT", &clock, json!({ "playing": false }), StatusCode::OK).await;
    tokio::time::sleep(std::time::Duration::from_millis(50)).await;
    assert_eq!(ok(&app, "GET", &clock, json!(null), StatusCode::OK).await, paused);
    // `set_time` sets the clock too.
    ok(&app, "POST", &format!("/scenes/{s}/commands"), json!({ "commands": [{ "set_time": { "seconds": 0.25 } }] }), StatusCode::OK).await;
    assert_eq!(ok(&app, "GET", &clock, json!(null), StatusCode::OK).await["time"], 0.25);
    // Not looping, fast: it runs into the end and stops there.
    ok(&app, "PUT", &clock, json!({ "playing": true, "rate": 20, "loop": false, "animation": "slide" }), StatusCode::OK).await;
    tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    assert_eq!(frame_time(&app, s).await, 1.0);
    let ended = ok(&app, "GET", &clock, json!(null), StatusCode::OK).await;
    assert_eq!((ended["time"].as_f64(), ended["playing"].as_bool()), (Some(1.0), Some(false)), "{ended}");
    assert!(close(&xs(&app, s).await, &[0.4, 0.6]));
}

#[tokio::test]
async fn an_edit_made_while_the_clock_plays_stays_and_the_animation_goes_on() {
    let app = app();
    let s = animated_scene(&app).await;
    ok(&app, "PUT", &format!("/scenes/{s}/clock"), json!({ "playing": true, "rate": 0.1 }), StatusCode::OK).await;
    let instances = ok(&app, "GET", &format!("/scenes/{s}/instances"), json!(null), StatusCode::OK).await;
    // The right square is not animated: moved, it stays moved while the left one plays on.
    let right = instances[1]["id"].clone();
    ok(&app, "PUT", &format!("/scenes/{s}/instances/{right}"), json!({ "transform": { "translate": [2, 0, 0] } }), StatusCode::OK).await;
    let before = frame_time(&app, s).await;
    tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    let after = frame_time(&app, s).await;
    assert!(after > before, "{after} after {before}");
    let x = xs(&app, s).await;
    assert!((x[0] - (-0.6 + after)).abs() < 1e-5 && (x[1] - 2.0).abs() < 1e-6, "{x:?} at {after}");
}

#[tokio::test]
async fn clock_changes_that_cannot_play_are_refused_naming_the_field_and_change_nothing() {
    let app = app();
    let s = animated_scene(&app).await;
    let clock = format!("/scenes/{s}/clock");
    let set = ok(&app, "PUT", &clock, json!({ "time": 0.5, "rate": 2 }), StatusCode::OK).await;
    let version = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"].clone();
    for (change, field) in [
        (json!({ "time": -1 }), "time"),
        (json!({ "time": 1e39 }), "time"),
        (json!({ "rate": 1001 }), "rate"),
        (json!({ "rate": -1e300, "playing": true }), "rate"),
        (json!({ "animation": 1, "playing": true }), "animation"),
        (json!({ "animation": "walk" }), "animation"),
    ] {
        assert_eq!(fails(&app, "PUT", &clock, change.clone(), StatusCode::UNPROCESSABLE_ENTITY).await, field, "{change}");
    }
    for malformed in [json!({ "speed": 2 }), json!({ "playing": "yes" }), json!({ "time": "0" }), json!([])] {
        let (status, body) = call(&app, "PUT", &clock, malformed.clone()).await;
        assert!(status == StatusCode::BAD_REQUEST || status == StatusCode::UNPROCESSABLE_ENTITY, "{malformed}: {status} {body}");
    }
    assert_eq!(ok(&app, "GET", &clock, json!(null), StatusCode::OK).await, set);
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"], version);
    // A scene without animations has no clock to set.
    let empty = new_scene(&app).await;
    assert_eq!(fails(&app, "PUT", &format!("/scenes/{empty}/clock"), json!({ "playing": true }), StatusCode::UNPROCESSABLE_ENTITY).await, "animation");
    assert_eq!(fails(&app, "GET", &format!("/scenes/{empty}/clock"), json!(null), StatusCode::NOT_FOUND).await, "clock");
}
