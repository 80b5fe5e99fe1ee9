//! Per-ray constants computed once per query and shared by the box and triangle tests.

use crate::ray::Ray;

/// Factor applied to the far distance of every box test: `1 + 2·γ(3)` with `γ(n) = n·ε/(1 − n·ε)`,
/// `ε = 2⁻²⁴`. The slab distances are each computed with three roundings (difference, reciprocal,
/// product); widening the far end by this factor makes the test conservative, so a triangle
/// lying exactly on a box face (every triangle touches its leaf's box) is never culled by
/// rounding (Ize, *Robust BVH Ray Traversal*, JCGT 2013).
pub(crate) const ROBUST_FAR: f32 = 1.0 + 2.0 * GAMMA3;
const GAMMA3: f32 = 3.0 * f32::EPSILON * 0.5 / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// A ray with its per-query constants: reciprocal direction for the slab test and the shear
/// transform of the watertight triangle test (Woop, Benthin, Wald 2013).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PreparedRay {
    /// Origin components.
    pub(crate) org: [f32; 3],
    /// Exact IEEE reciprocal of the direction: `±∞` for a `±0` component. The box tests then
    /// follow Williams et al. 2005 (seed DIGEST §3.1): the sign of the reciprocal picks the near
    /// plane, so `+0` and `−0` are told apart, and a ray lying exactly in a slab plane produces
    /// `0 · ∞ = NaN` for that plane, which the tests' NaN-ignoring `min`/`max` skip, leaving the
    /// axis unconstrained: such a ray counts as inside the slab for every `t`, as it is.
    pub(crate) inv: [f32; 3],
    /// Per axis: does the ray travel towards −∞ (then a box's near plane is its max)?
    pub(crate) neg: [bool; 3],
    /// Start of the segment.
    pub(crate) tnear: f32,
    /// End of the segment as given by the caller.
    pub(crate) tfar: f32,
    /// Woop's axis permutation: `kz` is the dominant direction axis, `kx`, `ky` the others,
    /// swapped when `dir[kz] < 0` to keep the triangle winding.
    pub(crate) k: [usize; 3],
    /// Woop's shear constants `Sx = dx/dz`, `Sy = dy/dz`, `Sz = 1/dz` in the permuted frame.
    pub(crate) shear: [f32; 3],
}

impl PreparedRay {
    /// Precomputes the per-ray constants.
    #[inline]
    pub(crate) fn new(ray: &Ray) -> PreparedRay {
        let org = ray.origin.to_array();
        let dir = ray.dir.to_array();
        let inv = dir.map(|d| 1.0 / d);
        let neg = inv.map(|i| i < 0.0);
        let abs = [dir[0].abs(), dir[1].abs(), dir[2].abs()];
        let kz = if abs[0] >= abs[1] && abs[0] >= abs[2] {
            0
        } else if abs[1] >= abs[2] {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let shear = [dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]];
        PreparedRay { org, inv, neg, tnear: ray.tnear, tfar: ray.tfar, k: [kx, ky, kz], shear }
    }
}
