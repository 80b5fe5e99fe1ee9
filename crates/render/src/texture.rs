//! Evaluating the scene's textures at a surface point, sampled as glTF's samplers say: wrap
//! modes, magnification filter, texture coordinate set and `KHR_texture_transform`.

use glam::{Vec2, Vec3, Vec4};
use raystage_scene::{Sampler, Texture};

use crate::sampler::hash;

/// The colour and coverage (alpha) of `texture` sampled by `sampler` at a point with
/// object-space position `p` and the mesh's texture coordinate sets `uvs` (where it has them;
/// coordinates it lacks read as 0, 0), for a lookup `footprint` wide in each set (images are
/// filtered over it, see `Sampler::image`). Procedural textures are opaque.
pub(crate) fn sample(texture: &Texture, sampler: &Sampler, p: Vec3, uvs: [Option<Vec2>; 2], footprint: [f32; 2]) -> Vec4 {
    let uv = sampler.uv(uvs);
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
        Texture::Image(image) => sampler.image(image, uv.unwrap_or(Vec2::ZERO), footprint[sampler.set.min(1)]),
    }
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
    use raystage_scene::{Image, Shader, Wrap};

    use super::*;

    /// The colour of `texture` at `p`, `uv`, sampled as glTF's default sampler does.
    fn lookup(texture: &Texture, p: Vec3, uv: Option<Vec2>) -> Vec3 {
        sample(texture, &Sampler::DEFAULT, p, [uv, None], [0.0; 2]).truncate()
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
        sample(&Texture::Image(img.into()), &sampler, Vec3::ZERO, [Some(Vec2::new(u, 0.5)), None], [0.0; 2]).x
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
        let at = |s: &Sampler| sample(&Texture::Image(img.clone().into()), s, Vec3::ZERO, [Some(Vec2::new(0.25, 0.5)), Some(Vec2::new(0.75, 0.5))], [0.0; 2]).x;
        assert_eq!((at(&Sampler::DEFAULT), at(&second)), (0.0, 1.0));
        assert_eq!(Sampler::of(&Shader::new("Diffuse").unwrap(), "diffuse"), Sampler::DEFAULT);
    }
}
