//! The matrix stacks, as in OpenGL: each call acts on the stack `rtMatrixMode` selects, and
//! multiplies its top matrix on the right. Matrices are affine (the camera is not a matrix).

use crate::abi::types::{RTdouble, RTenum, RTfloat};
use crate::boundary::{array, call};
use crate::error::single;
use crate::matrix::{MatrixMode, affine_from_columns, rotation, scaling, translation};

/// Selects the stack the matrix calls act on: `RT_MODELVIEW` (the default) or `RT_TEXTURE`.
#[unsafe(no_mangle)]
pub extern "C" fn rtMatrixMode(mode: RTenum) {
    call("rtMatrixMode", |ctx| {
        ctx.matrices.mode = MatrixMode::from_enum(mode)?;
        Ok(())
    })
}

/// Replaces the top matrix with the identity.
#[unsafe(no_mangle)]
pub extern "C" fn rtLoadIdentity() {
    call("rtLoadIdentity", |ctx| ctx.matrices.current().load(glam::Affine3A::IDENTITY))
}

/// Pushes a copy of the top matrix (`RT_STACK_OVERFLOW` beyond `RT_MAX_STACK_DEPTH`).
#[unsafe(no_mangle)]
pub extern "C" fn rtPushMatrix() {
    call("rtPushMatrix", |ctx| ctx.matrices.current().push())
}

/// Pops the top matrix (`RT_STACK_UNDERFLOW` if it is the only one).
#[unsafe(no_mangle)]
pub extern "C" fn rtPopMatrix() {
    call("rtPopMatrix", |ctx| ctx.matrices.current().pop())
}

/// Multiplies the top matrix by a translation. A matrix whose translation would exceed
/// `RT_MAX_COORDINATE` is refused (`RT_INVALID_VALUE`), by this call and every other matrix call.
#[unsafe(no_mangle)]
pub extern "C" fn rtTranslatef(x: RTfloat, y: RTfloat, z: RTfloat) {
    call("rtTranslatef", |ctx| ctx.matrices.current().multiply(translation(x, y, z)?))
}

/// Multiplies the top matrix by a rotation of `angle` degrees, counter-clockwise about the axis
/// `(x, y, z)` (any non-zero length).
#[unsafe(no_mangle)]
pub extern "C" fn rtRotatef(angle: RTfloat, x: RTfloat, y: RTfloat, z: RTfloat) {
    call("rtRotatef", |ctx| ctx.matrices.current().multiply(rotation(angle, x, y, z)?))
}

/// Multiplies the top matrix by a scaling: any finite factors (`RT_MAX_COORDINATE` bounds what
/// the matrix places, not its scale).
#[unsafe(no_mangle)]
pub extern "C" fn rtScalef(x: RTfloat, y: RTfloat, z: RTfloat) {
    call("rtScalef", |ctx| ctx.matrices.current().multiply(scaling(x, y, z)?))
}

/// Multiplies the top matrix by `m`: 16 floats in column-major order (OpenGL's), whose last row
/// must be 0 0 0 1.
///
/// # Safety
/// `m` must be NULL (an error) or point to 16 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtMultMatrixf(m: *const RTfloat) {
    // SAFETY: the caller's promise above.
    call("rtMultMatrixf", |ctx| ctx.matrices.current().multiply(affine_from_columns(&unsafe { array(m, "m")? })?))
}

/// Replaces the top matrix with `m`: 16 floats in column-major order, last row 0 0 0 1.
///
/// # Safety
/// `m` must be NULL (an error) or point to 16 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtLoadMatrixf(m: *const RTfloat) {
    // SAFETY: the caller's promise above.
    call("rtLoadMatrixf", |ctx| ctx.matrices.current().load(affine_from_columns(&unsafe { array(m, "m")? })?))
}

/// `rtTranslatef` in double precision (converted to single; beyond its range is an error).
#[unsafe(no_mangle)]
pub extern "C" fn rtTranslated(x: RTdouble, y: RTdouble, z: RTdouble) {
    call("rtTranslated", |ctx| {
        let [x, y, z] = single("(x, y, z)", [x, y, z])?;
        ctx.matrices.current().multiply(translation(x, y, z)?)
    })
}

/// `rtRotatef` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn rtRotated(angle: RTdouble, x: RTdouble, y: RTdouble, z: RTdouble) {
    call("rtRotated", |ctx| {
        let [angle] = single("angle", [angle])?;
        let [x, y, z] = single("(x, y, z)", [x, y, z])?;
        ctx.matrices.current().multiply(rotation(angle, x, y, z)?)
    })
}

/// `rtScalef` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn rtScaled(x: RTdouble, y: RTdouble, z: RTdouble) {
    call("rtScaled", |ctx| {
        let [x, y, z] = single("(x, y, z)", [x, y, z])?;
        ctx.matrices.current().multiply(scaling(x, y, z)?)
    })
}

/// `rtMultMatrixf` with 16 doubles.
///
/// # Safety
/// `m` must be NULL (an error) or point to 16 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtMultMatrixd(m: *const RTdouble) {
    // SAFETY: the caller's promise above.
    call("rtMultMatrixd", |ctx| ctx.matrices.current().multiply(affine_from_columns(&single("m", unsafe { array(m, "m")? })?)?))
}

/// `rtLoadMatrixf` with 16 doubles.
///
/// # Safety
/// `m` must be NULL (an error) or point to 16 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtLoadMatrixd(m: *const RTdouble) {
    // SAFETY: the caller's promise above.
    call("rtLoadMatrixd", |ctx| ctx.matrices.current().load(affine_from_columns(&single("m", unsafe { array(m, "m")? })?)?))
}
