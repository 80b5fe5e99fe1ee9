//! The HTTP routes: one module per resource, each handler a thin shell around an edit (run
//! through the service's [`SceneSlot::commands`]), a read, or a render.

mod animations;
mod camera;
mod classes;
mod commands;
mod frame;
mod gltf;
mod instances;
mod lights;
mod objects;
pub(crate) mod openapi;
mod renders;
mod scenes;
mod shaders;
mod textures;
pub(crate) mod web;

use std::sync::Arc;

use axum::extract::DefaultBodyLimit;
use axum::routing::get;
use axum::{Json, Router, middleware};
use raystage_service::model::Command;
use raystage_service::{AppState, Error, ErrorKind, SceneSlot};
use serde::Serialize;
use utoipa::ToSchema;

use crate::auth::require_token;
use crate::error::{ApiError, ApiResult};

/// The whole API as a router.
pub(crate) fn router(state: AppState) -> Router {
    let limits = state.config().limits;
    Router::new()
        .route("/", get(web::root))
        .route(web::SCRIPT_PATH, get(web::script))
        .route(web::STYLE_PATH, get(web::style))
        .route("/openapi.json", get(openapi::openapi_json))
        .route("/shader-classes", get(classes::list))
        .route("/scenes", get(scenes::list).post(scenes::create))
        .route("/scenes/{scene}", get(scenes::info).delete(scenes::delete))
        .route("/scenes/{scene}/stats", get(scenes::stats))
        .route("/scenes/{scene}/objects", get(objects::list).post(objects::add))
        .route("/scenes/{scene}/objects/{id}", get(objects::get).put(objects::define).patch(objects::move_vertices).delete(objects::delete))
        .route("/scenes/{scene}/instances", get(instances::list).post(instances::add))
        .route("/scenes/{scene}/instances/{id}", get(instances::get).put(instances::set).delete(instances::delete))
        .route("/scenes/{scene}/shaders", get(shaders::list).post(shaders::add))
        .route("/scenes/{scene}/shaders/{id}", get(shaders::get).put(shaders::define).patch(shaders::set_params).delete(shaders::delete))
        .route("/scenes/{scene}/lights", get(lights::list).post(lights::add))
        .route("/scenes/{scene}/lights/{id}", get(lights::get).put(lights::set).delete(lights::delete))
        .route("/scenes/{scene}/textures", get(textures::list).post(textures::add))
        .route("/scenes/{scene}/textures/{id}", get(textures::get).put(textures::set).delete(textures::delete))
        .route("/scenes/{scene}/animations", get(animations::list))
        .route("/scenes/{scene}/clock", get(animations::clock).put(animations::set_clock))
        .route("/scenes/{scene}/camera", get(camera::get).put(camera::set))
        .route("/scenes/{scene}/commands", axum::routing::post(commands::run))
        .route("/scenes/{scene}/gltf", axum::routing::post(gltf::upload))
        .route("/scenes/{scene}/frame.png", get(frame::frame_png))
        .route("/scenes/{scene}/channels/{channel}", get(frame::channel))
        .route("/scenes/{scene}/pick", get(frame::pick))
        .route("/scenes/{scene}/renders", axum::routing::post(renders::start))
        .route("/renders", get(renders::list))
        .route("/renders/{id}", get(renders::get).delete(renders::delete))
        .route("/renders/{id}/image.png", get(renders::image))
        .route("/scenes/{scene}/stream", get(crate::stream::stream))
        .fallback(|| async { ApiError(Error::not_found(None, "no such route: see /openapi.json")) })
        .method_not_allowed_fallback(|| async {
            ApiError(Error::new(ErrorKind::MethodNotAllowed, None, "this route does not take that method: see /openapi.json"))
        })
        .layer(middleware::from_fn_with_state(state.clone(), require_token))
        .layer(middleware::from_fn(give_back_after_large_bodies))
        .layer(DefaultBodyLimit::max(limits.max_body_bytes))
        .with_state(state)
}

/// A request body at least this large (a glTF file, a batch, an image) leaves megabytes its
/// parse freed.
const LARGE_BODY: u64 = 1 << 20;

/// Gives the memory a large request freed back to the system once it is answered, accepted or
/// refused: the body and whatever its parse allocated and dropped (tens of megabytes for a glTF
/// file of a few hundred thousand nodes) would otherwise stay resident, and the server's memory
/// would stop following what its scenes count (see [`raystage_service::give_back_memory`]).
async fn give_back_after_large_bodies(request: axum::extract::Request, next: middleware::Next) -> axum::response::Response {
    let length = request.headers().get(axum::http::header::CONTENT_LENGTH).and_then(|v| v.to_str().ok()?.parse::<u64>().ok());
    let response = next.run(request).await;
    if length.is_some_and(|n| n >= LARGE_BODY) {
        // Before the answer goes out (a few milliseconds), so that a client that sees it sees
        // the memory given back.
        let _ = tokio::task::spawn_blocking(raystage_service::give_back_memory).await;
    }
    response
}

/// What the server is and where its description is.
#[derive(Serialize, ToSchema)]
pub struct Index {
    /// `raystage`.
    pub name: &'static str,
    /// The server's version.
    pub version: &'static str,
    /// Where the OpenAPI description is.
    pub openapi: &'static str,
}

/// What this server is; a browser (`Accept: text/html`) gets the viewer page instead.
#[utoipa::path(get, path = "/", tag = "server", responses((status = 200, description = "Success: the index, or the viewer page for a browser", content(
    (Index = "application/json"),
    (String = "text/html"),
))))]
async fn index() -> Json<Index> {
    Json(Index { name: "raystage", version: env!("CARGO_PKG_VERSION"), openapi: "/openapi.json" })
}

/// After an edit.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct Updated {
    /// The scene's version after the edit.
    pub version: u64,
    /// Parameters the shader's class does not export: those writes were ignored.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ignored: Vec<String>,
}

/// After a creation.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct CreatedResponse {
    /// The new resource's id.
    pub id: u32,
    /// The scene's version after the edit.
    pub version: u64,
    /// Parameters the shader's class does not export: those writes were ignored.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ignored: Vec<String>,
}

/// Runs one edit that creates a resource: 201 with its id.
pub(crate) async fn create(state: &AppState, scene: &Arc<SceneSlot>, command: Command) -> ApiResult<(axum::http::StatusCode, Json<CreatedResponse>)> {
    let (mut results, version) = scene.commands(state, vec![command], false).await?;
    let result = results.pop().expect("one result per command");
    let id = result.id.ok_or_else(|| Error::internal("a creation returned no id"))?;
    Ok((axum::http::StatusCode::CREATED, Json(CreatedResponse { id, version, ignored: result.ignored })))
}

/// Runs one edit that changes or deletes a resource.
pub(crate) async fn update(state: &AppState, scene: &Arc<SceneSlot>, command: Command) -> ApiResult<Json<Updated>> {
    let (mut results, version) = scene.commands(state, vec![command], false).await?;
    let ignored = results.pop().map(|r| r.ignored).unwrap_or_default();
    Ok(Json(Updated { version, ignored }))
}
