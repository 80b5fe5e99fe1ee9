//! Robust secondary rays: hit points with a conservative bound on their rounding error, and ray
//! origins pushed off the surface by that bound (pbrt-v4, *Physically Based Rendering*, 4th ed.,
//! §6.8 "Managing Rounding Error": `Point3fi` hit points, `OffsetRayOrigin`).
//!
//! A hit point is computed from the triangle's vertices and the kernel's barycentrics in the
//! object's own space, then carried into the world by the instance's transform: more accurate
//! than `origin + t·dir`, whose error grows with the ray's length, not with the point. Each step's
//! rounding is bounded by the usual `γ(n) = n·ε / (1 − n·ε)` terms, so the true surface lies
//! within the bound of the computed point, component by component. A ray that leaves the surface
//! starts at the computed point moved along the geometric normal by the bound's extent in that
//! direction (and one more ulp away), so it starts on the side it leaves on whatever the scale
//! of the scene: a few ulps of the point's own coordinates, not a fixed distance that is too
//! large for millimetre objects and too small a million units from the origin.

use glam::{Affine3A, Vec3};
use raystage_kernel::Ray;

use crate::frame::SurfacePoint;
use crate::instance::Placed;

/// `γ(n)` of pbrt-v4 (after Higham): a bound on the relative error of `n` chained roundings.
const fn gamma(n: u32) -> f32 {
    let e = f32::EPSILON * 0.5;
    n as f32 * e / (1.0 - n as f32 * e)
}

/// The bound of the barycentric interpolation `w0·p0 + w1·p1 + w2·p2` with `w0 = 1 − u − v`
/// computed in single precision (pbrt-v4's `Triangle::InteractionFromIntersection`).
const INTERPOLATION: f32 = gamma(7);

/// The bound of the kernel's own rounding, relative to the largest vertex coordinate of the
/// triangle. pbrt-v4 rejects hits closer than a bound on the computed distance inside its
/// triangle test; raystage's kernel returns bit-identical hits from every layout and keeps that
/// test lean, so the origin is moved far enough instead. The watertight test translates the
/// vertices to the ray's origin and shears them into the ray's frame, which mixes the
/// components: the triangle's plane, as the kernel sees it, is off by a few ulps of the largest
/// coordinate involved in every direction, however small the point's own coordinate along the
/// normal is (a floor at y = 5e-7 with vertices at x = ±1e-3, say). The bound is isotropic, and
/// independent of the ray's angle: a grazing ray meets the plane's error further along, but
/// starts proportionally further from it too. `tests/hard_cases.rs` finds four ulps too few and
/// eight enough, down to a thousandth of a radian; sixteen leaves a margin.
const KERNEL: f32 = gamma(16);

/// The hit point in the world for barycentrics `w` on the object-space triangle `tri` of an
/// instance placed by `placed`, and a bound on its absolute error per component.
#[inline(always)]
pub(crate) fn hit_point(tri: &[Vec3; 3], w: [f32; 3], placed: &Placed) -> (Vec3, Vec3, Vec3) {
    let local = tri[0] * w[0] + tri[1] * w[1] + tri[2] * w[2];
    let largest = tri[0].abs().max(tri[1].abs()).max(tri[2].abs()).max_element();
    let local_error = INTERPOLATION * ((tri[0] * w[0]).abs() + (tri[1] * w[1]).abs() + (tri[2] * w[2]).abs()) + Vec3::splat(KERNEL * largest);
    placed_hit_point(local, local_error, placed)
}

/// The world hit point, its object-space point and the world bound of its error, for the
/// object-space point `local` whose error is bounded by `local_error`, on an instance placed
/// by `placed`.
#[inline(always)]
pub(crate) fn placed_hit_point(local: Vec3, local_error: Vec3, placed: &Placed) -> (Vec3, Vec3, Vec3) {
    if placed.identity {
        return (local, local, local_error);
    }
    let (world, error) = transform_with_error(&placed.to_world, local, local_error);
    // A ray spawned here is traced in the object's space: its origin goes back through the
    // inverse transform (itself rounded), whose rounding, carried out into the world again,
    // the push off the surface must cover too.
    let (_, back) = transform_with_error(&placed.to_object, world, Vec3::ZERO);
    (world, local, error + placed.to_world.matrix3.abs().mul_vec3(back) * (1.0 + gamma(3)))
}

/// `t` applied to `p`, whose components are off by at most `error`: the result and the bound of
/// its error (pbrt-v4's `Transform::operator()(Point3fi)`: three products and three sums per
/// component, one more rounding for the matrix entries themselves).
fn transform_with_error(t: &Affine3A, p: Vec3, error: Vec3) -> (Vec3, Vec3) {
    let abs = t.matrix3.abs();
    let carried = abs.mul_vec3(error) * (1.0 + gamma(4));
    let rounded = gamma(4) * (abs.mul_vec3(p.abs()) + Vec3::from(t.translation).abs());
    (t.transform_point3(p), carried + rounded)
}

/// [`SurfacePoint::spawn_origin`] of a point at `position`, off by at most `position_error`, on
/// a surface with unit geometric normal `n`.
#[inline]
pub(crate) fn spawn_origin(position: Vec3, position_error: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    let distance = n.abs().dot(position_error);
    let offset = if n.dot(dir) < 0.0 { -n * distance } else { n * distance };
    let moved = position + offset;
    // Rounding the sum may undo part of the push: round away from the surface instead.
    Vec3::new(nudge(moved.x, offset.x), nudge(moved.y, offset.y), nudge(moved.z, offset.z))
}

/// `x` moved to the next representable number in the direction of `sign` (none for 0).
#[inline]
fn nudge(x: f32, sign: f32) -> f32 {
    if sign > 0.0 {
        x.next_up()
    } else if sign < 0.0 {
        x.next_down()
    } else {
        x
    }
}

impl SurfacePoint<'_> {
    /// Where a ray leaving the surface in direction `dir` starts: the hit point pushed along the
    /// geometric normal, to the side `dir` points to, far enough that no rounding of the point
    /// or of the ray can put it back on the surface (pbrt-v4's `OffsetRayOrigin`). Rays that
    /// start here never re-hit the triangle they leave, on either side.
    #[inline]
    pub fn spawn_origin(&self, dir: Vec3) -> Vec3 {
        spawn_origin(self.position, self.position_error, self.geometric_normal, dir)
    }

    /// An unbounded ray leaving the surface in direction `dir` (reflection, refraction,
    /// scattering): see [`SurfacePoint::spawn_origin`].
    pub fn spawn_ray(&self, dir: Vec3) -> Ray {
        Ray::new(self.spawn_origin(dir), dir)
    }
}
