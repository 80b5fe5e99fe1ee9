//! Errors and the context's lifetime.

use std::ffi::c_char;

use crate::abi::types::RTenum;
use crate::boundary::query;
use crate::context::Context;

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
