//! The OpenAPI description, generated from the handlers and types (a copy is checked in as
//! `api/openapi.json`; a test fails when they differ).

use axum::Json;
use utoipa::OpenApi;

use crate::error::{ErrorBody, ErrorDetail};
use crate::model::*;
use crate::render::{IntegratorName, ToneMapName};
use crate::stats::{FrameReport, RaysJson};
use crate::stream::{ClientMessage, FrameMessage, ServerMessage, SettingsChange};

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
        super::commands::run,
        super::gltf::upload,
        super::frame::frame_png, super::frame::channel, super::frame::pick,
        super::renders::start, super::renders::list, super::renders::get, super::renders::image, super::renders::delete,
        crate::stream::stream,
    ),
    components(schemas(
        ErrorBody, ErrorDetail, FrameReport, RaysJson, Rgb, Transform, Rotation, Scale, Ref, ParamJson, ParamOut, Kind, MeshSpec,
        TextureParam, TextureKind, TextureDescription, IntegratorName, ToneMapName,
        ClientMessage, SettingsChange, ServerMessage, FrameMessage, Command, CommandResult,
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
///   since `LightSpec` forbids other properties and an `allOf` of the two would forbid `id`.
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
    }
}
