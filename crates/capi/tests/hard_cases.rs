//! NaN and infinity at the C ABI (DESIGN.md, "Numerical hard cases: NaN/Inf input rejected at the
//! API"): the calls `random_calls.rs` does not reach with them — whole matrices, products of
//! finite matrices that overflow, singular instance transforms, whole meshes — each refused with
//! `RT_INVALID_VALUE` and leaving the state as it was.

mod common;

use common::error;
use raystage_capi::abi::*;

#[track_caller]
fn refused(what: &str) {
    let (code, message) = error();
    assert_eq!(code, RT_INVALID_VALUE, "{what}: {message}");
}

#[track_caller]
fn accepted(what: &str) {
    let (code, message) = error();
    assert_eq!(code, RT_NO_ERROR, "{what}: {message}");
}

#[test]
fn matrices_with_nan_or_infinity_are_refused() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        for entry in 0..16 {
            let mut m = [1.0f32, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
            m[entry] = bad;
            unsafe { rtLoadMatrixf(m.as_ptr()) };
            refused(&format!("rtLoadMatrixf with {bad} at {entry}"));
            unsafe { rtMultMatrixf(m.as_ptr()) };
            refused(&format!("rtMultMatrixf with {bad} at {entry}"));
        }
    }
    // Finite factors whose product overflows.
    rtLoadIdentity();
    rtScalef(1e30, 1e30, 1e30);
    accepted("a large but finite scale");
    rtScalef(1e30, 1e30, 1e30);
    refused("a scale that overflows the matrix");
    rtTranslatef(1e38, 0.0, 0.0);
    rtTranslatef(1e38, 0.0, 0.0);
    refused("a translation that overflows");
}

#[test]
fn instances_need_finite_invertible_transforms() {
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_TRIANGLES);
    rtVertex3f(0.0, 0.0, 0.0);
    rtVertex3f(1.0, 0.0, 0.0);
    rtVertex3f(0.0, 1.0, 0.0);
    rtEnd();
    rtEndObject();
    accepted("a triangle");
    for (x, y, z) in [(0.0, 1.0, 1.0), (1e-30, 1e-30, 1e-30)] {
        rtLoadIdentity();
        rtScalef(x, y, z);
        let _ = error();
        assert_eq!(rtInstantiateObject(object), 0, "an instance with the singular scale ({x}, {y}, {z})");
        refused("a singular instance transform");
    }
    rtLoadIdentity();
    assert_ne!(rtInstantiateObject(object), 0);
    accepted("the identity");
}

#[test]
fn meshes_and_cameras_with_nan_or_infinity_are_refused() {
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    let null = std::ptr::null();
    let indices = [0u32, 1, 2];
    for bad in [f32::NAN, f32::INFINITY] {
        for entry in 0..9 {
            let mut positions = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
            positions[entry] = bad;
            unsafe { rtTriangleMesh(positions.as_ptr(), null, null, null, 3, indices.as_ptr(), 1) };
            refused(&format!("rtTriangleMesh with {bad} in position {entry}"));
            let positions = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
            let mut normals = [0.0f32, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
            normals[entry] = bad;
            unsafe { rtTriangleMesh(positions.as_ptr(), normals.as_ptr(), null, null, 3, indices.as_ptr(), 1) };
            refused(&format!("rtTriangleMesh with {bad} in normal {entry}"));
        }
        rtPerspective(45.0, bad, 0.1, 100.0);
        refused("rtPerspective with a bad aspect");
        rtLookAt(0.0, 0.0, bad, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
        refused("rtLookAt with a bad eye");
        rtLookAt(0.0, 0.0, 5.0, 0.0, 0.0, 0.0, 0.0, bad, 0.0);
        refused("rtLookAt with a bad up");
    }
    rtEndObject();
    let _ = error();
}
