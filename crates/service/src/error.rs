//! Errors as HTTP responses: every failure is a status and a JSON body
//! `{"error": {"code", "message", "field"}}`, mapped here and nowhere else.

use axum::Json;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use raystage_gltf_import::ImportError;
use raystage_scene::SceneError;
use serde::Serialize;
use utoipa::ToSchema;

/// A failed request: the status, a machine-readable code, a message for people, and the field
/// of the request at fault.
#[derive(Clone, Debug, PartialEq)]
pub struct ApiError {
    /// The HTTP status.
    pub status: StatusCode,
    /// The error's body.
    pub detail: ErrorDetail,
}

/// The body of every error response.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct ErrorBody {
    /// What went wrong.
    pub error: ErrorDetail,
}

/// What went wrong.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct ErrorDetail {
    /// `bad_request`, `unauthorized`, `not_found`, `conflict`, `timeout`, `too_large`,
    /// `unsupported_media_type`, `unprocessable`, `busy` or `internal`.
    pub code: &'static str,
    /// What was wrong, for a person.
    pub message: String,
    /// The part of the request at fault, as a path into the JSON body, a query parameter or a
    /// header (`commands[2].mesh.positions`, `width`, `content-type`), if one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field: Option<String>,
    /// The server limit the request ran into, as [`crate::Limits`] names it
    /// (`max_render_seconds`, `max_commands`, ...), if one did: a client can tell a limit it
    /// may work within (a smaller frame, a shorter batch) from a value that is wrong.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit: Option<&'static str>,
}

impl ApiError {
    fn new(status: StatusCode, code: &'static str, field: Option<String>, message: impl Into<String>) -> ApiError {
        ApiError { status, detail: ErrorDetail { code, message: message.into(), field, limit: None } }
    }

    /// 400: the request cannot be parsed.
    pub fn bad_request(field: Option<String>, message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::BAD_REQUEST, "bad_request", field, message)
    }

    /// 401: no token, or the wrong one.
    pub fn unauthorized() -> ApiError {
        ApiError::new(StatusCode::UNAUTHORIZED, "unauthorized", None, "this server needs `Authorization: Bearer <token>`")
    }

    /// 404: no such scene, resource or route.
    pub fn not_found(field: Option<String>, message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::NOT_FOUND, "not_found", field, message)
    }

    /// 409: the resource is not in a state to do that (a render job's image before it is done).
    pub fn conflict(message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::CONFLICT, "conflict", None, message)
    }

    /// 413: the request is larger than a limit allows.
    pub fn too_large(field: Option<String>, message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::PAYLOAD_TOO_LARGE, "too_large", field, message)
    }

    /// 415: a body of a content type the route does not take; the error names the
    /// `content-type` header.
    pub fn unsupported_media_type(message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::UNSUPPORTED_MEDIA_TYPE, "unsupported_media_type", Some("content-type".into()), message)
    }

    /// 422: well-formed, but a value is not acceptable (NaN, out of range, singular, ...).
    pub fn unprocessable(field: Option<String>, message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, "unprocessable", field, message)
    }

    /// 503: a limit on concurrent work is reached.
    pub fn busy(message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "busy", None, message)
    }

    /// 408: the request's body did not arrive within `limit`.
    pub fn timeout(limit: &'static str, message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::REQUEST_TIMEOUT, "timeout", None, message).limit(limit)
    }

    /// 503: a render ran past the time budget, `limit`.
    pub fn render_budget(limit: &'static str, message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "timeout", None, message).limit(limit)
    }

    /// The same error, naming the server limit (a field of [`crate::Limits`]) it is about.
    pub fn limit(mut self, limit: &'static str) -> ApiError {
        self.detail.limit = Some(limit);
        self
    }

    /// 500: a bug.
    pub fn internal(message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, "internal", None, message)
    }

    /// The same error about a field inside `prefix` (`commands[3]` + `mesh` =
    /// `commands[3].mesh`).
    pub fn within(mut self, prefix: &str) -> ApiError {
        self.detail.field = Some(match self.detail.field.take() {
            Some(field) if field.starts_with('[') => format!("{prefix}{field}"),
            Some(field) => format!("{prefix}.{field}"),
            None => prefix.to_string(),
        });
        self
    }
}

impl ApiError {
    /// The same error with `prefix` taken off its field (the scene names fields `camera.eye`,
    /// `light.position`; within a camera or light body they are `eye`, `position`).
    pub fn without_prefix(mut self, prefix: &str) -> ApiError {
        if let Some(field) = &mut self.detail.field
            && let Some(rest) = field.strip_prefix(prefix)
        {
            *field = rest.to_string();
        }
        self
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let mut response = (self.status, Json(ErrorBody { error: self.detail })).into_response();
        if self.status == StatusCode::UNAUTHORIZED {
            response.headers_mut().insert("www-authenticate", axum::http::HeaderValue::from_static("Bearer"));
        }
        if self.status == StatusCode::REQUEST_TIMEOUT {
            // The rest of a slow body may still be on its way: the connection cannot be reused.
            response.headers_mut().insert(axum::http::header::CONNECTION, axum::http::HeaderValue::from_static("close"));
        }
        response
    }
}

impl From<SceneError> for ApiError {
    /// Unknown ids are 404; every other refused edit is 422, naming the field the scene named
    /// (image bytes that cannot be decoded are a body, not a field: they name none).
    fn from(e: SceneError) -> ApiError {
        let message = e.to_string();
        let field = |f: &str| Some(f.to_string());
        match e {
            SceneError::UnknownObject(_) => ApiError::not_found(field("object"), message),
            SceneError::UnknownInstance(_) => ApiError::not_found(field("instance"), message),
            SceneError::UnknownShader(_) => ApiError::not_found(field("shader"), message),
            SceneError::UnknownLight(_) => ApiError::not_found(field("light"), message),
            SceneError::UnknownTexture(_) => ApiError::not_found(field("texture"), message),
            SceneError::UnknownShaderClass(_) => ApiError::unprocessable(field("class"), message),
            SceneError::EmptyMesh | SceneError::IndexOutOfRange { .. } => ApiError::unprocessable(field("indices"), message),
            SceneError::WrongLength { field: f, .. }
            | SceneError::NotFinite { field: f, .. }
            | SceneError::SingularTransform { field: f, .. }
            | SceneError::OutOfRange { field: f, .. } => ApiError::unprocessable(field(f), message),
            SceneError::WrongParameterType { ref name, .. } => ApiError::unprocessable(Some(format!("params.{name}")), message),
            SceneError::BadImage(_) => ApiError::unprocessable(None, message),
        }
    }
}

impl From<ImportError> for ApiError {
    /// A file that is not glTF is 400, one over the limits 413 (images that take longer to
    /// decode than a render may take naming `max_render_seconds`), one with bad content 422.
    fn from(e: ImportError) -> ApiError {
        let message = e.to_string();
        match e {
            ImportError::Syntax(_) => ApiError::bad_request(None, message),
            ImportError::TooLarge { .. } => ApiError::too_large(None, message),
            ImportError::TooSlow { .. } => ApiError::too_large(None, message).limit("max_render_seconds"),
            ImportError::Invalid { field, .. } => ApiError::unprocessable(Some(field), message),
            ImportError::Io { .. } | ImportError::Scene(_) | ImportError::Internal => ApiError::internal(message),
        }
    }
}

/// The result of a handler.
pub type ApiResult<T> = Result<T, ApiError>;
