//! # raystage
//!
//! The `raystage` command-line tool as a library: everything the binary does after parsing its
//! arguments, so that each command can be tested as a function call: `raystage render`, one
//! frame of a built-in demo scene or a glTF file written as PNG ([`render_scene`]), `raystage
//! serve`, the HTTP/JSON server ([`serve`]), `raystage report`, the accuracy report of a
//! scene ([`run_report`]), and `raystage view`, a server in-process with the viewer's window
//! on it ([`view`]). Built with the `mpi` feature, `raystage render --mpi` renders one frame
//! on every rank of an MPI job (`Cluster`, `render_scene_mpi`), and `raystage serve --mpi`
//! serves the API from rank 0 with every other rank rendering (`serve_mpi`).
//!
//! Not in here: the scene, rendering ([`raystage_render`]), the demo scenes
//! ([`raystage_demo`]), glTF import ([`raystage_gltf_import`]), the server
//! ([`raystage_server`]) and the viewer ([`raystage_client`]); this crate only wires them
//! together for a command line.

mod animate;
#[cfg(feature = "mpi")]
mod cluster;
mod render;
mod serve;
mod report;
mod view;

pub use animate::{ScenePose, Sequence, parse_frames};
pub use render::{
    AUTO_NOISE_THRESHOLD, AUTO_SAMPLES, DEFAULT_HEIGHT, DEFAULT_WIDTH, Environment, EnvironmentSource, FrameFlags, MAX_DIMENSION, MAX_THREADS, RenderJob, RenderReport, SceneSource,
    parse_demo, parse_environment, parse_switch, render_scene,
};
#[cfg(feature = "mpi")]
pub use cluster::{Cluster, Reported};
#[cfg(feature = "mpi")]
pub use render::render_scene_mpi;
pub use serve::{ServeJob, serve};
#[cfg(feature = "mpi")]
pub use serve::serve_mpi;
pub use report::{ReportJob, run_report};
pub use view::{ViewJob, view};
