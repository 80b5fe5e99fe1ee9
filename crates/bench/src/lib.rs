//! # raystage-bench
//!
//! raystage's benchmark harness. Every benchmark reproduces a baseline program from
//! `bench/` (scenes, cameras, ray generators, seeds) and, when built with the `embree` feature,
//! traces the identical rays through Embree 3 in the same run, so results are reported as ratios
//! measured side by side. The render benchmark instead sets the renderer's frames beside
//! raystage's own bare kernel on the same rays. Benchmarks measure; they never assert timings (the
//! tests don't either).

#[cfg(feature = "embree")]
pub mod embree;
pub mod animation;
pub mod bounces;
pub mod cluster_model;
pub mod dynamic;
pub mod kernel;
pub mod mpi;
pub mod page;
pub mod pathtrace;
pub mod plot;
pub mod rays;
pub mod render;
pub mod rtrps;
pub mod scaling;
pub mod stamp;
pub mod table;
