//! Evaluating the scene's textures at a surface point.

use glam::{Vec2, Vec3};
use raystage_scene::{Image, Texture};

use crate::sampler::hash;

/// The colour of `texture` at a point with object-space position `p` and texture coordinates
/// `uv` (if the mesh has them).
pub(crate) fn lookup(texture: &Texture, p: Vec3, uv: Option<Vec2>) -> Vec3 {
    match texture {
        Texture::Checker { a, b, scale } => {
            let q = match uv {
                Some(uv) => (uv * *scale).floor().extend(0.0),
                None => (p * *scale).floor(),
            };
            if (q.x + q.y + q.z).rem_euclid(2.0) < 1.0 { *a } else { *b }
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
            a.lerp(*b, (0.5 + 0.5 * sum * 1.4).clamp(0.0, 1.0))
        }
        Texture::Image(image) => bilinear(image, uv.unwrap_or(Vec2::ZERO)),
    }
}

/// Bilinear lookup with wrapping; `(0, 0)` is the top-left corner of the image.
fn bilinear(image: &Image, uv: Vec2) -> Vec3 {
    let x = uv.x * image.width() as f32 - 0.5;
    let y = uv.y * image.height() as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as i64, y0 as i64);
    let top = image.texel(x0, y0).lerp(image.texel(x0 + 1, y0), fx);
    let bottom = image.texel(x0, y0 + 1).lerp(image.texel(x0 + 1, y0 + 1), fx);
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
}
