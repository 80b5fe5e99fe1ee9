//! What can go wrong when editing a scene. Every error names the offending field or id, and an
//! edit that fails leaves the scene exactly as it was.

use crate::ids::{InstanceId, LightId, ObjectId, ShaderId, TextureId};

/// An edit the scene refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// No object has this id.
    #[error("unknown {0}")]
    UnknownObject(ObjectId),
    /// No instance has this id.
    #[error("unknown {0}")]
    UnknownInstance(InstanceId),
    /// No shader has this id.
    #[error("unknown {0}")]
    UnknownShader(ShaderId),
    /// No light has this id.
    #[error("unknown {0}")]
    UnknownLight(LightId),
    /// No texture has this id.
    #[error("unknown {0}")]
    UnknownTexture(TextureId),
    /// No shader class has this name.
    #[error("unknown shader class `{0}`")]
    UnknownShaderClass(String),
    /// A mesh without triangles.
    #[error("empty object: a mesh needs at least one triangle")]
    EmptyMesh,
    /// A vertex index that names no vertex.
    #[error("triangle {triangle} uses vertex {index}, but the mesh has {vertices} vertices")]
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The offending index.
        index: u32,
        /// The number of vertices.
        vertices: usize,
    },
    /// A per-vertex or per-triangle attribute array of the wrong length.
    #[error("{field} has {got} entries, expected {expected}")]
    WrongLength {
        /// The attribute.
        field: &'static str,
        /// Its length.
        got: usize,
        /// The length it must have.
        expected: usize,
    },
    /// A NaN or infinite number.
    #[error("{field} is not finite (entry {index})")]
    NotFinite {
        /// Where.
        field: &'static str,
        /// Which element.
        index: usize,
    },
    /// A transform that cannot be inverted (scale zero along some axis).
    #[error("{field} is singular (determinant {determinant:e})")]
    SingularTransform {
        /// Where.
        field: &'static str,
        /// Its determinant.
        determinant: f32,
    },
    /// A value outside its allowed range.
    #[error("{field} is out of range: {message}")]
    OutOfRange {
        /// Where.
        field: &'static str,
        /// What the range is.
        message: String,
    },
    /// Image bytes that could not be decoded, or pixels that do not make an image.
    #[error("the image cannot be read: {0}")]
    BadImage(String),
    /// A shader parameter written with the wrong type.
    #[error("parameter `{name}` of shader class `{class}` takes {expected}")]
    WrongParameterType {
        /// The class.
        class: &'static str,
        /// The parameter.
        name: String,
        /// What it takes.
        expected: &'static str,
    },
}
