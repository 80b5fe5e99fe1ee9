//! Errors: what failed, of what kind, and the field of the request at fault. The kind decides
//! how a front end answers (the HTTP crate maps each to its status); the [`ErrorDetail`] is what
//! the client reads, the same whichever front end it came through.

use raystage_gltf_import::ImportError;
use raystage_scene::SceneError;
use serde::Serialize;
use utoipa::ToSchema;

/// A failed request: its kind, and what the client is told.
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    /// What kind of failure it is.
    pub kind: ErrorKind,
    /// What the client is told.
    pub detail: ErrorDetail,
}

/// The kinds of failure: each is one `code` of [`ErrorDetail`], and one status in the HTTP API.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The request cannot be parsed.
    BadRequest,
    /// The route does not take the request's method (code `bad_request`).
    MethodNotAllowed,
    /// No token, or the wrong one.
    Unauthorized,
    /// No such scene, resource or route.
    NotFound,
    /// The resource is not in a state to do that (a render job's image before it is done).
    Conflict,
    /// The request's body did not arrive in time.
    Timeout,
    /// The request is larger than a limit allows.
    TooLarge,
    /// A body of a content type the route does not take.
    UnsupportedMediaType,
    /// Well-formed, but a value is not acceptable (NaN, out of range, singular, ...).
    Unprocessable,
    /// A limit on concurrent work is reached.
    Busy,
    /// A render ran past its time budget (code `timeout`).
    RenderBudget,
    /// A bug.
    Internal,
}

impl ErrorKind {
    /// The machine-readable code clients see.
    pub fn code(self) -> &'static str {
        match self {
            ErrorKind::BadRequest | ErrorKind::MethodNotAllowed => "bad_request",
            ErrorKind::Unauthorized => "unauthorized",
            ErrorKind::NotFound => "not_found",
            ErrorKind::Conflict => "conflict",
            ErrorKind::Timeout | ErrorKind::RenderBudget => "timeout",
            ErrorKind::TooLarge => "too_large",
            ErrorKind::UnsupportedMediaType => "unsupported_media_type",
            ErrorKind::Unprocessable => "unprocessable",
            ErrorKind::Busy => "busy",
            ErrorKind::Internal => "internal",
        }
    }
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

impl Error {
    /// An error of `kind` about `field`, if one is at fault.
    pub fn new(kind: ErrorKind, field: Option<String>, message: impl Into<String>) -> Error {
        Error { kind, detail: ErrorDetail { code: kind.code(), message: message.into(), field, limit: None } }
    }

    /// The request cannot be parsed.
    pub fn bad_request(field: Option<String>, message: impl Into<String>) -> Error {
        Error::new(ErrorKind::BadRequest, field, message)
    }

    /// No such scene or resource.
    pub fn not_found(field: Option<String>, message: impl Into<String>) -> Error {
        Error::new(ErrorKind::NotFound, field, message)
    }

    /// The resource is not in a state to do that (a render job's image before it is done).
    pub fn conflict(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Conflict, None, message)
    }

    /// The request is larger than a limit allows.
    pub fn too_large(field: Option<String>, message: impl Into<String>) -> Error {
        Error::new(ErrorKind::TooLarge, field, message)
    }

    /// Well-formed, but a value is not acceptable (NaN, out of range, singular, ...).
    pub fn unprocessable(field: Option<String>, message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Unprocessable, field, message)
    }

    /// A limit on concurrent work is reached.
    pub fn busy(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Busy, None, message)
    }

    /// A render ran past the time budget, `limit`.
    pub fn render_budget(limit: &'static str, message: impl Into<String>) -> Error {
        Error::new(ErrorKind::RenderBudget, None, message).limit(limit)
    }

    /// The same error, naming the server limit (a field of [`crate::Limits`]) it is about.
    pub fn limit(mut self, limit: &'static str) -> Error {
        self.detail.limit = Some(limit);
        self
    }

    /// A bug.
    pub fn internal(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Internal, None, message)
    }

    /// The same error about a field inside `prefix` (`commands[3]` + `mesh` =
    /// `commands[3].mesh`).
    pub fn within(mut self, prefix: &str) -> Error {
        self.detail.field = Some(match self.detail.field.take() {
            Some(field) if field.starts_with('[') => format!("{prefix}{field}"),
            Some(field) => format!("{prefix}.{field}"),
            None => prefix.to_string(),
        });
        self
    }
}

impl Error {
    /// The same error with `prefix` taken off its field (the scene names fields `camera.eye`,
    /// `light.position`; within a camera or light body they are `eye`, `position`).
    pub fn without_prefix(mut self, prefix: &str) -> Error {
        if let Some(field) = &mut self.detail.field
            && let Some(rest) = field.strip_prefix(prefix)
        {
            *field = rest.to_string();
        }
        self
    }
}

impl From<SceneError> for Error {
    /// Unknown ids are not found; every other refused edit is unprocessable, naming the field the
    /// scene named (image bytes that cannot be decoded are a body, not a field: they name none).
    fn from(e: SceneError) -> Error {
        let message = e.to_string();
        let field = |f: &str| Some(f.to_string());
        match e {
            SceneError::UnknownObject(_) => Error::not_found(field("object"), message),
            SceneError::UnknownInstance(_) => Error::not_found(field("instance"), message),
            SceneError::UnknownShader(_) => Error::not_found(field("shader"), message),
            SceneError::UnknownLight(_) => Error::not_found(field("light"), message),
            SceneError::UnknownTexture(_) => Error::not_found(field("texture"), message),
            SceneError::UnknownShaderClass(_) => Error::unprocessable(field("class"), message),
            SceneError::EmptyMesh | SceneError::IndexOutOfRange { .. } => Error::unprocessable(field("indices"), message),
            SceneError::WrongLength { field: f, .. }
            | SceneError::NotFinite { field: f, .. }
            | SceneError::SingularTransform { field: f, .. }
            | SceneError::OutOfRange { field: f, .. } => Error::unprocessable(field(f), message),
            SceneError::WrongParameterType { ref name, .. } => Error::unprocessable(Some(format!("params.{name}")), message),
            SceneError::BadImage(_) => Error::unprocessable(None, message),
        }
    }
}

impl From<ImportError> for Error {
    /// A file that is not glTF is a bad request, one over the limits too large (images that take
    /// longer to decode than a render may take naming `max_render_seconds`), one with bad content
    /// unprocessable.
    fn from(e: ImportError) -> Error {
        let message = e.to_string();
        match e {
            ImportError::Syntax(_) => Error::bad_request(None, message),
            ImportError::TooLarge { .. } => Error::too_large(None, message),
            ImportError::TooSlow { .. } => Error::too_large(None, message).limit("max_render_seconds"),
            ImportError::Invalid { field, .. } => Error::unprocessable(Some(field), message),
            ImportError::Io { .. } | ImportError::Scene(_) | ImportError::Internal => Error::internal(message),
        }
    }
}

/// The result of a request, or of a step of one.
pub type Result<T, E = Error> = std::result::Result<T, E>;
