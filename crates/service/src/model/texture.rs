//! Textures in JSON. Procedural textures (checker, noise) are described by their kind, two
//! colours and a scale, and can be made by JSON bodies and batch commands; image textures come
//! as the bytes of a PNG, JPEG, WebP or Radiance HDR file, and are described by their size only.

use glam::Vec3;
use raystage_scene::{Image, Texture};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::config::Limits;
use crate::error::{Error, Result};
use crate::model::light::Rgb;

/// The kinds of procedural texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum TextureKind {
    /// A 3D checkerboard of cubes of edge `1 / scale` alternating `a` and `b` (in texture
    /// coordinates where the mesh has them, else in object space).
    Checker,
    /// Solid noise (several octaves of gradient noise) blending `a` into `b`, `scale` features
    /// per unit length.
    Noise,
}

/// A procedural texture (`POST`/`PUT /scenes/{scene}/textures` with a JSON body, batch
/// `add_texture` and `set_texture`). Fields left out take their defaults. Image textures are
/// uploaded as files instead, to the routes only.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct TextureSpec {
    /// In a batch's `add_texture`, a name later commands can use for this texture instead of
    /// its id.
    pub label: Option<String>,
    /// `checker` or `noise`.
    pub kind: TextureKind,
    /// The first colour (checker: the cube at the origin; noise: where the noise is low),
    /// linear RGB, not negative; default 0.8.
    pub a: Option<Rgb>,
    /// The second colour (noise: where the noise is high); default 0.2.
    pub b: Option<Rgb>,
    /// Checker: cubes per unit length; noise: features per unit length. Positive; default 1.
    pub scale: Option<f32>,
}

impl TextureSpec {
    /// The scene's texture, checked (422 naming the field).
    pub fn to_texture(&self) -> Result<Texture> {
        let colour = |value: Option<Rgb>, default: f32, field: &str| -> Result<Vec3> {
            let c = value.map_or(Vec3::splat(default), Rgb::vec);
            if !c.is_finite() {
                return Err(Error::unprocessable(Some(field.into()), format!("{field} is not finite: {c}")));
            }
            if c.min_element() < 0.0 {
                return Err(Error::unprocessable(Some(field.into()), format!("{field} has a negative channel: {c}")));
            }
            Ok(c)
        };
        let (a, b) = (colour(self.a, 0.8, "a")?, colour(self.b, 0.2, "b")?);
        let scale = self.scale.unwrap_or(1.0);
        if !(scale.is_finite() && scale > 0.0) {
            return Err(Error::unprocessable(Some("scale".into()), format!("scale must be a positive number, not {scale}")));
        }
        Ok(match self.kind {
            TextureKind::Checker => Texture::Checker { a, b, scale },
            TextureKind::Noise => Texture::Noise { a, b, scale },
        })
    }
}

/// What a texture is. Image textures show their size, never their texels.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum TextureDescription {
    /// A checkerboard.
    Checker {
        /// The first colour.
        a: [f32; 3],
        /// The second colour.
        b: [f32; 3],
        /// Cubes per unit length.
        scale: f32,
    },
    /// Solid noise.
    Noise {
        /// Where the noise is low.
        a: [f32; 3],
        /// Where the noise is high.
        b: [f32; 3],
        /// Features per unit length.
        scale: f32,
    },
    /// An image, decoded to linear RGB.
    Image {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
    },
}

/// A texture with its id.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct TextureInfo {
    /// The texture's id.
    pub id: u32,
    /// The texture.
    #[serde(flatten)]
    pub texture: TextureDescription,
}

impl TextureInfo {
    /// A scene texture as JSON.
    pub fn of(id: u32, texture: &Texture) -> TextureInfo {
        let texture = match texture {
            Texture::Checker { a, b, scale } => TextureDescription::Checker { a: a.to_array(), b: b.to_array(), scale: *scale },
            Texture::Noise { a, b, scale } => TextureDescription::Noise { a: a.to_array(), b: b.to_array(), scale: *scale },
            Texture::Image(image) => TextureDescription::Image { width: image.width(), height: image.height() },
        };
        TextureInfo { id, texture }
    }
}

/// Bytes a decoded texel may take: three colour channels and coverage, as `f32`.
const TEXEL_BYTES: u64 = 4 * 4;

/// Decodes a PNG, JPEG, WebP or Radiance HDR file: 422 if it cannot be read, 413 if it is wider or
/// taller than the limit on image sizes or would take more memory than the texture budget
/// (both checked from its header, before it is decoded).
pub fn decode_image(bytes: &[u8], limits: &Limits) -> Result<Image> {
    let (width, height) = Image::dimensions(bytes)?;
    let max = limits.max_dimension;
    if width > max || height > max {
        return Err(Error::too_large(None, format!("the image is {width}×{height} texels: the limit is {max} a side")).limit("max_dimension"));
    }
    let decoded = width as u64 * height as u64 * TEXEL_BYTES;
    let budget = limits.max_texture_bytes as u64;
    if decoded > budget {
        return Err(Error::too_large(None, format!("the image is {width}×{height} texels, {decoded} bytes decoded: the limit is {budget} bytes"))
            .limit("max_texture_bytes"));
    }
    Ok(Image::decode(bytes)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ErrorKind;

    fn spec(kind: TextureKind) -> TextureSpec {
        TextureSpec { label: None, kind, a: None, b: None, scale: None }
    }

    #[test]
    fn left_out_fields_take_their_defaults_and_descriptions_show_them() {
        let texture = spec(TextureKind::Noise).to_texture().unwrap();
        assert_eq!(texture, Texture::Noise { a: Vec3::splat(0.8), b: Vec3::splat(0.2), scale: 1.0 });
        let grey = TextureSpec { a: Some(Rgb::Grey(0.5)), scale: Some(4.0), ..spec(TextureKind::Checker) };
        // As a response sends it: f32s written as the shortest decimal that reads back.
        let text = serde_json::to_string(&TextureInfo::of(3, &grey.to_texture().unwrap())).unwrap();
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(json, serde_json::json!({ "id": 3, "kind": "checker", "a": [0.5, 0.5, 0.5], "b": [0.2, 0.2, 0.2], "scale": 4.0 }));
    }

    #[test]
    fn bad_numbers_name_the_field() {
        let field = |s: TextureSpec| s.to_texture().unwrap_err().detail.field;
        assert_eq!(field(TextureSpec { scale: Some(0.0), ..spec(TextureKind::Checker) }).as_deref(), Some("scale"));
        assert_eq!(field(TextureSpec { scale: Some(f32::INFINITY), ..spec(TextureKind::Checker) }).as_deref(), Some("scale"));
        assert_eq!(field(TextureSpec { a: Some(Rgb::Rgb([0.0, f32::INFINITY, 0.0])), ..spec(TextureKind::Noise) }).as_deref(), Some("a"));
        assert_eq!(field(TextureSpec { b: Some(Rgb::Grey(-1.0)), ..spec(TextureKind::Noise) }).as_deref(), Some("b"));
    }

    #[test]
    fn images_past_the_size_limit_are_refused_before_decoding() {
        let mut png = std::io::Cursor::new(Vec::new());
        image::RgbImage::new(20, 4).write_to(&mut png, image::ImageFormat::Png).unwrap();
        let small = Limits { max_dimension: 16, ..Limits::default() };
        assert_eq!(decode_image(png.get_ref(), &small).unwrap_err().kind, ErrorKind::TooLarge);
        let image = decode_image(png.get_ref(), &Limits::default()).unwrap();
        assert_eq!((image.width(), image.height()), (20, 4));
        let budget = Limits { max_texture_bytes: 20 * 4 * 16 - 1, ..Limits::default() };
        let over = decode_image(png.get_ref(), &budget).unwrap_err();
        assert_eq!((over.kind, over.detail.limit), (ErrorKind::TooLarge, Some("max_texture_bytes")));
        let garbage = decode_image(b"\x89PNG\r\n\x1a\n but not really", &Limits::default()).unwrap_err();
        assert_eq!(garbage.kind, ErrorKind::Unprocessable);
        assert!(garbage.detail.message.starts_with("the image cannot be read"), "{}", garbage.detail.message);
    }
}
