//! The camera: `rtPerspective` (or `rtFrustum`, `rtOrtho`) and `rtLookAt` set the scene's
//! camera directly. As the seed says
//! (*The OpenRT API* §2.1), they take OpenGL's arguments but do not build matrices: there is no
//! projection matrix to distort, so the image's aspect ratio is always the frame buffer's, and a
//! ray tracer needs no clipping planes. Both are checked all the same, and the camera's points
//! and planes are bound by `RT_MAX_COORDINATE` as vertices are. `rtLens` and `rtShutter`
//! set the camera's thin lens and shutter, which only the distribution ray tracer and the path
//! tracer sample; each call keeps what the others set.

use glam::Vec3;
use raystage_scene::{Camera, Projection};

use crate::context::Context;
use crate::error::{Error, coordinates, finite, single};

impl Context {
    /// `rtPerspective`: the vertical field of view, in degrees.
    pub fn perspective(&mut self, fov_y: f32, aspect: f32, near: f32, far: f32) -> Result<(), Error> {
        finite("(fovy, aspect, near, far)", &[fov_y, aspect, near, far])?;
        if aspect <= 0.0 {
            return Err(Error::invalid_value(format!("aspect is {aspect}, not positive")));
        }
        if !(near > 0.0 && far > near) {
            return Err(Error::invalid_value(format!("near {near} and far {far} do not satisfy 0 < near < far")));
        }
        let camera = Camera { fov_y_degrees: fov_y, projection: Projection::Perspective, ..*self.scene.camera() };
        self.scene.set_camera(camera)?;
        Ok(())
    }

    /// `rtOrtho` (`orthographic`) or `rtFrustum`: a window projection, with OpenGL's checks.
    pub fn window_projection(&mut self, orthographic: bool, values: [f64; 6]) -> Result<(), Error> {
        let what = "(left, right, bottom, top, znear, zfar)";
        let [left, right, bottom, top, near, far] = single(what, values)?;
        coordinates(what, &[left, right, bottom, top, near, far])?;
        for (what, a, b) in [("left and right", left, right), ("bottom and top", bottom, top), ("znear and zfar", near, far)] {
            if a == b {
                return Err(Error::invalid_value(format!("{what} are both {a}: the volume is empty")));
            }
        }
        let projection = if orthographic {
            Projection::Orthographic { left, right, bottom, top, near }
        } else {
            if !(near > 0.0 && far > near) {
                return Err(Error::invalid_value(format!("znear {near} and zfar {far} do not satisfy 0 < znear < zfar")));
            }
            Projection::Frustum { left, right, bottom, top, near }
        };
        self.scene.set_camera(Camera { projection, ..*self.scene.camera() })?;
        Ok(())
    }

    /// `rtLookAt`: where the camera is, what it looks at, and which way is up.
    pub fn look_at(&mut self, eye: [f32; 3], center: [f32; 3], up: [f32; 3]) -> Result<(), Error> {
        coordinates("eye", &eye)?;
        coordinates("center", &center)?;
        finite("up", &up)?;
        let camera = Camera { eye: Vec3::from(eye), target: Vec3::from(center), up: Vec3::from(up), ..*self.scene.camera() };
        self.scene.set_camera(camera)?;
        Ok(())
    }

    /// `rtLens`: the thin lens's radius and focus distance (0 focuses on the point looked at).
    pub fn lens(&mut self, aperture_radius: f32, focus_distance: f32) -> Result<(), Error> {
        finite("(aperture_radius, focus_distance)", &[aperture_radius, focus_distance])?;
        for (what, v) in [("aperture_radius", aperture_radius), ("focus_distance", focus_distance)] {
            if v < 0.0 {
                return Err(Error::invalid_value(format!("{what} is {v}, negative")));
            }
        }
        let camera = Camera { aperture_radius, focus_distance, ..*self.scene.camera() };
        self.scene.set_camera(camera)?;
        Ok(())
    }

    /// `rtShutter`: when the shutter opens and closes, as times of the frame in `[0, 1]`.
    pub fn shutter(&mut self, open: f32, close: f32) -> Result<(), Error> {
        finite("(open, close)", &[open, close])?;
        if !(0.0 <= open && open <= close && close <= 1.0) {
            return Err(Error::invalid_value(format!("open {open} and close {close} do not satisfy 0 <= open <= close <= 1")));
        }
        let camera = Camera { shutter: [open, close], ..*self.scene.camera() };
        self.scene.set_camera(camera)?;
        Ok(())
    }
}
