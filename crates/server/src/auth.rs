//! The access token: with one configured, every request must carry it as
//! `Authorization: Bearer <token>` (a stream may pass it as `?token=`, since browsers cannot set
//! headers on a WebSocket), but for the viewer page and its files, which hold no data.

use axum::extract::{Request, State};
use axum::http::header::AUTHORIZATION;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use raystage_service::AppState;

use crate::error::ApiError;

/// Lets a request through if the server has no token, the request carries it, or it is for the
/// viewer page; 401 otherwise.
pub(crate) async fn require_token(State(state): State<AppState>, request: Request, next: Next) -> Response {
    let Some(token) = state.config().token.as_deref() else {
        return next.run(request).await;
    };
    if carries(&request, token) || crate::routes::web::is_public(&request) { next.run(request).await } else { ApiError::unauthorized().into_response() }
}

/// Whether the request carries `token`: as a bearer token, or in the query of a stream.
fn carries(request: &Request, token: &str) -> bool {
    let bearer = request.headers().get(AUTHORIZATION).and_then(|v| v.to_str().ok()).and_then(bearer_token);
    bearer.is_some_and(|b| same(b, token))
        || (request.uri().path().ends_with("/stream")
            && form_urlencoded::parse(request.uri().query().unwrap_or("").as_bytes()).any(|(k, v)| k == "token" && same(&v, token)))
}

/// The token of an `Authorization: Bearer <token>` value. The scheme is matched without
/// regard to case, and any number of spaces may follow it (RFC 9110, section 11.4).
fn bearer_token(value: &str) -> Option<&str> {
    let (scheme, token) = value.split_once(' ')?;
    scheme.eq_ignore_ascii_case("bearer").then(|| token.trim_start_matches(' '))
}

/// Compares in time independent of where the strings differ.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bearer_scheme_is_matched_in_any_case() {
        for value in ["Bearer s3cret", "bearer s3cret", "BEARER s3cret", "bEaReR   s3cret"] {
            assert_eq!(bearer_token(value), Some("s3cret"), "{value}");
        }
        for value in ["Basic s3cret", "Bearers3cret", "Bearer", "Token s3cret"] {
            assert_eq!(bearer_token(value), None, "{value}");
        }
    }
}
