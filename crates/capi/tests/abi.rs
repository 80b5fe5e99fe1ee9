//! The C ABI called in-process, as a C program would: frame semantics, picking, lights, errors.
//! Each test runs on its own thread, so each has its own context.

use std::ffi::CStr;

use raystage_capi::abi::*;

/// Takes the pending error with its message.
fn error() -> (RTenum, String) {
    let message = unsafe { CStr::from_ptr(rtGetErrorString()) }.to_string_lossy().into_owned();
    (rtGetError(), message)
}

fn assert_no_error() {
    let (code, message) = error();
    assert_eq!(code, RT_NO_ERROR, "{message}");
}

#[track_caller]
fn assert_error(expected: RTenum, fragment: &str) {
    let (code, message) = error();
    assert_eq!(code, expected, "{message}");
    assert!(message.contains(fragment), "{message:?} does not mention {fragment:?}");
}

/// Defines a class by name and a shader of it; returns the shader.
fn shader(class: &CStr) -> RTuint {
    let cid = rtGenShaderClasses(1);
    unsafe { rtNewShaderClass(cid, class.as_ptr(), std::ptr::null()) };
    let sid = rtGenShaders(1);
    rtNewShader(sid);
    sid
}

fn handle(name: &CStr) -> RTint {
    unsafe { rtParameterHandle(name.as_ptr()) }
}

/// A triangle of the unit square's size centred at (x, 0, 0), facing +z.
fn triangle(x: f32) {
    rtBegin(RT_TRIANGLES);
    rtVertex3f(x - 1.0, -1.0, 0.0);
    rtVertex3f(x + 1.0, -1.0, 0.0);
    rtVertex3f(x, 1.0, 0.0);
    rtEnd();
}

/// A frame buffer of `w × h` RGBA8 pixels, attached.
fn frame_buffer(w: usize, h: usize) -> Vec<u8> {
    let mut pixels = vec![0u8; w * h * 4];
    unsafe { rtFrameBuffer(pixels.as_mut_ptr().cast(), w, h, RT_RGBA8) };
    pixels
}

fn rgb(pixels: &[u8], w: usize, x: usize, y: usize) -> [u8; 3] {
    let i = (y * w + x) * 4;
    [pixels[i], pixels[i + 1], pixels[i + 2]]
}

#[test]
fn diffuse_red_then_green_gives_two_green_triangles() {
    let diffuse_shader = shader(c"Diffuse");
    rtBindShader(diffuse_shader);
    let diffuse = handle(c"diffuse");
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtParameter3f(diffuse, 1.0, 0.0, 0.0);
    triangle(-1.5);
    rtParameter3f(diffuse, 0.0, 1.0, 0.0);
    triangle(1.5);
    rtEndObject();
    rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let (w, h) = (64, 32);
    let pixels = frame_buffer(w, h);
    rtSwapBuffers();
    assert_no_error();
    for x in [w / 2 - 10, w / 2 + 10] {
        let [r, g, b] = rgb(&pixels, w, x, h / 2 + 4);
        assert!(g > 150 && r < 40 && b < 40, "pixel ({x}, {}) is {r} {g} {b}, not green", h / 2 + 4);
    }
}

#[test]
fn pick_names_instance_object_and_triangle() {
    let object = rtGenObjects(2) + 1;
    rtNewObject(object, RT_COMPILE);
    triangle(-1.5);
    triangle(1.5);
    rtEndObject();
    let left = rtInstantiateObject(object);
    rtTranslatef(0.0, 0.0, -20.0);
    let far = rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let _pixels = frame_buffer(64, 32);
    let (mut instance, mut obj, mut tri) = (0, 0, 0);
    assert_eq!(unsafe { rtPick(42, 17, &mut instance, &mut obj, &mut tri) }, 1);
    assert_eq!((instance, obj, tri), (left, object, 1), "the near instance's second triangle");
    assert_ne!(left, far);
    assert_eq!(unsafe { rtPick(32, 0, &mut instance, std::ptr::null_mut(), std::ptr::null_mut()) }, 0);
    assert_no_error();
    assert_eq!(unsafe { rtPick(64, 0, &mut instance, &mut obj, &mut tri) }, 0);
    assert_error(RT_INVALID_VALUE, "outside the 64 × 32 frame buffer");
}

#[test]
fn redefining_an_object_moves_every_instance() {
    rtObjectKind(RT_UNSTRUCTURED);
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    triangle(-1.5);
    rtEndObject();
    rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let _pixels = frame_buffer(64, 32);
    let hit = |x| unsafe { rtPick(x, 17, std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut()) };
    assert_eq!((hit(22), hit(42)), (1, 0));
    rtNewObject(object, RT_COMPILE);
    triangle(1.5);
    rtEndObject();
    assert_eq!((hit(22), hit(42)), (0, 1));
    assert_no_error();
}

#[test]
fn instances_move_and_go() {
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    triangle(0.0);
    rtEndObject();
    let instance = rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let _pixels = frame_buffer(64, 32);
    let hit = |x| unsafe { rtPick(x, 17, std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut()) };
    assert_eq!((hit(32), hit(52)), (1, 0));
    rtTranslatef(3.0, 0.0, 0.0);
    rtMoveInstance(instance);
    assert_eq!((hit(32), hit(52)), (0, 1));
    rtDeleteInstance(instance);
    assert_eq!(hit(52), 0);
    assert_no_error();
    rtMoveInstance(instance);
    assert_error(RT_INVALID_VALUE, &format!("instance {instance} does not exist"));
    rtScalef(0.0, 1.0, 1.0);
    assert_eq!(rtInstantiateObject(object), 0);
    assert_error(RT_INVALID_VALUE, "singular");
}

#[test]
fn a_point_light_shader_lights_the_scene_until_deleted() {
    let constant_white = shader(c"Diffuse");
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBindShader(constant_white);
    rtBegin(RT_QUADS);
    for (x, y) in [(-5.0, -5.0), (5.0, -5.0), (5.0, 5.0), (-5.0, 5.0)] {
        rtVertex3f(x, y, 0.0);
    }
    rtEnd();
    rtEndObject();
    rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let (w, h) = (32, 32);
    let pixels = frame_buffer(w, h);
    let render = |x: usize| {
        rtSwapBuffers();
        rgb(&pixels, w, x, h / 2)[0]
    };
    let eye_lit = render(16);
    let light = shader(c"PointLight");
    rtParameter3f(handle(c"position"), 3.0, 0.0, 1.0);
    rtParameter3f(handle(c"intensity"), 2.0, 2.0, 2.0);
    assert_no_error();
    let (left, right) = (render(4), render(28));
    assert!(right > left + 20, "the light at x = 3 brightens the right side: {left} vs {right}");
    rtDeleteShaders(light, 1);
    assert_eq!(render(16), eye_lit, "without lights, the eye light again");
    rtParameter3f(handle(c"position"), 0.0, 0.0, 1.0);
    assert_error(RT_INVALID_OPERATION, "no shader is bound");
}

#[test]
fn parameters_are_written_by_name_and_checked_by_count() {
    let constant = shader(c"Constant");
    rtParameter3f(handle(c"diffuseColor"), 1.0, 0.0, 0.0);
    assert_no_error();
    rtParameter1f(handle(c"color"), 1.0);
    assert_error(RT_INVALID_OPERATION, "parameter `color` of shader class `Constant` takes a colour (three numbers), not 1 number");
    rtParameter3f(handle(c"color"), f32::NAN, 0.0, 0.0);
    assert_error(RT_INVALID_VALUE, "NaN");
    rtParameter3f(0, 1.0, 1.0, 1.0);
    assert_error(RT_INVALID_VALUE, "not a parameter handle");
    assert_eq!(handle(c"color"), handle(c"color"));
    rtParameterScope(RT_PER_VERTEX);
    assert_error(RT_INVALID_ENUM, "per-vertex parameters are not supported");
    rtParameterScope(RT_PER_SHADER);
    assert_no_error();

    // A constant colour comes out exactly, in linear floats.
    rtParameter3f(handle(c"color"), 0.25, 0.5, 0.75);
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBindShader(constant);
    triangle(0.0);
    rtEndObject();
    rtInstantiateObject(object);
    let mut pixels = vec![0f32; 8 * 8 * 4];
    unsafe { rtFrameBuffer(pixels.as_mut_ptr().cast(), 8, 8, RT_RGBA32F) };
    rtSwapBuffers();
    assert_no_error();
    let centre = (4 * 8 + 4) * 4;
    assert_eq!(&pixels[centre..centre + 4], [0.25, 0.5, 0.75, 1.0]);
}

#[test]
fn unknown_shader_classes_are_refused_with_the_list() {
    let cid = rtGenShaderClasses(1);
    unsafe { rtNewShaderClass(cid, c"Cartoon".as_ptr(), c"libCartoon.so".as_ptr()) };
    assert_error(RT_INVALID_VALUE, "unknown shader class `Cartoon`: the built-in classes are Diffuse, VertexColor, Constant");
    rtNewShader(rtGenShaders(1));
    assert_error(RT_INVALID_OPERATION, "no shader class is bound");
    unsafe { rtNewShaderClass(cid, std::ptr::null(), std::ptr::null()) };
    assert_error(RT_INVALID_VALUE, "name is NULL");
}

#[test]
fn calls_in_the_wrong_state_are_refused_and_change_nothing() {
    rtVertex3f(0.0, 0.0, 0.0);
    assert_error(RT_INVALID_OPERATION, "rtVertex3f: a vertex outside rtBegin/rtEnd");
    rtBegin(RT_TRIANGLES);
    assert_error(RT_INVALID_OPERATION, "rtBegin outside rtNewObject/rtEndObject");
    rtEndObject();
    assert_error(RT_INVALID_OPERATION, "no object is being defined");
    let object = rtGenObjects(1);
    rtNewObject(object + 1, RT_COMPILE);
    assert_error(RT_INVALID_VALUE, "object 2 was not generated");
    rtNewObject(object, 0x1301);
    assert_error(RT_INVALID_ENUM, "not an object mode");
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_TRIANGLES);
    rtPushMatrix();
    assert_error(RT_INVALID_OPERATION, "rtPushMatrix: not allowed between rtBegin and rtEnd");
    rtVertex3f(0.0, 0.0, f32::INFINITY);
    assert_error(RT_INVALID_VALUE, "(x, y, z)[2] is inf");
    rtEnd();
    rtInstantiateObject(object);
    assert_error(RT_INVALID_OPERATION, "objects cannot hold instances");
    rtEndObject();
    assert_error(RT_INVALID_OPERATION, "object 1 has no triangles");
    rtInstantiateObject(object);
    assert_error(RT_INVALID_VALUE, "object 1 is not defined");
    rtSwapBuffers();
    assert_error(RT_INVALID_OPERATION, "no frame buffer");
    unsafe { rtWritePNG(c"/tmp/never.png".as_ptr()) };
    assert_error(RT_INVALID_OPERATION, "no frame has been rendered");
}

#[test]
fn the_first_error_sticks_until_read() {
    rtMatrixMode(0x1701);
    rtPopMatrix();
    assert_error(RT_INVALID_ENUM, "rtMatrixMode: 0x1701 is not a matrix mode");
    assert_no_error();
}

#[test]
fn matrix_stacks_overflow_and_underflow() {
    rtPopMatrix();
    assert_error(RT_STACK_UNDERFLOW, "only one matrix");
    for _ in 1..RT_MAX_STACK_DEPTH {
        rtPushMatrix();
    }
    assert_no_error();
    rtPushMatrix();
    assert_error(RT_STACK_OVERFLOW, "already holds 32 matrices");
    rtMatrixMode(RT_TEXTURE);
    rtPushMatrix();
    assert_no_error();
}

#[test]
fn bad_meshes_add_nothing() {
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    let positions = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let indices = [0u32, 1, 3];
    let null = std::ptr::null();
    unsafe { rtTriangleMesh(positions.as_ptr(), null, null, null, 3, indices.as_ptr(), 1) };
    assert_error(RT_INVALID_VALUE, "triangle 0 uses vertex 3, but there are 3 vertices");
    unsafe { rtTriangleMesh(null, null, null, null, 3, indices.as_ptr(), 1) };
    assert_error(RT_INVALID_VALUE, "positions is NULL");
    unsafe { rtTriangleMesh(positions.as_ptr(), null, null, null, usize::MAX / 4, indices.as_ptr(), 1) };
    assert_error(RT_INVALID_VALUE, "more than memory");
    rtEndObject();
    assert_error(RT_INVALID_OPERATION, "has no triangles");
    rtNewObject(object, RT_COMPILE);
    unsafe { rtTriangleMesh(positions.as_ptr(), null, null, null, 3, [0u32, 1, 2].as_ptr(), 1) };
    rtEndObject();
    assert_ne!(rtInstantiateObject(object), 0);
    assert_no_error();
}

#[test]
fn writing_a_png_where_it_cannot_be_written_is_an_io_error() {
    let _pixels = frame_buffer(4, 4);
    rtSwapBuffers();
    unsafe { rtWritePNG(c"/nonexistent-raystage-dir/frame.png".as_ptr()) };
    assert_error(RT_IO_ERROR, "/nonexistent-raystage-dir/frame.png");
    unsafe { rtFrameBuffer(std::ptr::null_mut(), 0, 0, RT_RGBA8) };
    rtSwapBuffers();
    assert_error(RT_INVALID_OPERATION, "no frame buffer");
    let mut pixels = [0u8; 4];
    unsafe { rtFrameBuffer(pixels.as_mut_ptr().cast(), 0, 1, RT_RGBA8) };
    assert_error(RT_INVALID_VALUE, "each side must be 1 to 16384");
}

#[test]
fn reset_forgets_everything() {
    let object = rtGenObjects(3);
    rtPushMatrix();
    rtResetContext();
    rtPopMatrix();
    assert_error(RT_STACK_UNDERFLOW, "only one matrix");
    assert_eq!(rtGenObjects(1), object, "ids start over");
}
