//! Textures: colours that vary over a surface, looked up by shaders through texture parameters.

use std::sync::Arc;

use glam::Vec3;

use crate::error::SceneError;

/// A texture. Procedural textures are evaluated where they are needed; image textures hold
/// linear RGB texels.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// A 3D checkerboard of cubes of edge `1 / scale`, alternating `a` and `b` (in object space,
    /// or in texture coordinates where the mesh has them).
    Checker {
        /// One colour.
        a: Vec3,
        /// The other.
        b: Vec3,
        /// Cubes per unit length.
        scale: f32,
    },
    /// Solid noise (Perlin's gradient noise, several octaves) blending `a` into `b`.
    Noise {
        /// Colour where the noise is low.
        a: Vec3,
        /// Colour where it is high.
        b: Vec3,
        /// Frequency: features per unit length.
        scale: f32,
    },
    /// An image, addressed by the mesh's texture coordinates (wrapping), bilinearly filtered.
    Image(Arc<Image>),
}

/// A linear-RGB image.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
}

impl Image {
    /// An image from `width × height` texels, row-major from the top row; every channel finite
    /// and non-negative.
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Result<Image, SceneError> {
        let expected = width as usize * height as usize;
        if width == 0 || height == 0 {
            return Err(SceneError::OutOfRange { field: "image size", message: format!("{width}x{height} is empty") });
        }
        if texels.len() != expected {
            return Err(SceneError::WrongLength { field: "texels", got: texels.len(), expected });
        }
        if let Some(index) = texels.iter().position(|t| !t.is_finite() || t.min_element() < 0.0) {
            return Err(SceneError::NotFinite { field: "texels", index });
        }
        Ok(Image { width, height, texels })
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texel in column `x`, row `y` (wrapping around).
    pub fn texel(&self, x: i64, y: i64) -> Vec3 {
        let (w, h) = (self.width as i64, self.height as i64);
        self.texels[(y.rem_euclid(h) * w + x.rem_euclid(w)) as usize]
    }
}

impl Texture {
    /// Checks the numbers of a procedural texture.
    pub fn validate(&self) -> Result<(), SceneError> {
        match self {
            Texture::Checker { a, b, scale } | Texture::Noise { a, b, scale } => {
                if !(a.is_finite() && b.is_finite() && scale.is_finite()) {
                    return Err(SceneError::NotFinite { field: "texture", index: 0 });
                }
                if *scale <= 0.0 {
                    return Err(SceneError::OutOfRange { field: "texture.scale", message: "must be positive".into() });
                }
                Ok(())
            }
            Texture::Image(_) => Ok(()),
        }
    }
}
