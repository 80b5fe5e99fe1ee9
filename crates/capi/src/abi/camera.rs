//! The camera: where it looks from, how the image maps to rays, its lens and its shutter. Like
//! OpenRT's, these calls set the camera and touch no matrix.

use crate::abi::types::{RTdouble, RTfloat};
use crate::boundary::call;

/// Sets a symmetric perspective projection with a vertical field of view of `fovy` degrees, in
/// (0, 180). `aspect`, `znear` and `zfar` are checked (positive, `znear < zfar`) but do not
/// change the image: its aspect ratio is the frame buffer's, and a ray tracer clips nothing.
/// Replaces the projection `rtFrustum` or `rtOrtho` set.
#[unsafe(no_mangle)]
pub extern "C" fn rtPerspective(fovy: RTfloat, aspect: RTfloat, znear: RTfloat, zfar: RTfloat) {
    call("rtPerspective", |ctx| ctx.perspective(fovy, aspect, znear, zfar))
}

/// Sets an off-axis perspective projection, as OpenGL's `glFrustum`: rays from the eye through
/// the window `[left, right] × [bottom, top]` on the plane at distance `znear` in front of it
/// (x to the right, y up, in the camera's frame that `rtLookAt` sets). The window fills the
/// frame buffer whatever its aspect ratio, as OpenGL's viewport does. Needs `left != right`,
/// `bottom != top`, 0 < `znear` < `zfar` and every argument within ±`RT_MAX_COORDINATE` (else
/// `RT_INVALID_VALUE`); `zfar` clips nothing.
/// Replaces the projection `rtPerspective` or `rtOrtho` set.
#[unsafe(no_mangle)]
pub extern "C" fn rtFrustum(left: RTdouble, right: RTdouble, bottom: RTdouble, top: RTdouble, znear: RTdouble, zfar: RTdouble) {
    call("rtFrustum", |ctx| ctx.window_projection(false, [left, right, bottom, top, znear, zfar]))
}

/// Sets an orthographic projection, as OpenGL's `glOrtho`: parallel rays along the view
/// direction, one through each point of the window `[left, right] × [bottom, top]` (in the
/// camera's frame), starting `znear` in front of the eye; `znear` may be negative, so that what
/// lies just behind the eye shows, as in OpenGL (`rtOrtho(0, w, 0, h, -1, 1)` with the camera at
/// z = 0 draws the plane z = 0). The window fills the frame buffer. Needs `left != right`,
/// `bottom != top`, `znear != zfar` and every argument within ±`RT_MAX_COORDINATE` (else
/// `RT_INVALID_VALUE`: a ray starting farther away would measure its depth beyond single
/// precision); `zfar` clips nothing. There
/// is no depth of field: `rtLens` has no effect while it is in force. Replaces the projection
/// `rtPerspective` or `rtFrustum` set.
#[unsafe(no_mangle)]
pub extern "C" fn rtOrtho(left: RTdouble, right: RTdouble, bottom: RTdouble, top: RTdouble, znear: RTdouble, zfar: RTdouble) {
    call("rtOrtho", |ctx| ctx.window_projection(true, [left, right, bottom, top, znear, zfar]))
}

/// Places the camera at the eye point, looking at the centre point, with `up` pointing up in the
/// image (it must not be parallel to the view direction). World coordinates: the modelview
/// matrix does not apply. Each coordinate of the eye and the centre must be within
/// ±`RT_MAX_COORDINATE` (else `RT_INVALID_VALUE`), as vertices are.
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

/// Gives the camera a thin lens of radius `aperture_radius` that focuses at `focus_distance`
/// from the eye, for depth of field: what lies nearer or farther is blurred, the more the wider
/// the lens. `focus_distance` 0 focuses on the point `rtLookAt` looks at; `aperture_radius` 0
/// (the default) is a pinhole, sharp everywhere. Both must be finite and not negative. Only
/// `RT_DISTRIBUTION` and `RT_PATH` (`rtRenderMode`) render the blur; raise
/// `RT_SAMPLES_PER_PIXEL` to smooth it.
#[unsafe(no_mangle)]
pub extern "C" fn rtLens(aperture_radius: RTfloat, focus_distance: RTfloat) {
    call("rtLens", |ctx| ctx.lens(aperture_radius, focus_distance))
}

/// Opens the shutter at time `open` and closes it at `close`, times of the frame with
/// 0 <= `open` <= `close` <= 1, for motion blur: instances given an end transform with
/// `rtInstanceMotion` move over the frame, and the image shows them over the time the shutter
/// is open. `open` equal to `close` (the default, 0 and 0) takes an instant: no blur. Only
/// `RT_DISTRIBUTION` and `RT_PATH` (`rtRenderMode`) render the blur; raise
/// `RT_SAMPLES_PER_PIXEL` to smooth it.
#[unsafe(no_mangle)]
pub extern "C" fn rtShutter(open: RTfloat, close: RTfloat) {
    call("rtShutter", |ctx| ctx.shutter(open, close))
}
