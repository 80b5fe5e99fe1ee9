//! RTUT, the seed's GLUT replacement: a window for a program's frames and the callbacks that
//! drive it. A GLUT program ports by renaming `glut*` to `rtut*` and calling `rtutSwapBuffers`
//! where it called `glutSwapBuffers`:
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
//! The window is the viewer's toolkit (egui on OpenGL, X11 or Wayland). Without a display
//! (neither `DISPLAY` nor `WAYLAND_DISPLAY` set, or `RTUT_HEADLESS` set) the same program runs
//! headless: `rtutMainLoop` calls the reshape callback once, then display whenever a redisplay
//! is posted and idle otherwise, writes each frame `rtutSwapBuffers` renders as
//! `RTUT_OUTPUT-NNNN.png` (`rtut-frame-0000.png`, ... by default) and returns after
//! `RTUT_FRAMES` frames (default 1), or when nothing is left to do. In a window,
//! `RTUT_SCREENSHOT=FILE.png` saves what the window showed once its first frame was on screen,
//! when the loop ends.
//!
//! Unlike GLUT, `rtutMainLoop` returns (when the window closes or `rtutLeaveMainLoop` is
//! called), so the program can clean up; it runs on the thread that calls it, whose context
//! the callbacks use. Errors are recorded as every `rt*` call's are (`rtGetError`).

use std::ffi::{c_char, c_int};

use crate::boundary::{c_str, call};
use crate::rtut::{self, RTUTkeyboardfunc, RTUTmousefunc, RTUTreshapefunc, RTUTvoidfunc};

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
    call("rtutInit", |_| {
        rtut::with(|r| r.init());
        Ok(())
    })
}

/// The size of the window's inside in pixels (each side 1 to `RT_MAX_FRAMEBUFFER_SIZE`;
/// GLUT's 300 × 300 by default), and of the frames rendered headless. Call before
/// `rtutCreateWindow`.
#[unsafe(no_mangle)]
pub extern "C" fn rtutInitWindowSize(width: c_int, height: c_int) {
    call("rtutInitWindowSize", |_| rtut::with(|r| r.init_window_size(width, height)))
}

/// Makes the window (shown when `rtutMainLoop` runs) and returns its id, 1, or 0 on error: RTUT
/// has one window, and needs `rtutInit` first. A redisplay is posted for it.
///
/// # Safety
/// `title` must be NULL (an error) or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtutCreateWindow(title: *const c_char) -> c_int {
    call("rtutCreateWindow", |_| {
        // SAFETY: the caller's promise above.
        let title = unsafe { c_str(title, "title")? }.to_string_lossy().into_owned();
        rtut::with(|r| r.create_window(title))
    })
}

/// The display callback (required): called when a redisplay is posted, it renders and shows a
/// frame with `rtutSwapBuffers`. NULL removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutDisplayFunc(func: RTUTvoidfunc) {
    rtut::with(|r| r.callbacks.display = func);
}

/// The reshape callback: called with the window's size in pixels when the window is first
/// shown and whenever it changes (the frame buffer follows it; a redisplay is posted). NULL
/// removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutReshapeFunc(func: RTUTreshapefunc) {
    rtut::with(|r| r.callbacks.reshape = func);
}

/// The keyboard callback: called for each key that types an ASCII character (and for Escape 27,
/// Enter 13, Backspace 8, Tab 9 and Delete 127), with the pointer's position in pixels from the
/// window's top left. NULL removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutKeyboardFunc(func: RTUTkeyboardfunc) {
    rtut::with(|r| r.callbacks.keyboard = func);
}

/// The mouse callback: called when a button goes down or up, with the button
/// (`RTUT_LEFT_BUTTON`, `RTUT_MIDDLE_BUTTON`, `RTUT_RIGHT_BUTTON`), the state (`RTUT_DOWN`,
/// `RTUT_UP`) and the position in pixels from the window's top left, which is the frame
/// buffer's: `rtPick(x, y, ...)` tells what is there. NULL removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutMouseFunc(func: RTUTmousefunc) {
    rtut::with(|r| r.callbacks.mouse = func);
}

/// The idle callback: called whenever no redisplay is posted and no event is waiting, for
/// animation (it edits the scene and calls `rtutPostRedisplay`). NULL removes it.
#[unsafe(no_mangle)]
pub extern "C" fn rtutIdleFunc(func: RTUTvoidfunc) {
    rtut::with(|r| r.callbacks.idle = func);
}

/// Asks for the display callback to be called once more, as soon as the loop can.
#[unsafe(no_mangle)]
pub extern "C" fn rtutPostRedisplay() {
    rtut::with(|r| r.redisplay = true);
}

/// Renders a frame of the scene as it is now (as `rtSwapBuffers` does, frame semantics and
/// all) into the window's frame buffer, which RTUT lends the context at the window's size, and
/// shows it; headless, also writes it as the next PNG file. Call it from the callbacks of
/// `rtutMainLoop` (`RT_INVALID_OPERATION` outside it, or without a window).
#[unsafe(no_mangle)]
pub extern "C" fn rtutSwapBuffers() {
    call("rtutSwapBuffers", |ctx| rtut::with(|r| r.swap_buffers(ctx)))
}

/// Shows the window and calls the callbacks until the window closes or `rtutLeaveMainLoop` is
/// called, then returns (headless: until the frames are written; see the module's
/// documentation). `RT_INVALID_OPERATION` without a window or a display callback, or inside a
/// running loop; a window system that fails (no display it can open) is `RT_INTERNAL_ERROR`
/// with its reason. Most window systems allow one window loop per process.
#[unsafe(no_mangle)]
pub extern "C" fn rtutMainLoop() {
    // The loop runs outside any `rt*` call: its callbacks make their own.
    let Some(backend) = call("rtutMainLoop", |_| rtut::plan().map(Some)) else { return };
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| rtut::run(backend))).unwrap_or_else(|panic| {
        let what = panic.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| panic.downcast_ref::<String>().cloned());
        Err(crate::error::Error::internal(format!("the main loop panicked: {} (please report this bug)", what.unwrap_or_default())))
    });
    if let Err(error) = result {
        call::<()>("rtutMainLoop", |_| Err(error));
    }
}

/// Ends `rtutMainLoop` once the callback that calls it returns (freeglut's
/// `glutLeaveMainLoop`): the window closes and `rtutMainLoop` returns.
#[unsafe(no_mangle)]
pub extern "C" fn rtutLeaveMainLoop() {
    rtut::with(|r| r.leave = true);
}
