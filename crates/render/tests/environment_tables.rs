//! An environment image is tabulated for sampling once and keeps its tables: every progressive
//! pass and every frame prepares its lights, and tabulating a large HDR image at each of them
//! took most of a pass.

mod common;

use common::{render_with, sphere_scene};
use glam::Vec3;
use raystage_render::Integrator;
use raystage_scene::{Image, Light, Texture};

#[test]
fn an_environment_image_is_tabulated_once_and_keeps_its_tables() {
    let mut scene = sphere_scene("Diffuse", &[]);
    let (w, h) = (64, 32);
    let texels = (0..w * h).map(|i| Vec3::splat(0.1 + (i % 7) as f32)).collect();
    let map = scene.add_texture(Texture::Image(std::sync::Arc::new(Image::new(w, h, texels).unwrap()))).unwrap();
    scene.add_light(Light::Environment { radiance: Vec3::ONE, map: Some(map), rotate_degrees: 30.0 }).unwrap();
    let Texture::Image(image) = scene.texture(map).unwrap() else { unreachable!("an image texture") };
    let texels_only = image.memory_bytes();
    // Frames borrow the scene as the image is borrowed here: nothing edits it in between.
    let (first, _) = render_with(&scene, Integrator::Path, 16, 16, 2);
    let tabulated = image.memory_bytes();
    assert!(tabulated > texels_only, "the frame left its tables with the image ({texels_only} bytes before and after)");
    let tables: *const _ = image.environment_tables();
    let (second, _) = render_with(&scene, Integrator::Path, 16, 16, 2);
    assert_eq!(image.memory_bytes(), tabulated, "a second frame adds no tables");
    assert!(std::ptr::eq(tables, image.environment_tables()), "the second frame sampled by the same tables");
    assert_eq!(common::pixels(&first), common::pixels(&second), "the same tables, the same image");
}
