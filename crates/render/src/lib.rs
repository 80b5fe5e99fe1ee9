//! # raystage-render
//!
//! The renderer of raystage: it turns a frame of the retained scene into a finished image.
//! Today that is primary rays traced in packets, tile by tile in parallel ([`render_tiles`]),
//! preview shading (Lambert with hard shadows, [`lambert`]), a sky for rays that miss
//! ([`sky`]), a linear-light [`Film`] encoded to sRGB PNG, and [`FrameStats`]. [`render_frame`]
//! runs the whole frame.
//!
//! Not in here: acceleration structures and ray/triangle tests (`raystage-kernel`), the scene and
//! its shader parameters (`raystage-scene`), and anything that talks to users (the CLI, the C
//! ABI, the HTTP server). Integrators beyond preview shading, sampling, accumulation and tone
//! mapping are planned and will live here.

mod error;
mod film;
mod frame;
pub mod lambert;
mod sky;
mod srgb;
mod tiles;

pub use error::Error;
pub use film::Film;
pub use frame::{FrameStats, render_frame};
pub use sky::sky;
pub use tiles::{TILE_SIZE, Tile, per_pixel, render_tiles};
