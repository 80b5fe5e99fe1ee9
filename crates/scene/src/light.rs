//! Light sources.

use glam::Vec3;

use crate::error::SceneError;

/// A light source. Intensities are linear RGB.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Light from a point, falling off with the square of the distance.
    Point {
        /// Where.
        position: Vec3,
        /// Radiant intensity: the irradiance at distance 1, facing the light.
        intensity: Vec3,
    },
    /// Parallel light from infinitely far away, like the sun.
    Directional {
        /// The direction the light travels in (towards the scene), any length.
        direction: Vec3,
        /// Irradiance on a surface facing the light.
        intensity: Vec3,
    },
}

impl Light {
    /// Checks every number is finite, intensities are not negative and a direction is not zero.
    pub fn validate(&self) -> Result<(), SceneError> {
        let (point, intensity) = match *self {
            Light::Point { position, intensity } => (("light.position", position), intensity),
            Light::Directional { direction, intensity } => {
                if direction.length_squared() == 0.0 {
                    return Err(SceneError::OutOfRange { field: "light.direction", message: "is zero".into() });
                }
                (("light.direction", direction), intensity)
            }
        };
        for (field, v) in [point, ("light.intensity", intensity)] {
            if !v.is_finite() {
                return Err(SceneError::NotFinite { field, index: 0 });
            }
        }
        if intensity.min_element() < 0.0 {
            return Err(SceneError::OutOfRange { field: "light.intensity", message: "is negative".into() });
        }
        Ok(())
    }

    /// The light reaching point `p`: unit direction from `p` towards the light, the distance to
    /// it (infinite for directional light), and the irradiance facing it.
    pub fn sample(&self, p: Vec3) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Point { position, intensity } => {
                let to_light = position - p;
                let d2 = to_light.length_squared();
                let d = d2.sqrt();
                (to_light / d, d, intensity / d2)
            }
            Light::Directional { direction, intensity } => (-direction.normalize(), f32::INFINITY, intensity),
        }
    }
}
