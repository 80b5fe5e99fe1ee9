//! The brute-force reference: every triangle, in index order. Slow and obviously right; the
//! property tests hold every acceleration structure to it.

use crate::prepared::PreparedRay;
use crate::ray::{Hit, Ray, closer};
use crate::triangle::{self, TriangleSource};

/// The closest hit of `ray` among all triangles of `tris` (ties broken by smaller index).
pub fn intersect(tris: &(impl TriangleSource + ?Sized), ray: &Ray) -> Option<Hit> {
    let pre = PreparedRay::new(ray);
    let mut best: Option<Hit> = None;
    for prim in 0..tris.triangle_count() as u32 {
        let v = tris.triangle(prim).map(|p| p.to_array());
        if let Some(h) = triangle::intersect(&pre, &v, ray.tfar) {
            let wins = match best {
                None => true,
                Some(b) => closer(h.t, prim, b.t, b.prim),
            };
            if wins {
                best = Some(Hit { t: h.t, prim, u: h.u, v: h.v });
            }
        }
    }
    best
}

/// Whether any triangle of `tris` is hit by `ray`.
pub fn occluded(tris: &(impl TriangleSource + ?Sized), ray: &Ray) -> bool {
    let pre = PreparedRay::new(ray);
    (0..tris.triangle_count() as u32)
        .any(|prim| triangle::intersect(&pre, &tris.triangle(prim).map(|p| p.to_array()), ray.tfar).is_some())
}
