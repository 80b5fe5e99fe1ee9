//! Evaluating the scene's textures at a surface point, sampled as glTF's samplers say: wrap
//! modes, magnification filter, texture coordinate set and `KHR_texture_transform`.

use glam::{Affine2, Mat2, Vec2, Vec3, Vec4};
use raystage_scene::{Image, Shader, Texture};

use crate::sampler::hash;

/// How texture coordinates outside [0, 1] find a texel along one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Wrap {
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
pub(crate) struct Sampler {
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
    #[cfg(test)]
    pub const DEFAULT: Sampler = Sampler { wrap: [Wrap::Repeat; 2], nearest: false, set: 0, transform: None };

    /// The sampler of texture slot `slot` of `shader` (its `{slot}_wrap_s`, `_wrap_t`,
    /// `_filter`, `_texcoord` and transform parameters); the default for a class without them.
    pub fn of(shader: &Shader, slot: &str) -> Sampler {
        let param = |name: &str, default: f32| match shader.get(&format!("{slot}_{name}")) {
            Some(raystage_scene::ParamValue::Float(f)) => f,
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

/// The colour and coverage (alpha) of `texture` sampled by `sampler` at a point with
/// object-space position `p` and the mesh's texture coordinate sets `uvs` (where it has them;
/// coordinates it lacks read as 0, 0). Procedural textures are opaque.
pub(crate) fn sample(texture: &Texture, sampler: &Sampler, p: Vec3, uvs: [Option<Vec2>; 2]) -> Vec4 {
    let uv = uvs[sampler.set.min(1)].map(|uv| sampler.transform.map_or(uv, |t| t.transform_point2(uv)));
    match texture {
        Texture::Checker { a, b, scale } => {
            let q = match uv {
                Some(uv) => (uv * *scale).floor().extend(0.0),
                None => (p * *scale).floor(),
            };
            (if (q.x + q.y + q.z).rem_euclid(2.0) < 1.0 { *a } else { *b }).extend(1.0)
        }
        Texture::Noise { a, b, scale } => {
            // Turbulence: four octaves of gradient noise, remapped to [0, 1].
            let mut sum = 0.0;
            let (mut freq, mut amp) = (*scale, 0.5);
            for _ in 0..4 {
                sum += amp * perlin(p * freq);
                freq *= 2.0;
                amp *= 0.5;
            }
            a.lerp(*b, (0.5 + 0.5 * sum * 1.4).clamp(0.0, 1.0)).extend(1.0)
        }
        Texture::Image(image) => filtered(image, sampler, uv.unwrap_or(Vec2::ZERO)),
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

/// Perlin's improved gradient noise in about [−1, 1], with a hashed lattice.
fn perlin(p: Vec3) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let (ix, iy, iz) = (cell.x as i32, cell.y as i32, cell.z as i32);
    let grad = |dx: i32, dy: i32, dz: i32| {
        let h = hash(hash(hash((ix + dx) as u32) ^ (iy + dy) as u32) ^ (iz + dz) as u32) % 12;
        let g = [
            Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, 0.0, 1.0), Vec3::new(-1.0, 0.0, 1.0), Vec3::new(1.0, 0.0, -1.0), Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, 1.0), Vec3::new(0.0, -1.0, 1.0), Vec3::new(0.0, 1.0, -1.0), Vec3::new(0.0, -1.0, -1.0),
        ][h as usize];
        g.dot(f - Vec3::new(dx as f32, dy as f32, dz as f32))
    };
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    lerp(
        lerp(lerp(grad(0, 0, 0), grad(1, 0, 0), u), lerp(grad(0, 1, 0), grad(1, 1, 0), u), v),
        lerp(lerp(grad(0, 0, 1), grad(1, 0, 1), u), lerp(grad(0, 1, 1), grad(1, 1, 1), u), v),
        w,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The colour of `texture` at `p`, `uv`, sampled as glTF's default sampler does.
    fn lookup(texture: &Texture, p: Vec3, uv: Option<Vec2>) -> Vec3 {
        sample(texture, &Sampler::DEFAULT, p, [uv, None]).truncate()
    }

    #[test]
    fn checker_alternates() {
        let t = Texture::Checker { a: Vec3::ZERO, b: Vec3::ONE, scale: 1.0 };
        assert_eq!(lookup(&t, Vec3::new(0.5, 0.5, 0.5), None), Vec3::ZERO);
        assert_eq!(lookup(&t, Vec3::new(1.5, 0.5, 0.5), None), Vec3::ONE);
        assert_eq!(lookup(&t, Vec3::ZERO, Some(Vec2::new(0.5, 1.5))), Vec3::ONE);
    }

    #[test]
    fn noise_is_smooth_and_bounded() {
        let t = Texture::Noise { a: Vec3::ZERO, b: Vec3::ONE, scale: 3.0 };
        let mut prev = lookup(&t, Vec3::ZERO, None).x;
        let mut distinct = false;
        for i in 1..200 {
            let v = lookup(&t, Vec3::new(i as f32 * 0.001, 0.3, 0.7), None).x;
            assert!((0.0..=1.0).contains(&v));
            assert!((v - prev).abs() < 0.05, "noise jumps at {i}");
            distinct |= v != prev;
            prev = v;
        }
        assert!(distinct);
    }

    #[test]
    fn images_wrap_and_filter() {
        let img = Image::new(2, 1, vec![Vec3::ZERO, Vec3::ONE]).unwrap();
        let t = Texture::Image(std::sync::Arc::new(img));
        assert_eq!(lookup(&t, Vec3::ZERO, Some(Vec2::new(0.25, 0.5))), Vec3::ZERO);
        assert_eq!(lookup(&t, Vec3::ZERO, Some(Vec2::new(0.75, 0.5))), Vec3::ONE);
        assert!((lookup(&t, Vec3::ZERO, Some(Vec2::new(0.5, 0.5))) - Vec3::splat(0.5)).length() < 1e-6);
    }

    /// A 4×1 ramp 0, 1/3, 2/3, 1, sampled by `sampler` at `u` (v mid-image).
    fn ramp(sampler: Sampler, u: f32) -> f32 {
        let img = Image::new(4, 1, (0..4).map(|i| Vec3::splat(i as f32 / 3.0)).collect()).unwrap();
        sample(&Texture::Image(img.into()), &sampler, Vec3::ZERO, [Some(Vec2::new(u, 0.5)), None]).x
    }

    #[test]
    fn wrap_modes_repeat_clamp_and_mirror() {
        let nearest = |wrap| Sampler { wrap: [wrap, Wrap::Repeat], nearest: true, ..Sampler::DEFAULT };
        // u = 1.125 is texel 4: the first again, the last clamped, the last mirrored.
        assert_eq!(ramp(nearest(Wrap::Repeat), 1.125), 0.0);
        assert_eq!(ramp(nearest(Wrap::Clamp), 1.125), 1.0);
        assert_eq!(ramp(nearest(Wrap::Mirror), 1.125), 1.0);
        // u = 1.375 (texel 5): the second, the last, the third.
        assert_eq!(ramp(nearest(Wrap::Repeat), 1.375), 1.0 / 3.0);
        assert_eq!(ramp(nearest(Wrap::Clamp), 1.375), 1.0);
        assert_eq!(ramp(nearest(Wrap::Mirror), 1.375), 2.0 / 3.0);
        // Far negative coordinates too.
        assert_eq!(ramp(nearest(Wrap::Clamp), -7.0), 0.0);
        assert_eq!(ramp(nearest(Wrap::Mirror), -0.125), 0.0);
    }

    #[test]
    fn nearest_keeps_texels_where_bilinear_blends_them() {
        // A quarter texel past the centre of texel 1 (u = 0.375 + 0.0625).
        let u = 0.4375;
        assert_eq!(ramp(Sampler { nearest: true, ..Sampler::DEFAULT }, u), 1.0 / 3.0);
        assert!((ramp(Sampler::DEFAULT, u) - (1.0 / 3.0 + 0.25 / 3.0)).abs() < 1e-6);
        // Clamped bilinear at the edge does not blend in the far side.
        let clamp = Sampler { wrap: [Wrap::Clamp; 2], ..Sampler::DEFAULT };
        assert_eq!(ramp(clamp, 0.999), 1.0);
        assert!(ramp(Sampler::DEFAULT, 0.999) < 0.6, "repeat blends the first texel in");
    }

    #[test]
    fn texture_transforms_follow_khr_texture_transform() {
        let mut shader = Shader::new("PhysicallyBased").unwrap();
        // The extension's own example: the lower-left quadrant, turned a quarter clockwise.
        for (name, value) in [("offset_u", 0.0), ("offset_v", 1.0), ("rotation", std::f32::consts::FRAC_PI_2), ("scale_u", 0.5), ("scale_v", 0.5)] {
            shader.set(&format!("base_color_{name}"), raystage_scene::ParamValue::Float(value)).unwrap();
        }
        let t = Sampler::of(&shader, "base_color").transform.unwrap();
        for (uv, expected) in [((0.0, 0.0), (0.0, 1.0)), ((1.0, 0.0), (0.0, 0.5)), ((1.0, 1.0), (0.5, 0.5)), ((0.0, 1.0), (0.5, 1.0))] {
            let got = t.transform_point2(Vec2::from(uv));
            assert!((got - Vec2::from(expected)).length() < 1e-6, "{uv:?} → {got}, not {expected:?}");
        }
        assert_eq!(Sampler::of(&Shader::new("PhysicallyBased").unwrap(), "base_color"), Sampler::DEFAULT);
        // The second coordinate set, and a class without samplers.
        shader.set("base_color_texcoord", raystage_scene::ParamValue::Float(1.0)).unwrap();
        let second = Sampler { transform: None, ..Sampler::of(&shader, "base_color") };
        let img = Image::new(2, 1, vec![Vec3::ZERO, Vec3::ONE]).unwrap();
        let at = |s: &Sampler| sample(&Texture::Image(img.clone().into()), s, Vec3::ZERO, [Some(Vec2::new(0.25, 0.5)), Some(Vec2::new(0.75, 0.5))]).x;
        assert_eq!((at(&Sampler::DEFAULT), at(&second)), (0.0, 1.0));
        assert_eq!(Sampler::of(&Shader::new("Diffuse").unwrap(), "diffuse"), Sampler::DEFAULT);
    }
}
