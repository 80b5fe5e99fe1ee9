//! # RTUT
//!
//! RTUT, OpenRT's GLUT replacement (docs/design/seeds.md §1.1): a window for a program's frames
//! and the callbacks that drive it, as the C library `librtut.so` with its header `rtut.h`. A
//! GLUT program ports by renaming `glut*` to `rtut*` and calling `rtutSwapBuffers` where it
//! called `glutSwapBuffers`:
//!
//! ```c
//! rtutInit(&argc, argv);
//! rtutInitWindowSize(640, 480);
//! rtutCreateWindow("scene");
//! rtutDisplayFunc(display);      // builds or edits the scene, then rtutSwapBuffers()
//! rtutKeyboardFunc(keyboard);    // rtutLeaveMainLoop() on 'q', rtutPostRedisplay() on edits
//! rtutMainLoop();                // returns when the window closes
//! ```
//!
//! The window is the viewer's toolkit (egui on OpenGL, X11 or Wayland). Without a display the
//! same program runs headless and writes its frames as PNG files (`rtutMainLoop` says how, and
//! which environment variables steer it).
//!
//! Unlike GLUT, `rtutMainLoop` returns (when the window closes or `rtutLeaveMainLoop` is
//! called), so the program can clean up; it runs on the thread that calls it, whose context
//! the callbacks use. Errors are recorded as every `rt*` call's are (`rtGetError`).
//!
//! RTUT is written on rt.h alone, as GLUT is on GL (the `rt` module): it renders with
//! `rtSwapBuffersKept`, copies frames out with `rtReadPixels` and reports errors with
//! `rtRecordError`, all of libraystage.so, so that a program that opens no window links no
//! window toolkit, and RTUT holds no C ABI state of its own. `rtut.h` is generated from this
//! file by cbindgen (crates/capi/tests/header.rs).

#![allow(non_snake_case)]

mod rt;
mod state;
mod window;

use std::ffi::{CStr, c_char, c_int, c_uchar};

use crate::rt::{Error, record};
use crate::state::with;

/// A display, idle or other callback without arguments.
pub type RTUTvoidfunc = Option<unsafe extern "C" fn()>;
/// A reshape callback: the window's new width and height in pixels.
pub type RTUTreshapefunc = Option<unsafe extern "C" fn(c_int, c_int)>;
/// A keyboard callback: the key's ASCII code and the pointer's position in pixels.
pub type RTUTkeyboardfunc = Option<unsafe extern "C" fn(c_uchar, c_int, c_int)>;
/// A mouse callback: the button (`RTUT_LEFT_BUTTON`, ...), its state (`RTUT_DOWN`, `RTUT_UP`)
/// and the pointer's position in pixels.
pub type RTUTmousefunc = Option<unsafe extern "C" fn(c_int, c_int, c_int, c_int)>;

/// The left mouse button, as the mouse callback names it (GLUT's `GLUT_LEFT_BUTTON`).
pub const RTUT_LEFT_BUTTON: c_int = 0;
/// The middle mouse button.
pub const RTUT_MIDDLE_BUTTON: c_int = 1;
/// The right mouse button.
pub const RTUT_RIGHT_BUTTON: c_int = 2;
/// A mouse button went down (GLUT's `GLUT_DOWN`).
pub const RTUT_DOWN: c_int = 0;
/// A mouse button went up (GLUT's `GLUT_UP`).
pub const RTUT_UP: c_int = 1;

/// Initialises RTUT; call it first, as `glutInit`. The arguments are GLUT's and are left as they
/// are (either may be NULL): RTUT takes no command-line options.
#[unsafe(no_mangle)]
pub extern "C" fn rtutInit(argc: *mut c_int, argv: *mut *mut c_char) {
    let _ = (argc, argv);
    with(|r| r.init());
}

/// The size of the window's inside in pixels (each side 1 to `RT_MAX_FRAMEBUFFER_SIZE`;
/// GLUT's 300 × 300 by default), and of the frames rendered headless. Call before
/// `rtutCreateWindow`.
#[unsafe(no_mangle)]
pub extern "C" fn rtutInitWindowSize(width: c_int, height: c_int) {
    if let Err(error) = with(|r| r.init_window_size(width, height)) {
        record("rtutInitWindowSize", error);
    }
}

/// Makes the window (shown when `rtutMainLoop` runs) and returns its id, 1, or 0 on error: RTUT
/// has one window, and needs `rtutInit` first. A redisplay is posted for it.
///
/// # Safety
/// `title` must be NULL (an error) or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtutCreateWindow(title: *const c_char) -> c_int {
    let created = if title.is_null() {
        Err(Error::invalid_value("title is NULL"))
    } else {
        // SAFETY: the caller's promise above.
        with(|r| r.create_window(unsafe { CStr::from_ptr(title) }.to_string_lossy().into_owned()))
    };
    created.unwrap_or_else(|error| {
        record("rtutCreateWindow", error);
        0
    })
}

/// The display callback (required): called when a redisplay is posted, it renders and shows a
/// frame with `rtutSwapBuffers`. NULL removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutDisplayFunc(func: RTUTvoidfunc) {
    with(|r| r.callbacks.display = func);
}

/// The reshape callback: called with the window's size in pixels when the window is first
/// shown and whenever it changes (the frame buffer follows it; a redisplay is posted). NULL
/// removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutReshapeFunc(func: RTUTreshapefunc) {
    with(|r| r.callbacks.reshape = func);
}

/// The keyboard callback: called for each key that types an ASCII character (and for Escape 27,
/// Enter 13, Backspace 8, Tab 9 and Delete 127), with the pointer's position in pixels from the
/// window's top left. NULL removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutKeyboardFunc(func: RTUTkeyboardfunc) {
    with(|r| r.callbacks.keyboard = func);
}

/// The mouse callback: called when a button goes down or up, with the button
/// (`RTUT_LEFT_BUTTON`, `RTUT_MIDDLE_BUTTON`, `RTUT_RIGHT_BUTTON`), the state (`RTUT_DOWN`,
/// `RTUT_UP`) and the position in pixels from the window's top left, which is the frame
/// buffer's: `rtPick(x, y, ...)` tells what is there. NULL removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutMouseFunc(func: RTUTmousefunc) {
    with(|r| r.callbacks.mouse = func);
}

/// The idle callback: called whenever no redisplay is posted and no event is waiting, for
/// animation (it edits the scene and calls `rtutPostRedisplay`). NULL removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutIdleFunc(func: RTUTvoidfunc) {
    with(|r| r.callbacks.idle = func);
}

/// Asks for the display callback to be called once more, as soon as the loop can.
#[unsafe(no_mangle)]
pub extern "C" fn rtutPostRedisplay() {
    with(|r| r.redisplay = true);
}

/// Renders a frame of the scene as it is now (as `rtSwapBuffers` does, frame semantics and
/// all) at the window's size in pixels with `rtSwapBuffersKept`, whose frame buffer becomes the
/// context's (so `rtPick` takes the window's pixels), and shows it; headless, writes it as the
/// next PNG file instead (`rtWritePNG`, whose `RT_IO_ERROR` a file that cannot be written
/// records, the frame rendered all the same). Call it from the callbacks of `rtutMainLoop`
/// (`RT_INVALID_OPERATION` outside it, or without a window). A frame `rtSwapBuffersKept`
/// refuses records its error under that name and changes nothing.
#[unsafe(no_mangle)]
pub extern "C" fn rtutSwapBuffers() {
    if let Err(error) = with(|r| r.swap_buffers()) {
        record("rtutSwapBuffers", error);
    }
}

/// Shows the window and calls the callbacks until the window closes or `rtutLeaveMainLoop` is
/// called, then returns. `RT_INVALID_OPERATION` without a window or a display callback, or
/// inside a running loop; a window system that fails (no display it can open) is
/// `RT_INTERNAL_ERROR` with its reason. Most window systems allow one window loop per process.
/// `RTUT_SCREENSHOT=FILE.png` saves what the window showed once its first frame was on screen.
///
/// Headless, where neither `DISPLAY` nor `WAYLAND_DISPLAY` is set or `RTUT_HEADLESS` is: the
/// reshape callback once, then display whenever a redisplay is posted and idle otherwise; each
/// frame `rtutSwapBuffers` renders is written as the file `RTUT_OUTPUT-NNNN.png`, `RTUT_OUTPUT`
/// naming the files up to the dash before their number (`rtut-frame` by default, so
/// `rtut-frame-0000.png`, `rtut-frame-0001.png`, ...; `RTUT_OUTPUT=out/shot` writes
/// `out/shot-0000.png`); the loop returns after `RTUT_FRAMES` frames (default 1), or when
/// nothing is left to do.
#[unsafe(no_mangle)]
pub extern "C" fn rtutMainLoop() {
    let result = state::plan().and_then(|backend| {
        // A panic must not unwind into C.
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| state::run(backend))).unwrap_or_else(|panic| {
            let what = panic.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| panic.downcast_ref::<String>().cloned());
            Err(Error::internal(format!("the main loop panicked: {} (please report this bug)", what.unwrap_or_default())))
        })
    });
    if let Err(error) = result {
        record("rtutMainLoop", error);
    }
}

/// Ends `rtutMainLoop` once the callback that calls it returns (freeglut's
/// `glutLeaveMainLoop`): the window closes and `rtutMainLoop` returns.
#[unsafe(no_mangle)]
pub extern "C" fn rtutLeaveMainLoop() {
    with(|r| r.leave = true);
}
