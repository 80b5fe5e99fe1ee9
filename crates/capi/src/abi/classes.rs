//! Introspection of the built-in shader classes, as ANARI's `anariGetObjectSubtypes` and
//! `anariGetParameterInfo`: classes by index (surface classes first, then light classes), and
//! each class's parameters by index, with their type, default, range and documentation. The
//! strings returned belong to raystage and stay valid for as long as the library is loaded.

use std::ffi::c_char;
use std::ptr;

use crate::abi::types::{RTenum, RTfloat, RTsizei};
use crate::boundary::{call, call_or, query};
use crate::error::Error;
use crate::introspection::{class, class_count, param};

/// How many built-in shader classes there are: every surface class, then every light class.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetShaderClassCount() -> RTsizei {
    query(0, |_| class_count())
}

/// The name of class `index` (0 to `rtGetShaderClassCount() - 1`), as `rtNewShaderClass` takes
/// it; NULL and `RT_INVALID_VALUE` if there is no such class.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetShaderClassName(index: RTsizei) -> *const c_char {
    call_or("rtGetShaderClassName", |_| ptr::null(), |_| Ok(class(index)?.name.as_ptr()))
}

/// What class `index` is, in a sentence; NULL and `RT_INVALID_VALUE` if there is no such class.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetShaderClassDoc(index: RTsizei) -> *const c_char {
    call_or("rtGetShaderClassDoc", |_| ptr::null(), |_| Ok(class(index)?.doc.as_ptr()))
}

/// `RT_SURFACE_CLASS` or `RT_LIGHT_CLASS`; 0 and `RT_INVALID_VALUE` if there is no such class.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetShaderClassKind(index: RTsizei) -> RTenum {
    call_or("rtGetShaderClassKind", |_| 0, |_| Ok(class(index)?.kind))
}

/// How many parameters class `index` exports (the names `rtParameterHandle` knows for its
/// shaders; any other name is ignored); 0 and `RT_INVALID_VALUE` if there is no such class.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetShaderParameterCount(index: RTsizei) -> RTsizei {
    call_or("rtGetShaderParameterCount", |_| 0, |_| Ok(class(index)?.params.len()))
}

/// The name of parameter `param` of class `index`; NULL and `RT_INVALID_VALUE` if there is none.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetShaderParameterName(index: RTsizei, param_index: RTsizei) -> *const c_char {
    call_or("rtGetShaderParameterName", |_| ptr::null(), |_| Ok(param(index, param_index)?.name.as_ptr()))
}

/// What parameter `param` of class `index` does, its units and its default, in words; NULL and
/// `RT_INVALID_VALUE` if there is none.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetShaderParameterDoc(index: RTsizei, param_index: RTsizei) -> *const c_char {
    call_or("rtGetShaderParameterDoc", |_| ptr::null(), |_| Ok(param(index, param_index)?.doc.as_ptr()))
}

/// The type of parameter `param` of class `index`: `RT_FLOAT` (one number, `rtParameter1f`),
/// `RT_FLOAT_VEC3` (three, `rtParameter3f`) or `RT_TEXTURE_2D` (`rtParameterTexture`); 0 and
/// `RT_INVALID_VALUE` if there is none.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetShaderParameterType(index: RTsizei, param_index: RTsizei) -> RTenum {
    call_or("rtGetShaderParameterType", |_| 0, |_| Ok(param(index, param_index)?.ty))
}

/// Writes the default of parameter `param` of class `index` to `value[0..3]`: three numbers, a
/// number in `value[0]` (the rest 0), or zeros for a texture (none). Nothing is written on error.
///
/// # Safety
/// `value` must point to three writable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtGetShaderParameterDefault(index: RTsizei, param_index: RTsizei, value: *mut RTfloat) {
    // SAFETY: the caller's promise above.
    call("rtGetShaderParameterDefault", |_| unsafe { write_floats(value, &param(index, param_index)?.default, "value") })
}

/// Writes the values parameter `param` of class `index` accepts to `range[0]` (least) and
/// `range[1]` (most), for each of its numbers; where it is open, the largest finite float or
/// `INFINITY` (negated for a least).
/// Nothing is written on error.
///
/// # Safety
/// `range` must point to two writable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtGetShaderParameterRange(index: RTsizei, param_index: RTsizei, range: *mut RTfloat) {
    // SAFETY: the caller's promise above.
    call("rtGetShaderParameterRange", |_| unsafe { write_floats(range, &param(index, param_index)?.range, "range") })
}

/// Writes `values` to the C array `out` (an error if it is NULL).
///
/// # Safety
/// `out` must be NULL or point to room for `values.len()` floats.
unsafe fn write_floats(out: *mut RTfloat, values: &[f32], what: &str) -> Result<(), Error> {
    if out.is_null() {
        return Err(Error::invalid_value(format!("{what} is NULL")));
    }
    for (i, &v) in values.iter().enumerate() {
        // SAFETY: not null; room for the values is the caller's promise.
        unsafe { out.add(i).write_unaligned(v) };
    }
    Ok(())
}
