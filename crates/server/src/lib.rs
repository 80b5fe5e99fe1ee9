//! # raystage-server
//!
//! raystage's HTTP/JSON API (axum on tokio): scenes and their objects, instances, shaders,
//! textures (procedural, or uploaded PNG, JPEG, WebP and Radiance HDR images), lights and camera as
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
//! The scenes, edits, limits and render jobs behind the routes are the service's
//! ([`raystage_service`]), which a cluster's workers (`raystage-cluster`, `raystage serve
//! --mpi`) replicate: an [`AppState`] made with [`AppState::clustered`] renders with them.
//!
//! Not in here: the service, the cluster, the scene ([`raystage_scene`]), rendering
//! ([`raystage_render`]), glTF reading ([`raystage_gltf_import`]), and the command line that
//! starts the server.

mod auth;
mod commands;
mod error;
mod extract;
mod png;
mod render;
mod routes;
mod stream;

use std::future::Future;
use std::time::Duration;

pub use error::{ApiError, ErrorBody};
pub use raystage_service::{AppState, ClusterTimes, Config, ErrorDetail, Limits, Refused, one_allocator_arena, usable_memory};
pub use routes::openapi::ApiDoc;

/// The whole API as a router, ready for `axum::serve` or `tower::ServiceExt::oneshot`.
pub fn router(state: AppState) -> axum::Router {
    routes::router(state)
}

/// The OpenAPI description of the API.
pub fn openapi() -> utoipa::openapi::OpenApi {
    <ApiDoc as utoipa::OpenApi>::openapi()
}

/// Serves the API on `listener` until `shutdown` completes, then lets the requests in flight
/// finish. Refuses (before serving anything) a listener on a non-loopback address when the
/// configuration has no token, and a blank token anywhere ([`Refused`]). A client has [`Limits::header_read_seconds`] to send a
/// request's headers, else its connection is closed.
pub async fn serve(listener: tokio::net::TcpListener, state: AppState, shutdown: impl Future<Output = ()> + Send + 'static) -> std::io::Result<()> {
    let addr = listener.local_addr()?;
    state.config().check_address(addr).map_err(|e| std::io::Error::new(std::io::ErrorKind::PermissionDenied, e))?;
    let header_timeout = Duration::from_secs(state.config().limits.header_read_seconds);
    let app = router(state);
    // `stop` tells the connections to finish their request in flight and close; each holds a
    // clone of `open` until it has, which `open_tx.closed()` waits for.
    let (stop_tx, stop) = tokio::sync::watch::channel(());
    let (open_tx, open) = tokio::sync::watch::channel(());
    let mut shutdown = std::pin::pin!(shutdown);
    // Connections are the clients whose renders take turns (`raystage_service::Client`); 0 is
    // no connection.
    let mut clients = 0u64;
    loop {
        let stream = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok((stream, _)) => stream,
                Err(e) => {
                    accept_failed(e).await;
                    continue;
                }
            },
            () = &mut shutdown => break,
        };
        clients += 1;
        let client = raystage_service::Client(clients);
        let app = tower::ServiceExt::map_request(app.clone(), move |mut request: axum::http::Request<hyper::body::Incoming>| {
            request.extensions_mut().insert(client);
            request
        });
        let service = hyper_util::service::TowerToHyperService::new(app);
        let (mut stop, open) = (stop.clone(), open.clone());
        tokio::spawn(async move {
            let mut builder = hyper::server::conn::http1::Builder::new();
            builder.timer(hyper_util::rt::TokioTimer::new()).header_read_timeout(header_timeout);
            let mut connection = std::pin::pin!(builder.serve_connection(hyper_util::rt::TokioIo::new(stream), service).with_upgrades());
            let mut stopping = false;
            loop {
                tokio::select! {
                    // An error is the client's doing (it went away, sent garbage or too slowly):
                    // nothing to do but close.
                    _ = connection.as_mut() => break,
                    _ = stop.changed(), if !stopping => {
                        stopping = true;
                        connection.as_mut().graceful_shutdown();
                    }
                }
            }
            drop(open);
        });
    }
    drop(listener);
    drop(open);
    // Wakes every connection's `stop.changed()`.
    drop(stop_tx);
    open_tx.closed().await;
    Ok(())
}

/// After a failed `accept`: a connection that failed on its way in is the client's problem;
/// anything else (out of file descriptors) gets a pause, so the loop does not spin.
async fn accept_failed(e: std::io::Error) {
    use std::io::ErrorKind::{ConnectionAborted, ConnectionRefused, ConnectionReset};
    if !matches!(e.kind(), ConnectionAborted | ConnectionRefused | ConnectionReset) {
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}
