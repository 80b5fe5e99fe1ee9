//! Textures: colours that vary over a surface, looked up by shaders through texture parameters.

use std::sync::{Arc, OnceLock};

use glam::Vec3;
use rayon::prelude::*;

use crate::distribution::EnvironmentTables;
use crate::error::SceneError;

/// A texture. Procedural textures are evaluated where they are needed; image textures hold
/// linear RGB texels.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// An image, addressed by the mesh's texture coordinates as its sampler says (wrap modes,
    /// magnification filter), trilinearly across its mip pyramid where a texel is smaller than
    /// the lookup's footprint.
    Image(Arc<Image>),
}

/// A linear-RGB image, with coverage (alpha) where the encoded image had it, and its mip pyramid:
/// the same image at every halved size down to one texel, which lookups far from the camera
/// read so that a texture many texels to the pixel does not alias.
#[derive(Clone, Debug)]
pub struct Image {
    /// The image as given: level 0 of the pyramid. Shared with the build of the coarser levels,
    /// which runs on the build pool (see [`Image::level`]).
    base: Arc<Level>,
    /// Levels 1 and on, each half the size of the one before (rounded down, at least 1), down to
    /// 1×1: built the first time a lookup needs them.
    coarser: OnceLock<Vec<Level>>,
    /// The tables that pick its texels by brightness where it lights a scene as an environment
    /// (see [`Image::environment_tables`]): built the first time a frame needs them.
    environment: OnceLock<EnvironmentTables>,
}

/// An image travels as its texels and coverage (level 0); the pyramid is built where it is
/// needed, as it was here.
impl serde::Serialize for Image {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.base.serialize(serializer)
    }
}

impl<'de> serde::Deserialize<'de> for Image {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Image, D::Error> {
        let base = Level::deserialize(deserializer)?;
        if base.texels.len() != base.width as usize * base.height as usize || !(base.alpha.is_empty() || base.alpha.len() == base.texels.len()) {
            return Err(serde::de::Error::custom("an image's texels do not match its size"));
        }
        Ok(Image { base: Arc::new(base), coarser: OnceLock::new(), environment: OnceLock::new() })
    }
}

/// Equal images have equal texels and coverage; whether their pyramids are built yet does not
/// matter.
impl PartialEq for Image {
    fn eq(&self, other: &Image) -> bool {
        self.base == other.base
    }
}

/// One level of an image's mip pyramid: texels and coverage, row-major from the top row.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Level {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
    /// Coverage in [0, 1] per texel, in `texels`' order; empty for an opaque image.
    alpha: Vec<f32>,
}

impl Image {
    /// The memory its texels and coverage take, with its mip pyramid's (counted whether built
    /// yet or not, as a budget must: any frame may build it), and its environment tables' once
    /// a frame has built them (only an image that lights a scene has them).
    pub fn memory_bytes(&self) -> u64 {
        let per_texel = if self.base.alpha.is_empty() { 12 } else { 16 };
        let pyramid: u64 = pyramid_sizes(self.width(), self.height()).map(|(w, h)| w as u64 * h as u64 * per_texel).sum();
        pyramid + self.environment.get().map_or(0, EnvironmentTables::memory_bytes)
    }

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
        Ok(Image { base: Arc::new(Level { width, height, texels, alpha: Vec::new() }), coarser: OnceLock::new(), environment: OnceLock::new() })
    }

    /// The same image with coverage `alpha` in [0, 1] per texel (glTF's base colour alpha, for
    /// masked and blended surfaces), in the texels' order.
    pub fn with_alpha(self, alpha: Vec<f32>) -> Result<Image, SceneError> {
        let expected = self.base.texels.len();
        if alpha.len() != expected {
            return Err(SceneError::WrongLength { field: "alpha", got: alpha.len(), expected });
        }
        if let Some(index) = alpha.iter().position(|a| !(0.0..=1.0).contains(a)) {
            return Err(SceneError::OutOfRange { field: "alpha", message: format!("texel {index} is not within [0, 1]") });
        }
        let Level { width, height, texels, .. } = Arc::unwrap_or_clone(self.base);
        Ok(Image { base: Arc::new(Level { width, height, texels, alpha }), coarser: OnceLock::new(), environment: OnceLock::new() })
    }

    /// An image from encoded bytes: PNG, JPEG, WebP, Radiance HDR (`.hdr`) or OpenEXR, told apart by
    /// their first bytes. Integer channels are sRGB-encoded, as these files store them, and are
    /// decoded to linear light; floating-point channels (HDR, EXR) are linear already. Grey images become
    /// grey texels; an alpha channel is kept as the image's coverage (linear, as stored).
    pub fn decode(bytes: &[u8]) -> Result<Image, SceneError> {
        Image::decode_with(bytes, srgb_to_linear)
    }

    /// [`Image::decode`] for a texture of data rather than colour (glTF's metallic-roughness
    /// and normal textures): integer channels are read as they are stored, `value / max`.
    pub fn decode_data(bytes: &[u8]) -> Result<Image, SceneError> {
        Image::decode_with(bytes, |v| v)
    }

    /// An image from encoded bytes, integer channels (as fractions of their maximum) mapped by
    /// `level`.
    fn decode_with(bytes: &[u8], level: fn(f32) -> f32) -> Result<Image, SceneError> {
        let decoded = image::load_from_memory(bytes).map_err(|e| SceneError::BadImage(e.to_string()))?;
        let (width, height) = (decoded.width(), decoded.height());
        let texels = match decoded {
            image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_) => decoded.to_rgb32f().pixels().map(|p| Vec3::from_array(p.0)).collect(),
            // 8- and 16-bit channels alike, as 16-bit values.
            _ => decoded.to_rgb16().pixels().map(|p| Vec3::from_array(p.0.map(|c| level(c as f32 / 65535.0)))).collect(),
        };
        let image = Image::new(width, height, texels)?;
        if !decoded.color().has_alpha() {
            return Ok(image);
        }
        // Alpha is coverage, never sRGB-encoded.
        image.with_alpha(decoded.to_rgba32f().pixels().map(|p| p.0[3].clamp(0.0, 1.0)).collect())
    }

    /// The width and height of the image in encoded bytes (as [`Image::decode`] takes them),
    /// read from its header alone: a caller can refuse an image too large to decode before
    /// decoding it.
    pub fn dimensions(bytes: &[u8]) -> Result<(u32, u32), SceneError> {
        let unreadable = |e: image::ImageError| SceneError::BadImage(e.to_string());
        let header = image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format().map_err(|e| unreadable(e.into()))?;
        header.into_dimensions().map_err(unreadable)
    }

    /// An image from `width × height` pixels of `channels` bytes each (1: grey, 3: RGB,
    /// 4: RGBA, alpha dropped), row-major from the top row: `srgb` bytes are sRGB-encoded and
    /// decoded to linear light, others are linear (`byte / 255`), as OpenGL reads `GL_SRGB8`
    /// and `GL_RGB8` data.
    pub fn from_bytes(width: u32, height: u32, channels: usize, bytes: &[u8], srgb: bool) -> Result<Image, SceneError> {
        let level = |b: u8| if srgb { srgb_to_linear(b as f32 / 255.0) } else { b as f32 / 255.0 };
        Image::new(width, height, texels_of(width, height, channels, bytes, level)?)
    }

    /// An image from `width × height` pixels of `channels` linear floats each (1: grey, 3: RGB,
    /// 4: RGBA, alpha dropped), row-major from the top row.
    pub fn from_floats(width: u32, height: u32, channels: usize, floats: &[f32]) -> Result<Image, SceneError> {
        Image::new(width, height, texels_of(width, height, channels, floats, |f| f)?)
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.base.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.base.height
    }

    /// The texel in column `x`, row `y` (wrapping around).
    pub fn texel(&self, x: i64, y: i64) -> Vec3 {
        self.base.texel(x, y)
    }

    /// The coverage of the texel in column `x`, row `y` (wrapping around): 1 for an opaque
    /// image.
    pub fn alpha(&self, x: i64, y: i64) -> f32 {
        self.base.alpha(x, y)
    }

    /// Whether the image has coverage other than 1 somewhere.
    pub fn has_alpha(&self) -> bool {
        self.base.alpha.iter().any(|&a| a < 1.0)
    }

    /// How many levels its mip pyramid has: 1 for a single texel, 1 + log2 of the longer side,
    /// rounded down, otherwise.
    pub fn levels(&self) -> usize {
        pyramid_sizes(self.width(), self.height()).count()
    }

    /// Level `i` of the mip pyramid (the last for any `i` beyond it): level 0 is the image.
    /// The first call for a coarser level builds them all, on the build pool, while any other
    /// thread that asks waits (as rays wait for a lazily built tree, and for the same reason:
    /// see `builds`); each level is a box filter of the one before, colours weighted by their
    /// coverage, so that the colour of a cut-out's transparent texels does not bleed into
    /// its edges.
    pub fn level(&self, i: usize) -> &Level {
        if i == 0 {
            return &self.base;
        }
        let coarser = self.coarser.get_or_init(|| {
            let base = Arc::clone(&self.base);
            crate::builds::on_build_pool(move || pyramid(&base)).unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        });
        // A 1×1 image has no coarser level: the image itself is the last.
        coarser.get(i - 1).or(coarser.last()).unwrap_or(&self.base)
    }

    /// The tables that pick its texels by the light they bring, where it lights a scene as an
    /// equirectangular environment. Built by the first frame that needs them, on the build pool
    /// as the pyramid is, and kept with the image: every progressive pass and every frame
    /// prepares its lights, and built at each of them the tables of a 1024×512 image took
    /// 14 ms a pass (40 % of a 64×64 path-traced render's hundred passes on one thread).
    pub fn environment_tables(&self) -> &EnvironmentTables {
        self.environment.get_or_init(|| {
            let base = Arc::clone(&self.base);
            crate::builds::on_build_pool(move || EnvironmentTables::of(&base)).unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        })
    }
}

impl Level {
    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texel in column `x`, row `y` (wrapping around).
    #[inline]
    pub fn texel(&self, x: i64, y: i64) -> Vec3 {
        self.texels[self.index(x, y)]
    }

    /// The coverage of the texel in column `x`, row `y` (wrapping around): 1 for an opaque
    /// image.
    #[inline]
    pub fn alpha(&self, x: i64, y: i64) -> f32 {
        if self.alpha.is_empty() { 1.0 } else { self.alpha[self.index(x, y)] }
    }

    /// The index of texel `(x, y)`, wrapped into the level.
    #[inline]
    fn index(&self, x: i64, y: i64) -> usize {
        let (w, h) = (self.width as i64, self.height as i64);
        (y.rem_euclid(h) * w + x.rem_euclid(w)) as usize
    }

    /// The level half this one's size (rounded down, at least 1 texel): each of its texels the
    /// average of the part of this level it covers (a box filter; an odd size gives the texels
    /// on a boundary to both neighbours in part), colours weighted by their coverage.
    fn halved(&self) -> Level {
        let (width, height) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let (across, down) = (box_weights(self.width, width), box_weights(self.height, height));
        let opaque = self.alpha.is_empty();
        let mut texels = vec![Vec3::ZERO; width as usize * height as usize];
        let mut alpha = if opaque { Vec::new() } else { vec![0.0; texels.len()] };
        let row = |y: usize, texels: &mut [Vec3], mut alpha: Option<&mut [f32]>| {
            for (x, texel) in texels.iter_mut().enumerate() {
                let (mut colour, mut coverage, mut plain) = (Vec3::ZERO, 0.0, Vec3::ZERO);
                for &(sy, wy) in &down[y] {
                    for &(sx, wx) in &across[x] {
                        let i = sy as usize * self.width as usize + sx as usize;
                        let (w, c) = (wx * wy, self.texels[i]);
                        let a = if opaque { 1.0 } else { self.alpha[i] };
                        colour += c * (w * a);
                        coverage += w * a;
                        plain += c * w;
                    }
                }
                // Where every texel is transparent their colour is all there is.
                *texel = if coverage > 0.0 { colour / coverage } else { plain };
                if let Some(alpha) = alpha.as_deref_mut() {
                    alpha[x] = coverage.min(1.0);
                }
            }
        };
        let w = width as usize;
        if opaque {
            texels.par_chunks_mut(w).enumerate().for_each(|(y, texels)| row(y, texels, None));
        } else {
            texels.par_chunks_mut(w).zip(alpha.par_chunks_mut(w)).enumerate().for_each(|(y, (texels, alpha))| row(y, texels, Some(alpha)));
        }
        Level { width, height, texels, alpha }
    }
}

/// The coarser levels of the pyramid over `base` (see [`Image::level`]), each row of each level
/// a task.
fn pyramid(base: &Level) -> Vec<Level> {
    let mut levels: Vec<Level> = Vec::new();
    while levels.last().unwrap_or(base).width > 1 || levels.last().unwrap_or(base).height > 1 {
        let next = levels.last().unwrap_or(base).halved();
        levels.push(next);
    }
    levels
}

/// The sizes of the levels of the pyramid of a `width × height` image, from the image's own.
fn pyramid_sizes(width: u32, height: u32) -> impl Iterator<Item = (u32, u32)> {
    std::iter::successors(Some((width, height)), |&(w, h)| (w > 1 || h > 1).then(|| ((w / 2).max(1), (h / 2).max(1))))
}

/// For each of the `to` texels of an axis shrunk from `from` texels, the texels of `from` it
/// covers and the share of it each covers (summing to 1).
fn box_weights(from: u32, to: u32) -> Vec<Vec<(u32, f32)>> {
    let ratio = from as f64 / to as f64;
    (0..to)
        .map(|i| {
            let (start, end) = (i as f64 * ratio, (i + 1) as f64 * ratio);
            (start.floor() as u32..(end.ceil() as u32).min(from))
                .map(|s| (s, ((end.min(s as f64 + 1.0) - start.max(s as f64)) / ratio) as f32))
                .filter(|&(_, w)| w > 0.0)
                .collect()
        })
        .collect()
}

/// The texels of `width × height` pixels of `channels` values each (1, 3 or 4), each value
/// turned into linear light by `level`.
fn texels_of<T: Copy>(width: u32, height: u32, channels: usize, values: &[T], level: impl Fn(T) -> f32) -> Result<Vec<Vec3>, SceneError> {
    if !matches!(channels, 1 | 3 | 4) {
        return Err(SceneError::OutOfRange { field: "image channels", message: format!("{channels} is not 1 (grey), 3 (RGB) or 4 (RGBA)") });
    }
    let expected = width as usize * height as usize * channels;
    if values.len() != expected {
        return Err(SceneError::WrongLength { field: "pixels", got: values.len(), expected });
    }
    Ok(values
        .chunks_exact(channels)
        .map(|p| if channels == 1 { Vec3::splat(level(p[0])) } else { Vec3::new(level(p[0]), level(p[1]), level(p[2])) })
        .collect())
}

/// Decodes an sRGB-encoded value in `[0, 1]` to linear light (IEC 61966-2-1).
pub fn srgb_to_linear(encoded: f32) -> f32 {
    if encoded <= 0.040_45 { encoded / 12.92 } else { ((encoded + 0.055) / 1.055).powf(2.4) }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `image` encoded in `format`.
    fn encoded(image: &image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
        let mut bytes = std::io::Cursor::new(Vec::new());
        image.write_to(&mut bytes, format).unwrap();
        bytes.into_inner()
    }

    #[test]
    fn png_bytes_are_decoded_from_srgb_to_linear_light() {
        let rgba = image::RgbaImage::from_fn(3, 2, |x, y| image::Rgba([(x * 100) as u8, (y * 255) as u8, 188, 7]));
        let decoded = Image::decode(&encoded(&rgba.into(), image::ImageFormat::Png)).unwrap();
        assert_eq!((decoded.width(), decoded.height()), (3, 2));
        // sRGB 188 is linear 0.5 (to three digits); 255 is 1; alpha is dropped.
        let t = decoded.texel(2, 1);
        assert!((t.x - srgb_to_linear(200.0 / 255.0)).abs() < 1e-6 && t.y == 1.0 && (t.z - 0.5029).abs() < 1e-3, "{t}");
        assert_eq!(decoded.texel(0, 0).x, 0.0);
        // Alpha is kept as linear coverage.
        assert!((decoded.alpha(2, 1) - 7.0 / 255.0).abs() < 1e-6 && decoded.has_alpha());
    }

    #[test]
    fn radiance_hdr_bytes_keep_their_linear_values_beyond_one() {
        let hdr = image::Rgb32FImage::from_fn(4, 1, |x, _| image::Rgb([x as f32 * 2.0, 0.25, 10.0]));
        let decoded = Image::decode(&encoded(&hdr.into(), image::ImageFormat::Hdr)).unwrap();
        // Radiance's shared exponent keeps about 8 bits of each channel.
        for x in 0..4 {
            let t = decoded.texel(x, 0);
            assert!((t - Vec3::new(x as f32 * 2.0, 0.25, 10.0)).abs().max_element() < 0.05, "texel {x}: {t}");
        }
    }

    #[test]
    fn bytes_that_are_not_an_image_are_refused_with_a_reason() {
        let error = Image::decode(b"not an image at all").unwrap_err();
        assert!(matches!(&error, SceneError::BadImage(reason) if !reason.is_empty()), "{error}");
        assert!(matches!(Image::dimensions(b"not an image at all"), Err(SceneError::BadImage(_))));
    }

    #[test]
    fn dimensions_come_from_the_header_alone() {
        let png = encoded(&image::RgbImage::new(300, 20).into(), image::ImageFormat::Png);
        assert_eq!(Image::dimensions(&png), Ok((300, 20)));
        // The header is enough: the pixels may be cut off.
        assert_eq!(Image::dimensions(&png[..png.len() - 20]), Ok((300, 20)));
    }

    #[test]
    fn raw_pixels_follow_opengl_srgb_and_linear_formats() {
        let grey = Image::from_bytes(2, 1, 1, &[0, 255], false).unwrap();
        assert_eq!((grey.texel(0, 0), grey.texel(1, 0)), (Vec3::ZERO, Vec3::ONE));
        let srgb = Image::from_bytes(1, 1, 4, &[188, 188, 188, 0], true).unwrap();
        assert!((srgb.texel(0, 0) - Vec3::splat(0.5029)).abs().max_element() < 1e-3);
        let linear = Image::from_bytes(1, 1, 3, &[51, 102, 255], false).unwrap();
        assert_eq!(linear.texel(0, 0), Vec3::new(0.2, 0.4, 1.0));
        let floats = Image::from_floats(1, 2, 3, &[4.0, 5.0, 6.0, 0.0, 0.5, 1.0]).unwrap();
        assert_eq!((floats.texel(0, 0), floats.texel(0, 1)), (Vec3::new(4.0, 5.0, 6.0), Vec3::new(0.0, 0.5, 1.0)));
    }

    #[test]
    fn raw_pixels_of_the_wrong_size_or_value_are_refused() {
        assert!(matches!(Image::from_bytes(2, 2, 3, &[0; 11], true), Err(SceneError::WrongLength { field: "pixels", got: 11, expected: 12 })));
        assert!(matches!(Image::from_bytes(1, 1, 2, &[0; 2], true), Err(SceneError::OutOfRange { field: "image channels", .. })));
        assert!(matches!(Image::from_floats(0, 1, 3, &[]), Err(SceneError::OutOfRange { field: "image size", .. })));
        assert!(matches!(Image::from_floats(1, 1, 3, &[0.0, f32::NAN, 0.0]), Err(SceneError::NotFinite { field: "texels", index: 0 })));
        assert!(matches!(Image::from_floats(1, 1, 3, &[0.0, -1.0, 0.0]), Err(SceneError::NotFinite { field: "texels", index: 0 })));
    }

    #[test]
    fn the_pyramid_halves_down_to_one_texel_keeping_the_mean() {
        // 5 × 3: 2 × 1, then 1 × 1; an odd side shares its middle texel between two.
        let texels: Vec<Vec3> = (0..15).map(|i| Vec3::splat(i as f32)).collect();
        let mean = texels.iter().sum::<Vec3>() / 15.0;
        let image = Image::new(5, 3, texels).unwrap();
        assert_eq!(image.levels(), 3);
        let sizes: Vec<_> = (0..4).map(|i| (image.level(i).width(), image.level(i).height())).collect();
        assert_eq!(sizes, [(5, 3), (2, 1), (1, 1), (1, 1)], "levels past the last are the last");
        // Left half of 5 columns: columns 0, 1 and half of 2, over the three rows.
        let left = (0..3).map(|y| (y * 5) as f32 * 2.5 + 1.0 + 0.5 * 2.0).sum::<f32>() / 7.5;
        assert!((image.level(1).texel(0, 0).x - left).abs() < 1e-4, "{} vs {left}", image.level(1).texel(0, 0));
        assert!((image.level(2).texel(0, 0) - mean).abs().max_element() < 1e-4);
        // The pyramid is counted in the memory the image takes before it is built.
        let fresh = Image::new(5, 3, vec![Vec3::ONE; 15]).unwrap();
        assert_eq!(fresh.memory_bytes(), (15 + 2 + 1) * 12);
        assert_eq!(image.memory_bytes(), fresh.memory_bytes());
    }

    #[test]
    fn coarser_levels_weigh_colours_by_their_coverage() {
        // A red texel beside a transparent black one: half covered, and red, not dark red.
        let image = Image::new(2, 1, vec![Vec3::X, Vec3::ZERO]).unwrap().with_alpha(vec![1.0, 0.0]).unwrap();
        assert_eq!((image.level(1).texel(0, 0), image.level(1).alpha(0, 0)), (Vec3::X, 0.5));
        // All transparent: the plain average.
        let clear = Image::new(2, 1, vec![Vec3::X, Vec3::ZERO]).unwrap().with_alpha(vec![0.0, 0.0]).unwrap();
        assert_eq!((clear.level(1).texel(0, 0), clear.level(1).alpha(0, 0)), (Vec3::new(0.5, 0.0, 0.0), 0.0));
    }

    #[test]
    fn threads_that_meet_an_unbuilt_pyramid_share_one_build() {
        let image = Image::new(256, 256, (0..256 * 256).map(|i| Vec3::splat((i % 2) as f32)).collect()).unwrap();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
        let firsts: Vec<usize> = pool.install(|| (0..16).into_par_iter().map(|_| image.level(1) as *const Level as usize).collect());
        assert!(firsts.iter().all(|&p| p == firsts[0]), "one pyramid");
        // Alternating columns average to grey.
        assert!((image.level(1).texel(7, 9) - Vec3::splat(0.5)).abs().max_element() < 1e-6);
    }
}
