//! Instances: an object placed in the world by an affine transform (and, for motion blur, a
//! second transform at the end of the shutter).

use glam::{Affine3A, Vec3, Vec3A};
use raystage_kernel::{Aabb, Ray};

use crate::error::SceneError;
use crate::ids::ObjectId;

/// An instance of an object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Instance {
    pub object: ObjectId,
    /// Object to world at the start of the shutter.
    pub start: Affine3A,
    /// Object to world at the end of the shutter, if the instance moves during it.
    pub end: Option<Affine3A>,
}

/// Checks that a transform is finite and invertible; returns it.
pub(crate) fn validate_transform(field: &'static str, t: Affine3A) -> Result<Affine3A, SceneError> {
    let columns = t.to_cols_array();
    if let Some(index) = columns.iter().position(|c| !c.is_finite()) {
        return Err(SceneError::NotFinite { field, index });
    }
    let determinant = t.matrix3.determinant();
    let inverse = t.inverse();
    if !determinant.is_normal() || !inverse.is_finite() {
        return Err(SceneError::SingularTransform { field, determinant });
    }
    Ok(t)
}

/// An instance as a frame traces it: both directions of its transform at the frame's time.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placed {
    /// Object to world (hit points are carried out into the world with it).
    pub to_world: Affine3A,
    /// World to object.
    pub to_object: Affine3A,
    /// Whether the transform is the identity (the ray needs no transform).
    pub identity: bool,
}

impl Placed {
    /// The instance's transform at shutter time `time` in `[0, 1]`: the start transform, or for a
    /// moving instance the entry-wise blend of start and end (exact for translations; rotations
    /// of a few degrees per frame stay within a small fraction of a pixel).
    pub fn at(instance: &Instance, time: f32) -> Placed {
        let to_world = match instance.end {
            Some(end) if time > 0.0 => {
                let (a, b) = (instance.start.to_cols_array(), end.to_cols_array());
                Affine3A::from_cols_array(&std::array::from_fn(|i| a[i] + (b[i] - a[i]) * time))
            }
            _ => instance.start,
        };
        Placed { to_world, to_object: to_world.inverse(), identity: to_world == Affine3A::IDENTITY }
    }

    /// The ray in object space. The direction is not renormalised, so the ray parameter `t` of
    /// a hit is the same in both spaces.
    #[inline]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        Ray {
            origin: self.to_object.transform_point3(ray.origin),
            dir: self.to_object.transform_vector3(ray.dir),
            ..*ray
        }
    }

    /// An object-space normal in world space (by the inverse transpose), not normalised.
    #[inline]
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        if self.identity {
            return n;
        }
        Vec3::from(self.to_object.matrix3.transpose() * Vec3A::from(n))
    }
}

/// The world box of an object under a transform. Most transforms turn the object, and the box
/// around its turned `bounds` then has corners sticking out past the geometry (a tree turned by
/// 45° gets a box 1.4 times as wide as its crown): rays pass through that slack and enter the
/// instance for nothing. So a turned object with a `cover` (boxes around its parts) gets the box
/// around its turned parts instead, each part's the tight box of a turned box (Arvo 1990),
/// padded by a few ulps of the terms a turned vertex sums, for the rounding. Without a cover,
/// or unturned, it gets the box around the eight turned corners of `bounds` (the seed's
/// conservative instance bounds, docs/design/seeds.md §1.3).
pub(crate) fn world_bounds(bounds: &Aabb, cover: &[Aabb], t: &Affine3A) -> Aabb {
    if bounds.is_empty() {
        return Aabb::EMPTY;
    }
    let m = t.matrix3;
    let turned = m.x_axis.y != 0.0 || m.x_axis.z != 0.0 || m.y_axis.x != 0.0 || m.y_axis.z != 0.0 || m.z_axis.x != 0.0 || m.z_axis.y != 0.0;
    if !turned || cover.len() <= 1 {
        let (lo, hi) = (bounds.min, bounds.max);
        return (0..8).fold(Aabb::EMPTY, |b, corner| {
            let pick = |bit: usize, l: f32, h: f32| if corner >> bit & 1 == 0 { l } else { h };
            b.grow(t.transform_point3(Vec3::new(pick(0, lo.x, hi.x), pick(1, lo.y, hi.y), pick(2, lo.z, hi.z))))
        });
    }
    let reach = glam::Mat3A::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs());
    // Rounding in transforming a vertex is relative to the terms it sums, not to the sum; the
    // terms of the vertices farthest out bound those of every part's.
    let terms = reach * Vec3A::from(bounds.min.abs().max(bounds.max.abs())) + t.translation.abs();
    let pad = terms * (8.0 * f32::EPSILON);
    cover.iter().fold(Aabb::EMPTY, |b, part| {
        let centre = t.transform_point3a(Vec3A::from(part.center()));
        let half = reach * Vec3A::from(part.extent() * 0.5) + pad;
        b.union(Aabb { min: (centre - half).into(), max: (centre + half).into() })
    })
}

#[cfg(test)]
mod tests {
    use glam::{Quat, Vec3};
    use proptest::prelude::*;

    use super::*;
    use crate::Mesh;

    proptest! {
        /// A turned instance's box from its cover holds every turned vertex, and is never
        /// (beyond the padding) wider than the box around the turned corners of its bounds.
        #[test]
        fn a_cover_box_holds_the_geometry_inside_the_corner_box(
            points in prop::collection::vec((-3.0f32..3.0, -1.0f32..5.0, -2.0f32..2.0), 3..200),
            axis in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_filter("axis", |(x, y, z)| x * x + y * y + z * z > 0.01),
            angle in 0.0f32..std::f32::consts::TAU,
            scale in (0.01f32..100.0, 0.01f32..100.0, 0.01f32..100.0),
            shift in (-1e3f32..1e3, -1e3f32..1e3, -1e3f32..1e3),
        ) {
            let positions: Vec<Vec3> = points.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect();
            let n = positions.len() as u32 / 3;
            let mesh = Mesh::new(positions, (0..n).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect());
            let rotation = Quat::from_axis_angle(Vec3::new(axis.0, axis.1, axis.2).normalize(), angle);
            let t = Affine3A::from_scale_rotation_translation(Vec3::new(scale.0, scale.1, scale.2), rotation, Vec3::new(shift.0, shift.1, shift.2));
            let bounds = mesh.bounds();
            let (tight, loose) = (world_bounds(&bounds, &mesh.cover(&bounds), &t), world_bounds(&bounds, &[], &t));
            for &p in &mesh.positions[..3 * n as usize] {
                let p = t.transform_point3(p);
                prop_assert!(tight.min.cmple(p).all() && p.cmple(tight.max).all(), "{p} outside {tight:?}");
            }
            let slack = (loose.min.abs().max(loose.max.abs()) + loose.extent()) * 1e-5;
            prop_assert!((loose.min - slack).cmple(tight.min).all() && tight.max.cmple(loose.max + slack).all(), "{tight:?} wider than {loose:?}");
        }
    }
}
