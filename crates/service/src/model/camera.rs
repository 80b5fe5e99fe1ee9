//! The camera in JSON.

use glam::Vec3;
use raystage_scene::{Camera, Projection};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::error::{Error, Result};

/// A change of the camera: the fields given replace the camera's, the others stay.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CameraPatch {
    /// Eye position.
    pub eye: Option<[f32; 3]>,
    /// The point looked at.
    pub target: Option<[f32; 3]>,
    /// Which way is up.
    pub up: Option<[f32; 3]>,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_degrees: Option<f32>,
    /// Lens radius; 0 for a pinhole (depth of field needs the distribution or path integrator).
    pub aperture_radius: Option<f32>,
    /// Distance in focus; 0 to focus on the target.
    pub focus_distance: Option<f32>,
    /// Shutter open and close times within the frame, in [0, 1].
    pub shutter: Option<[f32; 2]>,
    /// How rays leave the eye: perspective (the field of view), an off-axis frustum or an
    /// orthographic window, as the C ABI's `rtFrustum` and `rtOrtho` set them.
    pub projection: Option<ProjectionJson>,
}

/// A camera projection in JSON, told by `kind`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum ProjectionJson {
    /// Rays from the eye through a window centred on the view direction, `fov_y_degrees` high,
    /// as wide as the image's aspect ratio makes it.
    Perspective,
    /// Rays from the eye through the window `[left, right] × [bottom, top]` on the plane at
    /// distance `near` (> 0) along the view direction: an off-axis perspective (`rtFrustum`).
    Frustum {
        /// Left edge of the window.
        left: f32,
        /// Right edge (may be less than `left`: a mirrored image).
        right: f32,
        /// Bottom edge.
        bottom: f32,
        /// Top edge (may be less than `bottom`).
        top: f32,
        /// The window's distance from the eye, positive.
        near: f32,
    },
    /// Parallel rays along the view direction through the window `[left, right] × [bottom,
    /// top]`, starting at distance `near` along it (may be negative: behind the eye, as in
    /// OpenGL's `glOrtho`); no depth of field.
    Orthographic {
        /// Left edge of the window.
        left: f32,
        /// Right edge.
        right: f32,
        /// Bottom edge.
        bottom: f32,
        /// Top edge.
        top: f32,
        /// Where rays start along the view direction.
        near: f32,
    },
}

impl From<ProjectionJson> for Projection {
    fn from(p: ProjectionJson) -> Projection {
        match p {
            ProjectionJson::Perspective => Projection::Perspective,
            ProjectionJson::Frustum { left, right, bottom, top, near } => Projection::Frustum { left, right, bottom, top, near },
            ProjectionJson::Orthographic { left, right, bottom, top, near } => Projection::Orthographic { left, right, bottom, top, near },
        }
    }
}

impl From<Projection> for ProjectionJson {
    fn from(p: Projection) -> ProjectionJson {
        match p {
            Projection::Perspective => ProjectionJson::Perspective,
            Projection::Frustum { left, right, bottom, top, near } => ProjectionJson::Frustum { left, right, bottom, top, near },
            Projection::Orthographic { left, right, bottom, top, near } => ProjectionJson::Orthographic { left, right, bottom, top, near },
        }
    }
}

/// The camera.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, ToSchema)]
pub struct CameraJson {
    /// Eye position.
    pub eye: [f32; 3],
    /// The point looked at.
    pub target: [f32; 3],
    /// Which way is up.
    pub up: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
    /// Lens radius (0: pinhole).
    pub aperture_radius: f32,
    /// Distance in focus (0: the target's).
    pub focus_distance: f32,
    /// Shutter open and close times.
    pub shutter: [f32; 2],
    /// How rays leave the eye.
    pub projection: ProjectionJson,
}

impl CameraPatch {
    /// `camera` with the patch applied, checked (422 naming the field).
    pub fn apply(&self, camera: Camera) -> Result<Camera> {
        let v = |p: Option<[f32; 3]>, old: Vec3| p.map_or(old, Vec3::from);
        let out = Camera {
            eye: v(self.eye, camera.eye),
            target: v(self.target, camera.target),
            up: v(self.up, camera.up),
            fov_y_degrees: self.fov_y_degrees.unwrap_or(camera.fov_y_degrees),
            projection: self.projection.map_or(camera.projection, Projection::from),
            aperture_radius: self.aperture_radius.unwrap_or(camera.aperture_radius),
            focus_distance: self.focus_distance.unwrap_or(camera.focus_distance),
            shutter: self.shutter.unwrap_or(camera.shutter),
        };
        out.validate().map_err(|e| Error::from(e).without_prefix("camera."))?;
        Ok(out)
    }
}

impl From<&Camera> for CameraJson {
    fn from(c: &Camera) -> CameraJson {
        CameraJson {
            eye: c.eye.to_array(),
            target: c.target.to_array(),
            up: c.up.to_array(),
            fov_y_degrees: c.fov_y_degrees,
            aperture_radius: c.aperture_radius,
            focus_distance: c.focus_distance,
            shutter: c.shutter,
            projection: c.projection.into(),
        }
    }
}
