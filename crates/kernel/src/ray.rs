//! Rays and hit records: plain data, no hidden allocation.

use glam::Vec3;

/// A ray segment `origin + t * dir` for `t` in the half-open interval `(tnear, tfar]`.
///
/// The direction does not need to be normalised: instanced rays are transformed into object space
/// without renormalising, so `t` is shared between world and object space. Origin and direction must
/// be finite and the direction non-zero; the API layers reject anything else before it gets here.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Hits at `t <= tnear` are ignored (use a small positive value, or a robust origin offset, to
    /// avoid re-hitting the surface a secondary ray starts on).
    pub tnear: f32,
    /// Direction of travel; any non-zero length.
    pub dir: Vec3,
    /// Hits at `t > tfar` are ignored; `f32::INFINITY` for an unbounded ray.
    pub tfar: f32,
}

impl Ray {
    /// An unbounded ray starting at `origin`: `tnear = 0`, `tfar = ∞`.
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, tnear: 0.0, dir, tfar: f32::INFINITY }
    }

    /// A ray restricted to the segment `(tnear, tfar]`.
    pub fn segment(origin: Vec3, dir: Vec3, tnear: f32, tfar: f32) -> Self {
        Ray { origin, tnear, dir, tfar }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// The closest hit of a ray: distance, primitive and barycentric coordinates.
///
/// The hit point is `(1 - u - v) * v0 + u * v1 + v * v2` for the primitive's vertices `v0, v1, v2`
/// (the convention of Embree and OpenGL).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit, in `(tnear, tfar]`.
    pub t: f32,
    /// Index of the hit triangle in the mesh the acceleration structure was built from.
    pub prim: u32,
    /// Barycentric weight of the second vertex.
    pub u: f32,
    /// Barycentric weight of the third vertex.
    pub v: f32,
    /// The triangle's unnormalised geometric normal `(v1 − v0) × (v2 − v0)` (Embree's `Ng`),
    /// from the vertices the traversal already has at hand, so shading need not fetch them.
    pub ng: Vec3,
}

/// Whether a hit at `(t, prim)` wins over the current best `(best_t, best_prim)` under the kernel's
/// deterministic order: the smaller distance first and, for exactly equal distances, the smaller
/// primitive index. Every layout and the brute-force reference use this order, so coincident
/// triangles resolve identically whatever order the traversal visits them in.
#[inline(always)]
pub(crate) fn closer(t: f32, prim: u32, best_t: f32, best_prim: u32) -> bool {
    t < best_t || (t == best_t && prim < best_prim)
}
