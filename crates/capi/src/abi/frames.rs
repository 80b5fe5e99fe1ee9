//! Frames: the application's frame buffer, rendering, picking and PNG output.
//!
//! Frames render synchronously (`rtSwapBuffers`) or asynchronously, after OSPRay's
//! `ospRenderFrame` and its future (`ospIsReady`, `ospWait`, `ospCancel`, `ospGetProgress`):
//! `rtRenderFrameAsync` starts a frame and the `rtFrame*` calls follow it, so that an
//! interactive program keeps handling input while it renders, polls its progress, cancels it and
//! starts the next.

use std::ffi::{c_char, c_void};
use std::ptr::NonNull;

use crate::abi::types::{RTboolean, RTenum, RTfloat, RTsizei, RTuint};
use crate::boundary::{c_str, call, call_or, write_out};
use crate::frames::{ChannelBuffer, FrameBuffer, PixelFormat, channel_from_enum};
use crate::ids;

/// Lends raystage `width` × `height` pixels of memory (each side 1 to
/// `RT_MAX_FRAMEBUFFER_SIZE`, rows from the top) that `rtSwapBuffers` renders into: `RT_RGBA8`
/// (4 bytes per pixel, sRGB) or `RT_RGBA32F` (4 floats per pixel, linear). `pixels` NULL with
/// `width` and `height` 0 detaches the frame buffer. Refused (`RT_INVALID_OPERATION`) while an
/// asynchronous frame is in flight, since its image goes to the frame buffer it started with.
///
/// # Safety
/// The memory must stay valid and writable until the frame buffer is replaced, detached or the
/// context reset; raystage writes it only during `rtSwapBuffers`, and during the `rtFrameIsReady`
/// or `rtFrameWait` call that delivers an asynchronous frame.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtFrameBuffer(pixels: *mut c_void, width: RTsizei, height: RTsizei, format: RTenum) {
    call("rtFrameBuffer", |ctx| {
        let format = PixelFormat::from_enum(format)?;
        let target = match NonNull::new(pixels.cast::<u8>()) {
            // SAFETY: the caller's promise above.
            Some(pixels) => Some(unsafe { FrameBuffer::new(pixels, width, height, format)? }),
            None if width == 0 && height == 0 => None,
            None => return Err(crate::error::Error::invalid_value("pixels is NULL")),
        };
        ctx.set_frame_buffer(target)
    })
}

/// Lends raystage memory for a channel beside the colour, which every frame then fills with
/// what the first surface each pixel sees is (one ray through the pixel's centre), as OSPRay's
/// and ANARI's frame channels: `RT_DEPTH_CHANNEL` or `RT_Z_CHANNEL` (one float per pixel),
/// `RT_NORMAL_CHANNEL` or `RT_ALBEDO_CHANNEL` (three floats), `RT_INSTANCE_ID_CHANNEL`,
/// `RT_OBJECT_ID_CHANNEL` or `RT_PRIMITIVE_ID_CHANNEL` (one `RTuint`); rows from the top.
/// `width` and `height` must be the frame buffer's when a frame renders (else that frame is
/// refused with `RT_INVALID_OPERATION`). `data` NULL with `width` and `height` 0 takes the
/// channel back. Refused while an asynchronous frame is in flight.
///
/// # Safety
/// The memory (`width × height` values of 4 bytes, times 3 for normals and albedo) must stay
/// valid and writable until the channel is taken back or the context reset; raystage writes it
/// only when it writes the frame buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtChannelBuffer(channel: RTenum, data: *mut c_void, width: RTsizei, height: RTsizei) {
    call("rtChannelBuffer", |ctx| {
        let channel = channel_from_enum(channel)?;
        let buffer = match NonNull::new(data.cast::<u8>()) {
            // SAFETY: the caller's promise above.
            Some(data) => Some(unsafe { ChannelBuffer::new(channel, data, width, height)? }),
            None if width == 0 && height == 0 => None,
            None => return Err(crate::error::Error::invalid_value("data is NULL")),
        };
        ctx.set_channel_buffer(channel, buffer)
    })
}

/// Renders a frame into the frame buffer. Every reference is resolved now (frame semantics):
/// the shaders' parameters, the objects' geometry and the instances as they are at this call
/// decide the image, whenever they were set. Rendering runs on all cores; the call returns when
/// the frame is complete. Not allowed while an object is being defined, nor while a frame of
/// `rtRenderFrameAsync` is in flight.
#[unsafe(no_mangle)]
pub extern "C" fn rtSwapBuffers() {
    call("rtSwapBuffers", |ctx| ctx.swap_buffers())
}

/// Renders a frame of `width` × `height` pixels (each side 1 to `RT_MAX_FRAMEBUFFER_SIZE`) as
/// `rtSwapBuffers` does, into a frame buffer raystage keeps itself, which then becomes the frame
/// buffer in place of any memory lent with `rtFrameBuffer`: `rtPick` and `RT_VIEWPORT` take its
/// size, later frames go to it too, and `rtReadPixels` copies them out. For a window toolkit
/// such as RTUT, whose window has a size of its own and may be resized at any time: no memory of
/// the toolkit's is lent, so none it frees can be written. Returns 1 once the frame rendered; a
/// refused call (as `rtSwapBuffers` refuses, or a size out of range) returns 0 and changes
/// nothing, the frame buffer included.
#[unsafe(no_mangle)]
pub extern "C" fn rtSwapBuffersKept(width: RTsizei, height: RTsizei) -> RTboolean {
    call("rtSwapBuffersKept", |ctx| ctx.swap_buffers_kept(width, height).map(|()| 1))
}

/// Copies the `width` × `height` pixels from (`x`, `y`) on of the last frame rendered (by
/// `rtSwapBuffers`, `rtSwapBuffersKept` or an asynchronous frame delivered) into `pixels`, as
/// `glReadPixels` does, but with rows from the top as the frame buffer has them: `RT_RGBA8`
/// (sRGB bytes) or `RT_RGBA32F` (linear floats), whatever the frame buffer's layout.
/// `RT_INVALID_OPERATION` if no frame was rendered, `RT_INVALID_VALUE` if `pixels` is NULL or
/// the rectangle is not inside the frame.
///
/// # Safety
/// `pixels` must be NULL (an error) or point to `width × height × (4 or 16)` writable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtReadPixels(x: RTsizei, y: RTsizei, width: RTsizei, height: RTsizei, format: RTenum, pixels: *mut c_void) {
    call("rtReadPixels", |ctx| {
        let format = PixelFormat::from_enum(format)?;
        let pixels = NonNull::new(pixels.cast::<u8>()).ok_or_else(|| crate::error::Error::invalid_value("pixels is NULL"))?;
        // SAFETY: the caller's promise above.
        unsafe { ctx.read_pixels((x, y), (width, height), format, pixels) }
    })
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

/// Writes the last frame `rtSwapBuffers` rendered (or an asynchronous frame delivered) as an
/// sRGB PNG file at `path`, replacing any file there. `RT_INVALID_OPERATION` if no frame was
/// rendered, `RT_IO_ERROR` if the file cannot be written.
///
/// # Safety
/// `path` must be NULL (an error) or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtWritePNG(path: *const c_char) {
    // SAFETY: the caller's promise above.
    call("rtWritePNG", |ctx| ctx.write_png(unsafe { c_str(path, "path")? }.to_bytes()))
}

/// Starts rendering a frame into the frame buffer on a thread of its own and returns its handle
/// (never 0), or 0 on error. The frame follows frame semantics as `rtSwapBuffers` does, taken
/// at this call: the scene, the camera and the render settings as they are now decide the image,
/// and edits made afterwards (while it renders, or later) only affect later frames. The context
/// stays usable meanwhile.
///
/// The frame is *in flight* until `rtFrameIsReady` returns 1, `rtFrameWait` returns or
/// `rtFrameRelease`; meanwhile `rtSwapBuffers`, `rtRenderFrameAsync` and `rtFrameBuffer` are
/// refused with `RT_INVALID_OPERATION` (one frame at a time per context; each thread has its
/// own context, so frames of several threads render together). The image lands in the frame
/// buffer, as `rtSwapBuffers` puts it, in the `rtFrameIsReady` or `rtFrameWait` call that first
/// finds the frame completed; do not read the frame buffer before. `RT_INVALID_OPERATION`
/// without a frame buffer or while an object is being defined.
///
/// Handles belong to the context (the thread) that started the frame; each is released with
/// `rtFrameRelease` (or `rtResetContext`), and never names another frame afterwards: handles are
/// unique for the life of the process, across threads and `rtResetContext`, so a stale one
/// records `RT_INVALID_VALUE` whatever was started since.
#[unsafe(no_mangle)]
pub extern "C" fn rtRenderFrameAsync() -> RTuint {
    call("rtRenderFrameAsync", |ctx| ctx.render_frame_async())
}

/// Whether frame `frame` finished: 1 if it completed, was cancelled or failed (see
/// `rtFrameWait` for which), 0 while it renders or on error. The first call that returns 1 for a
/// completed frame has written its image into the frame buffer. Never blocks.
#[unsafe(no_mangle)]
pub extern "C" fn rtFrameIsReady(frame: RTuint) -> RTboolean {
    call("rtFrameIsReady", |ctx| ctx.frame_is_ready(frame).map(RTboolean::from))
}

/// Blocks until frame `frame` finished and returns its status: `RT_NO_ERROR` if it completed (its
/// image is then in the frame buffer), `RT_CANCELLED` if `rtFrameCancel` stopped it first, or
/// `RT_INTERNAL_ERROR` if it failed (the failure is also recorded, once). After `rtFrameCancel`
/// it returns promptly: rendering stops within one sample of a tile per render thread. A handle
/// that names no frame (0, unknown or released) records `RT_INVALID_VALUE` and returns it.
#[unsafe(no_mangle)]
pub extern "C" fn rtFrameWait(frame: RTuint) -> RTenum {
    call_or("rtFrameWait", |e| e.code, |ctx| ctx.frame_wait(frame))
}

/// Asks frame `frame` to stop rendering and returns at once; `rtFrameWait` then returns
/// `RT_CANCELLED` (or `RT_NO_ERROR` if it completed first) and the frame buffer is left as it
/// was. Does nothing to a frame that already finished.
#[unsafe(no_mangle)]
pub extern "C" fn rtFrameCancel(frame: RTuint) {
    call("rtFrameCancel", |ctx| ctx.frame_cancel(frame))
}

/// How much of frame `frame` is rendered, from 0 to 1: the share of the image's rows that are
/// final. It never decreases, and it is 1 once the frame completed; a cancelled frame stays
/// where it stopped. Returns 0 on error.
#[unsafe(no_mangle)]
pub extern "C" fn rtFrameProgress(frame: RTuint) -> RTfloat {
    call("rtFrameProgress", |ctx| ctx.frame_progress(frame))
}

/// Frees the handle `frame`. A frame still in flight is cancelled and waited for (promptly, as
/// after `rtFrameCancel`), and its image never reaches the frame buffer; once it returns nothing
/// of the frame runs any more. Releasing a handle again records `RT_INVALID_VALUE`.
#[unsafe(no_mangle)]
pub extern "C" fn rtFrameRelease(frame: RTuint) {
    call("rtFrameRelease", |ctx| ctx.frame_release(frame))
}
