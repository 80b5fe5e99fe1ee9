//! `api/openapi.json` is the generated description, checked in: this test fails when the two
//! differ. Set `RAYSTAGE_BLESS=1` to rewrite it.

mod common;

use axum::http::StatusCode;
use common::*;
use serde_json::json;

#[test]
fn the_checked_in_description_is_current() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../api/openapi.json");
    let generated = raystage_server::openapi().to_pretty_json().unwrap() + "\n";
    if std::env::var_os("RAYSTAGE_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap();
        return;
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        checked_in == generated,
        "api/openapi.json is out of date: run\n    RAYSTAGE_BLESS=1 cargo test -p raystage-server --test openapi\nand commit the result"
    );
}

#[tokio::test]
async fn the_server_serves_its_description_with_every_route() {
    let description = ok(&app(), "GET", "/openapi.json", json!(null), StatusCode::OK).await;
    let paths = description["paths"].as_object().unwrap();
    for path in ["/scenes", "/scenes/{scene}/objects/{id}", "/scenes/{scene}/commands", "/scenes/{scene}/frame.png", "/scenes/{scene}/stream", "/scenes/{scene}/gltf", "/scenes/{scene}/textures", "/scenes/{scene}/textures/{id}"] {
        assert!(paths.contains_key(path), "{path} is not described");
    }
}
