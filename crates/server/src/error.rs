//! Errors as HTTP responses: every failure is a status and a JSON body
//! `{"error": {"code", "message", "field"}}`, mapped here and nowhere else.

use axum::Json;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use raystage_service::{Error, ErrorDetail, ErrorKind};
use serde::Serialize;
use utoipa::ToSchema;

/// A failed request, as the HTTP API answers it: the service's [`Error`], with the status of
/// its kind.
#[derive(Clone, Debug, PartialEq)]
pub struct ApiError(pub Error);

/// The body of every error response.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct ErrorBody {
    /// What went wrong.
    pub error: ErrorDetail,
}

impl ApiError {
    /// 401: no token, or the wrong one.
    pub fn unauthorized() -> ApiError {
        ApiError(Error::new(ErrorKind::Unauthorized, None, "this server needs `Authorization: Bearer <token>`"))
    }

    /// 415: a body of a content type the route does not take; the error names the
    /// `content-type` header.
    pub fn unsupported_media_type(message: impl Into<String>) -> ApiError {
        ApiError(Error::new(ErrorKind::UnsupportedMediaType, Some("content-type".into()), message))
    }

    /// 408: the request's body did not arrive within `limit`.
    pub fn timeout(limit: &'static str, message: impl Into<String>) -> ApiError {
        ApiError(Error::new(ErrorKind::Timeout, None, message).limit(limit))
    }

    /// The HTTP status of the error's kind.
    pub fn status(&self) -> StatusCode {
        match self.0.kind {
            ErrorKind::BadRequest => StatusCode::BAD_REQUEST,
            ErrorKind::MethodNotAllowed => StatusCode::METHOD_NOT_ALLOWED,
            ErrorKind::Unauthorized => StatusCode::UNAUTHORIZED,
            ErrorKind::NotFound => StatusCode::NOT_FOUND,
            ErrorKind::Conflict => StatusCode::CONFLICT,
            ErrorKind::Timeout => StatusCode::REQUEST_TIMEOUT,
            ErrorKind::TooLarge => StatusCode::PAYLOAD_TOO_LARGE,
            ErrorKind::UnsupportedMediaType => StatusCode::UNSUPPORTED_MEDIA_TYPE,
            ErrorKind::Unprocessable => StatusCode::UNPROCESSABLE_ENTITY,
            ErrorKind::Busy | ErrorKind::RenderBudget => StatusCode::SERVICE_UNAVAILABLE,
            ErrorKind::Internal => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }
}

impl From<Error> for ApiError {
    fn from(e: Error) -> ApiError {
        ApiError(e)
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let status = self.status();
        let mut response = (status, Json(ErrorBody { error: self.0.detail })).into_response();
        if status == StatusCode::UNAUTHORIZED {
            response.headers_mut().insert("www-authenticate", axum::http::HeaderValue::from_static("Bearer"));
        }
        if status == StatusCode::REQUEST_TIMEOUT {
            // The rest of a slow body may still be on its way: the connection cannot be reused.
            response.headers_mut().insert(axum::http::header::CONNECTION, axum::http::HeaderValue::from_static("close"));
        }
        response
    }
}

/// The result of a handler.
pub type ApiResult<T> = Result<T, ApiError>;
