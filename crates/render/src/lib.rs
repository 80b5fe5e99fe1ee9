//! # raystage-render
//!
//! The renderer of raystage: it turns geometry and a camera into a finished image. Today that is
//! the first frame: primary rays traced tile by tile in parallel ([`render_tiles`]), eye-light
//! shading ([`EyeLight`]), a linear-light [`Film`] encoded to sRGB PNG, and [`FrameStats`].
//! [`render_frame`] runs the whole frame.
//!
//! Not in here: acceleration structures and ray/triangle tests (`raystage-kernel`), the retained
//! scene, lights and shader parameters (the planned `raystage-scene`), and anything that talks to
//! users (the CLI, the C ABI, the HTTP server). Integrators beyond eye light, sampling,
//! accumulation and tone mapping are planned and will live here.

mod camera;
mod error;
mod eyelight;
mod film;
mod frame;
mod srgb;
mod tiles;

pub use camera::Camera;
pub use error::Error;
pub use eyelight::EyeLight;
pub use film::Film;
pub use frame::{FrameStats, Geometry, render_frame};
pub use tiles::{TILE_SIZE, Tile, per_pixel, render_tiles};
