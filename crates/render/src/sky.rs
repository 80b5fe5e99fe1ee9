//! The background: what rays that hit nothing see.

use glam::Vec3;

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
    let s = ((dir.normalize_or_zero().y - GRADIENT_START) / (1.0 - GRADIENT_START)).clamp(0.0, 1.0);
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
}
