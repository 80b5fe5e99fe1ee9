//! What can be wrong with a glTF file.

use std::path::PathBuf;

use raystage_scene::SceneError;

/// Why a file could not be imported. Every variant that concerns a part of the file names it by
/// its JSON path (`meshes[0].primitives[1].attributes.POSITION`).
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// Not glTF: bad JSON, a bad GLB header, or a document that breaks the schema.
    // Not `#[from]`, which would make the gltf error this one's source as well: a report of
    // the chain (the command line's) then printed its message twice.
    #[error("not a valid glTF file: {0}")]
    Syntax(gltf::Error),
    /// A part of the file that cannot be read.
    #[error("{field}: {message}")]
    Invalid {
        /// Where, as a JSON path.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// More triangles, vertices, instances or levels of nodes than the limits allow.
    #[error("the file has {count} {what}, more than the limit of {limit}")]
    TooLarge {
        /// Triangles, vertices, instances or levels of nodes.
        what: &'static str,
        /// How many the file has (at least).
        count: usize,
        /// The limit.
        limit: usize,
    },
    /// Reading the file took longer than the limits allow.
    #[error("{what} took longer than the limit of {} s", limit.as_secs_f64())]
    TooSlow {
        /// What took long.
        what: &'static str,
        /// The limit.
        limit: std::time::Duration,
    },
    /// An external buffer could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The scene refused an edit (only a bug can cause this: [`crate::read`] checks everything).
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The reader failed unexpectedly (a bug); nothing was imported.
    #[error("internal error while reading the glTF file")]
    Internal,
}

impl From<gltf::Error> for ImportError {
    fn from(e: gltf::Error) -> ImportError {
        ImportError::Syntax(e)
    }
}

impl ImportError {
    /// An [`ImportError::Invalid`] about `field`.
    pub(crate) fn invalid(field: impl Into<String>, message: impl Into<String>) -> ImportError {
        ImportError::Invalid { field: field.into(), message: message.into() }
    }

    /// The part of the file the error is about, if it is about one.
    pub fn field(&self) -> Option<&str> {
        match self {
            ImportError::Invalid { field, .. } => Some(field),
            _ => None,
        }
    }
}
