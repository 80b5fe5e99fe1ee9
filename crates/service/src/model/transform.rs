//! Transforms in JSON: a 4×4 matrix, or translate / rotate / scale.

use glam::{Affine3A, Mat4, Quat, Vec3, Vec4};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::error::{Error, Result};

/// An object-to-world transform: either `matrix`, or any of `translate`, `rotate` (or
/// `quaternion`) and `scale`, applied as scale first, then rotation, then translation.
/// Omitted, it is the identity.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Transform {
    /// A 4×4 matrix, row by row, acting on column vectors (the translation is the last
    /// column); the last row must be `[0, 0, 0, 1]`.
    pub matrix: Option<[[f32; 4]; 4]>,
    /// A translation.
    pub translate: Option<[f32; 3]>,
    /// A rotation about an axis (as `rtRotatef`).
    pub rotate: Option<Rotation>,
    /// A rotation as a quaternion `[x, y, z, w]` (normalised here).
    pub quaternion: Option<[f32; 4]>,
    /// A uniform scale factor or one per axis.
    pub scale: Option<Scale>,
}

/// A rotation by `degrees` counter-clockwise about `axis` (any length but zero).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Rotation {
    /// The axis.
    pub axis: [f32; 3],
    /// The angle in degrees.
    pub degrees: f32,
}

/// A scale: one factor, or one per axis.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "a number or three numbers")]
pub enum Scale {
    /// The same factor on every axis.
    Uniform(f32),
    /// A factor per axis.
    PerAxis([f32; 3]),
}

impl Transform {
    /// The affine transform, checked to be finite and invertible (422 otherwise).
    pub fn to_affine(&self) -> Result<Affine3A> {
        let field = |f: &str| Some(f.to_string());
        let trs = self.translate.is_some() || self.rotate.is_some() || self.quaternion.is_some() || self.scale.is_some();
        let t = if let Some(rows) = self.matrix {
            if trs {
                return Err(Error::bad_request(field("matrix"), "give `matrix` or translate/rotate/scale, not both"));
            }
            let m = Mat4::from_cols_array_2d(&rows).transpose();
            if m.row(3) != Vec4::W {
                return Err(Error::unprocessable(field("matrix"), "the last row must be [0, 0, 0, 1]: projective transforms cannot place objects"));
            }
            Affine3A::from_mat4(m)
        } else {
            let rotation = match (self.rotate, self.quaternion) {
                (Some(_), Some(_)) => return Err(Error::bad_request(field("quaternion"), "give `rotate` or `quaternion`, not both")),
                (Some(r), None) => {
                    let axis = Vec3::from(r.axis).normalize_or_zero();
                    if axis == Vec3::ZERO {
                        return Err(Error::unprocessable(field("rotate.axis"), "the rotation axis must be finite and not zero"));
                    }
                    Quat::from_axis_angle(axis, r.degrees.to_radians())
                }
                (None, Some(q)) => {
                    let q = Quat::from_array(q);
                    if !q.is_finite() || q.length_squared() == 0.0 {
                        return Err(Error::unprocessable(field("quaternion"), "the quaternion must be finite and not zero"));
                    }
                    q.normalize()
                }
                (None, None) => Quat::IDENTITY,
            };
            let scale = match self.scale {
                Some(Scale::Uniform(s)) => Vec3::splat(s),
                Some(Scale::PerAxis(s)) => Vec3::from(s),
                None => Vec3::ONE,
            };
            Affine3A::from_scale_rotation_translation(scale, rotation, Vec3::from(self.translate.unwrap_or_default()))
        };
        check_affine(t)
    }

    /// The transform as a row-major matrix (for responses).
    pub fn rows(t: &Affine3A) -> [[f32; 4]; 4] {
        Mat4::from(*t).transpose().to_cols_array_2d()
    }
}

/// Finite and invertible, as the scene requires of an instance's transform.
fn check_affine(t: Affine3A) -> Result<Affine3A> {
    if !t.is_finite() {
        return Err(Error::unprocessable(None, "the transform is not finite"));
    }
    let determinant = t.matrix3.determinant();
    if !determinant.is_normal() || !t.inverse().is_finite() {
        return Err(Error::unprocessable(None, format!("the transform is singular (determinant {determinant:e}): a scale of zero?")));
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ErrorKind;

    #[test]
    fn trs_and_matrix_agree() {
        let trs = Transform {
            translate: Some([1.0, 2.0, 3.0]),
            rotate: Some(Rotation { axis: [0.0, 0.0, 1.0], degrees: 90.0 }),
            scale: Some(Scale::Uniform(2.0)),
            ..Transform::default()
        };
        let p = trs.to_affine().unwrap().transform_point3(Vec3::X);
        assert!((p - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5, "{p}");
        let matrix = Transform { matrix: Some([[0.0, -2.0, 0.0, 1.0], [2.0, 0.0, 0.0, 2.0], [0.0, 0.0, 2.0, 3.0], [0.0, 0.0, 0.0, 1.0]]), ..Transform::default() };
        let q = matrix.to_affine().unwrap().transform_point3(Vec3::X);
        assert!((q - p).length() < 1e-5);
        assert_eq!(Transform::rows(&matrix.to_affine().unwrap()), matrix.matrix.unwrap());
    }

    #[test]
    fn bad_transforms_are_refused() {
        let singular = Transform { scale: Some(Scale::PerAxis([1.0, 0.0, 1.0])), ..Transform::default() };
        assert_eq!(singular.to_affine().unwrap_err().kind, ErrorKind::Unprocessable);
        let projective = Transform { matrix: Some([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 1.0, 1.0]]), ..Transform::default() };
        assert_eq!(projective.to_affine().unwrap_err().detail.field.as_deref(), Some("matrix"));
        let infinite = Transform { translate: Some([f32::INFINITY, 0.0, 0.0]), ..Transform::default() };
        assert!(infinite.to_affine().is_err());
    }
}
