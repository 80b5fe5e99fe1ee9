//! The background: what rays that hit nothing see.

use glam::Vec3;
use raystage_kernel::{PACKET_SIZE, Ray};

/// Sky colours at the bottom of the gradient and straight up: sRGB (0.88, 0.92, 0.97) and
/// (0.42, 0.6, 0.88), in linear light.
const HORIZON: Vec3 = Vec3::new(0.748_414_1, 0.827_570_8, 0.933_106_84);
const ZENITH: Vec3 = Vec3::new(0.147_319, 0.318_546_78, 0.748_414_1);

/// Elevation (the `y` of the unit direction) where the sky gradient starts: a little below the
/// horizon, so that the gradient has no kink where a finite ground plane ends.
const GRADIENT_START: f32 = -0.2;

/// The colour (linear RGB) of a ray that hits nothing: a soft gradient from a pale horizon to a
/// blue zenith by the elevation of `dir` (any length). The gradient is a smoothstep, so it has
/// no visible band where it starts.
pub fn sky(dir: Vec3) -> Vec3 {
    sky_at(elevation(dir, 1.0 / dir.length()))
}

/// [`sky`] of the directions of up to a packet of `rays`, for the rays in `missed` (bit `k` for
/// `rays[k]`; the others get black): the same colours, their normalisations side by side.
pub fn skies(rays: &[Ray], missed: u32) -> [Vec3; PACKET_SIZE] {
    let mut length2 = [0.0f32; PACKET_SIZE];
    for (k, ray) in rays.iter().enumerate() {
        length2[k] = ray.dir.length_squared();
    }
    let rcp = raystage_kernel::reciprocal_sqrt8(length2);
    let mut out = [Vec3::ZERO; PACKET_SIZE];
    for (k, ray) in rays.iter().enumerate().filter(|(k, _)| missed & (1 << k) != 0) {
        out[k] = sky_at(elevation(ray.dir, rcp[k]));
    }
    out
}

/// The `y` of `dir` normalised, given the reciprocal of its length, as
/// `dir.normalize_or_zero().y` computes it (0 for a zero or infinite direction).
#[inline]
fn elevation(dir: Vec3, reciprocal_length: f32) -> f32 {
    if reciprocal_length.is_finite() && reciprocal_length > 0.0 { dir.y * reciprocal_length } else { 0.0 }
}

/// The sky's colour at `elevation` (see [`sky`]).
#[inline]
fn sky_at(elevation: f32) -> Vec3 {
    let s = ((elevation - GRADIENT_START) / (1.0 - GRADIENT_START)).clamp(0.0, 1.0);
    HORIZON.lerp(ZENITH, s * s * (3.0 - 2.0 * s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sky_brightens_towards_the_horizon() {
        let (up, level, down) = (sky(Vec3::Y), sky(Vec3::new(1.0, 0.0, -1.0)), sky(-Vec3::Y));
        assert!(down.x > level.x && level.x > up.x && up.z > up.x);
        assert_eq!((up, down), (ZENITH, HORIZON));
        let decoded = |c: [f32; 3]| Vec3::from_array(c).map(raystage_scene::srgb_to_linear);
        assert!((decoded([0.42, 0.6, 0.88]) - ZENITH).abs().max_element() < 1e-6);
        assert!((decoded([0.88, 0.92, 0.97]) - HORIZON).abs().max_element() < 1e-6);
        assert_eq!(sky(Vec3::new(0.0, -0.9, 0.1)), down, "the gradient stops below the horizon");
    }

    #[test]
    fn skies_of_a_packet_are_each_ray_s_sky_bit_for_bit() {
        let dirs = [Vec3::new(0.3, 0.2, -1.0), Vec3::Y, Vec3::new(1e-30, -1e-30, 0.0), Vec3::ZERO, Vec3::new(-2.0, 7.0, 0.5), Vec3::new(0.0, f32::INFINITY, 0.0)];
        let rays: Vec<Ray> = dirs.iter().map(|&d| Ray::new(Vec3::ZERO, d.normalize_or_zero().max(d))).chain(dirs.iter().map(|&d| Ray::new(Vec3::ONE, d))).take(PACKET_SIZE).collect();
        let missed = 0b1011_0111;
        let skies = skies(&rays, missed);
        for (k, ray) in rays.iter().enumerate() {
            let expected = if missed & (1 << k) != 0 { sky(ray.dir) } else { Vec3::ZERO };
            assert_eq!(skies[k].to_array().map(f32::to_bits), expected.to_array().map(f32::to_bits), "ray {k}: {:?}", ray.dir);
        }
    }
}
