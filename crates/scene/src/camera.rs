//! The camera: a pinhole looking from an eye point at a target.

use glam::Vec3;
use raystage_kernel::Ray;

use crate::error::SceneError;

/// A perspective pinhole camera (`rtPerspective` + `rtLookAt`). The horizontal field of view
/// follows from the image's aspect ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// Which way is up (need not be perpendicular to the view direction).
    pub up: Vec3,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub fov_y_degrees: f32,
}

impl Default for Camera {
    /// Looking down −z at the origin from (0, 0, 5), 45° vertical field of view.
    fn default() -> Self {
        Camera { eye: Vec3::new(0.0, 0.0, 5.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_degrees: 45.0 }
    }
}

impl Camera {
    /// A camera at `eye` looking at `target`, checked.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, fov_y_degrees: f32) -> Result<Camera, SceneError> {
        let camera = Camera { eye, target, up, fov_y_degrees };
        camera.validate()?;
        Ok(camera)
    }

    /// Checks every number is finite, the eye is not at the target, `up` is not along the view
    /// direction, and the field of view is in `(0, 180)` degrees.
    pub fn validate(&self) -> Result<(), SceneError> {
        for (field, v) in [("camera.eye", self.eye), ("camera.target", self.target), ("camera.up", self.up)] {
            if !v.is_finite() {
                return Err(SceneError::NotFinite { field, index: 0 });
            }
        }
        let forward = self.target - self.eye;
        if forward.length_squared() == 0.0 {
            return Err(SceneError::OutOfRange { field: "camera.target", message: "equals the eye position".into() });
        }
        if forward.cross(self.up).length_squared() <= f32::MIN_POSITIVE {
            return Err(SceneError::OutOfRange { field: "camera.up", message: "is parallel to the view direction".into() });
        }
        if !(self.fov_y_degrees > 0.0 && self.fov_y_degrees < 180.0) {
            return Err(SceneError::OutOfRange {
                field: "camera.fov_y_degrees",
                message: format!("{} is not in (0, 180)", self.fov_y_degrees),
            });
        }
        Ok(())
    }

    /// The camera's orthonormal frame: forward, right, up.
    fn frame(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        (forward, right, right.cross(forward))
    }

    /// The primary ray through image position `(px, py)` (in pixels, `(0, 0)` the top-left
    /// corner of the image, so pixel centres are at `x + 0.5`) of a `width × height` image.
    pub fn ray(&self, px: f32, py: f32, width: u32, height: u32) -> Ray {
        let (forward, right, up) = self.frame();
        let tan = (0.5 * self.fov_y_degrees.to_radians()).tan();
        let (w, h) = (width as f32, height as f32);
        let u = (px / w * 2.0 - 1.0) * tan * w / h;
        let v = (1.0 - py / h * 2.0) * tan;
        Ray::new(self.eye, (forward + right * u + up * v).normalize())
    }
}
