//! How wide a lookup's share of a pixel is where a ray meets a textured surface: the width
//! that image textures are filtered over (see `Sampler::image`), so that a texture seen from afar
//! averages its texels instead of aliasing.
//!
//! As pbrt-v4 does for every ray (its `Camera::Approximate_dp_dxy`), the footprint is the
//! pixel's as the camera sees the point, whichever path reached it: exact for camera rays,
//! a fair guess after a bounce, and free of any state carried along the path. Seen at a slant
//! the footprint stretches across the surface by 1 / cos along one axis; an isotropic filter
//! takes the longer axis, as GPUs' trilinear filtering does (the geometric mean of the two
//! leaves a floor's far checks in rings of moiré), blurring across it instead. And since a pixel's own samples already average
//! over its area, the footprint shrinks with the samples per pixel, as pbrt-v4's does: by
//! 1 / √spp, down to an eighth of a pixel.

use glam::Vec3;
use raystage_scene::CameraRays;

/// The slant past which a footprint stretches no further (about 89.1°): the stretch 1 / cos
/// stays below 64 instead of growing without bound along silhouettes.
const MIN_COS: f32 = 1.0 / 64.0;

/// The smallest share of a pixel a footprint is scaled to, however many samples it takes.
const MIN_SCALE: f32 = 0.125;

/// The pixel footprint of a frame's camera (see the module's documentation).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PixelFootprint {
    rays: CameraRays,
    scale: f32,
}

impl PixelFootprint {
    /// The footprint of the camera `rays` of a frame of `samples_per_pixel` samples.
    pub fn new(rays: CameraRays, samples_per_pixel: u32) -> PixelFootprint {
        PixelFootprint { rays, scale: (1.0 / (samples_per_pixel.max(1) as f32).sqrt()).max(MIN_SCALE) }
    }

    /// The footprint's width in the world at `position` on a surface of normal `normal` (of any
    /// length, facing either way).
    pub fn width(&self, position: Vec3, normal: Vec3) -> f32 {
        let (pixel, towards) = self.rays.pixel_footprint(position);
        let cos = normal.normalize_or_zero().dot(towards).abs().max(MIN_COS);
        pixel * self.scale / cos
    }

    /// The footprint's width in each set of texture coordinates, given how many units of each
    /// one unit of world length spans there (`density`, see `Frame::texture_density`); 0 (a
    /// point: the image itself) where that is not known.
    pub fn in_texture(&self, position: Vec3, normal: Vec3, density: impl Fn(usize) -> Option<f32>) -> [f32; 2] {
        let width = self.width(position, normal);
        [0, 1].map(|set| density(set).map_or(0.0, |d| width * d))
    }
}

#[cfg(test)]
mod tests {
    use raystage_scene::Camera;

    use super::*;

    /// A camera 90° across 100 pixels: a pixel is 2 / 100 wide at distance 1.
    fn footprint(samples: u32) -> PixelFootprint {
        let camera = Camera::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0).unwrap();
        PixelFootprint::new(camera.rays(100, 100), samples)
    }

    #[test]
    fn a_footprint_grows_with_distance_and_slant_and_shrinks_with_samples() {
        let (one, ahead) = (footprint(1), Vec3::new(0.0, 0.0, -1.0));
        assert!((one.width(ahead * 10.0, Vec3::Z) - 0.2).abs() < 1e-5);
        // Twice as far, twice as wide; either side of the surface alike.
        assert!((one.width(ahead * 20.0, -Vec3::Z) - 0.4).abs() < 1e-5);
        // At 60°, stretched by 1 / cos = 2.
        let slanted = Vec3::new(0.0, (60f32).to_radians().sin(), (60f32).to_radians().cos());
        assert!((one.width(ahead * 10.0, slanted) - 0.4).abs() < 1e-5);
        // Edge-on, bounded.
        assert!((one.width(ahead * 10.0, Vec3::Y) - 0.2 * 64.0).abs() < 1e-3);
        // 16 samples: a quarter; 1024: an eighth, no less.
        assert!((footprint(16).width(ahead * 10.0, Vec3::Z) - 0.05).abs() < 1e-6);
        assert!((footprint(1024).width(ahead * 10.0, Vec3::Z) - 0.025).abs() < 1e-6);
        // In texture coordinates, by each set's density; none where it is unknown.
        let [first, second] = one.in_texture(ahead * 10.0, Vec3::Z, |set| (set == 1).then_some(5.0));
        assert!(first == 0.0 && (second - 1.0).abs() < 1e-5, "{first}, {second}");
    }
}
