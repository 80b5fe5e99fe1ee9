//! The camera. Like OpenRT's, these calls set the camera and touch no matrix.

use crate::abi::types::RTfloat;
use crate::boundary::call;

/// Sets the camera's vertical field of view to `fovy` degrees, in (0, 180). `aspect`, `znear`
/// and `zfar` are checked (positive, `znear < zfar`) but do not change the image: its aspect
/// ratio is the frame buffer's, and a ray tracer clips nothing.
#[unsafe(no_mangle)]
pub extern "C" fn rtPerspective(fovy: RTfloat, aspect: RTfloat, znear: RTfloat, zfar: RTfloat) {
    call("rtPerspective", |ctx| ctx.perspective(fovy, aspect, znear, zfar))
}

/// Places the camera at the eye point, looking at the centre point, with `up` pointing up in the
/// image (it must not be parallel to the view direction). World coordinates: the modelview
/// matrix does not apply.
#[unsafe(no_mangle)]
pub extern "C" fn rtLookAt(
    eye_x: RTfloat,
    eye_y: RTfloat,
    eye_z: RTfloat,
    center_x: RTfloat,
    center_y: RTfloat,
    center_z: RTfloat,
    up_x: RTfloat,
    up_y: RTfloat,
    up_z: RTfloat,
) {
    call("rtLookAt", |ctx| ctx.look_at([eye_x, eye_y, eye_z], [center_x, center_y, center_z], [up_x, up_y, up_z]))
}
