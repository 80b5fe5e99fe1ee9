//! # raystage-kernel
//!
//! The ray-tracing kernel of raystage: rays and hits, robust ray/box and watertight ray/triangle
//! tests, BVH construction (binned SAH, multithreaded with rayon) and traversal of an 8-wide BVH
//! with SIMD kernels chosen at run time (AVX2, or a portable fallback with identical results).
//!
//! Layouts follow tinybvh's shape: each layout can be built and answers two queries, *intersect*
//! (closest hit) and *occluded* (any hit). [`Bvh2`] is the binary tree the builders make;
//! [`Bvh8`] is collapsed from it and is the one to trace with, one ray at a time or in packets of
//! rays that share an origin, and can be [refit](Bvh8::refit) when its triangles move.
//! [`BoxTree`] is the same wide layout over boxes whose contents the caller intersects: the top
//! level of a two-level scene. [`brute`] is the reference every layout is tested against.
//!
//! Not in here: scenes, instances, shaders, cameras. The kernel knows triangles and rays only.
//!
//! ```
//! use glam::Vec3;
//! use raystage_kernel::{BuildOptions, Bvh8, Ray};
//!
//! let tris = vec![[Vec3::new(-1.0, -1.0, 5.0), Vec3::new(1.0, -1.0, 5.0), Vec3::new(0.0, 1.0, 5.0)]];
//! let bvh = Bvh8::build(&tris, &BuildOptions::default());
//! let hit = bvh.intersect(&Ray::new(Vec3::ZERO, Vec3::Z)).unwrap();
//! assert_eq!((hit.t, hit.prim), (5.0, 0));
//! assert!(!bvh.occluded(&Ray::segment(Vec3::ZERO, Vec3::Z, 0.0, 4.0)));
//! ```

mod aabb;
mod boxtree;
pub mod brute;
mod build;
mod bvh2;
mod bvh8;
mod isa;
mod memory;
pub mod morton;
mod prepared;
mod ray;
mod ray_packet;
mod traverse;
mod triangle;
mod wide;

pub use aabb::Aabb;
pub use boxtree::BoxTree;
pub use build::{BuildOptions, BuildQuality, MAX_BINS, MAX_LEAF_SIZE};
pub use bvh2::Bvh2;
pub use bvh8::{Bvh8, Bvh8Stats, PACKET_SIZE};
pub use isa::Isa;
pub use memory::{huge_page_vec, prefetch};
pub use prepared::PreparedRay;
pub use ray::{Hit, Ray};
pub use ray_packet::{Entries, RayPacket};
pub use traverse::WalkCounts;
pub use triangle::{IndexedMesh, TriangleSource, geometric_normal, is_degenerate, prefetch_indexed};

/// Uniform floats in `[0, 1)` from a xorshift sequence started at `seed`: the unit tests' cheap,
/// repeatable randomness.
#[cfg(test)]
pub(crate) fn unit_floats(mut seed: u64) -> impl FnMut() -> f32 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    }
}
