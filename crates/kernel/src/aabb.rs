//! Axis-aligned bounding boxes and the robust ray/box slab test.

use glam::Vec3;

use crate::prepared::{PreparedRay, widen};

/// An axis-aligned box. The empty box has `min = +∞`, `max = −∞`, so growing it by anything
/// yields that thing and no ray ever hits it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The box that contains nothing.
    pub const EMPTY: Aabb = Aabb { min: Vec3::INFINITY, max: Vec3::NEG_INFINITY };

    /// The smallest box containing the given points.
    pub fn from_points(points: &[Vec3]) -> Aabb {
        points.iter().fold(Aabb::EMPTY, |b, &p| b.grow(p))
    }

    /// The smallest box containing a triangle: [`Aabb::from_points`] for three points, written
    /// out for the builders, which take it of every triangle.
    #[inline]
    pub fn of_triangle([a, b, c]: &[Vec3; 3]) -> Aabb {
        Aabb { min: a.min(*b).min(*c), max: a.max(*b).max(*c) }
    }

    /// This box grown to contain `p`.
    #[inline]
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    /// The smallest box containing both boxes.
    #[inline]
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// Whether the box contains no point.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// Edge lengths (zero or negative for empty boxes).
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Centre point.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Surface area; zero for an empty box. The SAH weighs nodes by it.
    #[inline]
    pub fn area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.extent();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// Whether `p` lies inside or on the boundary.
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// The entry distance of the prepared ray into this box, or `None` if the ray's segment misses
    /// it. Conservative: a box that touches the segment, even in a single point or along a face the
    /// ray lies in, is never reported as missed. See [`PreparedRay`] for how ±0 directions and
    /// rounding are handled.
    #[inline]
    pub fn intersect(&self, ray: &PreparedRay, tfar: f32) -> Option<f32> {
        let lo = [self.min.x, self.min.y, self.min.z];
        let hi = [self.max.x, self.max.y, self.max.z];
        let mut tn = ray.tnear;
        let mut tf = widen(tfar);
        for a in 0..3 {
            let (near, far) = if ray.neg[a] { (hi[a], lo[a]) } else { (lo[a], hi[a]) };
            // `f32::max`/`min` return the other operand for a NaN (ray in the plane).
            tn = ((near - ray.org[a]) * ray.inv[a]).max(tn);
            tf = ((far - ray.org[a]) * ray.inv_far[a]).min(tf);
        }
        (tn <= tf).then_some(tn)
    }
}
