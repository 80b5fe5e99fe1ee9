//! How shaders sample image textures, as glTF's samplers say: wrap modes, magnification filter,
//! texture coordinate set and `KHR_texture_transform`. Shading (in the renderer) and the
//! frame's alpha test both sample through it.

use glam::{Affine2, Mat2, Vec2, Vec4};

use crate::shader::{ParamValue, Shader};
use crate::texture::Image;

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

    /// Colour and coverage of `image` at `uv`, `(0, 0)` its top-left corner.
    #[inline]
    pub fn image(&self, image: &Image, uv: Vec2) -> Vec4 {
        filtered(image, self, uv)
    }
}

/// Colour and coverage of `image` at `uv`, `(0, 0)` its top-left corner, by the sampler's filter
/// and wrap modes.
fn filtered(image: &Image, sampler: &Sampler, uv: Vec2) -> Vec4 {
    let (w, h) = (image.width() as i64, image.height() as i64);
    let [wrap_s, wrap_t] = sampler.wrap;
    let texel = |x: i64, y: i64| {
        let (x, y) = (wrap_s.index(x, w), wrap_t.index(y, h));
        image.texel(x, y).extend(image.alpha(x, y))
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
pub fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}
