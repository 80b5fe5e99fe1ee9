//! The scalar types of the C ABI, named like OpenGL's (`GLenum` → `RTenum`), so that a ported
//! program's declarations keep their shape.

/// An enumerated value: one of the `RT_*` constants.
pub type RTenum = u32;
/// A signed integer (parameter handles).
pub type RTint = i32;
/// An unsigned integer: object, instance, shader and shader class ids (0 names nothing).
pub type RTuint = u32;
/// A single-precision number.
pub type RTfloat = f32;
/// A double-precision number (the `d` variants of the calls, `rtOrtho`, `rtFrustum`): converted
/// to single precision, which raystage computes in; a value beyond single precision's range
/// is refused.
pub type RTdouble = f64;
/// A count or size (`size_t`).
pub type RTsizei = usize;
/// A truth value: 0 is false, 1 is true.
pub type RTboolean = u8;
