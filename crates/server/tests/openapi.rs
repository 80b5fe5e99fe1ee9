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

#[tokio::test]
async fn lights_as_answered_match_their_schema_and_a_plain_request_for_a_stream_gets_json() {
    let app = app();
    let description = ok(&app, "GET", "/openapi.json", json!(null), StatusCode::OK).await;
    // A light's schema is the one-of's branch for its class.
    let variants = description["components"]["schemas"]["LightInfo"]["oneOf"].as_array().unwrap();
    let schema = variants.iter().find(|v| v["properties"]["class"]["enum"][0] == "SpotLight").unwrap();
    let s = new_scene(&app).await;
    ok(&app, "POST", &format!("/scenes/{s}/lights"), json!({ "class": "SpotLight", "position": [0, 2, 0] }), StatusCode::CREATED).await;
    let lights = ok(&app, "GET", &format!("/scenes/{s}/lights"), json!(null), StatusCode::OK).await;
    let light = lights[0].as_object().unwrap();
    // Every property the server sends is described (the schema allows no others), and every
    // required one is sent.
    assert_eq!(schema["additionalProperties"], false);
    for key in light.keys() {
        assert!(schema["properties"].get(key).is_some(), "`{key}` of {light:?} is not in LightInfo");
    }
    for key in schema["required"].as_array().unwrap() {
        assert!(light.contains_key(key.as_str().unwrap()), "required `{key}` is missing from {light:?}");
    }
    assert_eq!(description["paths"]["/scenes"]["post"]["requestBody"]["required"], false, "an empty body makes an empty scene");

    // Without the WebSocket handshake, the stream answers the API's JSON error.
    let (status, error) = call(&app, "GET", &format!("/scenes/{s}/stream"), json!(null)).await;
    assert_eq!((status, error["error"]["field"].as_str()), (StatusCode::BAD_REQUEST, Some("upgrade")), "{error}");
}

#[test]
fn every_array_of_numbers_has_its_length() {
    let description: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../api/openapi.json")).unwrap()).unwrap();
    // Every array whose items are numbers is a fixed-size one (a vector, a colour, a matrix row,
    // a range): the description must give its length, as the server checks it.
    fn open(node: &serde_json::Value, path: String, found: &mut Vec<String>) {
        match node {
            serde_json::Value::Object(map) => {
                let array = map.get("type").is_some_and(|t| t == "array" || t.as_array().is_some_and(|a| a.iter().any(|t| t == "array")));
                if array && map.get("items").is_some_and(|i| i["type"] == "number") && !(map.contains_key("minItems") && map.contains_key("maxItems")) {
                    found.push(path.clone());
                }
                for (key, value) in map {
                    open(value, format!("{path}/{key}"), found);
                }
            }
            serde_json::Value::Array(list) => list.iter().enumerate().for_each(|(i, v)| open(v, format!("{path}/{i}"), found)),
            _ => {}
        }
    }
    let mut found = Vec::new();
    open(&description["components"], String::new(), &mut found);
    assert!(found.is_empty(), "arrays of numbers without a length: {found:?}");
    let positions = &description["components"]["schemas"]["MeshSpec"]["allOf"][0]["properties"]["positions"]["items"];
    assert_eq!((&positions["minItems"], &positions["maxItems"]), (&serde_json::json!(3), &serde_json::json!(3)));
}

#[tokio::test]
async fn every_class_the_description_names_is_accepted() {
    let app = app();
    let description = ok(&app, "GET", "/openapi.json", json!(null), StatusCode::OK).await;
    let schemas = &description["components"]["schemas"];
    let s = new_scene(&app).await;
    for class in schemas["ShaderBody"]["properties"]["class"]["enum"].as_array().unwrap() {
        ok(&app, "POST", &format!("/scenes/{s}/shaders"), json!({ "class": class }), StatusCode::CREATED).await;
    }
    let classes = |schema: &str| -> Vec<serde_json::Value> { schemas[schema]["oneOf"].as_array().unwrap().iter().map(|v| v["properties"]["class"]["enum"][0].clone()).collect() };
    for class in classes("LightSpec") {
        ok(&app, "POST", &format!("/scenes/{s}/lights"), json!({ "class": class }), StatusCode::CREATED).await;
    }
    assert_eq!(classes("LightInfo"), classes("LightSpec"));
    assert_eq!(classes("LightSpec").len(), 6);
    assert!(schemas["NewScene"]["allOf"][0]["properties"]["demo"]["pattern"].as_str().unwrap().contains("|museum-[0-9]+|"));
}

/// Every setting of a frame is described wherever the API takes one, under the name it takes
/// it by: the frame's query (for `GET frame.png` and `POST renders`), the stream's query and its
/// `settings` message. The types are made from one list; this fails if a setting reaches the
/// renderer's patch but not the API's description.
#[test]
fn every_frame_setting_is_described_wherever_the_api_takes_one() {
    let description: serde_json::Value = serde_json::from_str(&raystage_server::openapi().to_json().unwrap()).unwrap();
    let parameters = |path: &str, method: &str| -> Vec<String> {
        let listed = description["paths"][path][method]["parameters"].as_array().unwrap_or_else(|| panic!("{method} {path} has no parameters"));
        listed.iter().filter(|p| p["in"] == "query").map(|p| p["name"].as_str().unwrap().to_string()).collect()
    };
    let message = description["components"]["schemas"]["SettingsChange"]["properties"].as_object().unwrap();
    for &setting in raystage_render::SettingsPatch::NAMES {
        // The sample count is named for what it counts: a frame's samples, or those a stream
        // refines to.
        let (frame, stream) = match setting {
            "samples_per_pixel" => ("spp", "max_samples"),
            name => (name, name),
        };
        for (path, method) in [("/scenes/{scene}/frame.png", "get"), ("/scenes/{scene}/renders", "post")] {
            assert!(parameters(path, method).iter().any(|p| p == frame), "{method} {path} does not describe `{frame}`");
        }
        assert!(parameters("/scenes/{scene}/stream", "get").iter().any(|p| p == stream), "the stream's query does not describe `{stream}`");
        assert!(message.contains_key(stream), "the settings message does not describe `{stream}`");
    }
}

/// The request examples in the description are requests the server takes, so that clients and
/// generated tests (schemathesis's examples phase) have a valid mesh and a valid batch to start
/// from: indices that name vertices, a label used after it is defined, relations no schema
/// states.
#[tokio::test]
async fn the_description_s_request_examples_are_accepted() {
    let app = app();
    let description = ok(&app, "GET", "/openapi.json", json!(null), StatusCode::OK).await;
    let schemas = &description["components"]["schemas"];
    for (schema, route, status) in [("ObjectBody", "objects", StatusCode::CREATED), ("Commands", "commands", StatusCode::OK)] {
        let example = schemas[schema]["example"].clone();
        assert!(example.is_object(), "{schema} has no example");
        let s = new_scene(&app).await;
        ok(&app, "POST", &format!("/scenes/{s}/{route}"), example, status).await;
        let info = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await;
        assert_eq!(info["triangles"], 2, "{schema}'s example builds its quad: {info}");
    }
}
