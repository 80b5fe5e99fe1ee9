//! Frames: the application's frame buffer, rendering, picking and PNG output.

use std::ffi::{c_char, c_void};
use std::ptr::NonNull;

use crate::abi::types::{RTboolean, RTenum, RTsizei, RTuint};
use crate::boundary::{c_str, call, write_out};
use crate::frames::{FrameBuffer, PixelFormat};
use crate::ids;

/// Lends raystage `width` × `height` pixels of memory (each side 1 to
/// `RT_MAX_FRAMEBUFFER_SIZE`, rows from the top) that `rtSwapBuffers` renders into: `RT_RGBA8`
/// (4 bytes per pixel, sRGB) or `RT_RGBA32F` (4 floats per pixel, linear). `pixels` NULL with
/// `width` and `height` 0 detaches the frame buffer.
///
/// # Safety
/// The memory must stay valid and writable until the frame buffer is replaced, detached or the
/// context reset; raystage writes it only during `rtSwapBuffers`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtFrameBuffer(pixels: *mut c_void, width: RTsizei, height: RTsizei, format: RTenum) {
    call("rtFrameBuffer", |ctx| {
        let format = PixelFormat::from_enum(format)?;
        ctx.frames.target = match NonNull::new(pixels.cast::<u8>()) {
            // SAFETY: the caller's promise above.
            Some(pixels) => Some(unsafe { FrameBuffer::new(pixels, width, height, format)? }),
            None if width == 0 && height == 0 => None,
            None => return Err(crate::error::Error::invalid_value("pixels is NULL")),
        };
        Ok(())
    })
}

/// Renders a frame into the frame buffer. Every reference is resolved now (frame semantics):
/// the shaders' parameters, the objects' geometry and the instances as they are at this call
/// decide the image, whenever they were set. Rendering runs on all cores; the call returns when
/// the frame is complete. Not allowed while an object is being defined.
#[unsafe(no_mangle)]
pub extern "C" fn rtSwapBuffers() {
    call("rtSwapBuffers", |ctx| ctx.swap_buffers())
}

/// What pixel (`x`, `y`) of the frame buffer sees in the scene as it is now. Returns 1 and writes
/// the instance, object and triangle through the pointers that are not NULL; returns 0 if the
/// pixel sees nothing or on error, and writes nothing. The triangle is counted from 0 in the
/// order the object's triangles were issued, after primitives are split into triangles (a
/// quadrilateral is two, a polygon of n vertices n - 2).
///
/// # Safety
/// Each non-NULL pointer must point to a writable `RTuint`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtPick(x: RTuint, y: RTuint, instance: *mut RTuint, object: *mut RTuint, triangle: *mut RTuint) -> RTboolean {
    call("rtPick", |ctx| {
        let Some(hit) = ctx.pick(x, y)? else {
            return Ok(0);
        };
        // SAFETY: the caller's promise above.
        unsafe {
            write_out(instance, ids::to_c(hit.instance.0));
            write_out(object, ids::to_c(hit.object.0));
            write_out(triangle, hit.prim);
        }
        Ok(1)
    })
}

/// Writes the last frame `rtSwapBuffers` rendered as an sRGB PNG file at `path`, replacing any
/// file there. `RT_INVALID_OPERATION` if no frame was rendered, `RT_IO_ERROR` if the file cannot
/// be written.
///
/// # Safety
/// `path` must be NULL (an error) or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtWritePNG(path: *const c_char) {
    // SAFETY: the caller's promise above.
    call("rtWritePNG", |ctx| ctx.write_png(unsafe { c_str(path, "path")? }.to_bytes()))
}
