//! Glass: light through an absorbing slab falls off as Beer's law says, with the Fresnel
//! losses at both faces; beyond the critical angle nothing gets out.

mod common;

use common::{place, render_with, shader};
use glam::Vec3;
use raystage_demo::shading::box_mesh;
use raystage_render::Integrator;
use raystage_scene::{Camera, Light, Mesh, ParamValue, Scene};

/// Reflectance of glass of index 1.5 at normal incidence: ((1.5 − 1) / (1.5 + 1))².
const F0: f32 = 0.04;

/// A glass slab of thickness `thickness` (faces at z = ±thickness/2) with absorption `sigma`,
/// in front of a white emitting wall, seen head-on from the dark side.
fn slab(thickness: f32, sigma: Vec3) -> Scene {
    let mut scene = Scene::new();
    let glass = shader(&mut scene, "Glass", &[("ior", ParamValue::Float(1.5)), ("absorption", ParamValue::Color(sigma))]);
    let h = thickness / 2.0;
    place(&mut scene, box_mesh(Vec3::new(-50.0, -50.0, -h), Vec3::new(50.0, 50.0, h)), glass);
    let wall = shader(&mut scene, "Constant", &[("color", ParamValue::Color(Vec3::ONE))]);
    place(&mut scene, box_mesh(Vec3::new(-500.0, -500.0, -20.0), Vec3::new(500.0, 500.0, -19.0)), wall);
    // A black environment: what the slab reflects towards the camera is dark.
    scene.add_light(Light::Environment { radiance: Vec3::ZERO, map: None, rotate_degrees: 0.0 }).unwrap();
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y, 1.0).unwrap()).unwrap();
    scene
}

/// Light through a slab at normal incidence: each pass through the glass keeps e^(−σd); light
/// bouncing back and forth inside adds a geometric series of F² e^(−2σd).
fn expected_transmission(thickness: f32, sigma: Vec3) -> Vec3 {
    let pass = (-sigma * thickness).exp();
    (1.0 - F0) * (1.0 - F0) * pass / (Vec3::ONE - F0 * F0 * pass * pass)
}

#[test]
fn absorption_follows_beers_law() {
    let sigma = Vec3::new(0.1, 0.5, 2.0);
    for thickness in [0.25, 1.0, 2.0] {
        let scene = slab(thickness, sigma);
        let (film, stats) = render_with(&scene, Integrator::Whitted, 8, 8, 1);
        assert!(stats.effects.refraction);
        let centre = film.pixel(4, 4);
        let expected = expected_transmission(thickness, sigma);
        assert!(((centre - expected) / expected).abs().max_element() < 2e-3, "thickness {thickness}: {centre} vs {expected}");
    }
}

#[test]
fn the_path_tracer_agrees_with_beer_on_average() {
    let sigma = Vec3::new(0.1, 0.5, 2.0);
    let scene = slab(1.0, sigma);
    let (film, _) = render_with(&scene, Integrator::Path, 8, 8, 1024);
    let expected = expected_transmission(1.0, sigma);
    let centre = film.pixel(4, 4);
    assert!(((centre - expected) / expected).abs().max_element() < 0.05, "{centre} vs {expected}");
}

/// A right-angled glass prism, its legs on the planes x = 0 and y = 0 and its hypotenuse
/// facing (1, 1), 2 long on each leg and 2 deep along z, facing outwards.
fn prism() -> Mesh {
    let (z0, z1) = (-1.0, 1.0);
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let positions = vec![p(0.0, 0.0, z0), p(2.0, 0.0, z0), p(0.0, 2.0, z0), p(0.0, 0.0, z1), p(2.0, 0.0, z1), p(0.0, 2.0, z1)];
    let indices = vec![
        [0, 2, 1], [3, 4, 5], // caps at z0 (facing −z) and z1 (facing +z)
        [0, 1, 4], [0, 4, 3], // bottom leg, facing −y
        [0, 3, 5], [0, 5, 2], // left leg, facing −x
        [1, 2, 5], [1, 5, 4], // hypotenuse, facing (1, 1)
    ];
    let mesh = Mesh::new(positions, indices);
    let centre = Vec3::new(2.0 / 3.0, 2.0 / 3.0, 0.0);
    for k in 0..mesh.indices.len() as u32 {
        let [a, b, c] = mesh.triangle(k);
        assert!((b - a).cross(c - a).dot((a + b + c) / 3.0 - centre) > 0.0, "prism face {k} faces inwards");
    }
    mesh
}

/// Light entering a right-angled prism through one leg meets the hypotenuse at 45°, beyond
/// the critical angle of glass (41.8° for index 1.5): all of it reflects and leaves through the
/// other leg, turned by 90°. Looking up into the prism from below, one sees what lies to the
/// left, and nothing of what lies beyond the hypotenuse.
#[test]
fn total_internal_reflection_turns_a_prism_into_a_mirror() {
    let mut scene = Scene::new();
    let glass = shader(&mut scene, "Glass", &[("ior", ParamValue::Float(1.5))]);
    place(&mut scene, prism(), glass);
    let red = shader(&mut scene, "Constant", &[("color", ParamValue::Color(Vec3::X))]);
    let green = shader(&mut scene, "Constant", &[("color", ParamValue::Color(Vec3::Y))]);
    place(&mut scene, box_mesh(Vec3::new(-31.0, -100.0, -100.0), Vec3::new(-30.0, 100.0, 100.0)), red);
    place(&mut scene, box_mesh(Vec3::new(30.0, -100.0, -100.0), Vec3::new(31.0, 100.0, 100.0)), green);
    place(&mut scene, box_mesh(Vec3::new(-29.0, 30.0, -100.0), Vec3::new(29.0, 31.0, 100.0)), green);
    scene.add_light(Light::Environment { radiance: Vec3::ZERO, map: None, rotate_degrees: 0.0 }).unwrap();
    scene.set_camera(Camera::look_at(Vec3::new(0.5, -10.0, 0.0), Vec3::new(0.5, 0.0, 0.0), Vec3::Z, 1.0).unwrap()).unwrap();
    for integrator in [Integrator::Whitted, Integrator::Path] {
        let (film, _) = render_with(&scene, integrator, 4, 4, 64);
        let seen = film.pixel(2, 2);
        // Two perpendicular crossings lose F0 each; the total reflection loses nothing.
        assert!((seen.x - (1.0 - F0) * (1.0 - F0)).abs() < 0.02, "{integrator:?}: {seen}");
        assert!(seen.y < 0.01, "{integrator:?}: light got through the hypotenuse: {seen}");
    }
}

/// 600 glass triangles at random around the origin, a point light among them, and the camera
/// inside the cluster: every camera ray meets glass after glass.
fn glass_cluster() -> Scene {
    let mut scene = Scene::new();
    let glass = shader(&mut scene, "Glass", &[("ior", ParamValue::Float(1.5))]);
    // A small linear congruential generator: the same cluster every run.
    let mut state = 12345u32;
    let mut next = move || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
    };
    let mut positions = Vec::new();
    for _ in 0..600 {
        let centre = Vec3::new(next(), next(), next());
        positions.extend((0..3).map(|_| centre + Vec3::new(next(), next(), next())));
    }
    let indices = (0..600).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    place(&mut scene, Mesh::new(positions, indices), glass);
    scene.add_light(Light::Point { position: Vec3::new(0.3, 0.2, 0.1), intensity: Vec3::ONE }).unwrap();
    scene.set_camera(Camera::look_at(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), Vec3::Y, 60.0).unwrap()).unwrap();
    scene
}

/// Whitted's glass traces both branches only for the first few bounces (then one, by Russian
/// roulette) and drops rays of little weight, so the rays a frame traces grow with the depth
/// limit linearly: at the deepest limit the cluster renders in bounded work, where splitting at
/// every bounce would trace 2^64 rays per pixel.
#[test]
fn ray_trees_grow_linearly_with_the_depth_limit() {
    let scene = glass_cluster();
    let secondary = |max_depth: u32| {
        let settings = raystage_render::RenderSettings {
            width: 8,
            height: 8,
            integrator: Integrator::Whitted,
            max_depth,
            ..raystage_render::RenderSettings::default()
        };
        let (film, stats) = raystage_render::render(&scene.frame(), &settings).unwrap();
        assert_eq!(stats.non_finite, 0);
        assert!((0..8).all(|y| (0..8).all(|x| film.pixel(x, y).is_finite())));
        stats.rays.reflection + stats.rays.refraction
    };
    let (shallow, deepest) = (secondary(8), secondary(raystage_render::MAX_DEPTH));
    // At most 2^6 leaves of the split levels per pixel, each a chain of at most the depth limit.
    eprintln!("{shallow} secondary rays at depth 8, {deepest} at depth 64");
    assert!(deepest <= 64 * 64 * raystage_render::MAX_DEPTH as u64, "{deepest} rays at depth 64");
    assert!(deepest < shallow * 16, "{shallow} rays at depth 8, {deepest} at depth 64");
}
