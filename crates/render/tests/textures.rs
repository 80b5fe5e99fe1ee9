//! Image textures and environment maps from encoded files, as the C ABI and the HTTP API load
//! them: decoded to linear light, looked up by the renderer, and gone from the frame after the
//! texture is removed.

mod common;

use common::{pixels, render_with, shader};
use glam::{Affine3A, Vec2, Vec3};
use raystage_render::Integrator;
use raystage_scene::{Camera, Image, Light, Mesh, ObjectKind, ParamValue, Scene, Texture};

/// `image` encoded as a file of `format`.
fn file(image: image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, format).unwrap();
    bytes.into_inner()
}

/// A 2 × 2 quad facing +z at the origin, texture coordinates (0, 0) at its top left.
fn quad() -> Mesh {
    let corners = [(-1.0, 1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)];
    let mut mesh = Mesh::new(corners.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect(), vec![[0, 3, 2], [0, 2, 1]]);
    mesh.uvs = vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
    mesh
}

#[test]
fn a_png_texture_colours_a_quad_until_it_is_removed() {
    // Left half red, right half blue (sRGB 255 is linear 1).
    let png = image::RgbImage::from_fn(8, 8, |x, _| if x < 4 { image::Rgb([255, 0, 0]) } else { image::Rgb([0, 0, 255]) });
    let mut scene = Scene::new();
    let texture = scene.add_texture(Texture::Image(Image::decode(&file(png.into(), image::ImageFormat::Png)).unwrap().into())).unwrap();
    let white = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::ONE)), ("diffuse_texture", ParamValue::Texture(Some(texture)))]);
    let object = scene.add_object(ObjectKind::Static, quad().with_shader(white)).unwrap();
    scene.add_instance(object, Affine3A::IDENTITY).unwrap();
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();

    // The eye light faces the quad: the colour is the texel's, within the cosine's falloff.
    let (film, _) = render_with(&scene, Integrator::EyeLight, 32, 32, 1);
    let (left, right) = (film.pixel(12, 16), film.pixel(20, 16));
    assert!(left.x > 0.97 && left.y == 0.0 && left.z == 0.0, "left of the quad: {left}");
    assert!(right.z > 0.97 && right.x == 0.0 && right.y == 0.0, "right of the quad: {right}");

    // Shaders refer to textures by id: without it, the quad is plain white.
    scene.remove_texture(texture).unwrap();
    let (film, _) = render_with(&scene, Integrator::EyeLight, 32, 32, 1);
    let (left, right) = (film.pixel(12, 16), film.pixel(20, 16));
    assert!(left.min_element() > 0.97 && right.min_element() > 0.97, "untextured: {left} {right}");
}

#[test]
fn a_radiance_hdr_environment_map_is_seen_at_its_linear_values() {
    let sky = Vec3::new(3.0, 1.0, 0.5);
    let hdr = image::Rgb32FImage::from_pixel(16, 8, image::Rgb(sky.to_array()));
    let mut scene = Scene::new();
    let map = scene.add_texture(Texture::Image(Image::decode(&file(hdr.into(), image::ImageFormat::Hdr)).unwrap().into())).unwrap();
    scene.add_light(Light::Environment { radiance: Vec3::splat(2.0), map: Some(map) }).unwrap();
    scene.set_camera(Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0).unwrap()).unwrap();
    let (film, _) = render_with(&scene, Integrator::Path, 8, 8, 1);
    for pixel in pixels(&film) {
        // The map scaled by the light's radiance, to Radiance's 8 bits per channel.
        assert!((pixel - 2.0 * sky).abs().max_element() < 0.05, "{pixel}");
    }
}
