//! White furnace tests: under a uniform white environment, a closed object that neither emits
//! nor absorbs is invisible, and one that absorbs a fraction of what it receives shows exactly
//! what it keeps. Any energy gained or lost by an estimator, a sampling density or a
//! multiple-importance weight shows up as a pixel that is not the expected value.

mod common;

use common::{pixels, place, render_with, shader, sphere_scene};
use glam::Vec3;
use raystage_demo::shading::sphere_mesh;
use raystage_render::Integrator;
use raystage_scene::{Light, ParamValue, Scene};

/// `scene` under a uniform environment of radiance 1.
fn in_furnace(mut scene: Scene) -> Scene {
    scene.add_light(Light::Environment { radiance: Vec3::ONE, map: None, rotate_degrees: 0.0 }).unwrap();
    scene
}

/// Mean of the pixels of a `size²` image, and the largest deviation of a pixel from `expected`,
/// over the pixels inside the sphere's outline (whose neighbours see the sphere too, so that no
/// sample of theirs sees the environment behind it).
fn furnace_pixels(scene: &Scene, integrator: Integrator, size: u32, spp: u32, expected: f32) -> (f32, f32) {
    let (film, _) = render_with(scene, integrator, size, size, spp);
    let frame = scene.frame();
    let sees_sphere = |x: i64, y: i64| {
        (0..size as i64).contains(&x) && (0..size as i64).contains(&y) && frame.pick(x as u32, y as u32, size, size).is_some()
    };
    let inside = |x: i64, y: i64| (-1..=1).all(|dy| (-1..=1).all(|dx| sees_sphere(x + dx, y + dy)));
    let on_sphere: Vec<Vec3> = pixels(&film)
        .into_iter()
        .enumerate()
        .filter(|(i, _)| inside((*i as u32 % size) as i64, (*i as u32 / size) as i64))
        .map(|(_, p)| p)
        .collect();
    assert!(on_sphere.len() as u32 > size * size / 4, "the sphere fills the view");
    let mean = on_sphere.iter().map(|p| p.element_sum() / 3.0).sum::<f32>() / on_sphere.len() as f32;
    let worst = on_sphere.iter().map(|p| (*p - Vec3::splat(expected)).abs().max_element()).fold(0.0, f32::max);
    (mean, worst)
}

#[test]
fn a_white_diffuse_sphere_disappears() {
    let scene = in_furnace(sphere_scene("Diffuse", &[("diffuse", ParamValue::Color(Vec3::ONE))]));
    let (mean, worst) = furnace_pixels(&scene, Integrator::Path, 48, 16, 1.0);
    assert!((mean - 1.0).abs() < 0.01, "mean {mean}");
    assert!(worst < 0.05, "a pixel is off by {worst}");
}

#[test]
fn a_grey_diffuse_sphere_keeps_half() {
    let scene = in_furnace(sphere_scene("Diffuse", &[("diffuse", ParamValue::Color(Vec3::splat(0.5)))]));
    let (mean, worst) = furnace_pixels(&scene, Integrator::Path, 48, 16, 0.5);
    assert!((mean - 0.5).abs() < 0.005, "mean {mean}");
    assert!(worst < 0.025, "a pixel is off by {worst}");
}

#[test]
fn the_distribution_ray_tracer_agrees_on_a_diffuse_sphere() {
    // No indirect light is needed on a convex object: direct light from the environment,
    // sampled over the hemisphere, is all there is.
    let scene = in_furnace(sphere_scene("Diffuse", &[("diffuse", ParamValue::Color(Vec3::splat(0.5)))]));
    let (mean, _) = furnace_pixels(&scene, Integrator::Distribution, 32, 16, 0.5);
    assert!((mean - 0.5).abs() < 0.005, "mean {mean}");
}

#[test]
fn glass_never_creates_energy() {
    let scene = in_furnace(sphere_scene("Glass", &[("ior", ParamValue::Float(1.5))]));
    // Whitted splits every glass hit into Fresnel-weighted reflection and refraction: the
    // weights sum to one, so nothing exceeds the environment, and with a deep enough
    // recursion little is lost.
    let (mean, worst) = furnace_pixels(&scene, Integrator::Whitted, 32, 1, 1.0);
    let (film, _) = render_with(&scene, Integrator::Whitted, 32, 32, 1);
    assert!(pixels(&film).iter().all(|p| p.max_element() <= 1.0 + 1e-4), "a glass pixel is brighter than the light");
    assert!(mean > 0.97 && mean <= 1.0 + 1e-4, "mean {mean}, worst {worst}");
    // The path tracer picks one of the two at random: the same on average.
    let (mean, _) = furnace_pixels(&scene, Integrator::Path, 32, 32, 1.0);
    assert!(mean > 0.97 && mean <= 1.01, "mean {mean}");
}

/// A single-scattering microfacet metal loses the light that would bounce between its facets
/// (Kulla and Conty 2017): little when smooth, much when rough; it never gains any.
#[test]
fn rough_metal_loses_energy_but_never_gains_it() {
    let mut previous = f32::INFINITY;
    for roughness in [0.02, 0.4, 1.0] {
        let scene = in_furnace(sphere_scene("Glossy", &[("reflectance", ParamValue::Color(Vec3::ONE)), ("roughness", ParamValue::Float(roughness))]));
        let (mean, _) = furnace_pixels(&scene, Integrator::Path, 32, 16, 1.0);
        assert!(mean <= 1.01 && mean < previous, "roughness {roughness}: mean {mean}");
        assert!(roughness > 0.1 || mean > 0.97, "a nearly smooth metal keeps nearly everything: {mean}");
        previous = mean;
    }
}

/// More shadow rays per light change the weights of multiple importance sampling, not the
/// answer; neither does turning Russian roulette off.
#[test]
fn light_samples_and_roulette_keep_the_furnace_balanced() {
    let scene = in_furnace(sphere_scene("Diffuse", &[("diffuse", ParamValue::Color(Vec3::splat(0.5)))]));
    for (light_samples, russian_roulette) in [(4, true), (1, false), (3, false)] {
        let settings = raystage_render::RenderSettings {
            width: 32,
            height: 32,
            integrator: Integrator::Path,
            samples_per_pixel: 8,
            light_samples,
            russian_roulette,
            ..Default::default()
        };
        let (film, _) = raystage_render::render(&scene.frame(), &settings).unwrap();
        let centre = film.pixel(16, 16);
        assert!((centre - Vec3::splat(0.5)).abs().max_element() < 0.01, "{light_samples} light samples, roulette {russian_roulette}: {centre}");
    }
}

/// The furnace made of geometry: a closed sphere of emitting triangles of radiance 1, facing in,
/// around a white diffuse sphere. Light sampled from the emitters and light found by bounces
/// (weighed against each other in the path tracer) must add up to exactly 1, as must Whitted's
/// and the distribution ray tracer's samples of the emitters alone.
#[test]
fn a_white_sphere_inside_a_sphere_of_emitters_disappears() {
    let mut scene = sphere_scene("Diffuse", &[("diffuse", ParamValue::Color(Vec3::ONE))]);
    let glow = shader(&mut scene, "Emissive", &[("emission", ParamValue::Color(Vec3::ONE))]);
    let mut shell = sphere_mesh(Vec3::ZERO, 30.0, 64, 32);
    shell.indices.iter_mut().for_each(|t| t.swap(1, 2));
    shell.normals.clear();
    place(&mut scene, shell, glow);
    for integrator in [Integrator::Path, Integrator::Distribution, Integrator::Whitted] {
        let (mean, worst) = furnace_pixels(&scene, integrator, 48, 16, 1.0);
        assert!((mean - 1.0).abs() < 0.01, "{integrator:?}: mean {mean}");
        // Light sampling alone (Whitted, distribution) is noisy where half its samples fall
        // behind the surface; with the bounces weighed in, each pixel is close.
        if integrator == Integrator::Path {
            assert!(worst < 0.25, "a pixel is off by {worst}");
        }
    }
}

/// The physically based material under the uniform environment, across metallic × roughness:
/// a white surface disappears, dielectric or metal, smooth or rough. Its layers keep their
/// energy (the multiple-scattering lobe gives back what bounces between microfacets, the base
/// gets what the specular layer leaves). Measured: 1.000 for every one (0.999–1.002); before,
/// with a single-scattering layer and the base weighted by Fresnel, 0.97 for the rough
/// dielectric and 0.89 and 0.37 for the metals of roughness 0.5 and 1.
#[test]
fn physically_based_white_disappears() {
    for metallic in [0.0, 1.0] {
        for roughness in [0.1, 0.5, 1.0] {
            let params = [
                ("base_color", ParamValue::Color(Vec3::ONE)),
                ("metallic", ParamValue::Float(metallic)),
                ("roughness", ParamValue::Float(roughness)),
            ];
            let scene = in_furnace(sphere_scene("PhysicallyBased", &params));
            // The distribution tracer lights the surface through the same BSDF (its glossy rays
            // see no environment: the light samples count it), and agrees where light samples
            // find the lobe (measured 0.994–1.000 from roughness 0.5; 0.81 for the metal of
            // roughness 0.1, whose sharp lobe cosine-distributed samples of the environment
            // rarely meet). Whitted adds a mirror ray to the lights seen through the whole
            // BSDF, an approximation that counts the specular layer's light twice (measured
            // 1.00–1.10).
            let integrators: &[Integrator] = if roughness >= 0.5 { &[Integrator::Path, Integrator::Distribution] } else { &[Integrator::Path] };
            for &integrator in integrators {
                let (mean, _) = furnace_pixels(&scene, integrator, 32, 16, 1.0);
                assert!((mean - 1.0).abs() < 0.01, "{integrator:?}, metallic {metallic}, roughness {roughness}: mean {mean}");
            }
        }
    }
}

/// A transmitting physically based sphere under the uniform environment: white, non-absorbing
/// and smooth, what Fresnel does not reflect goes through, in and out again, so the sphere
/// disappears, as glass does (a solid volume and a thin-walled shell alike); rough, it loses
/// what single scattering loses and never gains. Whitted's smooth refraction and mirror
/// approximate it, and stay within the light too.
#[test]
fn a_transmitting_white_sphere_disappears_when_smooth_and_never_gains() {
    for (thickness, roughness) in [(1.0, 0.0), (0.0, 0.0), (1.0, 0.5), (0.0, 0.5)] {
        let params = [
            ("base_color", ParamValue::Color(Vec3::ONE)),
            ("metallic", ParamValue::Float(0.0)),
            ("roughness", ParamValue::Float(roughness)),
            ("transmission", ParamValue::Float(1.0)),
            ("thickness", ParamValue::Float(thickness)),
        ];
        let scene = in_furnace(sphere_scene("PhysicallyBased", &params));
        let (mean, worst) = furnace_pixels(&scene, Integrator::Path, 32, 32, 1.0);
        eprintln!("thickness {thickness}, roughness {roughness}: mean {mean}, worst {worst}");
        assert!(mean <= 1.01, "thickness {thickness}, roughness {roughness}: mean {mean}");
        if roughness == 0.0 {
            assert!(mean > 0.99, "thickness {thickness}: a smooth clear sphere keeps {mean}");
        } else {
            // Measured: 0.80 for the volume, 0.78 for the thin shell. A rough dielectric loses
            // what bounces between its microfacets (a boundary at α 0.25 sends on 0.79 to 0.99
            // of the light by angle and side, a thin wall 0.85 to 0.91, as a rough metal's
            // reflection keeps), at each of the crossings and internal reflections a path makes.
            assert!(mean > 0.75, "thickness {thickness}, roughness {roughness}: mean {mean}");
        }
        let (film, stats) = render_with(&scene, Integrator::Whitted, 32, 32, 1);
        assert!(stats.effects.refraction, "transmission turns refraction on");
        // Whitted's approximation of rough surfaces (the lights through the whole BSDF, plus a
        // mirror ray faded by roughness) is not energy-exact; smooth, it is glass.
        if roughness == 0.0 {
            assert!(pixels(&film).iter().all(|p| p.max_element() <= 1.0 + 1e-3), "thickness {thickness}: a Whitted pixel is brighter than the light");
            // Measured 0.94 for the volume: Whitted's mirror fades by 1 − √α, 3 % at the
            // smallest α, at every reflection inside the sphere.
            let (mean, _) = furnace_pixels(&scene, Integrator::Whitted, 32, 1, 1.0);
            assert!(mean > 0.93, "thickness {thickness}: Whitted keeps {mean}");
            // The distribution tracer samples the BTDF where Whitted refracts one ray, and its
            // reflection samples the specular layer itself (measured 0.947 for the volume and
            // the thin shell; 0.93 and 0.94 when it sampled a Schlick metal of the layer's
            // colour, which knows no total internal reflection).
            let (mean, _) = furnace_pixels(&scene, Integrator::Distribution, 32, 16, 1.0);
            assert!(mean > 0.9 && mean <= 1.01, "thickness {thickness}: the distribution tracer keeps {mean}");
        }
    }
}
