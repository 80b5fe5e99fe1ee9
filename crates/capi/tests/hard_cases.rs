//! NaN and infinity at the C ABI (docs/design/hard-cases.md: NaN and infinity refused at
//! every API): the calls `random_calls.rs` does not reach with them — whole matrices, products of
//! finite matrices that overflow, singular instance transforms, whole meshes — each refused with
//! `RT_INVALID_VALUE` and leaving the state as it was; and huge coordinates: a scene as large as
//! `RT_MAX_COORDINATE` renders as it does at unit scale, and geometry beyond it is refused.

mod common;

use common::{error, handle, shader};
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

/// A floor and a triangle above it, lit by a point light that casts the triangle's shadow,
/// every length scaled by `s` (the light's intensity by `s²`, so that the lighting stays), ray
/// traced; the pixels.
fn shadowed_scene(s: f32) -> Vec<u8> {
    rtResetContext();
    let (w, h) = (64usize, 48usize);
    let mut pixels = vec![0u8; w * h * 4];
    shader(c"Diffuse");
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtScalef(s, s, s);
    rtBegin(RT_QUADS);
    rtNormal3f(0.0, 1.0, 0.0);
    for (x, z) in [(-3.0, 3.0), (3.0, 3.0), (3.0, -3.0), (-3.0, -3.0)] {
        rtVertex3f(x, 0.0, z);
    }
    rtEnd();
    rtBegin(RT_TRIANGLES);
    rtNormal3f(0.0, 0.0, 1.0);
    rtVertex3f(-0.5, 0.5, 0.0);
    rtVertex3f(0.5, 0.5, 0.0);
    rtVertex3f(0.0, 1.5, 0.0);
    rtEnd();
    rtEndObject();
    rtLoadIdentity();
    rtInstantiateObject(object);
    shader(c"PointLight");
    rtParameter3f(handle(c"position"), 0.5 * s, 3.0 * s, 2.0 * s);
    let intensity = 10.0 * s * s;
    rtParameter3f(handle(c"intensity"), intensity, intensity, intensity);
    rtLookAt(0.0, 2.0 * s, 6.0 * s, 0.0, 0.5 * s, 0.0, 0.0, 1.0, 0.0);
    rtRenderMode(RT_WHITTED);
    unsafe { rtFrameBuffer(pixels.as_mut_ptr().cast(), w, h, RT_RGBA8) };
    rtSwapBuffers();
    accepted(&format!("the scene at scale {s:e}"));
    pixels
}

/// The limit is where single precision still renders correctly: the scene reaching out to
/// `RT_MAX_COORDINATE` (its camera is 6 units out) looks exactly as at unit scale, with its
/// shading and shadow. (At ten times the limit the shadows already go wrong.)
#[test]
fn a_scene_as_large_as_the_limit_renders_as_at_unit_scale() {
    let unit = shadowed_scene(1.0);
    let shaded = unit.chunks(4).filter(|p| p[0] > 20).count();
    assert!(shaded > 1000, "{shaded} lit pixels");
    let large = shadowed_scene(RT_MAX_COORDINATE / 6.0);
    let worst = unit.iter().zip(&large).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
    assert!(worst <= 2, "a channel differs by {worst}");
}

#[test]
fn geometry_beyond_the_limit_is_refused() {
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_TRIANGLES);
    rtVertex3f(0.0, 0.0, 0.0);
    rtVertex3f(RT_MAX_COORDINATE, 0.0, 0.0);
    accepted("a vertex at the limit");
    rtVertex3f(0.0, 2.0 * RT_MAX_COORDINATE, 0.0);
    let (code, message) = error();
    assert_eq!(code, RT_INVALID_VALUE);
    assert_eq!(message, "rtVertex3f: the vertex is at (0e0, 2e8, 0e0), beyond RT_MAX_COORDINATE (1e8) once transformed by the modelview matrix");
    rtVertex3d(0.0, 1e20, 0.0);
    refused("a double-precision vertex far beyond");
    rtVertex3f(0.0, -RT_MAX_COORDINATE, 0.0);
    rtEnd();
    accepted("the refused vertices were left out");
    rtScalef(1e4, 1e4, 1e4);
    rtBegin(RT_TRIANGLES);
    rtVertex3f(1e5, 0.0, 0.0);
    refused("a vertex the modelview matrix carries beyond");
    rtEnd();
    rtLoadIdentity();
    let positions = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1e9, 0.0];
    unsafe { rtTriangleMesh(positions.as_ptr(), std::ptr::null(), std::ptr::null(), std::ptr::null(), 3, [0u32, 1, 2].as_ptr(), 1) };
    refused("a mesh beyond");
    rtEndObject();
    accepted("the one triangle within the limit");
    // Matrices: a translation beyond, and an instance that a scale carries beyond.
    rtTranslatef(0.0, 0.0, 2e8);
    refused("a translation beyond the limit");
    rtScalef(10.0, 10.0, 10.0);
    assert_eq!(rtInstantiateObject(object), 0);
    let (code, message) = error();
    assert_eq!(code, RT_INVALID_VALUE);
    assert_eq!(message, "rtInstantiateObject: object 1 would reach (0e0, -1e9, 0e0), beyond RT_MAX_COORDINATE (1e8)");
    rtLoadIdentity();
    let instance = rtInstantiateObject(object);
    accepted("the object where it was defined");
    rtScalef(2.0, 1.0, 1.0);
    rtMoveInstance(instance);
    refused("moved beyond");
    rtInstanceMotion(instance);
    refused("moving beyond");
}
