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

/// The world box of an object box under a transform: the box around its eight transformed
/// corners (the seed's conservative instance bounds, DIGEST §1.3).
pub(crate) fn world_bounds(bounds: &Aabb, t: &Affine3A) -> Aabb {
    if bounds.is_empty() {
        return Aabb::EMPTY;
    }
    let (lo, hi) = (bounds.min, bounds.max);
    (0..8).fold(Aabb::EMPTY, |b, corner| {
        let pick = |bit: usize, l: f32, h: f32| if corner >> bit & 1 == 0 { l } else { h };
        b.grow(t.transform_point3(Vec3::new(pick(0, lo.x, hi.x), pick(1, lo.y, hi.y), pick(2, lo.z, hi.z))))
    })
}
