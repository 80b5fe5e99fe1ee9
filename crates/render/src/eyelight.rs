//! Eye-light shading: the first-frame shader, lit by a light at the eye.
//!
//! Every surface is lit from the viewer's position, so brightness follows `|cos|` between the
//! surface normal and the ray and shapes read clearly with no lights, materials or shadow rays.
//! Colour identifies the geometry: triangles are taken in consecutive groups (one group per object
//! of a demo mesh) and each group gets a colour of its own. The full shading library replaces this
//! once the scene carries materials and lights.

use glam::Vec3;
use raystage_kernel::{Hit, geometric_normal};

use crate::srgb;

/// Brightness of a surface seen exactly edge-on, so that silhouettes stay visible.
const AMBIENT: f32 = 0.15;

/// Golden-ratio conjugate: stepping the hue by it keeps consecutive groups far apart on the colour
/// wheel however many groups there are.
const HUE_STEP: f32 = 0.618_034;

/// Base colour of the triangles from [`EyeLight::plain_from`] on: a light grey, in sRGB.
const PLAIN_SRGB: f32 = 0.8;

/// Sky colours (sRGB) at the bottom of the gradient and straight up.
const HORIZON_SRGB: [f32; 3] = [0.88, 0.92, 0.97];
const ZENITH_SRGB: [f32; 3] = [0.42, 0.6, 0.88];

/// Elevation (the `y` of the unit direction) where the sky gradient starts: a little below the
/// horizon, so that the gradient has no kink where a finite ground plane ends.
const GRADIENT_START: f32 = -0.2;

/// The eye-light shader and its palette.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EyeLight {
    /// Triangles `prim` with the same `prim / group_size` share a colour (must be non-zero).
    pub group_size: u32,
    /// Triangles with `prim >= plain_from` are light grey (a ground plane, say); `u32::MAX` for none.
    pub plain_from: u32,
}

impl EyeLight {
    /// The colour of a hit on triangle `triangle` (the vertices of `hit.prim`) by a ray with
    /// direction `dir` (any length): base colour × (0.15 + 0.85·|cos|), linear RGB.
    pub fn shade_hit(&self, dir: Vec3, hit: &Hit, triangle: &[Vec3; 3]) -> Vec3 {
        let normal = geometric_normal(triangle).normalize_or_zero();
        let cos = normal.dot(dir.normalize_or_zero()).abs();
        self.base_colour(hit.prim) * (AMBIENT + (1.0 - AMBIENT) * cos)
    }

    /// The base colour (linear RGB) of triangle `prim`.
    pub fn base_colour(&self, prim: u32) -> Vec3 {
        if prim >= self.plain_from {
            return Vec3::splat(srgb::decode(PLAIN_SRGB));
        }
        let hue = ((prim / self.group_size) as f32 * HUE_STEP).fract();
        hsv_to_srgb(hue, 0.55, 0.95).map(srgb::decode)
    }

    /// The colour (linear RGB) of a ray that hits nothing: a soft gradient from a pale horizon to
    /// a blue zenith, by the elevation of `dir` (any length). The gradient is a smoothstep, so
    /// it has no visible band where it starts.
    pub fn sky(&self, dir: Vec3) -> Vec3 {
        let s = ((dir.normalize_or_zero().y - GRADIENT_START) / (1.0 - GRADIENT_START)).clamp(0.0, 1.0);
        let horizon = Vec3::from_array(HORIZON_SRGB).map(srgb::decode);
        let zenith = Vec3::from_array(ZENITH_SRGB).map(srgb::decode);
        horizon.lerp(zenith, s * s * (3.0 - 2.0 * s))
    }
}

/// HSV (all in `[0, 1]`) to sRGB.
fn hsv_to_srgb(hue: f32, saturation: f32, value: f32) -> Vec3 {
    let channel = |n: f32| {
        let k = (n + hue * 6.0) % 6.0;
        value - value * saturation * k.min(4.0 - k).clamp(0.0, 1.0)
    };
    Vec3::new(channel(5.0), channel(3.0), channel(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPHERES: EyeLight = EyeLight { group_size: 10_000, plain_from: 1_000_000 };

    /// A triangle in the plane z = 5 with normal +z.
    const FACING: [Vec3; 3] = [Vec3::new(-1.0, -1.0, 5.0), Vec3::new(1.0, -1.0, 5.0), Vec3::new(0.0, 1.0, 5.0)];

    fn hit(prim: u32) -> Hit {
        Hit { t: 5.0, prim, u: 0.25, v: 0.25 }
    }

    #[test]
    fn a_head_on_hit_gets_the_full_base_colour() {
        let colour = SPHERES.shade_hit(Vec3::Z, &hit(3), &FACING);
        assert!((colour - SPHERES.base_colour(3)).abs().max_element() < 1e-6);
    }

    #[test]
    fn shading_follows_the_cosine_and_ignores_length_and_side() {
        let base = SPHERES.base_colour(0);
        let dir = Vec3::new(0.0, 3.0_f32.sqrt(), 1.0); // 60° from the normal: cos = 0.5.
        let expected = base * (0.15 + 0.85 * 0.5);
        for d in [dir, dir * 7.0, -dir] {
            assert!((SPHERES.shade_hit(d, &hit(0), &FACING) - expected).abs().max_element() < 1e-6, "{d}");
        }
    }

    #[test]
    fn a_grazing_hit_keeps_the_ambient_part() {
        let colour = SPHERES.shade_hit(Vec3::X, &hit(0), &FACING);
        assert!((colour - SPHERES.base_colour(0) * AMBIENT).abs().max_element() < 1e-6);
    }

    #[test]
    fn groups_share_a_colour_and_neighbours_differ() {
        assert_eq!(SPHERES.base_colour(0), SPHERES.base_colour(9_999));
        for group in 0..99 {
            let (a, b) = (SPHERES.base_colour(group * 10_000), SPHERES.base_colour((group + 1) * 10_000));
            assert!((a - b).abs().max_element() > 0.05, "groups {group} and {}", group + 1);
        }
    }

    #[test]
    fn the_plain_tail_is_light_grey() {
        let grey = SPHERES.base_colour(1_000_001);
        assert_eq!(grey, Vec3::splat(grey.x));
        assert_eq!(srgb::encode(grey.x), (PLAIN_SRGB * 255.0).round() as u8);
    }

    #[test]
    fn the_sky_brightens_towards_the_horizon() {
        let (up, level, down) = (SPHERES.sky(Vec3::Y), SPHERES.sky(Vec3::new(1.0, 0.0, -1.0)), SPHERES.sky(-Vec3::Y));
        assert!(down.x > level.x && level.x > up.x && up.z > up.x);
        assert_eq!(up, Vec3::from_array(ZENITH_SRGB).map(srgb::decode));
        assert_eq!(down, Vec3::from_array(HORIZON_SRGB).map(srgb::decode));
        assert_eq!(SPHERES.sky(Vec3::new(0.0, -0.9, 0.1)), down, "the gradient stops below the horizon");
    }

    #[test]
    fn hsv_primaries() {
        assert_eq!(hsv_to_srgb(0.0, 1.0, 1.0), Vec3::X);
        assert_eq!(hsv_to_srgb(1.0 / 3.0, 1.0, 1.0), Vec3::Y);
        assert_eq!(hsv_to_srgb(2.0 / 3.0, 1.0, 1.0), Vec3::Z);
    }
}
