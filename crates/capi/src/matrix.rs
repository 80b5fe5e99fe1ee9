//! The matrix stacks (`rtMatrixMode`, `rtPushMatrix`, ...), with OpenGL's semantics (seed: the
//! matrix stack of a scene graph, docs/design/seeds.md §1.1): every operation multiplies the top
//! matrix on the right, so the last transform named applies to the vertices first.
//!
//! raystage's matrices are affine (there is no projection matrix: the camera is set with
//! `rtPerspective` and `rtLookAt`), so each stack holds [`Affine3A`]s.

use glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};

use crate::abi::enums::{RT_MAX_COORDINATE, RT_MAX_STACK_DEPTH, RT_MODELVIEW, RT_TEXTURE};
use crate::abi::types::RTenum;
use crate::error::{Error, finite};

/// Which stack the matrix calls act on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MatrixMode {
    /// Vertices and instances.
    ModelView,
    /// Texture coordinates.
    Texture,
}

impl MatrixMode {
    /// The mode named by an `RT_*` constant.
    pub fn from_enum(mode: RTenum) -> Result<MatrixMode, Error> {
        match mode {
            RT_MODELVIEW => Ok(MatrixMode::ModelView),
            RT_TEXTURE => Ok(MatrixMode::Texture),
            _ => Err(Error::invalid_enum(format!(
                "{mode:#x} is not a matrix mode (RT_MODELVIEW or RT_TEXTURE; the camera is set with rtPerspective and rtLookAt)"
            ))),
        }
    }
}

/// One matrix stack: never empty, at most [`RT_MAX_STACK_DEPTH`] deep.
#[derive(Clone, Debug)]
pub(crate) struct MatrixStack {
    stack: Vec<Affine3A>,
}

impl Default for MatrixStack {
    /// A stack holding the identity.
    fn default() -> Self {
        MatrixStack { stack: vec![Affine3A::IDENTITY] }
    }
}

impl MatrixStack {
    /// The current (top) matrix.
    pub fn top(&self) -> Affine3A {
        *self.stack.last().expect("a matrix stack is never empty")
    }

    /// Replaces the top matrix, if every entry of `m` is finite and its translation within
    /// [`RT_MAX_COORDINATE`] (beyond, what it places could not be rendered correctly).
    pub fn load(&mut self, m: Affine3A) -> Result<(), Error> {
        if !m.is_finite() {
            return Err(Error::invalid_value("the resulting matrix would not be finite"));
        }
        if let Some(t) = Vec3::from(m.translation).to_array().into_iter().find(|t| t.abs() > RT_MAX_COORDINATE) {
            return Err(Error::invalid_value(format!(
                "the resulting matrix would translate by {t:e}, beyond RT_MAX_COORDINATE ({RT_MAX_COORDINATE:e})"
            )));
        }
        *self.stack.last_mut().expect("a matrix stack is never empty") = m;
        Ok(())
    }

    /// Multiplies the top matrix by `m` on the right.
    pub fn multiply(&mut self, m: Affine3A) -> Result<(), Error> {
        self.load(self.top() * m)
    }

    /// How many matrices the stack holds.
    pub fn depth(&self) -> usize {
        self.stack.len()
    }

    /// Pushes a copy of the top matrix.
    pub fn push(&mut self) -> Result<(), Error> {
        if self.stack.len() >= RT_MAX_STACK_DEPTH {
            return Err(Error::stack_overflow(format!("the stack already holds {RT_MAX_STACK_DEPTH} matrices")));
        }
        self.stack.push(self.top());
        Ok(())
    }

    /// Pops the top matrix.
    pub fn pop(&mut self) -> Result<(), Error> {
        if self.stack.len() == 1 {
            return Err(Error::stack_underflow("the stack holds only one matrix"));
        }
        self.stack.pop();
        Ok(())
    }
}

/// The two stacks and the mode that selects between them.
#[derive(Clone, Debug)]
pub(crate) struct Matrices {
    pub mode: MatrixMode,
    pub modelview: MatrixStack,
    pub texture: MatrixStack,
}

impl Default for Matrices {
    fn default() -> Self {
        Matrices { mode: MatrixMode::ModelView, modelview: MatrixStack::default(), texture: MatrixStack::default() }
    }
}

impl Matrices {
    /// The stack the current mode selects.
    pub fn current(&mut self) -> &mut MatrixStack {
        match self.mode {
            MatrixMode::ModelView => &mut self.modelview,
            MatrixMode::Texture => &mut self.texture,
        }
    }

    /// A texture coordinate through the texture matrix (as `(s, t, 0, 1)`, OpenGL's convention).
    pub fn transform_uv(&self, uv: Vec2) -> Vec2 {
        self.texture.top().transform_point3(uv.extend(0.0)).truncate()
    }
}

/// `rtTranslatef`'s matrix.
pub(crate) fn translation(x: f32, y: f32, z: f32) -> Result<Affine3A, Error> {
    finite("(x, y, z)", &[x, y, z])?;
    Ok(Affine3A::from_translation(Vec3::new(x, y, z)))
}

/// `rtScalef`'s matrix. Zero factors are allowed (they flatten what follows), as in OpenGL.
pub(crate) fn scaling(x: f32, y: f32, z: f32) -> Result<Affine3A, Error> {
    finite("(x, y, z)", &[x, y, z])?;
    Ok(Affine3A::from_scale(Vec3::new(x, y, z)))
}

/// `rtRotatef`'s matrix: `degrees` counter-clockwise about the axis `(x, y, z)` (any length).
pub(crate) fn rotation(degrees: f32, x: f32, y: f32, z: f32) -> Result<Affine3A, Error> {
    finite("angle", &[degrees])?;
    finite("(x, y, z)", &[x, y, z])?;
    let axis = Vec3::new(x, y, z).normalize_or_zero();
    if axis == Vec3::ZERO {
        return Err(Error::invalid_value("the rotation axis is zero (or too small to normalise)"));
    }
    Ok(Affine3A::from_axis_angle(axis, degrees.to_radians()))
}

/// A column-major 4×4 matrix as given to `rtLoadMatrixf`/`rtMultMatrixf`, which must be affine.
pub(crate) fn affine_from_columns(m: &[f32; 16]) -> Result<Affine3A, Error> {
    finite("m", m)?;
    let m = Mat4::from_cols_array(m);
    if m.row(3) != Vec4::W {
        return Err(Error::invalid_value(format!(
            "the matrix's last row is {:?}, not (0, 0, 0, 1): raystage's matrices are affine",
            m.row(3).to_array()
        )));
    }
    Ok(Affine3A::from_mat4(m))
}

/// The matrix that carries normals through `m`: the cofactor matrix of its linear part, which is
/// the inverse transpose scaled by the determinant. Unlike the inverse it exists for singular
/// matrices too; normals are normalised when shaded, so the scale does not matter.
pub(crate) fn normal_transform(m: &Affine3A) -> glam::Mat3 {
    let (a, b, c) = (Vec3::from(m.matrix3.x_axis), Vec3::from(m.matrix3.y_axis), Vec3::from(m.matrix3.z_axis));
    glam::Mat3::from_cols(b.cross(c), c.cross(a), a.cross(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::enums::{RT_STACK_OVERFLOW, RT_STACK_UNDERFLOW};

    #[test]
    fn push_and_pop_within_limits() {
        let mut s = MatrixStack::default();
        assert_eq!(s.pop().unwrap_err().code, RT_STACK_UNDERFLOW);
        for _ in 1..RT_MAX_STACK_DEPTH {
            s.push().unwrap();
        }
        assert_eq!(s.push().unwrap_err().code, RT_STACK_OVERFLOW);
        for _ in 1..RT_MAX_STACK_DEPTH {
            s.pop().unwrap();
        }
        assert_eq!(s.pop().unwrap_err().code, RT_STACK_UNDERFLOW, "a failed push changes nothing");
    }

    #[test]
    fn push_copies_and_pop_restores() {
        let mut s = MatrixStack::default();
        s.multiply(translation(1.0, 2.0, 3.0).unwrap()).unwrap();
        s.push().unwrap();
        s.multiply(scaling(2.0, 2.0, 2.0).unwrap()).unwrap();
        assert_eq!(s.top().transform_point3(Vec3::ONE), Vec3::new(3.0, 4.0, 5.0));
        s.pop().unwrap();
        assert_eq!(s.top().transform_point3(Vec3::ONE), Vec3::new(2.0, 3.0, 4.0));
    }

    #[test]
    fn the_last_transform_named_applies_first() {
        // OpenGL: translate then rotate = rotate the vertex about the origin, then translate.
        let mut s = MatrixStack::default();
        s.multiply(translation(10.0, 0.0, 0.0).unwrap()).unwrap();
        s.multiply(rotation(90.0, 0.0, 0.0, 2.0).unwrap()).unwrap();
        let p = s.top().transform_point3(Vec3::X);
        assert!((p - Vec3::new(10.0, 1.0, 0.0)).length() < 1e-6, "{p}");
    }

    #[test]
    fn bad_arguments_change_nothing() {
        let mut s = MatrixStack::default();
        assert!(rotation(30.0, 0.0, 0.0, 0.0).is_err());
        assert!(translation(f32::NAN, 0.0, 0.0).is_err());
        let huge = scaling(1e30, 1e30, 1e30).unwrap();
        s.multiply(huge).unwrap();
        assert!(s.multiply(huge).is_err(), "1e60 overflows");
        assert_eq!(s.top(), huge);
        let far = translation(0.0, 1e8, 0.0).unwrap();
        let mut s = MatrixStack::default();
        s.multiply(far).unwrap();
        let error = s.multiply(far).unwrap_err();
        assert!(error.message.contains("2e8, beyond RT_MAX_COORDINATE (1e8)"), "{}", error.message);
        assert_eq!(s.top(), far);
    }

    #[test]
    fn loaded_matrices_are_column_major_and_affine() {
        let mut m = Affine3A::from_translation(Vec3::new(1.0, 2.0, 3.0)).to_cols_array().to_vec();
        m.splice(3..3, [0.0]);
        m.splice(7..7, [0.0]);
        m.splice(11..11, [0.0]);
        m.push(1.0);
        let columns: [f32; 16] = m.try_into().unwrap();
        assert_eq!(affine_from_columns(&columns).unwrap().translation, Vec3::new(1.0, 2.0, 3.0).into());
        let mut projective = columns;
        projective[3] = 0.5;
        assert!(affine_from_columns(&projective).unwrap_err().message.contains("affine"));
    }

    #[test]
    fn normals_stay_perpendicular_under_non_uniform_scale() {
        let m = scaling(1.0, 4.0, 1.0).unwrap();
        // The surface y = x has normal (1, −1, 0); scaled, it becomes y = 4x, normal (4, −1, 0).
        let n = (normal_transform(&m) * Vec3::new(1.0, -1.0, 0.0)).normalize();
        assert!((n - Vec3::new(4.0, -1.0, 0.0).normalize()).length() < 1e-6);
        assert!(normal_transform(&scaling(0.0, 1.0, 1.0).unwrap()).is_finite());
    }

    #[test]
    fn texture_coordinates_follow_the_texture_matrix() {
        let mut m = Matrices { mode: MatrixMode::Texture, ..Matrices::default() };
        m.current().multiply(scaling(2.0, 3.0, 1.0).unwrap()).unwrap();
        assert_eq!(m.transform_uv(Vec2::new(0.5, 0.5)), Vec2::new(1.0, 1.5));
        assert_eq!(m.modelview.top(), Affine3A::IDENTITY);
    }
}
