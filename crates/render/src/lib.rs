//! # raystage-render
//!
//! The renderer of raystage: it turns a frame of the retained scene into an image. Camera rays
//! are traced tile by tile in parallel, neighbouring ones together; an
//! [`Integrator`] colours them (eye-light preview, Whitted, Cook's distribution ray tracing, or
//! path tracing), simulating only the effects the frame's [`EffectSet`] calls for. Samples come
//! from stratified, decorrelated per-pixel sequences and accumulate progressively
//! ([`Progressive`]) into a linear-light [`Film`] encoded to sRGB PNG; [`FrameStats`] says
//! what a frame cost; a [`Cancel`] token stops a render that nobody waits for.
//!
//! Not in here: acceleration structures and ray/triangle tests (`raystage-kernel`), the scene and
//! its shader parameters (`raystage-scene`), and anything that talks to users (the CLI, the C
//! ABI, the HTTP server).

mod bsdf;
mod cancel;
mod channels;
mod effects;
mod error;
mod film;
mod footprint;
mod integrator;
mod lights;
mod material;
mod microfacet;
mod renderer;
mod sampler;
mod settings;
mod sheen;
mod sky;
mod srgb;
mod stats;
mod texture;
mod tiles;
mod warp;

pub use cancel::Cancel;
pub use channels::{Channel, ChannelImage, NO_ID, exr_with_channels, render_channels};
pub use effects::EffectSet;
pub use error::Error;
pub use film::{Film, Look, OutputFormat, ToneMap};
pub use renderer::{Progressive, Rows, render, render_frame, render_rows, render_share};
pub use settings::{FrameSettings, Filter, Integrator, MAX_DEPTH, MAX_DIMENSION, MAX_LIGHT_SAMPLES, MAX_SAMPLES, MIN_ADAPTIVE_SAMPLES, RenderSettings, SettingsPatch};
pub use sky::sky;
pub use stats::{FrameStats, PhaseTimes, RayCounts, TaskTimes};
pub use tiles::{Share, TILE_SIZE, tasks};
