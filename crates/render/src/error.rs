//! The crate's error type.

use std::path::PathBuf;

/// Everything that can go wrong in `raystage-render`.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The image encoder rejected the film (for example a zero-sized image).
    #[error("cannot encode the image: {0}")]
    Encode(#[from] image::ImageError),
    /// The OpenEXR encoder failed (an image with channels beside its colour).
    #[error("cannot encode the OpenEXR image: {0}")]
    Exr(String),
    /// Bytes that are not an image the film reads.
    #[error("cannot read the image: {0}")]
    Decode(String),
    /// A file name whose extension names no format a film can be written as.
    #[error("cannot write {}: its name must end in .png, .exr or .pfm", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// A render setting outside its range.
    #[error("{field} is out of range: {message}")]
    Setting {
        /// The setting.
        field: &'static str,
        /// What its range is.
        message: String,
    },
    /// The render was stopped through its [`crate::Cancel`] token before it finished: there is
    /// no image.
    #[error("the render was cancelled")]
    Cancelled,
    /// Writing the encoded image failed.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
}
