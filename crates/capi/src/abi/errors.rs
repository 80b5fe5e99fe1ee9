//! Errors and the context's lifetime.

use std::ffi::c_char;

use crate::abi::types::RTenum;
use crate::boundary::{c_str, call_in_primitive, query};
use crate::context::Context;
use crate::error::Error;

/// Returns the first error recorded since the last call of `rtGetError` (`RT_NO_ERROR` if none)
/// and clears it. As with `glGetError`, later errors are not recorded while one is pending, so a
/// program can make many calls and check once; a failed call changes nothing.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetError() -> RTenum {
    query(0, |ctx| ctx.errors.take())
}

/// A message naming the problem: that of the pending error if there is one, else of the error
/// the last `rtGetError` returned, else "no error". It starts with the name of the failed call.
/// The string belongs to raystage and stays valid until the next `rtGetError` or
/// `rtResetContext` on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn rtGetErrorString() -> *const c_char {
    query(c"rtGetErrorString: the context is not available".as_ptr(), |ctx| ctx.errors.message().as_ptr())
}

/// Records error `code` as call `call` failing with `message`, as every `rt*` call records its
/// own (`rtGetErrorString` then reads "call: message"; an earlier error still unread sticks):
/// for libraries written on rt.h, such as RTUT, whose calls report through `rtGetError` too.
/// `code` must be an error code (`RT_INVALID_ENUM` ... `RT_OUT_OF_MEMORY`, `RT_IO_ERROR`,
/// `RT_INTERNAL_ERROR`), else `RT_INVALID_ENUM` is recorded instead; NULL strings record
/// `RT_INVALID_VALUE`. Allowed between `rtBegin` and `rtEnd`.
///
/// # Safety
/// `call` and `message` must be NULL (an error) or NUL-terminated strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtRecordError(code: RTenum, call: *const c_char, message: *const c_char) {
    call_in_primitive("rtRecordError", |ctx| {
        if !Error::CODES.contains(&code) {
            return Err(Error::invalid_enum(format!("{code:#x} is not an error code")));
        }
        // SAFETY: the caller's promise above.
        let (call, message) = unsafe { (c_str(call, "call")?.to_string_lossy(), c_str(message, "message")?.to_string_lossy()) };
        ctx.errors.record(&call, Error { code, message: message.into_owned() });
        Ok(())
    })
}

/// Discards this thread's context: the scene, every id, the matrices, bindings, frame buffer
/// and errors, as if no `rt` call had been made; its memory is freed. Frames in flight are
/// cancelled and waited for (promptly), and their handles released. Allowed anywhere.
#[unsafe(no_mangle)]
pub extern "C" fn rtResetContext() {
    query((), |ctx| {
        // The MPI job outlives the context: the workers start the new, empty scene over.
        #[cfg(feature = "mpi")]
        let cluster = ctx.cluster.take();
        *ctx = Context::default();
        #[cfg(feature = "mpi")]
        ctx.keep_cluster(cluster);
    });
}
