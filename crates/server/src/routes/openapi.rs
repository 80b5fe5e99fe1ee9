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

/// What the derive cannot say, said exactly (a validator checks responses against it):
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
        let Some(RefOr::T(Schema::Object(spec))) = components.schemas.get("LightSpec").cloned() else { return };
        let mut info = spec;
        info.description = Some("A light with its id: the `LightSpec` it was given, with every parameter, and `id`.".into());
        let id = ObjectBuilder::new().schema_type(Type::Integer).format(Some(utoipa::openapi::schema::SchemaFormat::KnownFormat(utoipa::openapi::schema::KnownFormat::Int32))).minimum(Some(0)).description(Some("The light's id."));
        info.properties.insert("id".into(), RefOr::T(Schema::Object(id.build())));
        info.required.push("id".into());
        components.schemas.insert("LightInfo".into(), RefOr::T(Schema::Object(info)));
    }
}
