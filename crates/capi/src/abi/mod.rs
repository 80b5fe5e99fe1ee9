//! The C ABI: every `extern "C"` function and constant of `rt.h`, grouped by topic. Each function
//! converts its arguments, reading C pointers through the helpers of the crate's `boundary`
//! module, and hands the call to the context through that module.
#![allow(non_snake_case)]

pub mod camera;
pub mod classes;
pub mod cluster;
pub mod enums;
pub mod errors;
pub mod frames;
pub mod geometry;
pub mod instances;
pub mod matrices;
pub mod objects;
pub mod parameters;
pub mod rendering;
pub mod shaders;
pub mod state;
pub mod textures;
pub mod types;

pub use camera::*;
pub use classes::*;
pub use cluster::*;
pub use enums::*;
pub use errors::*;
pub use frames::*;
pub use geometry::*;
pub use instances::*;
pub use matrices::*;
pub use objects::*;
pub use parameters::*;
pub use rendering::*;
pub use shaders::*;
pub use state::*;
pub use textures::*;
pub use types::*;
