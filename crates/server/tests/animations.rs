//! Animations over HTTP: a glTF file's animation is listed, `set_time` poses the scene (in a
//! batch, so in the stream's `commands` too), and times or animations it cannot play are
//! refused with the field named and nothing changed.

mod common;

use axum::body::Body;
use axum::http::StatusCode;
use common::*;
use serde_json::{Value, json};

/// A scene made from [`animated_glb`].
async fn animated_scene(app: &axum::Router) -> u64 {
    let (status, _, body) = send(app, "POST", "/scenes", Body::from(animated_glb()), &[("content-type", "model/gltf-binary")]).await;
    let info: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(status, StatusCode::CREATED, "{info}");
    info["id"].as_u64().unwrap()
}

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
