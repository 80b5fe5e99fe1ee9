//! # raystage-bench
//!
//! raystage's benchmark harness. Every benchmark reproduces a baseline program from
//! `bench/` (scenes, cameras, ray generators, seeds) and, when built with the `embree` feature,
//! traces the identical rays through Embree 3 in the same run, so results are reported as ratios
//! measured side by side. Benchmarks measure; they never assert timings (the tests don't either).

#[cfg(feature = "embree")]
pub mod embree;
pub mod dynamic;
pub mod kernel;
pub mod rays;
pub mod table;
