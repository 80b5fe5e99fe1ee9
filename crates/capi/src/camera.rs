//! The camera: `rtPerspective` and `rtLookAt` set the scene's camera directly. As the seed says
//! (*The OpenRT API* §2.1), they take OpenGL's arguments but do not build matrices: there is no
//! projection matrix to distort, so the image's aspect ratio is always the frame buffer's, and a
//! ray tracer needs no clipping planes. Both are checked all the same.

use glam::Vec3;
use raystage_scene::Camera;

use crate::context::Context;
use crate::error::{Error, finite};

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
        let camera = Camera { fov_y_degrees: fov_y, ..*self.scene.camera() };
        self.scene.set_camera(camera)?;
        Ok(())
    }

    /// `rtLookAt`: where the camera is, what it looks at, and which way is up.
    pub fn look_at(&mut self, eye: [f32; 3], center: [f32; 3], up: [f32; 3]) -> Result<(), Error> {
        finite("eye", &eye)?;
        finite("center", &center)?;
        finite("up", &up)?;
        let fov = self.scene.camera().fov_y_degrees;
        self.scene.set_camera(Camera::look_at(Vec3::from(eye), Vec3::from(center), Vec3::from(up), fov)?)?;
        Ok(())
    }
}
