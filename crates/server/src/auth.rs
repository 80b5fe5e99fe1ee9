//! The access token: with one configured, every request must carry it as
//! `Authorization: Bearer <token>` (a stream may pass it as `?token=`, since browsers cannot set
//! headers on a WebSocket).

use axum::extract::{Request, State};
use axum::http::header::AUTHORIZATION;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::error::ApiError;
use crate::state::AppState;

/// Lets a request through if the server has no token or the request carries it; 401 otherwise.
pub(crate) async fn require_token(State(state): State<AppState>, request: Request, next: Next) -> Response {
    let Some(token) = state.config().token.as_deref() else {
        return next.run(request).await;
    };
    if carries(&request, token) { next.run(request).await } else { ApiError::unauthorized().into_response() }
}

/// Whether the request carries `token`: as a bearer token, or in the query of a stream.
fn carries(request: &Request, token: &str) -> bool {
    let bearer = request.headers().get(AUTHORIZATION).and_then(|v| v.to_str().ok()).and_then(|v| v.strip_prefix("Bearer "));
    bearer.is_some_and(|b| same(b, token))
        || (request.uri().path().ends_with("/stream")
            && form_urlencoded::parse(request.uri().query().unwrap_or("").as_bytes()).any(|(k, v)| k == "token" && same(&v, token)))
}

/// Compares in time independent of where the strings differ.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}
