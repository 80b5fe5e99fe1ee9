//! The OpenAPI description, generated from the handlers and types (a copy is checked in as
//! `api/openapi.json`; a test fails when they differ).

use axum::Json;
use raystage_service::model::*;
use raystage_service::{CameraChoice, ClockChange, ClockState, ErrorDetail, FrameReport, RaysJson};
use utoipa::OpenApi;

use crate::error::ErrorBody;
use crate::render::{IntegratorName, ToneMapName};
use crate::stream::{ClientMessage, Encoding, FrameMessage, ServerMessage, SettingsChange};

/// The API's description.
#[derive(OpenApi)]
#[openapi(
    info(
        title = "raystage",
        description = "A ray-tracing rendering server: build and edit retained scenes over HTTP/JSON, render PNG frames, or watch a WebSocket stream of progressive frames. Every error is JSON: `{\"error\": {\"code\", \"message\", \"field\"}}`. With a token configured, every request needs `Authorization: Bearer <token>`.",
        license(name = "MIT OR Apache-2.0"),
    ),
    paths(
        super::index,
        super::classes::list,
        super::scenes::list, super::scenes::create, super::scenes::info, super::scenes::delete, super::scenes::stats,
        super::objects::list, super::objects::add, super::objects::get, super::objects::define, super::objects::move_vertices, super::objects::delete,
        super::instances::list, super::instances::add, super::instances::get, super::instances::set, super::instances::delete,
        super::shaders::list, super::shaders::add, super::shaders::get, super::shaders::define, super::shaders::set_params, super::shaders::delete,
        super::lights::list, super::lights::add, super::lights::get, super::lights::set, super::lights::delete,
        super::textures::list, super::textures::add, super::textures::get, super::textures::set, super::textures::delete,
        super::camera::get, super::camera::set,
        super::animations::list, super::animations::clock, super::animations::set_clock,
        super::commands::run,
        super::gltf::upload,
        super::frame::frame_png, super::frame::channel, super::frame::pick,
        super::renders::start, super::renders::list, super::renders::get, super::renders::image, super::renders::delete,
        crate::stream::stream,
    ),
    components(schemas(
        ErrorBody, ErrorDetail, FrameReport, RaysJson, Rgb, Transform, Rotation, Scale, Ref, ParamJson, ParamOut, Kind, MeshSpec,
        TextureParam, TextureKind, TextureDescription, IntegratorName, ToneMapName, CameraChoice,
        ClientMessage, SettingsChange, ServerMessage, FrameMessage, Encoding, Command, CommandResult,
        ClockState, ClockChange,
    )),
    modifiers(&Exact),
    tags(
        (name = "scenes", description = "Scenes: empty, built-in demos, glTF files"),
        (name = "objects", description = "Geometry with its own acceleration structure"),
        (name = "instances", description = "Objects placed in the world"),
        (name = "shaders", description = "Surface shaders of the built-in classes"),
        (name = "lights", description = "Light sources"),
        (name = "textures", description = "Procedural and image textures, for shaders' texture parameters and environment maps"),
        (name = "camera", description = "The camera"),
        (name = "animations", description = "Animations of glTF files, posed by the batch command `set_time` or played by the scene's clock"),
        (name = "commands", description = "Batches of edits, all or nothing"),
        (name = "frames", description = "Rendering: PNG frames, picking, the progressive stream"),
        (name = "server", description = "The server itself"),
    ),
)]
pub struct ApiDoc;

/// The OpenAPI description of this server.
pub(crate) async fn openapi_json() -> Json<utoipa::openapi::OpenApi> {
    Json(ApiDoc::openapi())
}

/// The lengths of the fixed-size arrays (Rust's `[f32; 3]` and the like), which the derive leaves
/// open: `(schema, path, length, length of each item)`, the path a property's name, or
/// `oneOf/N` (then optionally `/property`) inside a one-of. Checked by `tests/openapi.rs`: no
/// array of numbers is left without.
const LENGTHS: &[(&str, &str, Option<usize>, Option<usize>)] = &[
    ("CameraJson", "eye", Some(3), None),
    ("CameraJson", "target", Some(3), None),
    ("CameraJson", "up", Some(3), None),
    ("CameraJson", "shutter", Some(2), None),
    ("CameraPatch", "eye", Some(3), None),
    ("CameraPatch", "target", Some(3), None),
    ("CameraPatch", "up", Some(3), None),
    ("CameraPatch", "shutter", Some(2), None),
    ("LightSpec", "corner", Some(3), None),
    ("LightSpec", "direction", Some(3), None),
    ("LightSpec", "edge_u", Some(3), None),
    ("LightSpec", "edge_v", Some(3), None),
    ("LightSpec", "position", Some(3), None),
    ("Rgb", "oneOf/1", Some(3), None),
    ("ParamJson", "oneOf/1", Some(3), None),
    ("ParamOut", "oneOf/1", Some(3), None),
    ("Scale", "oneOf/1", Some(3), None),
    ("Rotation", "axis", Some(3), None),
    ("Transform", "translate", Some(3), None),
    ("Transform", "quaternion", Some(4), None),
    ("Transform", "matrix", Some(4), Some(4)),
    ("InstanceInfo", "matrix", Some(4), Some(4)),
    ("PickHit", "position", Some(3), None),
    ("ParamInfo", "range", Some(2), None),
    ("MeshSpec", "positions", None, Some(3)),
    ("MeshSpec", "normals", None, Some(3)),
    ("MeshSpec", "colors", None, Some(3)),
    ("MeshSpec", "uvs", None, Some(2)),
    ("MeshSpec", "indices", None, Some(3)),
    ("PositionsBody", "positions", None, Some(3)),
    ("SetPositions", "positions", None, Some(3)),
    ("TextureDescription", "oneOf/0/a", Some(3), None),
    ("TextureDescription", "oneOf/0/b", Some(3), None),
    ("TextureDescription", "oneOf/1/a", Some(3), None),
    ("TextureDescription", "oneOf/1/b", Some(3), None),
];

/// The schema at `path` inside `schema` ([`LENGTHS`]' paths).
fn find<'a>(schema: &'a mut utoipa::openapi::RefOr<utoipa::openapi::schema::Schema>, path: &str) -> Option<&'a mut utoipa::openapi::RefOr<utoipa::openapi::schema::Schema>> {
    use utoipa::openapi::RefOr;
    use utoipa::openapi::schema::Schema;
    let (head, rest) = path.split_once('/').map_or((path, None), |(h, r)| (h, Some(r)));
    let (next, rest) = match (schema, head) {
        (RefOr::T(Schema::OneOf(one)), "oneOf") => {
            let rest = rest?;
            let (index, rest) = rest.split_once('/').map_or((rest, None), |(i, r)| (i, Some(r)));
            (one.items.get_mut(index.parse::<usize>().ok()?)?, rest)
        }
        (RefOr::T(Schema::Object(object)), property) => (object.properties.get_mut(property)?, rest),
        _ => return None,
    };
    match rest {
        Some(rest) => find(next, rest),
        None => Some(next),
    }
}

/// Sets an array schema's length (both bounds), and its items' if they are arrays too.
fn fix_length(schema: &mut utoipa::openapi::RefOr<utoipa::openapi::schema::Schema>, length: Option<usize>, items: Option<usize>) {
    use utoipa::openapi::RefOr;
    use utoipa::openapi::schema::{ArrayItems, Schema};
    let RefOr::T(Schema::Array(array)) = schema else { return };
    if length.is_some() {
        (array.min_items, array.max_items) = (length, length);
    }
    if let (Some(n), ArrayItems::RefOrSchema(inner)) = (items, &mut array.items) {
        fix_length(inner, Some(n), None);
    }
}

/// What the derive cannot say, said exactly (a validator checks requests and responses against
/// it):
/// - fixed-size arrays have their lengths ([`LENGTHS`]);
/// - shader and light classes are enums of the built-in classes, and demo names a pattern;
/// - `POST /scenes` takes no body at all for an empty scene;
/// - a light as the API answers it (`LightInfo`) is a `LightSpec` with an `id`: its own object,
///   since `LightSpec` forbids other properties and an `allOf` of the two would forbid `id`;
/// - and what [`exact_json`] says.
struct Exact;

impl utoipa::Modify for Exact {
    fn modify(&self, openapi: &mut utoipa::openapi::OpenApi) {
        use utoipa::openapi::schema::{ObjectBuilder, Schema, Type};
        use utoipa::openapi::{RefOr, Required};
        if let Some(body) = openapi.paths.paths.get_mut("/scenes").and_then(|p| p.post.as_mut()).and_then(|op| op.request_body.as_mut()) {
            body.required = Some(Required::False);
        }
        let Some(components) = openapi.components.as_mut() else { return };
        for &(name, property, length, items) in LENGTHS {
            if let Some(schema) = components.schemas.get_mut(name).and_then(|s| find(s, property)) {
                fix_length(schema, length, items);
            }
        }
        let surfaces: Vec<serde_json::Value> = raystage_scene::SHADER_CLASSES.iter().map(|c| c.name.into()).collect();
        let lights: Vec<serde_json::Value> = LIGHT_CLASSES.iter().map(|(name, _)| (*name).into()).collect();
        let classes = ["DefineShader", "ShaderBody", "ShaderInfo", "ShaderSummary", "ShaderUpdate"].map(|s| (s, &surfaces));
        for (name, values) in classes.into_iter().chain([("LightSpec", &lights)]) {
            if let Some(RefOr::T(Schema::Object(class))) = components.schemas.get_mut(name).and_then(|s| find(s, "class")) {
                class.enum_values = Some(values.clone());
            }
        }
        if let Some(RefOr::T(Schema::Object(demo))) = components.schemas.get_mut("NewScene").and_then(|s| find(s, "demo")) {
            let names: Vec<String> = raystage_demo::animated::Demo::NAMES.split(", ").map(|n| n.replace("<triangles>", "[0-9]+")).collect();
            demo.pattern = Some(format!("^({})$", names.join("|")));
        }
        let Some(RefOr::T(Schema::Object(spec))) = components.schemas.get("LightSpec").cloned() else { return };
        let mut info = spec;
        info.description = Some("A light with its id: the `LightSpec` it was given, with every parameter, and `id`.".into());
        let id = ObjectBuilder::new().schema_type(Type::Integer).format(Some(utoipa::openapi::schema::SchemaFormat::KnownFormat(utoipa::openapi::schema::KnownFormat::Int32))).minimum(Some(0)).description(Some("The light's id."));
        info.properties.insert("id".into(), RefOr::T(Schema::Object(id.build())));
        info.required.push("id".into());
        components.schemas.insert("LightInfo".into(), RefOr::T(Schema::Object(info)));
        // The rest is said most plainly in the description's JSON.
        let mut json = serde_json::to_value(&*openapi).expect("the description is JSON");
        exact_json(&mut json);
        *openapi = serde_json::from_value(json).expect("the description reads back");
    }
}

/// A decimal number that is not negative, as the query's colours and radii are written (Rust
/// reads more spellings; these are the ones the description promises).
const DECIMAL: &str = "(0|[1-9][0-9]{0,5})(\\.[0-9]{1,6})?";

/// The rules of the description that the derive cannot state, on its JSON:
/// - `u32` is an integer up to 2³² − 1 (the derive calls it `int32`, whose range stops at 2³¹ − 1,
///   so a client that believes it cannot name ids and indices past that, and a server that
///   answers them looks as if it accepts what the description forbids);
/// - query parameters have the ranges (of the default [`Limits`](crate::Limits)) and spellings
///   the server checks: image sizes and samples, backgrounds, filters, environments;
/// - fields that exclude each other (`matrix` or translate/rotate/scale, `rotate` or
///   `quaternion`, a demo's `frame` without `demo`) say so: one side must be absent or null (a
///   mesh's attributes and their `_base64` spellings say it in words: the schema of every pair's
///   exclusion is more than schemathesis can generate from, and the server answers 422);
/// - a projection's kinds take their own fields only, and a mesh or new positions need
///   `positions` or `positions_base64`;
/// - a light takes the parameters of its class only: `LightSpec` and `LightInfo` are one-ofs by
///   `class`, each class's other parameters null if present (the server reads null as absent);
/// - a `_base64` field is padded standard base64 (the server refuses other text with 400);
/// - `set_time`'s seconds are a time the scene can hold.
fn exact_json(json: &mut serde_json::Value) {
    use serde_json::{Value, json};
    fn unsigned(node: &mut Value) {
        match node {
            Value::Object(map) => {
                let integer = map.get("type").is_some_and(|t| t == "integer" || t.as_array().is_some_and(|a| a.contains(&json!("integer"))));
                if integer && map.get("format") == Some(&json!("int32")) && map.get("minimum") == Some(&json!(0)) {
                    map.insert("format".into(), json!("int64"));
                    map.insert("maximum".into(), json!(u32::MAX));
                }
                map.values_mut().for_each(unsigned);
            }
            Value::Array(list) => list.iter_mut().for_each(unsigned),
            _ => {}
        }
    }
    unsigned(json);
    fn base64(node: &mut Value) {
        match node {
            Value::Object(map) => {
                for (key, value) in map.iter_mut() {
                    if key.ends_with("_base64")
                        && let Some(schema) = value.as_object_mut()
                    {
                        schema.insert("pattern".into(), json!("^(?:[A-Za-z0-9+/]{4})*(?:[A-Za-z0-9+/]{2}==|[A-Za-z0-9+/]{3}=)?$"));
                    }
                    base64(value);
                }
            }
            Value::Array(list) => list.iter_mut().for_each(base64),
            _ => {}
        }
    }
    base64(json);

    let limits = crate::Limits::default();
    let colour = format!("{DECIMAL}(,{DECIMAL},{DECIMAL})?");
    let radius = "0\\.[0-9]{0,5}[1-9]|[1-3](\\.[0-9]{1,6})?|4(\\.0{1,6})?";
    let query: [(&str, Value); 6] = [
        ("width", json!({ "maximum": limits.max_dimension })),
        ("height", json!({ "maximum": limits.max_dimension })),
        ("spp", json!({ "maximum": limits.max_spp })),
        ("background", json!({ "pattern": format!("^(sky|black|{colour})$") })),
        ("environment", json!({ "pattern": format!("^(studio|none|{colour})$") })),
        ("filter", json!({ "pattern": format!("^(box|gaussian|gaussian:({radius}))$") })),
    ];
    for operation in json["paths"].as_object_mut().into_iter().flat_map(|p| p.values_mut()).filter_map(Value::as_object_mut).flat_map(|o| o.values_mut()) {
        for parameter in operation.get_mut("parameters").and_then(Value::as_array_mut).into_iter().flatten() {
            let Some((_, rule)) = query.iter().find(|(name, _)| parameter["name"] == *name && parameter["in"] == "query") else { continue };
            if let (Some(schema), Some(rule)) = (parameter["schema"].as_object_mut(), rule.as_object()) {
                schema.extend(rule.clone());
            }
        }
    }

    let schemas = &mut json["components"]["schemas"];
    // The scene's times are `f32`: past its largest, a number of seconds would be infinite.
    let seconds = &mut schemas["SetTime"]["properties"]["seconds"];
    seconds["minimum"] = json!(0);
    seconds["maximum"] = json!(f32::MAX as f64);
    for kind in schemas["ProjectionJson"]["oneOf"].as_array_mut().into_iter().flatten() {
        kind["additionalProperties"] = json!(false);
    }
    let absent = |names: &[&str]| json!({ "type": "object", "properties": names.iter().map(|n| (n.to_string(), json!({ "type": "null" }))).collect::<serde_json::Map<_, _>>() });
    // An object with these as well is an `allOf` of it and them: the description's types hold
    // no `anyOf` beside `properties`.
    let mut both = |name: &str, rules: Vec<Value>| {
        let object = schemas[name].clone();
        schemas[name] = json!({ "description": object["description"], "allOf": std::iter::once(object).chain(rules).collect::<Vec<_>>() });
    };
    both("Transform", vec![
        json!({ "anyOf": [absent(&["matrix"]), absent(&["translate", "rotate", "quaternion", "scale"])] }),
        json!({ "anyOf": [absent(&["rotate"]), absent(&["quaternion"])] }),
    ]);
    let positions = json!({ "anyOf": [
        { "type": "object", "required": ["positions"], "properties": { "positions": { "type": "array" } } },
        { "type": "object", "required": ["positions_base64"], "properties": { "positions_base64": { "type": "string" } } },
    ] });
    both("PositionsBody", vec![positions.clone()]);
    both("MeshSpec", vec![positions]);
    both("NewScene", vec![json!({ "anyOf": [absent(&["frame"]), { "type": "object", "required": ["demo"], "properties": { "demo": { "type": "string" } } }] })]);

    for (name, with_id) in [("LightSpec", false), ("LightInfo", true)] {
        let spec = schemas[name].clone();
        let variants: Vec<Value> = LIGHT_CLASSES
            .iter()
            .map(|(class, params)| {
                let mut properties = serde_json::Map::new();
                properties.insert("class".into(), json!({ "type": "string", "enum": [class] }));
                for (key, value) in spec["properties"].as_object().into_iter().flatten() {
                    match key.as_str() {
                        "class" => {}
                        "label" if with_id => {}
                        "label" | "id" => _ = properties.insert(key.clone(), value.clone()),
                        _ if params.contains(&key.as_str()) => _ = properties.insert(key.clone(), value.clone()),
                        _ => _ = properties.insert(key.clone(), json!({ "type": "null" })),
                    }
                }
                let required = if with_id { json!(["class", "id"]) } else { json!(["class"]) };
                json!({ "type": "object", "title": class, "required": required, "properties": properties, "additionalProperties": false })
            })
            .collect();
        schemas[name] = json!({ "description": spec["description"], "oneOf": variants });
    }
}
