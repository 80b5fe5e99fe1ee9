//! State queries, as OpenGL's `glGetFloatv`, `glGetDoublev` and `glGetIntegerv`: each writes the
//! values of the state `pname` names (see the `RT_*` query constants for how many) to `params`.

use crate::abi::types::{RTdouble, RTenum, RTfloat, RTint};
use crate::boundary::call_in_primitive;
use crate::error::Error;

/// Writes the values of state `pname` into `params` converted by `convert`.
///
/// # Safety
/// `params` must be NULL (an error) or point to room for as many values as `pname` has.
unsafe fn get<T>(name: &'static str, pname: RTenum, params: *mut T, convert: fn(f64) -> T) {
    call_in_primitive(name, |ctx| {
        let values = ctx.state(pname)?;
        if params.is_null() {
            return Err(Error::invalid_value("params is NULL"));
        }
        for (i, &v) in values.as_slice().iter().enumerate() {
            // SAFETY: not null; room for the values is the caller's promise.
            unsafe { params.add(i).write_unaligned(convert(v)) };
        }
        Ok(())
    })
}

/// Writes the values of state `pname` to `params` as floats: `RT_MODELVIEW_MATRIX`,
/// `RT_TEXTURE_MATRIX` (16 each), `RT_CURRENT_COLOR`, `RT_CURRENT_TEXTURE_COORDS`,
/// `RT_COLOR_CLEAR_VALUE`, `RT_VIEWPORT` (4 each), `RT_CURRENT_NORMAL` (3), or one of
/// `RT_MODELVIEW_STACK_DEPTH`, `RT_TEXTURE_STACK_DEPTH`, `RT_MATRIX_MODE`, `RT_SHADE_MODEL`,
/// `RT_TEXTURE_BINDING_2D`, `RT_SHADER_BINDING`. Another `pname` records `RT_INVALID_ENUM` and writes nothing;
/// allowed between `rtBegin` and `rtEnd`.
///
/// # Safety
/// `params` must be NULL (an error) or point to room for as many floats as `pname` has.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtGetFloatv(pname: RTenum, params: *mut RTfloat) {
    // SAFETY: the caller's promise above.
    unsafe { get("rtGetFloatv", pname, params, |v| v as RTfloat) }
}

/// `rtGetFloatv` in double precision.
///
/// # Safety
/// `params` must be NULL (an error) or point to room for as many doubles as `pname` has.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtGetDoublev(pname: RTenum, params: *mut RTdouble) {
    // SAFETY: the caller's promise above.
    unsafe { get("rtGetDoublev", pname, params, |v| v) }
}

/// `rtGetFloatv` as integers, each value rounded to the nearest (colours too: unlike OpenGL,
/// they are not scaled to the integer range, since raystage's colours may exceed 1).
///
/// # Safety
/// `params` must be NULL (an error) or point to room for as many integers as `pname` has.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtGetIntegerv(pname: RTenum, params: *mut RTint) {
    // SAFETY: the caller's promise above; `as` saturates values beyond the integer range.
    unsafe { get("rtGetIntegerv", pname, params, |v| v.round() as RTint) }
}
