//! What RTUT keeps per thread: the window asked for, the callbacks, and the frame shown; and
//! what `rtutSwapBuffers` and `rtutMainLoop` do with it.
//!
//! `rtutSwapBuffers` renders with `rtSwapBuffersKept` at the window's size in pixels: into a
//! frame buffer the library keeps, which becomes the context's, so that `rtPick` in a mouse
//! callback takes the callback's coordinates; the window then copies the frame out with
//! `rtReadPixels`. RTUT lends the context no memory, so a resize (which changes the size of the
//! next frame) can never leave the context writing memory RTUT freed, and a refused swap
//! changes nothing. Callbacks run on the thread that called `rtutMainLoop`, whose context they
//! use, with no borrow of this module's state held while they run.

use std::cell::RefCell;
use std::ffi::{CString, c_int};
use std::os::unix::ffi::OsStrExt;
use std::path::PathBuf;

use crate::rt::{self, Error, RT_MAX_FRAMEBUFFER_SIZE};
use crate::window;
use crate::{RTUTkeyboardfunc, RTUTmousefunc, RTUTreshapefunc, RTUTvoidfunc};

/// The callbacks a program registered.
#[derive(Clone, Copy, Default)]
pub(crate) struct Callbacks {
    pub display: RTUTvoidfunc,
    pub reshape: RTUTreshapefunc,
    pub keyboard: RTUTkeyboardfunc,
    pub mouse: RTUTmousefunc,
    pub idle: RTUTvoidfunc,
}

/// What this thread's RTUT knows: the window asked for, the callbacks, and the frame shown.
#[derive(Default)]
pub(crate) struct Rtut {
    initialised: bool,
    /// Asked by `rtutInitWindowSize` (GLUT's default: 300 × 300).
    size: Option<(u32, u32)>,
    /// The window's title, once `rtutCreateWindow` made it.
    title: Option<String>,
    pub callbacks: Callbacks,
    /// A redisplay is posted: the loop calls the display callback next.
    pub redisplay: bool,
    /// `rtutLeaveMainLoop` was called.
    pub leave: bool,
    running: bool,
    /// The size of the frames `rtutSwapBuffers` renders: the window's inside in pixels.
    frame_size: (u32, u32),
    /// The last frame swapped, as the window shows it: RGBA8 sRGB, rows from the top, of its
    /// own size (the window may have been resized since).
    shown: ((u32, u32), Vec<u8>),
    /// Frames `rtutSwapBuffers` rendered, and where a headless loop writes them.
    pub swapped: u64,
    headless: Option<PathBuf>,
}

thread_local! {
    static RTUT: RefCell<Rtut> = RefCell::new(Rtut::default());
}

/// Runs `f` on this thread's RTUT state (never across a callback).
pub(crate) fn with<R>(f: impl FnOnce(&mut Rtut) -> R) -> R {
    RTUT.with(|cell| f(&mut cell.borrow_mut()))
}

/// GLUT's window size when none is asked for.
const DEFAULT_SIZE: (u32, u32) = (300, 300);

impl Rtut {
    /// `rtutInit`.
    pub fn init(&mut self) {
        self.initialised = true;
    }

    /// `rtutInitWindowSize`: each side 1 to `RT_MAX_FRAMEBUFFER_SIZE`.
    pub fn init_window_size(&mut self, width: c_int, height: c_int) -> Result<(), Error> {
        let side = 1..=RT_MAX_FRAMEBUFFER_SIZE as c_int;
        if !side.contains(&width) || !side.contains(&height) {
            return Err(Error::invalid_value(format!("a window of {width} × {height} pixels; each side must be 1 to {RT_MAX_FRAMEBUFFER_SIZE}")));
        }
        self.size = Some((width as u32, height as u32));
        Ok(())
    }

    /// `rtutCreateWindow`: the one window, id 1, shown by the main loop with a redisplay posted.
    pub fn create_window(&mut self, title: String) -> Result<c_int, Error> {
        if !self.initialised {
            return Err(Error::invalid_operation("call rtutInit first"));
        }
        if self.title.is_some() {
            return Err(Error::invalid_operation("RTUT has one window, and it exists"));
        }
        self.title = Some(title);
        self.redisplay = true;
        Ok(1)
    }

    /// Checks that a window exists, for the calls that need one.
    pub fn window(&self, what: &str) -> Result<(), Error> {
        match self.title {
            Some(_) => Ok(()),
            None => Err(Error::invalid_operation(format!("{what} needs a window: call rtutCreateWindow first"))),
        }
    }

    /// Sizes the frames to come to `width × height` pixels.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.frame_size = (width, height);
    }

    /// The size of the frames to come.
    pub fn frame_size(&self) -> (u32, u32) {
        self.frame_size
    }

    /// The last frame swapped: its size and its pixels (RGBA8, rows from the top).
    pub fn shown(&self) -> ((u32, u32), &[u8]) {
        (self.shown.0, &self.shown.1)
    }

    /// `rtutSwapBuffers`: renders a frame at the window's size into the frame buffer the library
    /// keeps, and shows it: in the window, or headless as the next PNG file. `Ok(())` when the
    /// frame was refused too: `rtSwapBuffersKept` recorded why, and nothing changed.
    pub fn swap_buffers(&mut self) -> Result<(), Error> {
        self.window("rtutSwapBuffers")?;
        if !self.running {
            return Err(Error::invalid_operation("rtutSwapBuffers shows a frame in the window: call it from a callback of rtutMainLoop"));
        }
        let (width, height) = self.frame_size;
        if !rt::swap_buffers_kept(width, height) {
            return Ok(());
        }
        match &self.headless {
            Some(name) => {
                let mut path = name.clone().into_os_string();
                path.push(format!("-{:04}.png", self.swapped));
                let path = CString::new(path.as_bytes()).expect("an environment variable holds no NUL byte");
                rt::write_png(&path);
            }
            None => self.shown = ((width, height), rt::read_frame(width, height)),
        }
        self.swapped += 1;
        Ok(())
    }
}

/// How `rtutMainLoop` runs: in a window, or headless.
pub(crate) enum Backend {
    /// A window titled so, of the size asked for; with a screenshot of it saved at the path once
    /// it shows its first frame (`RTUT_SCREENSHOT`).
    Window { title: String, size: (u32, u32), screenshot: Option<PathBuf> },
    /// No display: each frame swapped is written as `RTUT_OUTPUT-NNNN.png` (the name is kept in
    /// the state, where `rtutSwapBuffers` finds it), and the loop ends after `frames` of them.
    Headless { frames: u64 },
}

/// What `rtutMainLoop` will do, checked before it starts: a window and a display callback are
/// needed, and the loop runs once at a time. Headless where `RTUT_HEADLESS` is set or neither
/// `DISPLAY` nor `WAYLAND_DISPLAY` is; `RTUT_OUTPUT` names the headless files before their
/// `-NNNN.png` (default `rtut-frame`), `RTUT_FRAMES` how many frames a headless loop renders
/// (default 1).
pub(crate) fn plan() -> Result<Backend, Error> {
    with(|r| {
        r.window("rtutMainLoop")?;
        if r.callbacks.display.is_none() {
            return Err(Error::invalid_operation("rtutMainLoop needs a display callback: call rtutDisplayFunc first"));
        }
        if r.running {
            return Err(Error::invalid_operation("rtutMainLoop is running already"));
        }
        let env = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
        let headless = env("RTUT_HEADLESS").is_some() || (env("DISPLAY").is_none() && env("WAYLAND_DISPLAY").is_none());
        let (width, height) = r.size.unwrap_or(DEFAULT_SIZE);
        if headless {
            let frames = match env("RTUT_FRAMES") {
                Some(n) => n.to_str().and_then(|n| n.parse().ok()).filter(|&n| n > 0).ok_or_else(|| Error::invalid_value("RTUT_FRAMES must be a whole number above 0"))?,
                None => 1,
            };
            let name = env("RTUT_OUTPUT").map_or_else(|| PathBuf::from("rtut-frame"), PathBuf::from);
            r.resize(width, height);
            r.headless = Some(name);
            return Ok(Backend::Headless { frames });
        }
        let title = r.title.clone().unwrap_or_default();
        Ok(Backend::Window { title, size: (width, height), screenshot: env("RTUT_SCREENSHOT").map(PathBuf::from) })
    })
}

/// Runs the main loop `backend` says until the window closes, `rtutLeaveMainLoop` is called or,
/// headless, the frames are written (or nothing is left to do: no redisplay posted and no idle
/// callback). Callbacks are called with no state borrowed.
pub(crate) fn run(backend: Backend) -> Result<(), Error> {
    /// Marks the loop ended however it ends, a panic included.
    struct Running;
    impl Drop for Running {
        fn drop(&mut self) {
            with(|r| {
                r.running = false;
                r.headless = None;
            });
        }
    }
    with(|r| {
        r.running = true;
        r.leave = false;
    });
    let _running = Running;
    match backend {
        Backend::Window { title, size, screenshot } => window::run(title, size, screenshot),
        Backend::Headless { frames } => {
            headless(frames);
            Ok(())
        }
    }
}

/// The headless loop: the reshape callback once, then the display callback whenever a redisplay
/// is posted, else the idle callback, until `frames` frames are swapped.
fn headless(frames: u64) {
    let (reshape, (width, height)) = with(|r| (r.callbacks.reshape, r.frame_size));
    if let Some(reshape) = reshape {
        // SAFETY: a callback the program registered, called as GLUT calls it.
        unsafe { reshape(width as c_int, height as c_int) };
    }
    let first = with(|r| r.swapped);
    loop {
        let (callbacks, redisplay, leave, swapped) = with(|r| {
            let redisplay = std::mem::take(&mut r.redisplay);
            (r.callbacks, redisplay, r.leave, r.swapped)
        });
        if leave || swapped - first >= frames {
            return;
        }
        // SAFETY (both calls): callbacks the program registered, called as GLUT calls them.
        match (redisplay, callbacks.display, callbacks.idle) {
            (true, Some(display), _) => unsafe { display() },
            (_, _, Some(idle)) => unsafe { idle() },
            _ => return,
        }
    }
}
