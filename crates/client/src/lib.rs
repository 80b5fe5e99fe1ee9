//! # raystage-client
//!
//! raystage's viewer: an egui window (eframe, OpenGL) that shows the frame stream of one scene
//! of a raystage server (`/scenes/{scene}/stream`, `api/stream.md`), moves the scene's camera
//! with the mouse (left-drag orbits around the target, right- or middle-drag pans, scroll
//! zooms), chooses the integrator and the samples per pixel, follows the window's size, plays
//! a glTF scene's animations, and lists the frame statistics and the scene's objects and
//! instances.
//!
//! [`run`] opens the window; `raystage-client` and `raystage view` are thin shells around it.
//! The network runs in a background thread ([`net::connect`]) and talks to the UI
//! ([`Viewer`]) through two channels ([`Link`]), so the UI never waits on the network and tests
//! can play either side.
//!
//! Not in here: the server, which the client reaches only over the network (it has no
//! dependency on `raystage-server`), and any editing of the scene beyond its camera.

pub mod http;
pub mod net;
pub mod orbit;
pub mod protocol;
mod timeline;
mod viewer;

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use eframe::egui;

pub use http::Server;
pub use net::{Event, Frame, Link, Remote, SceneSnapshot, StreamConfig, connect};
pub use orbit::Orbit;
pub use protocol::{FrameStats, Request, Settings};
pub use viewer::{INTEGRATORS, MAX_SAMPLES, RESIZE_DEBOUNCE, ScreenshotSlot, Viewer, ViewerOptions};

/// What can go wrong.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A server address that is not `http://host:port`.
    #[error("bad server address: {0}")]
    Url(String),
    /// An option out of range.
    #[error("{0}")]
    Options(String),
    /// An HTTP request failed.
    #[error("{0}")]
    Http(String),
    /// The stream failed or closed.
    #[error("{0}")]
    Stream(String),
    /// The window could not be opened.
    #[error("cannot open the window: {0}")]
    Window(String),
    /// No screenshot was taken, or it could not be saved.
    #[error("screenshot: {0}")]
    Screenshot(String),
}

/// How to start the viewer.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// The server: `http://host:port`.
    pub server: String,
    /// The scene, or `None` for the first the server lists.
    pub scene: Option<u32>,
    /// The bearer token, if the server needs one.
    pub token: Option<String>,
    /// The integrator, or `None` for the server's choice (`whitted` if the scene has lights).
    pub integrator: Option<String>,
    /// Samples per pixel to refine to.
    pub max_samples: u32,
    /// Whether a scene that nothing lights is lit by the server's default sky.
    pub default_lights: bool,
    /// Save a screenshot of the window here once the first frame is shown, then exit.
    pub screenshot: Option<PathBuf>,
    /// Seconds to keep streaming after the first frame is shown before the screenshot.
    pub screenshot_delay: f64,
    /// The window's size in points.
    pub window_size: [f32; 2],
}

impl Default for Options {
    fn default() -> Options {
        Options {
            server: "http://127.0.0.1:8080".into(),
            scene: None,
            token: None,
            integrator: None,
            max_samples: 256,
            default_lights: true,
            screenshot: None,
            screenshot_delay: 0.0,
            window_size: [1280.0, 760.0],
        }
    }
}

/// Opens the viewer's window and returns when it is closed. Needs a display (X11 or Wayland).
pub fn run(options: Options) -> Result<(), Error> {
    let server = Server::parse(&options.server, options.token.clone())?;
    if let Some(name) = options.integrator.as_deref().filter(|name| !INTEGRATORS.contains(name)) {
        return Err(Error::Options(format!("unknown integrator `{name}`: expected one of {}", INTEGRATORS.join(", "))));
    }
    if !(options.screenshot_delay >= 0.0 && options.screenshot_delay.is_finite()) {
        return Err(Error::Options("the screenshot delay must be a number of seconds, at least 0".into()));
    }
    if options.max_samples == 0 {
        return Err(Error::Options("samples per pixel must be at least 1".into()));
    }
    let config = StreamConfig {
        server: server.clone(),
        scene: options.scene,
        settings: Settings {
            integrator: options.integrator.clone(),
            max_samples: Some(options.max_samples),
            // Sent only when off, so that the server's default stands otherwise.
            default_lights: (!options.default_lights).then_some(false),
            ..Settings::default()
        },
    };
    let slot: Option<ScreenshotSlot> = options.screenshot.as_ref().map(|_| Arc::new(Mutex::new(None)));
    let viewer_options = ViewerOptions { integrator: options.integrator.clone(), max_samples: options.max_samples, screenshot: slot.clone(), screenshot_delay: options.screenshot_delay };
    let title = match options.scene {
        Some(scene) => format!("raystage: scene {scene} on {}", server.authority),
        None => format!("raystage: {}", server.authority),
    };
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default().with_title(title).with_inner_size(options.window_size),
        ..eframe::NativeOptions::default()
    };
    eframe::run_native(
        "raystage",
        native,
        Box::new(move |cc| {
            let ctx = cc.egui_ctx.clone();
            let link = connect(config, move || ctx.request_repaint());
            Ok(Box::new(Viewer::new(link, viewer_options)))
        }),
    )
    .map_err(|e| Error::Window(e.to_string()))?;

    let (Some(path), Some(slot)) = (&options.screenshot, slot) else { return Ok(()) };
    let image = slot.lock().unwrap_or_else(|e| e.into_inner()).take();
    let image = image.ok_or_else(|| Error::Screenshot("the window closed before a frame was shown (see the messages above)".into()))?;
    let [width, height] = image.size;
    let rgba: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
    image::save_buffer(path, &rgba, width as u32, height as u32, image::ExtendedColorType::Rgba8)
        .map_err(|e| Error::Screenshot(format!("cannot write {}: {e}", path.display())))
}
