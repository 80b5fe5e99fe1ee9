//! Light sources: the OpenGL/VRML kinds the OpenRT API ships as default light shaders (point,
//! spot, directional, ambient; docs/design/seeds.md §1.1), plus the two a ray tracer adds: a
//! parallelogram area light for soft shadows and an environment that surrounds the scene.
//! Intensities are linear RGB.

use glam::Vec3;

use crate::error::SceneError;
use crate::ids::TextureId;

/// A light source.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Light {
    /// Light from a point, falling off with the square of the distance.
    Point {
        /// Where.
        position: Vec3,
        /// Radiant intensity: the irradiance at distance 1, facing the light.
        intensity: Vec3,
    },
    /// A point light that shines into a cone, fading out between two angles.
    Spot {
        /// Where.
        position: Vec3,
        /// The cone's axis (the way the light shines), any length.
        direction: Vec3,
        /// Radiant intensity along the axis.
        intensity: Vec3,
        /// Half-angle of the cone, in degrees, in `(0, 90]`: nothing outside it.
        cone_degrees: f32,
        /// Half-angle where the fall-off starts, in degrees, at most `cone_degrees`: full
        /// intensity inside it.
        falloff_degrees: f32,
    },
    /// Parallel light from infinitely far away, like the sun.
    Directional {
        /// The direction the light travels in (towards the scene), any length.
        direction: Vec3,
        /// Irradiance on a surface facing the light.
        intensity: Vec3,
    },
    /// Light from everywhere at once, unshadowed (OpenGL's ambient term).
    Ambient {
        /// Irradiance it adds to every surface.
        intensity: Vec3,
    },
    /// A one-sided emitting parallelogram: the points `corner + s·edge_u + t·edge_v` for s, t in
    /// [0, 1], emitting on the side `edge_u × edge_v` points to. Casts soft shadows.
    Area {
        /// One corner.
        corner: Vec3,
        /// First edge from the corner.
        edge_u: Vec3,
        /// Second edge from the corner.
        edge_v: Vec3,
        /// Emitted radiance.
        radiance: Vec3,
    },
    /// Light arriving from infinitely far away in every direction: a constant colour, or a
    /// latitude-longitude image (its top row straight up, +y; its middle column towards −z)
    /// scaled by that colour.
    Environment {
        /// Radiance, or the scale of the image.
        radiance: Vec3,
        /// The image, if any.
        map: Option<TextureId>,
        /// Turns the image about the up axis (+y) by this many degrees, counter-clockwise seen
        /// from above: what lay at azimuth `a` lies at `a` minus this (0 by default).
        #[serde(default)]
        rotate_degrees: f32,
    },
}

impl Light {
    /// Checks every number is finite, intensities are not negative, directions and edges are
    /// not zero, and angles are in range.
    pub fn validate(&self) -> Result<(), SceneError> {
        let finite = |field: &'static str, v: Vec3| if v.is_finite() { Ok(()) } else { Err(SceneError::NotFinite { field, index: 0 }) };
        let nonzero = |field: &'static str, v: Vec3| {
            if v.length_squared() > 0.0 { Ok(()) } else { Err(SceneError::OutOfRange { field, message: "is zero".into() }) }
        };
        let power = |field: &'static str, v: Vec3| {
            finite(field, v)?;
            if v.min_element() >= 0.0 { Ok(()) } else { Err(SceneError::OutOfRange { field, message: "is negative".into() }) }
        };
        match *self {
            Light::Point { position, intensity } => {
                finite("light.position", position)?;
                power("light.intensity", intensity)
            }
            Light::Spot { position, direction, intensity, cone_degrees, falloff_degrees } => {
                finite("light.position", position)?;
                finite("light.direction", direction)?;
                nonzero("light.direction", direction)?;
                power("light.intensity", intensity)?;
                if !(cone_degrees > 0.0 && cone_degrees <= 90.0) {
                    return Err(SceneError::OutOfRange { field: "light.cone_degrees", message: format!("{cone_degrees} is not in (0, 90]") });
                }
                if !(falloff_degrees >= 0.0 && falloff_degrees <= cone_degrees) {
                    return Err(SceneError::OutOfRange {
                        field: "light.falloff_degrees",
                        message: format!("{falloff_degrees} is not in [0, cone_degrees]"),
                    });
                }
                Ok(())
            }
            Light::Directional { direction, intensity } => {
                finite("light.direction", direction)?;
                nonzero("light.direction", direction)?;
                power("light.intensity", intensity)
            }
            Light::Ambient { intensity } => power("light.intensity", intensity),
            Light::Area { corner, edge_u, edge_v, radiance } => {
                finite("light.corner", corner)?;
                finite("light.edge_u", edge_u)?;
                finite("light.edge_v", edge_v)?;
                nonzero("light.edges", edge_u.cross(edge_v))?;
                power("light.radiance", radiance)
            }
            Light::Environment { radiance, rotate_degrees, .. } => {
                if !rotate_degrees.is_finite() {
                    return Err(SceneError::NotFinite { field: "light.rotate_degrees", index: 0 });
                }
                power("light.radiance", radiance)
            }
        }
    }
}
