//! Shader parameters, written by name through handles. Writing a parameter the bound shader's
//! class does not export is silently ignored (so a front end can write the same material fields
//! to every shader); writing one with the wrong number of values records `RT_INVALID_OPERATION`.

use std::ffi::c_char;

use crate::abi::types::{RTenum, RTfloat, RTint, RTuint};
use crate::boundary::{array, call, text};

/// The handle of the parameter called `name` (1 to 255 bytes of UTF-8): the same name always
/// gives the same handle, whatever shader is bound. Returns 0 on error.
///
/// # Safety
/// `name` must be NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtParameterHandle(name: *const c_char) -> RTint {
    // SAFETY: the caller's promise above.
    call("rtParameterHandle", |ctx| ctx.parameter_handle(unsafe { text(name, "name")? }))
}

/// Selects where parameter values are stored. Every built-in class stores its parameters per
/// shader: `RT_PER_SHADER` is accepted, and `RT_PER_SCENE`, `RT_PER_OBJECT`, `RT_PER_TRIANGLE`
/// and `RT_PER_VERTEX` record `RT_INVALID_ENUM` with a message saying so.
#[unsafe(no_mangle)]
pub extern "C" fn rtParameterScope(scope: RTenum) {
    call("rtParameterScope", |ctx| ctx.parameter_scope(scope))
}

/// Writes one number to parameter `handle` of the bound shader.
#[unsafe(no_mangle)]
pub extern "C" fn rtParameter1f(handle: RTint, x: RTfloat) {
    call("rtParameter1f", |ctx| ctx.parameter(handle, &[x]))
}

/// Writes two numbers to parameter `handle` of the bound shader.
#[unsafe(no_mangle)]
pub extern "C" fn rtParameter2f(handle: RTint, x: RTfloat, y: RTfloat) {
    call("rtParameter2f", |ctx| ctx.parameter(handle, &[x, y]))
}

/// Writes three numbers (a colour, a position, a direction) to parameter `handle` of the bound
/// shader.
#[unsafe(no_mangle)]
pub extern "C" fn rtParameter3f(handle: RTint, x: RTfloat, y: RTfloat, z: RTfloat) {
    call("rtParameter3f", |ctx| ctx.parameter(handle, &[x, y, z]))
}

/// Writes four numbers to parameter `handle` of the bound shader.
#[unsafe(no_mangle)]
pub extern "C" fn rtParameter4f(handle: RTint, x: RTfloat, y: RTfloat, z: RTfloat, w: RTfloat) {
    call("rtParameter4f", |ctx| ctx.parameter(handle, &[x, y, z, w]))
}

/// `rtParameter3f` with the numbers in an array of three.
///
/// # Safety
/// `v` must be NULL (an error) or point to three floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtParameter3fv(handle: RTint, v: *const RTfloat) {
    // SAFETY: the caller's promise above.
    call("rtParameter3fv", |ctx| ctx.parameter(handle, &unsafe { array::<f32, 3>(v, "v")? }))
}

/// Makes parameter `handle` of the bound shader name texture `texture` (from `rtGenTextures`,
/// with an image or procedural definition), or no texture for 0: "diffuse_texture" of a
/// "Diffuse" shader, "map" of an "EnvironmentLight". The shader refers to the texture by id,
/// so redefining the texture later changes it. Writing numbers to a texture parameter, or a
/// texture to a number parameter, records `RT_INVALID_OPERATION`.
#[unsafe(no_mangle)]
pub extern "C" fn rtParameterTexture(handle: RTint, texture: RTuint) {
    call("rtParameterTexture", |ctx| ctx.parameter_texture(handle, texture))
}
