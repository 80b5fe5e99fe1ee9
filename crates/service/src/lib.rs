//! # raystage-service
//!
//! What a server of scenes does, whatever protocol its clients speak: it holds scenes in slots
//! ([`AppState`], [`SceneSlot`]), each with a version that every edit advances; applies edits
//! ([`Edit`]: the JSON model's [`model::Command`]s in batches that apply all or nothing, image
//! files, glTF files, a C program's journal) under the scene's write lock, within the memory
//! budget; renders frames on a turn shared fairly between clients ([`on_a_turn`]), within the
//! memory and time budgets of [`Limits`]; keeps render [`Jobs`]; and reports what frames cost
//! ([`FrameReport`]). Nothing a request sends can panic it or leave a scene half-edited.
//!
//! Failures are an [`Error`] of an [`ErrorKind`], which each front end answers its own way (the
//! HTTP crate with a status). In a cluster, the scenes are replicated to render [`Workers`]
//! that `raystage-cluster` provides.
//!
//! Not in here: HTTP (`raystage-server`: routes, extraction, the stream, PNG responses), MPI
//! (`raystage-cluster`), the scene itself ([`raystage_scene`]) and rendering
//! ([`raystage_render`]).

mod batch;
mod budget;
mod build;
mod clock;
mod config;
mod edit;
mod error;
mod gltf;
mod jobs;
pub mod model;
mod state;
mod stats;
mod turns;
mod workers;

pub use budget::{CancelOnDrop, give_back_memory, on_a_turn, one_allocator_arena, within_budget};
pub use build::{SceneBuild, SceneStart};
pub use clock::{ClockChange, ClockState};
pub use config::{Config, Limits, Refused, usable_memory};
pub use edit::{Applied, Blob, Edit, unknown_texture};
pub use error::{Error, ErrorDetail, ErrorKind, Result};
pub use gltf::{CameraChoice, Environment, GltfAdded, add_environment, import_limits, parse_environment};
pub use jobs::{Job, JobStatus, Jobs, RenderJobInfo, Rendered};
pub use state::{AppState, RenderTurn, RunningRender, SceneSlot, StreamGuard};
pub use stats::{ClusterTimes, FrameReport, RaysJson, scene_time};
pub use turns::{Client, Urgency};
pub use workers::{Accumulate, Workers};
