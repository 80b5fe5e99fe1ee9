//! The effect set: each frame simulates only what its scene calls for, and its statistics say
//! so. The assertions are on rays counted by kind, which the integrators cannot trace without
//! counting.

mod common;

use common::{diffuse_scene, place, point_light, render_with, shader, sphere_scene};
use glam::{Affine3A, Vec3};
use raystage_demo::shading::box_mesh;
use raystage_render::{Integrator, RenderSettings, render};
use raystage_scene::{Camera, Light, ParamValue};

#[test]
fn a_diffuse_scene_traces_no_reflection_or_refraction_rays() {
    let mut scene = diffuse_scene();
    scene.add_light(point_light()).unwrap();
    for integrator in [Integrator::Whitted, Integrator::Distribution, Integrator::Path] {
        let (_, stats) = render_with(&scene, integrator, 32, 24, 2);
        assert!(!stats.effects.reflection && !stats.effects.refraction, "{integrator:?}: {:?}", stats.effects);
        assert_eq!((stats.rays.reflection, stats.rays.refraction), (0, 0), "{integrator:?}");
        assert!(stats.rays.shadow > 0, "{integrator:?} lights the scene");
        assert_eq!(stats.rays.primary, 32 * 24 * 2);
    }
    let (_, path) = render_with(&scene, Integrator::Path, 32, 24, 2);
    assert!(path.rays.diffuse > 0, "the path tracer bounces diffusely");
}

#[test]
fn mirrors_and_glass_trace_what_they_need() {
    let mut scene = sphere_scene("Mirror", &[]);
    scene.add_light(point_light()).unwrap();
    let (_, stats) = render_with(&scene, Integrator::Whitted, 32, 24, 1);
    assert!(stats.effects.reflection && !stats.effects.refraction);
    assert!(stats.rays.reflection > 0 && stats.rays.refraction == 0);

    let mut scene = sphere_scene("Glass", &[]);
    scene.add_light(point_light()).unwrap();
    let (_, stats) = render_with(&scene, Integrator::Whitted, 32, 24, 1);
    assert!(stats.effects.refraction && stats.effects.transparent_shadows);
    assert!(stats.rays.refraction > 0 && stats.rays.reflection > 0);
}

#[test]
fn emitting_surfaces_are_lights_and_keep_the_defaults_away() {
    let mut scene = diffuse_scene();
    let lamp = shader(&mut scene, "Emissive", &[("emission", ParamValue::Color(Vec3::splat(5.0)))]);
    place(&mut scene, box_mesh(Vec3::new(-1.0, 3.0, -1.0), Vec3::new(1.0, 3.2, 1.0)), lamp);
    for integrator in [Integrator::Whitted, Integrator::Distribution, Integrator::Path] {
        let (film, stats) = render_with(&scene, integrator, 32, 24, 2);
        assert!(!stats.default_lights, "{integrator:?}: the box lights the scene");
        assert!(stats.effects.shadows && stats.rays.shadow > 0, "{integrator:?}: the box's light is sampled, with shadow rays");
        assert_eq!(stats.non_finite, 0);
        // The floor under the box is lit by it, in every integrator.
        let lit = (0..24).flat_map(|y| (0..32).map(move |x| (x, y))).filter(|&(x, y)| film.pixel(x, y).max_element() > 0.0).count();
        assert!(lit > 100, "{integrator:?}: {lit} pixels lit");
    }
}

#[test]
fn a_scene_nothing_lights_gets_the_default_sky_and_says_so() {
    let scene = diffuse_scene();
    let (film, stats) = render_with(&scene, Integrator::Path, 32, 24, 2);
    assert!(stats.default_lights && stats.effects.area_lights && stats.rays.shadow > 0);
    // The floor's pixels below the sphere, on average (one pixel's two samples may both
    // find the sphere's shadow).
    let floor = (18..24).flat_map(|y| (8..24).map(move |x| (x, y))).map(|(x, y)| film.pixel(x, y)).sum::<Vec3>() / 96.0;
    assert!(floor.max_element() > 0.05, "the sky lights the floor: {floor}");
    // Turned off, nothing lights it: no shadow rays, and a black image (the backdrop is black
    // too, the scene having no environment).
    let settings = RenderSettings { width: 32, height: 24, integrator: Integrator::Whitted, default_lights: false, ..RenderSettings::default() };
    let (film, stats) = render(&scene.frame(), &settings).unwrap();
    assert!(!stats.default_lights && !stats.effects.shadows);
    assert_eq!(stats.rays.shadow, 0);
    assert!((0..24).all(|y| (0..32).all(|x| film.pixel(x, y) == Vec3::ZERO)));
    // A light of the scene's own: no defaults.
    let mut lit = diffuse_scene();
    lit.add_light(point_light()).unwrap();
    let (_, stats) = render_with(&lit, Integrator::Path, 16, 16, 1);
    assert!(!stats.default_lights);
}

#[test]
fn a_still_scene_draws_no_time_samples_even_with_the_shutter_open() {
    let mut scene = diffuse_scene();
    scene.add_light(point_light()).unwrap();
    let camera = Camera { shutter: [0.0, 1.0], ..*scene.camera() };
    scene.set_camera(camera).unwrap();
    let (_, stats) = render_with(&scene, Integrator::Distribution, 32, 24, 2);
    assert!(!stats.effects.motion_blur);
    assert_eq!(stats.time_samples, 0);

    // Something moves while the shutter is open: now every camera ray gets a time.
    let (instance, _, _) = scene.instances().next().unwrap();
    scene.set_motion(instance, Affine3A::IDENTITY, Some(Affine3A::from_translation(Vec3::new(0.5, 0.0, 0.0)))).unwrap();
    let (_, stats) = render_with(&scene, Integrator::Distribution, 32, 24, 2);
    assert!(stats.effects.motion_blur);
    assert_eq!(stats.time_samples, 32 * 24 * 2);

    // Whitted's rays are not distributed over time: no motion blur.
    let (_, stats) = render_with(&scene, Integrator::Whitted, 32, 24, 2);
    assert_eq!(stats.time_samples, 0);
}

#[test]
fn only_a_lens_with_an_aperture_draws_lens_samples() {
    let mut scene = diffuse_scene();
    let (_, stats) = render_with(&scene, Integrator::Distribution, 16, 16, 1);
    assert_eq!(stats.lens_samples, 0);
    let camera = Camera { aperture_radius: 0.1, focus_distance: 4.0, ..*scene.camera() };
    scene.set_camera(camera).unwrap();
    let (_, stats) = render_with(&scene, Integrator::Distribution, 16, 16, 1);
    assert!(stats.effects.depth_of_field);
    assert_eq!(stats.lens_samples, 16 * 16);
}

#[test]
fn only_extended_lights_need_soft_shadows() {
    let mut scene = diffuse_scene();
    scene.add_light(point_light()).unwrap();
    let (_, stats) = render_with(&scene, Integrator::Distribution, 16, 16, 1);
    assert!(!stats.effects.area_lights);
    scene
        .add_light(Light::Area { corner: Vec3::new(-1.0, 4.0, -1.0), edge_u: Vec3::X * 2.0, edge_v: Vec3::Z * 2.0, radiance: Vec3::ONE })
        .unwrap();
    let (_, stats) = render_with(&scene, Integrator::Distribution, 16, 16, 1);
    assert!(stats.effects.area_lights && stats.effects.shadows);
}

#[test]
fn the_eye_light_preview_traces_camera_rays_only() {
    let mut scene = sphere_scene("Glass", &[]);
    scene.add_light(point_light()).unwrap();
    let (_, stats) = render_with(&scene, Integrator::EyeLight, 32, 24, 1);
    assert_eq!(stats.rays.total(), stats.rays.primary);
    assert!(stats.effects.names().is_empty(), "{:?}", stats.effects.names());
}
