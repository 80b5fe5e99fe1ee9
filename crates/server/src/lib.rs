//! # raystage-server
//!
//! raystage's HTTP/JSON API (axum on tokio): scenes and their objects, instances, shaders,
//! textures (procedural, or uploaded PNG, JPEG and Radiance HDR images), lights and camera as
//! resources, batches of edits that apply all or nothing, glTF uploads, PNG frames, picking,
//! and a WebSocket stream of progressively refined frames. The OpenAPI description is
//! generated from the handlers ([`openapi`]); `api/openapi.json` is a copy and `api/stream.md`
//! describes the stream.
//!
//! [`router`] is the whole API as a tower service (tests drive it without a socket);
//! [`serve`] runs it on a listener, refusing a non-loopback address without a token. Rendering
//! runs on the blocking pool and rayon, never on the reactor's threads; every request is checked
//! against [`Limits`] before work starts, and nothing a request sends can panic the server or
//! leave a scene half-edited.
//!
//! Not in here: the scene ([`raystage_scene`]), rendering ([`raystage_render`]), glTF reading
//! ([`raystage_gltf_import`]), and the command line that starts the server.

mod auth;
mod batch;
mod config;
mod error;
mod extract;
mod model;
mod png;
mod render;
mod routes;
mod state;
mod stats;
mod stream;

use std::future::Future;

pub use config::{Config, ExposedWithoutToken, Limits};
pub use error::{ApiError, ErrorBody, ErrorDetail};
pub use routes::openapi::ApiDoc;
pub use state::AppState;

/// The whole API as a router, ready for `axum::serve` or `tower::ServiceExt::oneshot`.
pub fn router(state: AppState) -> axum::Router {
    routes::router(state)
}

/// The OpenAPI description of the API.
pub fn openapi() -> utoipa::openapi::OpenApi {
    <ApiDoc as utoipa::OpenApi>::openapi()
}

/// Serves the API on `listener` until `shutdown` completes. Refuses (before serving anything)
/// a listener on a non-loopback address when the configuration has no token.
pub async fn serve(listener: tokio::net::TcpListener, state: AppState, shutdown: impl Future<Output = ()> + Send + 'static) -> std::io::Result<()> {
    let addr = listener.local_addr()?;
    state.config().check_address(addr).map_err(|e| std::io::Error::new(std::io::ErrorKind::PermissionDenied, e))?;
    axum::serve(listener, router(state)).with_graceful_shutdown(shutdown).await
}
