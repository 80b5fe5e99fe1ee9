//! How shaders sample image textures, as glTF's samplers say: wrap modes, magnification filter,
//! texture coordinate set, `KHR_texture_transform` and mipmapped minification. Shading (in the renderer) and the
//! frame's alpha test both sample through it.

use glam::{Affine2, Mat2, Vec2, Vec4};

use crate::shader::{ParamValue, Shader};
use crate::texture::{Image, Level};

/// How texture coordinates outside [0, 1] find a texel along one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles the plane.
    Repeat,
    /// The edge texels extend outwards.
    Clamp,
    /// The image tiles the plane, every other copy mirrored.
    Mirror,
}

impl Wrap {
    /// The wrap mode of a glTF (OpenGL) code; repeat, glTF's default, for any other.
    fn of_code(code: f32) -> Wrap {
        match code as u32 {
            33071 => Wrap::Clamp,
            33648 => Wrap::Mirror,
            _ => Wrap::Repeat,
        }
    }

    /// Texel index `i` of an axis of `n` texels, brought into `0..n`.
    #[inline(always)]
    fn index(self, i: i64, n: i64) -> i64 {
        match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m < n { m } else { 2 * n - 1 - m }
            }
        }
    }
}

/// How a shader samples one of its textures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampler {
    /// Wrap modes across u and v.
    pub wrap: [Wrap; 2],
    /// Nearest texel rather than bilinear magnification.
    pub nearest: bool,
    /// Which texture coordinates: 0 the mesh's first set, 1 its second.
    pub set: usize,
    /// The map of texture coordinates before the lookup (`None`: identity).
    pub transform: Option<Affine2>,
}

impl Sampler {
    /// glTF's default: repeat, bilinear, first coordinates, untransformed.
    pub const DEFAULT: Sampler = Sampler { wrap: [Wrap::Repeat; 2], nearest: false, set: 0, transform: None };

    /// The sampler of texture slot `slot` of `shader` (its `{slot}_wrap_s`, `_wrap_t`,
    /// `_filter`, `_texcoord` and transform parameters); the default for a class without them.
    pub fn of(shader: &Shader, slot: &str) -> Sampler {
        let param = |name: &str, default: f32| match shader.get(&format!("{slot}_{name}")) {
            Some(ParamValue::Float(f)) => f,
            _ => default,
        };
        let (offset, rotation) = (Vec2::new(param("offset_u", 0.0), param("offset_v", 0.0)), param("rotation", 0.0));
        let scale = Vec2::new(param("scale_u", 1.0), param("scale_v", 1.0));
        // KHR_texture_transform: scale, then rotate, then offset. Its rotation turns u towards
        // −v (counter-clockwise with v pointing down the image).
        let (sin, cos) = rotation.sin_cos();
        let turn = Mat2::from_cols(Vec2::new(cos, -sin), Vec2::new(sin, cos));
        let transform = Affine2::from_mat2_translation(turn * Mat2::from_diagonal(scale), offset);
        Sampler {
            wrap: [Wrap::of_code(param("wrap_s", 10497.0)), Wrap::of_code(param("wrap_t", 10497.0))],
            nearest: param("filter", 9729.0) == 9728.0,
            set: param("texcoord", 0.0) as usize,
            transform: (transform != Affine2::IDENTITY).then_some(transform),
        }
    }
}

impl Sampler {
    /// The texture coordinates this sampler reads of a point with the mesh's sets `uvs` (where
    /// it has them), transformed.
    #[inline(always)]
    pub fn uv(&self, uvs: [Option<Vec2>; 2]) -> Option<Vec2> {
        uvs[self.set.min(1)].map(|uv| self.transform.map_or(uv, |t| t.transform_point2(uv)))
    }

    /// Colour and coverage of `image` at `uv`, `(0, 0)` its top-left corner, for a lookup whose
    /// footprint is `footprint` wide in the mesh's texture coordinates (before this sampler's
    /// transform; 0 for a point): where a texel is smaller than the footprint, the mip level
    /// whose texels are as wide as it, blended with the next (trilinear filtering, as GPUs and
    /// pbrt do), so that a texture seen from afar averages its texels instead of aliasing;
    /// otherwise the image itself by the magnification filter. The footprint is isotropic, the
    /// longer side of the image sets the level (a footprint of one texel along the denser axis),
    /// and glTF's minification filter is not read: every minified lookup is trilinear.
    #[inline]
    pub fn image(&self, image: &Image, uv: Vec2, footprint: f32) -> Vec4 {
        // Texels across the footprint, along the image's longer side (the transform scales
        // coordinates by the square root of its determinant on average).
        let stretch = self.transform.map_or(1.0, |t| t.matrix2.determinant().abs().sqrt());
        let texels = footprint * stretch * image.width().max(image.height()) as f32;
        let lod = texels.log2();
        // A footprint that is not a number reads the image itself.
        if lod.is_nan() || lod <= 0.0 {
            return filtered(image.level(0), self, uv);
        }
        let last = image.levels() - 1;
        let fine = (lod.floor() as usize).min(last);
        let blend = if fine == last { 0.0 } else { lod - lod.floor() };
        let linear = Sampler { nearest: false, ..*self };
        let near = filtered(image.level(fine), &linear, uv);
        if blend == 0.0 { near } else { near.lerp(filtered(image.level(fine + 1), &linear, uv), blend) }
    }
}

/// Colour and coverage of `level` at `uv`, `(0, 0)` its top-left corner, by the sampler's
/// filter and wrap modes.
fn filtered(level: &Level, sampler: &Sampler, uv: Vec2) -> Vec4 {
    let (w, h) = (level.width() as i64, level.height() as i64);
    let [wrap_s, wrap_t] = sampler.wrap;
    let texel = |x: i64, y: i64| {
        let (x, y) = (wrap_s.index(x, w), wrap_t.index(y, h));
        level.texel(x, y).extend(level.alpha(x, y))
    };
    let x = uv.x * w as f32;
    let y = uv.y * h as f32;
    if sampler.nearest {
        // Saturating casts: coordinates beyond i64 land on an edge texel, never wrap unsoundly.
        return texel(x.floor() as i64, y.floor() as i64);
    }
    let (x, y) = (x - 0.5, y - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as i64, y0 as i64);
    let top = texel(x0, y0).lerp(texel(x0.saturating_add(1), y0), fx);
    let bottom = texel(x0, y0.saturating_add(1)).lerp(texel(x0.saturating_add(1), y0.saturating_add(1)), fx);
    top.lerp(bottom, fy)
}

/// A 32-bit integer hash (the lowbias32 finaliser): well-mixed bits for decisions that must be
/// random-looking yet repeatable (the renderer's sample sequences, BLEND's coverage coin).
#[inline]
pub const fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    /// Columns alternating black and white, 64 × 64: grey from level 1 on.
    fn stripes() -> Image {
        Image::new(64, 64, (0..64 * 64).map(|i| Vec3::splat((i % 2) as f32)).collect()).unwrap()
    }

    #[test]
    fn a_footprint_of_a_texel_or_less_reads_the_image_and_wider_ones_its_pyramid() {
        let (image, s) = (stripes(), Sampler { nearest: true, ..Sampler::DEFAULT });
        // The centre of texel 3 (white): a point, and a footprint of one texel.
        let uv = Vec2::new(3.5, 10.5) / 64.0;
        assert_eq!(s.image(&image, uv, 0.0).x, 1.0);
        assert_eq!(s.image(&image, uv, 1.0 / 64.0).x, 1.0);
        // Two texels: level 1, grey; 1.5 texels: half way between white and grey.
        assert!((s.image(&image, uv, 2.0 / 64.0).x - 0.5).abs() < 1e-6);
        let between = s.image(&image, uv, 2f32.powf(0.5) / 64.0).x;
        assert!((between - 0.75).abs() < 1e-5, "{between}");
        // Wider than the image: its mean, never past the last level.
        assert!((s.image(&image, uv, 1e6).x - 0.5).abs() < 1e-6);
        // Not a number: the image itself.
        assert_eq!(s.image(&image, uv, f32::NAN).x, 1.0);
    }

    #[test]
    fn a_texture_transform_that_magnifies_the_texture_shrinks_the_footprint() {
        let image = stripes();
        let mut shader = Shader::new("PhysicallyBased").unwrap();
        for (name, value) in [("scale_u", 0.25), ("scale_v", 0.25), ("filter", 9728.0)] {
            shader.set(&format!("base_color_{name}"), ParamValue::Float(value)).unwrap();
        }
        let s = Sampler::of(&shader, "base_color");
        // Four texels of footprint before the transform, one after it: the image itself (the
        // centre of texel 3, white).
        let uv = s.uv([Some(Vec2::new(14.0, 42.0) / 64.0), None]).unwrap();
        assert_eq!(s.image(&image, uv, 4.0 / 64.0).x, 1.0);
        assert!((Sampler { transform: None, ..s }.image(&image, uv, 4.0 / 64.0).x - 0.5).abs() < 1e-6);
    }
}
