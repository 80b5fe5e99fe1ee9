//! The C ABI called in-process, as a C program would: frame semantics, picking, lights, errors.
//! Each test runs on its own thread, so each has its own context.

mod common;


use common::{assert_error, assert_no_error, frame_buffer, handle, rgb, shader};
use raystage_capi::abi::*;

/// A triangle of the unit square's size centred at (x, 0, 0), facing +z.
fn triangle(x: f32) {
    rtBegin(RT_TRIANGLES);
    rtVertex3f(x - 1.0, -1.0, 0.0);
    rtVertex3f(x + 1.0, -1.0, 0.0);
    rtVertex3f(x, 1.0, 0.0);
    rtEnd();
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

    // Ray traced with no light at all, the default sky lights the square, unless turned off.
    rtRenderMode(RT_WHITTED);
    assert!(render(16) > 100, "the sky lights an unlit scene");
    rtRenderParameteri(RT_DEFAULT_LIGHTS, 0);
    assert_eq!(render(16), 0, "left dark");
    assert_eq!(rtGetRenderParameteri(RT_DEFAULT_LIGHTS), 0);
    rtRenderParameteri(RT_DEFAULT_LIGHTS, 2);
    assert_error(RT_INVALID_VALUE, "RT_DEFAULT_LIGHTS is 2");
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

#[test]
fn render_settings_are_checked_and_a_refused_value_changes_nothing() {
    let get = rtGetRenderParameteri;
    let defaults = [(RT_RENDER_MODE, RT_AUTO as RTint), (RT_SAMPLES_PER_PIXEL, 1), (RT_RAY_DEPTH, 6), (RT_LIGHT_SAMPLES, 1)];
    for (pname, value) in defaults.into_iter().chain([(RT_RUSSIAN_ROULETTE, 1), (RT_SEED, 0)]) {
        assert_eq!(get(pname), value, "default of {pname:#x}");
    }
    rtRenderMode(RT_PATH);
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, RT_MAX_SAMPLES);
    rtRenderParameteri(RT_RAY_DEPTH, 3);
    rtRenderParameteri(RT_SEED, 7);
    assert_no_error();

    rtRenderMode(RT_TRIANGLES);
    assert_error(RT_INVALID_ENUM, "rtRenderMode: 0x4 is not a render mode (RT_AUTO, RT_EYELIGHT");
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 0);
    assert_error(RT_INVALID_VALUE, "RT_SAMPLES_PER_PIXEL is 0, not in 1..=65536");
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, RT_MAX_SAMPLES + 1);
    assert_error(RT_INVALID_VALUE, "RT_SAMPLES_PER_PIXEL is 65537");
    rtRenderParameteri(RT_RAY_DEPTH, RT_MAX_RAY_DEPTH + 1);
    assert_error(RT_INVALID_VALUE, "RT_RAY_DEPTH is 65, not in 1..=64");
    rtRenderParameteri(RT_SEED, -1);
    assert_error(RT_INVALID_VALUE, "RT_SEED is -1");
    rtRenderParameteri(RT_RUSSIAN_ROULETTE, 2);
    assert_error(RT_INVALID_VALUE, "RT_RUSSIAN_ROULETTE is 2, not in 0..=1");
    rtRenderParameteri(RT_RENDER_MODE, RT_WHITTED as RTint);
    assert_error(RT_INVALID_ENUM, "RT_RENDER_MODE is set with rtRenderMode");
    rtRenderParameteri(0x9999, 1);
    assert_error(RT_INVALID_ENUM, "0x9999 is not a render parameter");
    assert_eq!(get(0x9999), 0);
    assert_error(RT_INVALID_ENUM, "rtGetRenderParameteri: 0x9999 is not a render parameter");

    let set = [(RT_RENDER_MODE, RT_PATH as RTint), (RT_SAMPLES_PER_PIXEL, RT_MAX_SAMPLES), (RT_RAY_DEPTH, 3), (RT_SEED, 7)];
    for (pname, value) in set {
        assert_eq!(get(pname), value, "{pname:#x} as last set");
    }
    rtResetContext();
    assert_eq!(get(RT_RENDER_MODE), RT_AUTO as RTint, "reset restores the defaults");
}

/// A quadrilateral with corners `c` (counter-clockwise seen from its front).
fn quad(c: [[f32; 3]; 4]) {
    rtBegin(RT_QUADS);
    for [x, y, z] in c {
        rtVertex3f(x, y, z);
    }
    rtEnd();
}

/// The mean of the red channel over rows `rows` of a `w`-wide RGBA8 image.
fn mean_red(pixels: &[u8], w: usize, rows: std::ops::Range<usize>) -> f64 {
    let n = rows.len() * w;
    rows.flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| rgb(pixels, w, x, y)[0] as f64).sum::<f64>() / n as f64
}

/// A diffuse floor under an emitting panel, with no light shader: the panel is the only light.
fn floor_under_a_glowing_panel() {
    let floor = shader(c"Diffuse");
    let panel = shader(c"Emissive");
    rtParameter3f(handle(c"emission"), 4.0, 4.0, 4.0);
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBindShader(floor);
    quad([[-8.0, 0.0, 8.0], [8.0, 0.0, 8.0], [8.0, 0.0, -8.0], [-8.0, 0.0, -8.0]]);
    rtBindShader(panel);
    quad([[-1.0, 1.5, -1.0], [1.0, 1.5, -1.0], [1.0, 1.5, 1.0], [-1.0, 1.5, 1.0]]);
    rtEndObject();
    rtInstantiateObject(object);
    rtLookAt(0.0, 4.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
}

#[test]
fn the_path_tracer_lights_the_floor_by_bounces_and_samples_reduce_its_noise() {
    floor_under_a_glowing_panel();
    let (w, h) = (32, 32);
    let pixels = frame_buffer(w, h);
    let floor = |mode| {
        rtRenderMode(mode);
        rtSwapBuffers();
        mean_red(&pixels, w, 24..32)
    };
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 16);
    // The glowing panel is a light to both: Whitted samples it, the path tracer too, and the
    // floor (lit by nothing else, the panel reflecting nothing) comes out the same in both.
    let (whitted, path) = (floor(RT_WHITTED), floor(RT_PATH));
    assert!(whitted > 30.0 && (path - whitted).abs() < 5.0, "the floor's red: {whitted} with Whitted, {path} path traced");
    rtRenderParameteri(RT_RAY_DEPTH, 1);
    assert!(floor(RT_PATH) < 5.0, "paths of one segment see the panel, not the light it sheds");
    rtRenderParameteri(RT_RAY_DEPTH, 6);
    assert_no_error();

    // Each seed gives its own noise, the same each time; more samples give less of it (in
    // linear light: sRGB bytes would stretch the dark floor's noise and clip the bright).
    let mut linear = vec![0f32; w * h * 4];
    unsafe { rtFrameBuffer(linear.as_mut_ptr().cast(), w, h, RT_RGBA32F) };
    let image = |spp, seed| {
        rtRenderParameteri(RT_SAMPLES_PER_PIXEL, spp);
        rtRenderParameteri(RT_SEED, seed);
        rtSwapBuffers();
        linear.clone()
    };
    let noise = |a: &[f32], b: &[f32]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f32>();
    let (one, one_again, other) = (image(1, 0), image(1, 0), image(1, 1));
    assert_eq!(one, one_again, "the same seed renders the same image");
    let (many, many_other) = (image(64, 0), image(64, 1));
    assert!(
        noise(&many, &many_other) * 3.0 < noise(&one, &other),
        "64 samples differ by {} between seeds, 1 sample by {}",
        noise(&many, &many_other),
        noise(&one, &other)
    );
    assert_no_error();
}

/// A white square of side 2 at the origin facing +z, as instance of its own object, in front of
/// a black wall at z = -1; the camera looks at it from (0, 0, 6). Returns the square's instance.
fn white_square_before_a_black_wall() -> RTuint {
    let white = shader(c"Constant");
    rtParameter3f(handle(c"color"), 1.0, 1.0, 1.0);
    let black = shader(c"Constant");
    rtParameter3f(handle(c"color"), 0.0, 0.0, 0.0);
    let square = rtGenObjects(2);
    let wall = square + 1;
    rtNewObject(square, RT_COMPILE);
    rtBindShader(white);
    quad([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]);
    rtEndObject();
    rtNewObject(wall, RT_COMPILE);
    rtBindShader(black);
    quad([[-20.0, -20.0, -1.0], [20.0, -20.0, -1.0], [20.0, 20.0, -1.0], [-20.0, 20.0, -1.0]]);
    rtEndObject();
    rtInstantiateObject(wall);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    rtInstantiateObject(square)
}

/// How many pixels of the middle row of a `w × h` image are neither black nor white: blurred.
fn grey_pixels(pixels: &[u8], w: usize, h: usize) -> usize {
    (0..w).filter(|&x| (30..225).contains(&rgb(pixels, w, x, h / 2)[0])).count()
}

#[test]
fn a_wide_lens_blurs_what_it_does_not_focus_on() {
    white_square_before_a_black_wall();
    let (w, h) = (32, 32);
    let pixels = frame_buffer(w, h);
    let blur = |mode| {
        rtRenderMode(mode);
        rtSwapBuffers();
        grey_pixels(&pixels, w, h)
    };
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 32);
    let sharp = blur(RT_DISTRIBUTION);
    rtLens(0.5, 2.0);
    assert_no_error();
    let blurred = blur(RT_DISTRIBUTION);
    assert!(sharp <= 2 && blurred >= 6, "{sharp} grey pixels through a pinhole, {blurred} through the lens");
    assert!(blur(RT_WHITTED) <= 2, "Whitted's ray tracer sees through a pinhole");
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    assert_eq!(blur(RT_DISTRIBUTION), blurred, "rtLookAt keeps the lens");

    let before = pixels.clone();
    for (aperture, focus, fragment) in [(-0.5, 2.0, "aperture_radius is -0.5, negative"), (0.5, f32::NAN, "[1] is NaN"), (f32::INFINITY, 1.0, "[0] is inf")] {
        rtLens(aperture, focus);
        assert_error(RT_INVALID_VALUE, fragment);
    }
    rtSwapBuffers();
    assert_eq!(pixels, before, "refused lenses change nothing");
}

#[test]
fn an_instance_in_motion_blurs_while_the_shutter_is_open() {
    let square = white_square_before_a_black_wall();
    let (w, h) = (32, 32);
    let pixels = frame_buffer(w, h);
    let blur = || {
        rtSwapBuffers();
        grey_pixels(&pixels, w, h)
    };
    rtRenderMode(RT_DISTRIBUTION);
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 32);
    rtTranslatef(-1.0, 0.0, 0.0);
    rtMoveInstance(square);
    rtLoadIdentity();
    rtTranslatef(1.0, 0.0, 0.0);
    rtInstanceMotion(square);
    assert_no_error();
    let still = blur();
    assert!(still <= 2, "the shutter takes an instant by default: {still} grey pixels");
    rtShutter(0.0, 1.0);
    let moving = blur();
    assert!(moving >= 8, "the square sweeps 2 units while the shutter is open: {moving} grey pixels");

    let before = pixels.clone();
    for (open, close, fragment) in [(0.5, 0.2, "open 0.5 and close 0.2 do not satisfy"), (0.0, 2.0, "close 2"), (f32::NAN, 1.0, "[0] is NaN")] {
        rtShutter(open, close);
        assert_error(RT_INVALID_VALUE, fragment);
    }
    rtInstanceMotion(0);
    assert_error(RT_INVALID_VALUE, "instance 0 does not exist");
    rtInstanceMotion(square + 1);
    assert_error(RT_INVALID_VALUE, &format!("instance {} does not exist", square + 1));
    rtScalef(0.0, 1.0, 1.0);
    rtInstanceMotion(square);
    assert_error(RT_INVALID_VALUE, "singular");
    rtSwapBuffers();
    assert_eq!(pixels, before, "refused calls change nothing");

    rtLoadIdentity();
    rtMoveInstance(square);
    assert!(blur() <= 2, "rtMoveInstance stops the motion");
    assert_no_error();
}

#[test]
fn channel_buffers_say_what_each_pixel_sees() {
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    triangle(-1.5);
    triangle(1.5);
    rtEndObject();
    let instance = rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let (w, h) = (64, 32);
    let _pixels = frame_buffer(w, h);
    let mut depth = vec![0f32; w * h];
    let mut normal = vec![0f32; w * h * 3];
    let mut instances = vec![7u32; w * h];
    let mut primitives = vec![7u32; w * h];
    unsafe {
        rtChannelBuffer(RT_DEPTH_CHANNEL, depth.as_mut_ptr().cast(), w, h);
        rtChannelBuffer(RT_NORMAL_CHANNEL, normal.as_mut_ptr().cast(), w, h);
        rtChannelBuffer(RT_INSTANCE_ID_CHANNEL, instances.as_mut_ptr().cast(), w, h);
        rtChannelBuffer(RT_PRIMITIVE_ID_CHANNEL, primitives.as_mut_ptr().cast(), w, h);
    }
    rtSwapBuffers();
    assert_no_error();
    // Pixel (42, 17) sees the second triangle (as rtPick says), on the plane z = 0 6 ahead: a
    // little further along its ray, off the view axis.
    let at = 17 * w + 42;
    assert!(depth[at] > 6.0 && depth[at] < 6.5, "{}", depth[at]);
    assert_eq!((&normal[at * 3..at * 3 + 3], instances[at], primitives[at]), (&[0.0, 0.0, 1.0][..], instance, 1));
    assert_eq!((depth[0], instances[0], primitives[0]), (f32::INFINITY, 0, RT_NO_PRIMITIVE), "the corner sees nothing");

    // Asynchronous frames fill them too, with the scene as the frame started.
    depth.fill(0.0);
    let frame = rtRenderFrameAsync();
    rtDeleteInstance(instance);
    assert_eq!(rtFrameWait(frame), RT_NO_ERROR);
    assert!(depth[at] > 6.0 && depth[at] < 6.5, "{}", depth[at]);
    rtFrameRelease(frame);

    // Bad input: an unknown channel, NULL with a size, a size that is not the frame buffer's.
    unsafe { rtChannelBuffer(0x1234, depth.as_mut_ptr().cast(), w, h) };
    assert_error(RT_INVALID_ENUM, "not a channel");
    unsafe { rtChannelBuffer(RT_Z_CHANNEL, std::ptr::null_mut(), w, h) };
    assert_error(RT_INVALID_VALUE, "NULL");
    let mut small = vec![0f32; 4];
    unsafe { rtChannelBuffer(RT_Z_CHANNEL, small.as_mut_ptr().cast(), 2, 2) };
    assert_no_error();
    rtSwapBuffers();
    assert_error(RT_INVALID_OPERATION, "the z channel buffer is 2 × 2 and the frame buffer 64 × 32");
    assert_eq!(small, [0.0; 4], "nothing was written");
    unsafe { rtChannelBuffer(RT_Z_CHANNEL, std::ptr::null_mut(), 0, 0) };
    rtSwapBuffers();
    assert_no_error();
}

#[test]
fn every_class_and_parameter_can_be_asked_for() {
    use std::ffi::CStr;
    let text = |p: *const std::ffi::c_char| unsafe { CStr::from_ptr(p) }.to_str().unwrap().to_string();
    let count = rtGetShaderClassCount();
    let names: Vec<String> = (0..count).map(|i| text(rtGetShaderClassName(i))).collect();
    // Surface classes first (as the scene's registry has them), then the light classes.
    let surfaces: Vec<&str> = raystage_scene::SHADER_CLASSES.iter().map(|c| c.name).collect();
    assert_eq!(&names[..surfaces.len()], &surfaces[..]);
    assert_eq!(&names[surfaces.len()..], ["PointLight", "SpotLight", "DirectionalLight", "AmbientLight", "AreaLight", "EnvironmentLight"]);
    for (i, name) in names.iter().enumerate() {
        let light = i >= surfaces.len();
        assert_eq!(rtGetShaderClassKind(i), if light { RT_LIGHT_CLASS } else { RT_SURFACE_CLASS }, "{name}");
        assert!(!text(rtGetShaderClassDoc(i)).is_empty(), "{name} is documented");
        for p in 0..rtGetShaderParameterCount(i) {
            let param = text(rtGetShaderParameterName(i, p));
            assert!(text(rtGetShaderParameterDoc(i, p)).len() > 10, "{name}.{param} is documented");
            let ty = rtGetShaderParameterType(i, p);
            assert!([RT_FLOAT, RT_FLOAT_VEC3, RT_TEXTURE_2D].contains(&ty), "{name}.{param}: {ty:#x}");
            let (mut default, mut range) = ([f32::NAN; 3], [f32::NAN; 2]);
            unsafe {
                rtGetShaderParameterDefault(i, p, default.as_mut_ptr());
                rtGetShaderParameterRange(i, p, range.as_mut_ptr());
            }
            let numbers = if ty == RT_FLOAT_VEC3 { 3 } else if ty == RT_FLOAT { 1 } else { 0 };
            assert!(default[..numbers].iter().all(|v| *v >= range[0] && *v <= range[1]), "{name}.{param}: {default:?} in {range:?}");
            // The name is one the class really takes: a shader of the class accepts a handle for it.
            if !light {
                let id = shader(&std::ffi::CString::new(name.as_str()).unwrap());
                rtBindShader(id);
                assert!(handle(&std::ffi::CString::new(param.as_str()).unwrap()) >= 0, "{name}.{param}");
            }
        }
        assert_no_error();
    }
    // Phong's exponent: the porter can tell which name is real.
    let phong = names.iter().position(|n| n == "Phong").unwrap();
    let params: Vec<String> = (0..rtGetShaderParameterCount(phong)).map(|p| text(rtGetShaderParameterName(phong, p))).collect();
    assert!(params.contains(&"shininess".to_string()) ^ params.contains(&"exponent".to_string()), "{params:?}");
    // The spot's cone: a number, 30 degrees by default, at most 90.
    let spot = names.iter().position(|n| n == "SpotLight").unwrap();
    let cone = (0..rtGetShaderParameterCount(spot)).position(|p| text(rtGetShaderParameterName(spot, p)) == "cone").unwrap();
    let (mut default, mut range) = ([0f32; 3], [0f32; 2]);
    unsafe {
        rtGetShaderParameterDefault(spot, cone, default.as_mut_ptr());
        rtGetShaderParameterRange(spot, cone, range.as_mut_ptr());
    }
    assert_eq!((rtGetShaderParameterType(spot, cone), default[0], range[1]), (RT_FLOAT, 30.0, 90.0));

    // Out of range: NULL or 0 and RT_INVALID_VALUE, and nothing written.
    assert!(rtGetShaderClassName(count).is_null());
    assert_error(RT_INVALID_VALUE, &format!("class {count} does not exist"));
    assert!(rtGetShaderParameterName(0, 999).is_null());
    assert_error(RT_INVALID_VALUE, "has no parameter 999");
    let mut untouched = [7f32; 3];
    unsafe { rtGetShaderParameterDefault(count, 0, untouched.as_mut_ptr()) };
    assert_error(RT_INVALID_VALUE, "does not exist");
    assert_eq!(untouched, [7.0; 3]);
    unsafe { rtGetShaderParameterRange(0, 0, std::ptr::null_mut()) };
    assert_error(RT_INVALID_VALUE, "range is NULL");
}

#[test]
fn the_header_documents_every_class_and_parameter() {
    use std::ffi::CStr;
    let header = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../api/include/raystage/rt.h")).unwrap();
    let text = |p: *const std::ffi::c_char| unsafe { CStr::from_ptr(p) }.to_str().unwrap().to_string();
    for c in 0..rtGetShaderClassCount() {
        let class = text(rtGetShaderClassName(c));
        assert!(header.contains(&format!("\"{class}\":")), "rt.h does not document {class}");
        let slots: Vec<String> = (0..rtGetShaderParameterCount(c)).map(|p| text(rtGetShaderParameterName(c, p))).filter(|n| n.ends_with("_texture")).collect();
        for p in 0..rtGetShaderParameterCount(c) {
            let param = text(rtGetShaderParameterName(c, p));
            // A texture's sampling parameters are documented once, for every `X_texture`.
            let sampling = slots.iter().any(|slot| param.starts_with(slot.trim_end_matches("texture")) && param != *slot);
            assert!(sampling || header.contains(&param), "rt.h does not document {class}'s {param}");
        }
    }
}

/// Where rt.h gives a number's range ("shininess (1f, the Blinn-Phong exponent, 1 to 10000)"),
/// it is the range the library takes (`rtGetShaderParameterRange`): the header does not promise
/// values the calls refuse.
#[test]
fn the_header_gives_the_ranges_the_library_takes() {
    use std::ffi::CStr;
    let header = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../api/include/raystage/rt.h")).unwrap();
    let header = header.replace("\n * ", " ");
    let text = |p: *const std::ffi::c_char| unsafe { CStr::from_ptr(p) }.to_str().unwrap().to_string();
    let mut checked = 0;
    for c in 0..rtGetShaderClassCount() {
        let class = text(rtGetShaderClassName(c));
        let Some(start) = header.find(&format!("- \"{class}\":")) else { continue };
        let entry = &header[start + 1..];
        let entry = &entry[..entry.find("- \"").unwrap_or(entry.len())];
        for p in 0..rtGetShaderParameterCount(c) {
            let param = text(rtGetShaderParameterName(c, p));
            let Some(at) = entry.match_indices(&format!("{param} (1f, ")).map(|(i, _)| i).find(|&i| !entry[..i].ends_with(|ch: char| ch.is_alphanumeric() || ch == '_')) else {
                continue;
            };
            // The range closes the parenthesis: "... A to B)".
            let inside = &entry[at..][..entry[at..].find(')').unwrap()];
            let words: Vec<&str> = inside.split([' ', ',']).filter(|w| !w.is_empty()).collect();
            let Some(to) = words.iter().rposition(|&w| w == "to") else { continue };
            let number = |w: &str| w.trim_end_matches([';', ':', '.']).parse::<f32>();
            let (Ok(least), Ok(most)) = (number(words[to - 1]), number(words[to + 1])) else { continue };
            let mut range = [0.0f32; 2];
            unsafe { rtGetShaderParameterRange(c, p, range.as_mut_ptr()) };
            assert_eq!(range, [least, most], "rt.h gives {class}'s {param} {least} to {most}; the library takes {range:?}");
            checked += 1;
        }
    }
    assert_no_error();
    assert!(checked >= 3, "only {checked} ranges found in rt.h");
}

/// `rtSwapBuffersKept` renders what `rtSwapBuffers` renders into lent memory, into a frame buffer
/// the library keeps, whose size `RT_VIEWPORT` and `rtPick` then take; `rtReadPixels` copies any
/// rectangle of it out, as bytes or floats. A refused kept frame leaves the lent frame buffer.
#[test]
fn a_kept_frame_buffer_is_read_back_as_the_lent_one_is_written() {
    let diffuse_shader = shader(c"Diffuse");
    rtBindShader(diffuse_shader);
    rtParameter3f(handle(c"diffuse"), 0.0, 1.0, 0.0);
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    triangle(1.5);
    rtEndObject();
    rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let (w, h) = (64, 32);
    let lent = frame_buffer(w, h);
    rtSwapBuffers();
    assert_no_error();

    // Refused inside a definition: the lent frame buffer stays.
    rtNewObject(object, RT_COMPILE);
    assert_eq!(rtSwapBuffersKept(16, 16), 0);
    assert_error(RT_INVALID_OPERATION, "rtSwapBuffersKept while object");
    triangle(1.5);
    rtEndObject();
    assert_eq!(rtSwapBuffersKept(0, 16), 0);
    assert_error(RT_INVALID_VALUE, "each side must be 1 to");
    let mut viewport = [0 as RTint; 4];
    unsafe { rtGetIntegerv(RT_VIEWPORT, viewport.as_mut_ptr()) };
    assert_eq!(viewport, [0, 0, w as RTint, h as RTint], "the lent frame buffer, still");

    assert_eq!(rtSwapBuffersKept(w, h), 1);
    assert_no_error();
    unsafe { rtGetIntegerv(RT_VIEWPORT, viewport.as_mut_ptr()) };
    assert_eq!(viewport, [0, 0, w as RTint, h as RTint]);
    let mut kept = vec![0u8; w * h * 4];
    unsafe { rtReadPixels(0, 0, w, h, RT_RGBA8, kept.as_mut_ptr().cast()) };
    assert_no_error();
    assert!(kept == lent, "the kept frame is the frame rendered into lent memory");
    let mut instance = 0;
    assert_eq!(unsafe { rtPick(42, 17, &mut instance, std::ptr::null_mut(), std::ptr::null_mut()) }, 1, "rtPick in the kept frame");

    // A rectangle, as floats: the triangle's green, linear, and the alpha 1.
    let mut floats = [0.0f32; 2 * 4];
    unsafe { rtReadPixels(42, 20, 2, 1, RT_RGBA32F, floats.as_mut_ptr().cast()) };
    assert_no_error();
    assert!(floats[1] > 0.3 && floats[0] < 0.05 && floats[3] == 1.0, "pixel (42, 20) reads {floats:?}");
    unsafe { rtReadPixels(63, 0, 2, 1, RT_RGBA8, kept.as_mut_ptr().cast()) };
    assert_error(RT_INVALID_VALUE, "not all inside the last frame, 64 × 32");
    unsafe { rtReadPixels(0, 0, 1, 1, RT_RGBA8, std::ptr::null_mut()) };
    assert_error(RT_INVALID_VALUE, "pixels is NULL");
    rtResetContext();
    unsafe { rtReadPixels(0, 0, 1, 1, RT_RGBA8, kept.as_mut_ptr().cast()) };
    assert_error(RT_INVALID_OPERATION, "no frame has been rendered");
}

/// `rtRecordError` records as any call does: the first error sticks, with its call's name, and
/// a code that is not an error's is refused.
#[test]
fn a_library_records_its_errors_as_calls_do() {
    unsafe { rtRecordError(RT_INVALID_OPERATION, c"rtutMainLoop".as_ptr(), c"needs a window".as_ptr()) };
    unsafe { rtRecordError(RT_INVALID_VALUE, c"rtutInit".as_ptr(), c"a later error".as_ptr()) };
    assert_error(RT_INVALID_OPERATION, "rtutMainLoop: needs a window");
    unsafe { rtRecordError(RT_NO_ERROR, c"rtutInit".as_ptr(), c"no error".as_ptr()) };
    assert_error(RT_INVALID_ENUM, "rtRecordError: 0x0 is not an error code");
    unsafe { rtRecordError(RT_IO_ERROR, std::ptr::null(), c"lost".as_ptr()) };
    assert_error(RT_INVALID_VALUE, "rtRecordError: call is NULL");
}

/// `RT_MAX_COORDINATE` bounds what a matrix places, and its translation, not its other entries:
/// rt.h says so, the matrix calls take any finite scale (a large one may place a small object
/// well within the bound), and vertices or instances placed beyond the bound are refused.
#[test]
fn the_largest_coordinate_bounds_what_matrices_place_not_their_scale() {
    let header = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../api/include/raystage/rt.h")).unwrap();
    let doc = &header[..header.find("#define RT_MAX_COORDINATE").unwrap()];
    let doc = doc[doc.rfind("/**").unwrap()..].replace("\n * ", " ");
    assert!(doc.contains("need only be finite"), "rt.h's RT_MAX_COORDINATE does not say what the matrix calls take:\n{doc}");

    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtScalef(2e8, 1.0, 1.0);
    rtScaled(1.0, -2e8, 1.0);
    let mut m = [0.0f64; 16];
    (m[0], m[5], m[10], m[15]) = (2e8, 1.0, 1.0, 1.0);
    unsafe { rtMultMatrixd(m.as_ptr()) };
    assert_no_error();
    rtBegin(RT_TRIANGLES);
    rtVertex3f(1e-9, 0.0, 0.0);
    rtVertex3f(0.0, 1e-9, 0.0);
    rtVertex3f(0.0, 0.0, 0.0);
    assert_no_error();
    rtVertex3f(1.0, 0.0, 0.0);
    assert_error(RT_INVALID_VALUE, "beyond RT_MAX_COORDINATE");
    rtEnd();
    rtEndObject();
    assert_no_error();
    rtLoadIdentity();
    rtScalef(1e10, 1.0, 1.0);
    assert_no_error();
    assert_eq!(rtInstantiateObject(object), 0, "an instance of the object, placed 1e10 times larger");
    assert_error(RT_INVALID_VALUE, "beyond RT_MAX_COORDINATE");
}
