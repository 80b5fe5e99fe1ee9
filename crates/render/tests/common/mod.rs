//! Small scenes the renderer's tests share.

#![allow(dead_code)]

use glam::{Affine3A, Vec3};
use raystage_demo::shading::{box_mesh, sphere_mesh};
use raystage_render::{Film, FrameStats, Integrator, RenderSettings, render};
use raystage_scene::{Camera, Light, Mesh, ObjectKind, ParamValue, Scene, ShaderId};

/// A shader of `class` with `params` set.
pub fn shader(scene: &mut Scene, class: &str, params: &[(&str, ParamValue)]) -> ShaderId {
    let id = scene.add_shader(class).unwrap();
    for (name, value) in params {
        assert!(scene.set_param(id, name, *value).unwrap(), "{class} has no `{name}`");
    }
    id
}

/// Adds `mesh` as a static object with one instance at the identity.
pub fn place(scene: &mut Scene, mesh: Mesh, shader: ShaderId) {
    let object = scene.add_object(ObjectKind::Static, mesh.with_shader(shader)).unwrap();
    scene.add_instance(object, Affine3A::IDENTITY).unwrap();
}

/// A unit sphere at the origin, seen from +z so that it fills most of the image.
pub fn sphere_scene(class: &str, params: &[(&str, ParamValue)]) -> Scene {
    let mut scene = Scene::new();
    let s = shader(&mut scene, class, params);
    place(&mut scene, sphere_mesh(Vec3::ZERO, 1.0, 96, 48), s);
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 35.0).unwrap()).unwrap();
    scene
}

/// A `PhysicallyBased` sphere of `params` lit by a point light at the camera.
pub fn lit_from_the_camera(params: &[(&str, ParamValue)]) -> Scene {
    let mut scene = sphere_scene("PhysicallyBased", params);
    scene.add_light(Light::Point { position: Vec3::new(0.0, 0.0, 4.0), intensity: Vec3::splat(10.0) }).unwrap();
    scene
}

/// A diffuse sphere on a diffuse floor.
pub fn diffuse_scene() -> Scene {
    let mut scene = sphere_scene("Diffuse", &[]);
    let floor = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::splat(0.5)))]);
    place(&mut scene, box_mesh(Vec3::new(-10.0, -2.0, -10.0), Vec3::new(10.0, -1.0, 10.0)), floor);
    scene
}

/// A point light above and in front.
pub fn point_light() -> Light {
    Light::Point { position: Vec3::new(2.0, 5.0, 4.0), intensity: Vec3::splat(40.0) }
}

/// Renders `scene` at `width × height` with `integrator` and `spp` samples per pixel.
pub fn render_with(scene: &Scene, integrator: Integrator, width: u32, height: u32, spp: u32) -> (Film, FrameStats) {
    let settings = RenderSettings { width, height, integrator, samples_per_pixel: spp, max_depth: 16, ..RenderSettings::default() };
    render(&scene.frame(), &settings).unwrap()
}

/// Every pixel of `film`.
pub fn pixels(film: &Film) -> Vec<Vec3> {
    (0..film.height()).flat_map(|y| (0..film.width()).map(move |x| (x, y))).map(|(x, y)| film.pixel(x, y)).collect()
}
