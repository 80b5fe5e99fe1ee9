//! The crate's error type.

use std::path::PathBuf;

/// Everything that can go wrong in `raystage-render`.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The image encoder rejected the film (for example a zero-sized image).
    #[error("cannot encode PNG: {0}")]
    Encode(#[from] image::ImageError),
    /// A render setting outside its range.
    #[error("{field} is out of range: {message}")]
    Setting {
        /// The setting.
        field: &'static str,
        /// What its range is.
        message: String,
    },
    /// Writing the encoded image failed.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
}
