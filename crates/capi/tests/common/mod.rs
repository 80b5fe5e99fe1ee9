//! Helpers the C ABI's tests share: reading the error log, defining shaders, naming parameters,
//! reading pixels, as a C program would call them.

#![allow(dead_code)]

use std::ffi::CStr;

use raystage_capi::abi::*;

/// Takes the pending error with its message.
pub fn error() -> (RTenum, String) {
    let message = unsafe { CStr::from_ptr(rtGetErrorString()) }.to_string_lossy().into_owned();
    (rtGetError(), message)
}

/// Fails unless no error is pending.
#[track_caller]
pub fn assert_no_error() {
    let (code, message) = error();
    assert_eq!(code, RT_NO_ERROR, "{message}");
}

/// Fails unless error `expected` is pending with a message that contains `fragment`.
#[track_caller]
pub fn assert_error(expected: RTenum, fragment: &str) {
    let (code, message) = error();
    assert_eq!(code, expected, "{message}");
    assert!(message.contains(fragment), "{message:?} does not mention {fragment:?}");
}

/// Defines a class by name and a shader of it, bound; returns the shader.
pub fn shader(class: &CStr) -> RTuint {
    let cid = rtGenShaderClasses(1);
    unsafe { rtNewShaderClass(cid, class.as_ptr(), std::ptr::null()) };
    let sid = rtGenShaders(1);
    rtNewShader(sid);
    sid
}

/// The handle of parameter `name`.
pub fn handle(name: &CStr) -> RTint {
    unsafe { rtParameterHandle(name.as_ptr()) }
}

/// A frame buffer of `w × h` RGBA8 pixels, attached; it must outlive the frames rendered into it.
pub fn frame_buffer(w: usize, h: usize) -> Vec<u8> {
    let mut pixels = vec![0u8; w * h * 4];
    unsafe { rtFrameBuffer(pixels.as_mut_ptr().cast(), w, h, RT_RGBA8) };
    pixels
}

/// Pixel `(x, y)` of a `w`-wide RGBA8 image, without its alpha.
pub fn rgb(pixels: &[u8], w: usize, x: usize, y: usize) -> [u8; 3] {
    let i = (y * w + x) * 4;
    [pixels[i], pixels[i + 1], pixels[i + 2]]
}
