//! Textures through the C ABI, called in-process as a C program would: images from memory and
//! from files, procedural textures, environment maps, late binding, deletion and bad input.
//! Each test runs on its own thread, so each has its own context.

mod common;

use std::ffi::CString;

use common::{assert_error, assert_no_error, handle, rgb, shader};
use raystage_capi::abi::*;

/// An 8 × 8 RGB image in memory: left half red, right half blue.
fn red_blue() -> Vec<u8> {
    (0..8).flat_map(|_| (0..8).flat_map(|x| if x < 4 { [255, 0, 0] } else { [0, 0, 255] })).collect()
}

/// A white "Diffuse" quad filling the middle of the view, textured with `texture`, seen by the
/// eye light; returns the 32 × 32 frame.
fn textured_quad_frame(texture: RTuint) -> Vec<u8> {
    let white = shader(c"Diffuse");
    rtParameter3f(handle(c"diffuse"), 1.0, 1.0, 1.0);
    rtParameterTexture(handle(c"diffuse_texture"), texture);
    assert_no_error();
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBindShader(white);
    rtBegin(RT_QUADS);
    for (s, t, x, y) in [(0.0, 1.0, -1.0, -1.0), (1.0, 1.0, 1.0, -1.0), (1.0, 0.0, 1.0, 1.0), (0.0, 0.0, -1.0, 1.0)] {
        rtTexCoord2f(s, t);
        rtVertex3f(x, y, 0.0);
    }
    rtEnd();
    rtEndObject();
    rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    rtPerspective(20.0, 1.0, 0.1, 100.0);
    rtRenderMode(RT_EYELIGHT);
    swap(32, 32)
}

/// Renders a `w × h` RGBA8 frame.
fn swap(w: usize, h: usize) -> Vec<u8> {
    let mut pixels = vec![0u8; w * h * 4];
    unsafe { rtFrameBuffer(pixels.as_mut_ptr().cast(), w, h, RT_RGBA8) };
    rtSwapBuffers();
    assert_no_error();
    pixels
}


#[test]
fn an_image_from_memory_colours_a_quad_and_follows_its_redefinition() {
    let texture = rtGenTextures(1);
    rtBindTexture(RT_TEXTURE_2D, texture);
    unsafe { rtTexImage2D(RT_TEXTURE_2D, 0, RT_SRGB8 as RTint, 8, 8, 0, RT_RGB, RT_UNSIGNED_BYTE, red_blue().as_ptr().cast()) };
    assert_no_error();
    let pixels = textured_quad_frame(texture);
    assert_eq!((rgb(&pixels, 32, 12, 16), rgb(&pixels, 32, 20, 16)), ([255, 0, 0], [0, 0, 255]), "red left, blue right");

    // Late binding: a new image for the same id changes the quad in the next frame.
    let green: Vec<f32> = [0.0f32, 1.0, 0.0].repeat(4);
    unsafe { rtTexImage2D(RT_TEXTURE_2D, 0, RT_RGB32F as RTint, 2, 2, 0, RT_RGB, RT_FLOAT, green.as_ptr().cast()) };
    assert_no_error();
    let pixels = swap(32, 32);
    assert_eq!((rgb(&pixels, 32, 12, 16), rgb(&pixels, 32, 20, 16)), ([0, 255, 0], [0, 255, 0]));

    // Deleted, the texture no longer colours the quad, which is white again.
    rtDeleteTextures(texture, 1);
    assert_no_error();
    let pixels = swap(32, 32);
    assert!(rgb(&pixels, 32, 12, 16).iter().all(|&c| c > 250), "{:?}", rgb(&pixels, 32, 12, 16));
}

#[test]
fn linear_and_srgb_bytes_are_read_as_opengl_reads_them() {
    // sRGB 188 is linear 0.5, which the frame buffer encodes back as 188; linear 188/255 is
    // brighter (0.74 encodes as 224).
    let texture = rtGenTextures(2);
    for (id, internal) in [(texture, RT_SRGB8), (texture + 1, RT_RGB8)] {
        rtBindTexture(RT_TEXTURE_2D, id);
        unsafe { rtTexImage2D(RT_TEXTURE_2D, 0, internal as RTint, 1, 1, 0, RT_LUMINANCE, RT_UNSIGNED_BYTE, [188u8].as_ptr().cast()) };
        assert_no_error();
    }
    let pixels = textured_quad_frame(texture);
    let [r, g, b] = rgb(&pixels, 32, 16, 16);
    assert!((187..=189).contains(&r) && r == g && g == b, "sRGB grey: {r} {g} {b}");
    rtParameterTexture(handle(c"diffuse_texture"), texture + 1);
    let pixels = swap(32, 32);
    let [r, ..] = rgb(&pixels, 32, 16, 16);
    assert!((222..=226).contains(&r), "linear grey: {r}");
}

#[test]
fn a_checker_texture_alternates_its_colours() {
    let texture = rtGenTextures(1);
    rtBindTexture(RT_TEXTURE_2D, texture);
    // Cubes of edge 0.5 in texture coordinates: a 2 × 2 board over the quad.
    unsafe { rtTexChecker(RT_TEXTURE_2D, [1.0f32, 1.0, 0.0].as_ptr(), [0.0f32, 0.0, 1.0].as_ptr(), 2.0) };
    assert_no_error();
    let pixels = textured_quad_frame(texture);
    let corners = [rgb(&pixels, 32, 12, 12), rgb(&pixels, 32, 20, 12), rgb(&pixels, 32, 12, 20), rgb(&pixels, 32, 20, 20)];
    let yellow = |c: [u8; 3]| c[0] > 240 && c[1] > 240 && c[2] < 10;
    let blue = |c: [u8; 3]| c[0] < 10 && c[1] < 10 && c[2] > 240;
    assert!(yellow(corners[0]) == blue(corners[1]) && blue(corners[1]) == blue(corners[2]) && yellow(corners[3]) == yellow(corners[0]), "{corners:?}");
    assert!(yellow(corners[0]) || blue(corners[0]), "{corners:?}");
}

#[test]
fn an_hdr_file_lights_the_scene_as_an_environment_map() {
    let sky = image::Rgb32FImage::from_pixel(16, 8, image::Rgb([0.25, 0.5, 1.0]));
    let path = std::env::temp_dir().join(format!("raystage-capi-environment-{}.hdr", std::process::id()));
    image::DynamicImage::from(sky).save(&path).unwrap();
    let texture = rtGenTextures(1);
    rtBindTexture(RT_TEXTURE_2D, texture);
    let c_path = CString::new(path.to_str().unwrap()).unwrap();
    unsafe { rtTexImageFile(RT_TEXTURE_2D, c_path.as_ptr()) };
    std::fs::remove_file(&path).unwrap();
    assert_no_error();
    shader(c"EnvironmentLight");
    rtParameterTexture(handle(c"map"), texture);
    assert_no_error();
    rtLookAt(0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
    rtRenderMode(RT_PATH);
    // Nothing but the sky: every pixel is the map's colour, sRGB-encoded (0.25 → 137, 0.5 →
    // 188, 1 → 255).
    let pixels = swap(8, 8);
    for (x, y) in [(0, 0), (4, 4), (7, 7)] {
        let [r, g, b] = rgb(&pixels, 8, x, y);
        assert!(r.abs_diff(137) <= 2 && g.abs_diff(188) <= 2 && b == 255, "pixel ({x}, {y}): {r} {g} {b}");
    }
}

#[test]
fn bad_texture_calls_are_refused_and_change_nothing() {
    let pixels = red_blue();
    let image = |internal: RTenum, w: usize, format: RTenum, ty: RTenum, p: *const u8| unsafe {
        rtTexImage2D(RT_TEXTURE_2D, 0, internal as RTint, w, 8, 0, format, ty, p.cast())
    };
    image(RT_SRGB8, 8, RT_RGB, RT_UNSIGNED_BYTE, pixels.as_ptr());
    assert_error(RT_INVALID_OPERATION, "rtTexImage2D: no texture is bound: call rtBindTexture before rtTexImage2D");
    rtBindTexture(RT_TEXTURE_2D, 5);
    assert_error(RT_INVALID_VALUE, "rtBindTexture: texture 5 was not generated by rtGenTextures");
    let texture = rtGenTextures(1);
    rtBindTexture(0x1234, texture);
    assert_error(RT_INVALID_ENUM, "0x1234 is not a texture target");
    rtBindTexture(RT_TEXTURE_2D, texture);
    assert_no_error();

    image(0x1234, 8, RT_RGB, RT_UNSIGNED_BYTE, pixels.as_ptr());
    assert_error(RT_INVALID_ENUM, "0x1234 is not a texture internal format");
    image(RT_SRGB8, 8, RT_RGBA8, RT_UNSIGNED_BYTE, pixels.as_ptr());
    assert_error(RT_INVALID_ENUM, "is not a pixel format");
    image(RT_SRGB8, 8, RT_RGB, RT_FLOAT, pixels.as_ptr());
    assert_error(RT_INVALID_OPERATION, "RT_FLOAT pixels are linear");
    image(RT_SRGB8, 0, RT_RGB, RT_UNSIGNED_BYTE, pixels.as_ptr());
    assert_error(RT_INVALID_VALUE, "width is 0: a texture side is 1 to 16384");
    image(RT_SRGB8, RT_MAX_TEXTURE_SIZE + 1, RT_RGB, RT_UNSIGNED_BYTE, pixels.as_ptr());
    assert_error(RT_INVALID_VALUE, "width is 16385");
    image(RT_SRGB8, 8, RT_RGB, RT_UNSIGNED_BYTE, std::ptr::null());
    assert_error(RT_INVALID_VALUE, "pixels is NULL");
    unsafe { rtTexImage2D(RT_TEXTURE_2D, 1, RT_RGB as RTint, 8, 8, 0, RT_RGB, RT_UNSIGNED_BYTE, pixels.as_ptr().cast()) };
    assert_error(RT_INVALID_VALUE, "level is 1");
    let nan = [f32::NAN, 0.0, 0.0];
    unsafe { rtTexImage2D(RT_TEXTURE_2D, 0, RT_RGB32F as RTint, 1, 1, 0, RT_RGB, RT_FLOAT, nan.as_ptr().cast()) };
    assert_error(RT_INVALID_VALUE, "pixels[0] is NaN");
    let negative = [0.0f32, -1.0, 0.0];
    unsafe { rtTexImage2D(RT_TEXTURE_2D, 0, RT_RGB32F as RTint, 1, 1, 0, RT_RGB, RT_FLOAT, negative.as_ptr().cast()) };
    assert_error(RT_INVALID_VALUE, "texels");
    unsafe { rtTexChecker(RT_TEXTURE_2D, [1.0f32; 3].as_ptr(), [0.0f32; 3].as_ptr(), 0.0) };
    assert_error(RT_INVALID_VALUE, "rtTexChecker: texture.scale is out of range: must be positive");
    unsafe { rtTexNoise(RT_TEXTURE_2D, std::ptr::null(), [0.0f32; 3].as_ptr(), 1.0) };
    assert_error(RT_INVALID_VALUE, "a is NULL");

    let missing = CString::new("/nonexistent/raystage/sky.hdr").unwrap();
    unsafe { rtTexImageFile(RT_TEXTURE_2D, missing.as_ptr()) };
    assert_error(RT_IO_ERROR, "cannot read /nonexistent/raystage/sky.hdr");
    let garbage = std::env::temp_dir().join(format!("raystage-capi-garbage-{}.png", std::process::id()));
    std::fs::write(&garbage, b"not a PNG at all").unwrap();
    let c_garbage = CString::new(garbage.to_str().unwrap()).unwrap();
    unsafe { rtTexImageFile(RT_TEXTURE_2D, c_garbage.as_ptr()) };
    std::fs::remove_file(&garbage).unwrap();
    assert_error(RT_INVALID_VALUE, "the image cannot be read");
    // Too wide to be a texture: refused from the header, before 16385 × 1 texels are decoded.
    let wide = std::env::temp_dir().join(format!("raystage-capi-wide-{}.png", std::process::id()));
    image::RgbImage::new(RT_MAX_TEXTURE_SIZE as u32 + 1, 1).save(&wide).unwrap();
    let c_wide = CString::new(wide.to_str().unwrap()).unwrap();
    unsafe { rtTexImageFile(RT_TEXTURE_2D, c_wide.as_ptr()) };
    std::fs::remove_file(&wide).unwrap();
    assert_error(RT_INVALID_VALUE, "the image's width is 16385: a texture side is 1 to 16384");

    // Nothing above defined the texture: shaders cannot name it yet.
    shader(c"Diffuse");
    rtParameterTexture(handle(c"diffuse_texture"), texture);
    assert_error(RT_INVALID_VALUE, &format!("texture {texture} has no image"));
    rtParameterTexture(handle(c"diffuse_texture"), texture + 1);
    assert_error(RT_INVALID_VALUE, "was not generated by rtGenTextures");
    rtParameterTexture(handle(c"diffuse"), 0);
    assert_error(RT_INVALID_OPERATION, "parameter `diffuse` of shader class `Diffuse` takes a colour");
    rtParameter3f(handle(c"diffuse_texture"), 1.0, 0.0, 0.0);
    assert_error(RT_INVALID_OPERATION, "takes a texture: write it with rtParameterTexture");
    shader(c"EnvironmentLight");
    rtParameter1f(handle(c"map"), 1.0);
    assert_error(RT_INVALID_OPERATION, "parameter `map` of shader class `EnvironmentLight` takes a texture");
    rtParameterTexture(handle(c"radiance"), 0);
    assert_error(RT_INVALID_OPERATION, "takes numbers, not a texture");
    rtParameterTexture(handle(c"no_such_parameter"), 0);
    assert_no_error();
}
