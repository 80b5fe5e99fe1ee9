//! # raystage
//!
//! The `raystage` command-line tool as a library: everything the binary does after parsing its
//! arguments, so that each command can be tested as a function call. Today that is `raystage
//! render`, one frame of a built-in demo scene written as PNG ([`render_demo`]).
//!
//! Not in here: the scene, rendering ([`raystage_render`]) and the demo scenes
//! ([`raystage_demo`]); this crate only wires them together for a command line.

mod render;

pub use render::{MAX_DIMENSION, MAX_THREADS, RenderJob, RenderReport, parse_demo, parse_integrator, render_demo};
