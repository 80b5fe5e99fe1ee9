//! The brute-force reference: every triangle that has an area, in index order. Slow and
//! obviously right; the property tests hold every acceleration structure to it. Triangles
//! without area ([`crate::is_degenerate`]) are skipped, as the builders leave them out of every
//! tree that is not refittable.

use crate::prepared::PreparedRay;
use crate::ray::{Hit, Ray, closer};
use crate::triangle::{self, TriangleSource};

/// The closest hit of `ray` among all triangles of `tris` (ties broken by smaller index).
pub fn intersect(tris: &(impl TriangleSource + ?Sized), ray: &Ray) -> Option<Hit> {
    let pre = PreparedRay::new(ray);
    let mut best: Option<Hit> = None;
    for prim in 0..tris.triangle_count() as u32 {
        let tri = tris.triangle(prim);
        if triangle::is_degenerate(&tri) {
            continue;
        }
        if let Some(h) = triangle::intersect(&pre, &tri.map(|p| p.to_array()), ray.tfar) {
            let wins = match best {
                None => true,
                Some(b) => closer(h.t, prim, b.t, b.prim),
            };
            if wins {
                best = Some(Hit { t: h.t, prim, u: h.u, v: h.v, ng: triangle::geometric_normal(&tri) });
            }
        }
    }
    best
}

/// Whether any triangle of `tris` is hit by `ray`.
pub fn occluded(tris: &(impl TriangleSource + ?Sized), ray: &Ray) -> bool {
    let pre = PreparedRay::new(ray);
    (0..tris.triangle_count() as u32).any(|prim| {
        let tri = tris.triangle(prim);
        !triangle::is_degenerate(&tri) && triangle::intersect(&pre, &tri.map(|p| p.to_array()), ray.tfar).is_some()
    })
}
