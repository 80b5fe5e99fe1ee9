//! A neutral studio environment, made in code: the light glTF viewers (the Khronos sample viewer,
//! model-viewer, three.js's room environment) give a file that brings no lights of its own, so
//! that a model looks as its author saw it without anything to download.
//!
//! It is a latitude-longitude image in the renderer's orientation (the top row straight up, the
//! middle column towards −z, +x a quarter turn to the right of it): a soft grey dome over a darker
//! floor, and four white softboxes — a key light up and to the front right of a model seen from
//! +z (glTF's front), a dimmer fill to the front left, a rim light behind and a panel overhead —
//! whose reflections show the shape of glossy and metallic surfaces. Everything is grey, so it
//! adds no colour cast, and the image is scaled so that its mean radiance over the sphere is 1:
//! a model is about as bright as under a uniform environment of radiance 1.

use std::f32::consts::{PI, TAU};

use glam::Vec3;

use crate::texture::Image;

/// Texels of the image: fine enough that softbox edges stay clean in mirror reflections.
const SIZE: (u32, u32) = (256, 128);

/// A softbox: a rectangle of directions, `width × height` degrees of azimuth and elevation
/// centred on (`azimuth`, `elevation`) (azimuth 0 towards −z, 90 towards +x), of `radiance`
/// relative to the dome, its edges softened over `soft` degrees.
struct Softbox {
    azimuth: f32,
    elevation: f32,
    width: f32,
    height: f32,
    radiance: f32,
    soft: f32,
}

/// Key, fill, rim and top, as a photographer sets a product shot. With the dome, a surface
/// facing the front (+z) receives 1.4 times the irradiance of a uniform environment of the same
/// mean, one facing up 1.7 times, the sides about 1, the back 0.8 and the floor's 0.3.
const SOFTBOXES: [Softbox; 4] = [
    Softbox { azimuth: 135.0, elevation: 35.0, width: 40.0, height: 30.0, radiance: 8.0, soft: 6.0 },
    Softbox { azimuth: -135.0, elevation: 20.0, width: 40.0, height: 25.0, radiance: 4.0, soft: 8.0 },
    Softbox { azimuth: -20.0, elevation: 30.0, width: 30.0, height: 20.0, radiance: 6.0, soft: 5.0 },
    Softbox { azimuth: 0.0, elevation: 90.0, width: 360.0, height: 30.0, radiance: 1.5, soft: 10.0 },
];

/// How bright the dome is at `elevation` degrees: a lighter ceiling, walls a little darker
/// towards the horizon, and a floor that bounces some light back, curving into the walls as a
/// photographer's cyclorama does (no hard horizon behind a model).
fn dome(elevation: f32) -> f32 {
    let wall = 0.6 + 0.1 * (elevation.max(0.0) / 90.0);
    let floor = 0.4 - 0.1 * (-elevation).max(0.0) / 90.0;
    let t = ((elevation + 20.0) / 30.0).clamp(0.0, 1.0);
    floor + (wall - floor) * t * t * (3.0 - 2.0 * t)
}

/// 1 inside `[-half, half]`, 0 beyond `half + soft`, smooth between.
fn window(offset: f32, half: f32, soft: f32) -> f32 {
    let t = ((offset.abs() - half) / soft).clamp(0.0, 1.0);
    1.0 - t * t * (3.0 - 2.0 * t)
}

impl Softbox {
    /// How much of the softbox's light comes from (`azimuth`, `elevation`), in degrees.
    fn at(&self, azimuth: f32, elevation: f32) -> f32 {
        // The shorter way round the azimuth circle.
        let turn = (azimuth - self.azimuth + 540.0).rem_euclid(360.0) - 180.0;
        let across = if self.width >= 360.0 { 1.0 } else { window(turn, self.width / 2.0, self.soft) };
        across * window(elevation - self.elevation, self.height / 2.0, self.soft) * self.radiance
    }
}

/// The studio environment: a latitude-longitude image whose mean radiance over the sphere is 1.
pub fn studio_environment() -> Image {
    let (w, h) = SIZE;
    let mut texels = Vec::with_capacity(w as usize * h as usize);
    let (mut sum, mut weight) = (0.0f64, 0.0f64);
    for y in 0..h {
        let elevation = 90.0 - 180.0 * (y as f32 + 0.5) / h as f32;
        // A row's solid angle per texel is proportional to the sine of its polar angle.
        let solid_angle = f64::from((PI * (y as f32 + 0.5) / h as f32).sin());
        for x in 0..w {
            let azimuth = (TAU * ((x as f32 + 0.5) / w as f32 - 0.5)).to_degrees();
            let radiance = dome(elevation) + SOFTBOXES.iter().map(|b| b.at(azimuth, elevation)).sum::<f32>();
            sum += f64::from(radiance) * solid_angle;
            weight += solid_angle;
            texels.push(Vec3::splat(radiance));
        }
    }
    let scale = (weight / sum) as f32;
    let texels = texels.into_iter().map(|t| t * scale).collect();
    Image::new(w, h, texels).expect("a studio image of a valid size")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The radiance the image holds towards `dir`, by the renderer's mapping.
    fn towards(image: &Image, dir: Vec3) -> f32 {
        let dir = dir.normalize();
        let u = dir.x.atan2(-dir.z) / TAU + 0.5;
        let v = dir.y.clamp(-1.0, 1.0).acos() / PI;
        let (w, h) = (image.width() as f32, image.height() as f32);
        image.texel(((u * w) as i64).min(w as i64 - 1), ((v * h) as i64).min(h as i64 - 1)).x
    }

    #[test]
    fn the_studio_is_grey_with_mean_radiance_one() {
        let image = studio_environment();
        let (w, h) = (image.width() as i64, image.height() as i64);
        let (mut sum, mut weight) = (0.0f64, 0.0f64);
        for y in 0..h {
            let solid_angle = (PI as f64 * (y as f64 + 0.5) / h as f64).sin();
            for x in 0..w {
                let t = image.texel(x, y);
                assert!(t.x == t.y && t.y == t.z && t.x > 0.0, "texel ({x}, {y}) is {t}: grey and not black");
                sum += f64::from(t.x) * solid_angle;
                weight += solid_angle;
            }
        }
        assert!((sum / weight - 1.0).abs() < 1e-4, "mean radiance {}", sum / weight);
    }

    #[test]
    fn the_key_light_is_up_front_right_and_the_floor_is_dim() {
        let image = studio_environment();
        let key = towards(&image, Vec3::new(1.0, 1.0, 1.0));
        let fill = towards(&image, Vec3::new(-1.0, 0.6, 1.0));
        let floor = towards(&image, -Vec3::Y);
        let wall = towards(&image, Vec3::new(1.0, 0.0, -0.2));
        assert!(key > 1.5 * fill && fill > 2.0 * wall && wall > floor, "key {key}, fill {fill}, wall {wall}, floor {floor}");
    }
}
