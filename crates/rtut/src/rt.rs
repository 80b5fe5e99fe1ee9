//! The calls of rt.h that RTUT makes, declared as a C program declares them (rt.h) and resolved
//! when librtut.so is loaded, from the libraystage.so the program runs with: RTUT is written on
//! the public C ABI alone, as GLUT is on GL's. Their constants are rt.h's values, which this
//! module's test checks against the C ABI's.

use std::ffi::{CString, c_char, c_void};

/// rt.h's `RTenum`.
pub(crate) type RTenum = u32;
/// rt.h's `RTboolean`.
type RTboolean = u8;

/// rt.h's `RT_INVALID_VALUE`.
pub(crate) const RT_INVALID_VALUE: RTenum = 0x0501;
/// rt.h's `RT_INVALID_OPERATION`.
pub(crate) const RT_INVALID_OPERATION: RTenum = 0x0502;
/// rt.h's `RT_IO_ERROR`.
pub(crate) const RT_IO_ERROR: RTenum = 0x9000;
/// rt.h's `RT_INTERNAL_ERROR`.
pub(crate) const RT_INTERNAL_ERROR: RTenum = 0x9001;
/// rt.h's `RT_RGBA8`: sRGB bytes.
const RT_RGBA8: RTenum = 0x8058;
/// rt.h's `RT_MAX_FRAMEBUFFER_SIZE`: the largest side of a frame, and of RTUT's window.
pub(crate) const RT_MAX_FRAMEBUFFER_SIZE: usize = 16384;

unsafe extern "C" {
    fn rtRecordError(code: RTenum, call: *const c_char, message: *const c_char);
    fn rtSwapBuffersKept(width: usize, height: usize) -> RTboolean;
    fn rtReadPixels(x: usize, y: usize, width: usize, height: usize, format: RTenum, pixels: *mut c_void);
    fn rtWritePNG(path: *const c_char);
}

/// A refused RTUT call: an rt.h error code and what went wrong.
#[derive(Debug)]
pub(crate) struct Error {
    pub code: RTenum,
    pub message: String,
}

impl Error {
    /// `RT_INVALID_VALUE`.
    pub fn invalid_value(message: impl Into<String>) -> Error {
        Error { code: RT_INVALID_VALUE, message: message.into() }
    }

    /// `RT_INVALID_OPERATION`.
    pub fn invalid_operation(message: impl Into<String>) -> Error {
        Error { code: RT_INVALID_OPERATION, message: message.into() }
    }

    /// `RT_IO_ERROR`.
    pub fn io(message: impl Into<String>) -> Error {
        Error { code: RT_IO_ERROR, message: message.into() }
    }

    /// `RT_INTERNAL_ERROR`.
    pub fn internal(message: impl Into<String>) -> Error {
        Error { code: RT_INTERNAL_ERROR, message: message.into() }
    }
}

/// Records `error` as RTUT call `call`'s, where `rtGetError` reads every rt.h call's.
pub(crate) fn record(call: &str, error: Error) {
    // A title's NUL bytes would end the message early: replaced, as the C ABI replaces them.
    let text = |s: &str| CString::new(s.replace('\0', "\u{FFFD}")).expect("NUL bytes were replaced");
    let (call, message) = (text(call), text(&error.message));
    // SAFETY: two NUL-terminated strings, alive during the call.
    unsafe { rtRecordError(error.code, call.as_ptr(), message.as_ptr()) }
}

/// `rtSwapBuffersKept`: renders a `width × height` frame into the frame buffer the library
/// keeps; `false` if it was refused (its error recorded).
pub(crate) fn swap_buffers_kept(width: u32, height: u32) -> bool {
    // SAFETY: a call without pointers.
    unsafe { rtSwapBuffersKept(width as usize, height as usize) != 0 }
}

/// `rtReadPixels` of the whole last frame, `width × height`, as RGBA8 sRGB bytes.
pub(crate) fn read_frame(width: u32, height: u32) -> Vec<u8> {
    let mut pixels = vec![0u8; width as usize * height as usize * 4];
    // SAFETY: room for `width × height` RGBA8 pixels.
    unsafe { rtReadPixels(0, 0, width as usize, height as usize, RT_RGBA8, pixels.as_mut_ptr().cast()) };
    pixels
}

/// `rtWritePNG`: the last frame into the file at `path` (its error recorded if it cannot be).
pub(crate) fn write_png(path: &std::ffi::CStr) {
    // SAFETY: a NUL-terminated string, alive during the call.
    unsafe { rtWritePNG(path.as_ptr()) }
}

#[cfg(test)]
mod tests {
    use raystage_capi::abi;

    #[test]
    fn the_constants_are_rt_h_s() {
        assert_eq!(super::RT_INVALID_VALUE, abi::RT_INVALID_VALUE);
        assert_eq!(super::RT_INVALID_OPERATION, abi::RT_INVALID_OPERATION);
        assert_eq!(super::RT_IO_ERROR, abi::RT_IO_ERROR);
        assert_eq!(super::RT_INTERNAL_ERROR, abi::RT_INTERNAL_ERROR);
        assert_eq!(super::RT_RGBA8, abi::RT_RGBA8);
        assert_eq!(super::RT_MAX_FRAMEBUFFER_SIZE, abi::RT_MAX_FRAMEBUFFER_SIZE);
    }
}
