//! Numerically hard cases for the renderer (docs/design/hard-cases.md): secondary rays
//! at scales from 1e-4 to 1e6 leave their surface without acne and without skipping walls
//! (Wächter and Binder, Ray Tracing Gems ch. 6, 2019; pbrt-v4 §6.8), nested dielectrics never
//! create energy, a glass slab transmits what Fresnel's equations say at every angle, and NaN
//! or infinite render settings are refused.

mod common;

use common::{pixels, place, shader};
use glam::Vec3;
use raystage_demo::shading::{box_mesh, sphere_mesh};
use raystage_render::{Filter, Film, Integrator, RenderSettings, render};
use raystage_scene::{Camera, Light, ObjectId, ParamValue, Scene};

fn settings(integrator: Integrator, size: u32, spp: u32) -> RenderSettings {
    RenderSettings { width: size, height: size, integrator, samples_per_pixel: spp, max_depth: 16, ..RenderSettings::default() }
}

/// The light of [`floor_and_sphere`]: the sun, or a point light (whose shadow rays from camera
/// hits are traced in packets from the light) ten radii away in the same direction.
#[derive(Clone, Copy, Debug)]
enum Lamp {
    Sun,
    Point,
}

/// Unit direction of the light from the scene's centre.
fn towards_light() -> Vec3 {
    -Vec3::new(1.0, -0.8, 0.3).normalize()
}

/// A diffuse sphere of radius `s` resting on a diffuse floor, lit by a directional light of
/// irradiance π (or a point light giving that irradiance at the sphere's centre), seen from
/// above; everything scaled by `s` and moved by `offset`. Returns the scene, the sphere's
/// centre and the point light's position.
fn floor_and_sphere(s: f32, offset: Vec3, lamp: Lamp) -> (Scene, Vec3, Vec3) {
    let mut scene = Scene::new();
    let grey = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::splat(0.5)))]);
    let centre = offset + Vec3::new(0.0, s, 0.0);
    place(&mut scene, box_mesh(offset + Vec3::new(-20.0, -1.0, -20.0) * s, offset + Vec3::new(20.0, 0.0, 20.0) * s), grey);
    place(&mut scene, sphere_mesh(centre, s, 96, 48), grey);
    let lamp_position = centre + towards_light() * (10.0 * s);
    let pi = std::f32::consts::PI;
    let light = match lamp {
        Lamp::Sun => Light::Directional { direction: -towards_light(), intensity: Vec3::splat(pi) },
        Lamp::Point => Light::Point { position: lamp_position, intensity: Vec3::splat(pi * (10.0 * s) * (10.0 * s)) },
    };
    scene.add_light(light).unwrap();
    let eye = offset + Vec3::new(1.0, 4.0, 3.0) * s;
    scene.set_camera(Camera::look_at(eye, offset + Vec3::new(-0.5, 0.0, -0.5) * s, Vec3::Y, 60.0).unwrap()).unwrap();
    (scene, centre, lamp_position)
}

/// Whether the ray from `p` towards the light (`-direction`) passes within `margin` of the
/// sphere (of centre `c`, radius `r`): `Some(true)` clearly blocked, `Some(false)` clearly
/// free, `None` too close to the shadow's edge to tell.
fn sphere_shadow(p: Vec3, towards: Vec3, c: Vec3, r: f32, margin: f32) -> Option<bool> {
    let along = (c - p).dot(towards);
    let miss = ((c - p) - towards * along).length();
    if along <= 0.0 {
        return Some(false);
    }
    if miss < r - margin {
        Some(true)
    } else if miss > r + margin {
        Some(false)
    } else {
        None
    }
}

/// No shadow acne, no lost contact shadows: the floor is exactly as bright as Lambert says
/// wherever the sphere does not shadow it and black where it does, and the sphere's lit side
/// is never speckled by its own shadow, from 1e-4 at the origin to 1e2 a million units out,
/// under the sun and under a point light.
/// (The old offset, 1e-4 × |p|, was as big as the whole scene at the first scale and 100 units
/// at the last.)
#[test]
fn no_shadow_acne_or_light_leaks_at_any_scale() {
    for lamp in [Lamp::Sun, Lamp::Point] {
        for (s, offset) in [(1e-4f32, Vec3::ZERO), (1e-2, Vec3::new(3.0, -1.0, 2.0)), (1.0, Vec3::new(1e3, 0.0, -1e3)), (1e2, Vec3::new(-6e5, 1e5, 8e5))] {
            check_shadows(s, offset, lamp);
        }
    }
}

/// [`no_shadow_acne_or_light_leaks_at_any_scale`] for one scale, offset and light.
fn check_shadows(s: f32, offset: Vec3, lamp: Lamp) {
    let (scene, centre, lamp_position) = floor_and_sphere(s, offset, lamp);
    let r = s;
    // The light's direction and the irradiance it gives (relative to π) at a point.
    let light_at = |p: Vec3| match lamp {
        Lamp::Sun => (towards_light(), 1.0),
        Lamp::Point => ((lamp_position - p).normalize(), (10.0 * s) * (10.0 * s) / (lamp_position - p).length_squared()),
    };
    let size = 64;
    let (film, _) = render(&scene.frame(), &settings(Integrator::Whitted, size, 1)).unwrap();
    let frame = scene.frame();
    let floor = ObjectId(0);
    let (mut lit, mut shadowed, mut sphere_lit) = (0, 0, 0);
    for y in 0..size {
        for x in 0..size {
            let ray = frame.camera().ray(x as f32 + 0.5, y as f32 + 0.5, size, size);
            let Some(hit) = frame.intersect(&ray, 0.0) else { continue };
            // The box filter jitters samples inside the pixel; judge pixels whose
            // neighbours see the same thing.
            let same = (-1..=1i32).all(|dy| {
                (-1..=1i32).all(|dx| {
                    let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                    (0..size as i32).contains(&nx)
                        && (0..size as i32).contains(&ny)
                        && frame.pick(nx as u32, ny as u32, size, size).is_some_and(|h| h.object == hit.object)
                })
            });
            if !same {
                continue;
            }
            let p = frame.surface(&ray, &hit, 0.0).position;
            let (towards, irradiance) = light_at(p);
            let value = film.pixel(x, y).x;
            let case = format!("{lamp:?} at scale {s:e} at {offset}, pixel ({x}, {y})");
            if hit.object == floor {
                match sphere_shadow(p, towards, centre, r, 0.1 * r) {
                    Some(false) => {
                        let expected = 0.5 * towards.y * irradiance;
                        assert!((value - expected).abs() < 0.01 * expected, "{case}: lit floor {value} instead of {expected} (acne)");
                        lit += 1;
                    }
                    Some(true) => {
                        assert_eq!(value, 0.0, "{case}: light leaked into the sphere's shadow");
                        shadowed += 1;
                    }
                    None => {}
                }
            } else {
                let n = (p - centre).normalize();
                if n.dot(towards) > 0.3 {
                    let expected = 0.5 * n.dot(towards) * irradiance;
                    assert!(value > 0.9 * expected, "{case}: lit sphere {value} instead of about {expected} (acne)");
                    sphere_lit += 1;
                }
            }
        }
    }
    assert!(lit > 300 && shadowed > 30 && sphere_lit > 100, "{lamp:?} at scale {s:e}: {lit} lit, {shadowed} shadowed floor pixels, {sphere_lit} lit sphere pixels");
}

/// A closed room of walls a thousandth of its size thick, a million units from the origin, with
/// the sun, a point light and a bright sky outside and the camera inside: not a photon gets in.
#[test]
fn light_never_leaks_through_thin_walls_far_from_the_origin() {
    for (size, offset) in [(1e-2f32, Vec3::ZERO), (10.0, Vec3::new(1e3, 2e3, -1e3)), (1e3, Vec3::new(1e6, -5e5, 2e5))] {
        let mut scene = Scene::new();
        let white = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::ONE))]);
        let t = 1e-3 * size;
        let (lo, hi) = (offset - Vec3::splat(size), offset + Vec3::splat(size));
        for axis in 0..3 {
            for side in [lo[axis], hi[axis]] {
                let (mut a, mut b) = (lo - Vec3::splat(t), hi + Vec3::splat(t));
                a[axis] = side - t;
                b[axis] = side + t;
                place(&mut scene, box_mesh(a, b), white);
            }
        }
        scene.add_light(Light::Environment { radiance: Vec3::splat(5.0), map: None, rotate_degrees: 0.0 }).unwrap();
        scene.add_light(Light::Directional { direction: Vec3::new(0.3, -1.0, 0.2), intensity: Vec3::splat(10.0) }).unwrap();
        scene.add_light(Light::Point { position: offset + Vec3::new(1.5, 0.3, -0.2) * size, intensity: Vec3::splat(100.0 * size * size) }).unwrap();
        scene.set_camera(Camera::look_at(offset + Vec3::new(0.7, 0.2, 0.6) * size, offset + Vec3::new(-1.0, -0.6, -0.9) * size, Vec3::Y, 100.0).unwrap()).unwrap();
        for integrator in [Integrator::Whitted, Integrator::Path] {
            let (film, _) = render(&scene.frame(), &settings(integrator, 24, 8)).unwrap();
            let brightest = pixels(&film).iter().map(|p| p.max_element()).fold(0.0, f32::max);
            assert_eq!(brightest, 0.0, "{integrator:?}, room of {size} at {offset}: light got in");
        }
    }
}

/// `scene` in a uniform white environment.
fn in_furnace(mut scene: Scene) -> Scene {
    scene.add_light(Light::Environment { radiance: Vec3::ONE, map: None, rotate_degrees: 0.0 }).unwrap();
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 35.0).unwrap()).unwrap();
    scene
}

/// A glass sphere of radius 1, with, inside it, a sphere of radius 0.6 of index `inner` (none
/// for `None`).
fn nested(inner: Option<f32>) -> Scene {
    let mut scene = Scene::new();
    let glass = shader(&mut scene, "Glass", &[("ior", ParamValue::Float(1.5))]);
    place(&mut scene, sphere_mesh(Vec3::ZERO, 1.0, 96, 48), glass);
    if let Some(ior) = inner {
        let core = shader(&mut scene, "Glass", &[("ior", ParamValue::Float(ior))]);
        place(&mut scene, sphere_mesh(Vec3::new(0.1, -0.1, 0.0), 0.6, 96, 48), core);
    }
    in_furnace(scene)
}

/// Nested media (the renderer tracks up to four): water in glass and glass in glass, in a white
/// furnace. Refraction and reflection at every interface, total internal reflection inside,
/// and still no pixel brighter than the light; the mean stays close to it (a lossless
/// dielectric only redistributes light). Glass inside glass of the same index is no boundary
/// at all: the image equals that of the outer sphere alone.
#[test]
fn nested_dielectrics_never_create_energy() {
    // Whitted splits at every glass hit: deep trees on few pixels for the comparison, deep
    // enough that the two extra crossings of the inner sphere cut no path short.
    let deep = RenderSettings { max_depth: 24, ..settings(Integrator::Whitted, 8, 1) };
    let alone = render(&nested(None).frame(), &deep).unwrap().0;
    for (name, inner) in [("water in glass", 1.33), ("glass in glass", 1.5), ("diamond in glass", 2.42)] {
        let scene = nested(Some(inner));
        let (film, _) = render(&scene.frame(), &RenderSettings { max_depth: 12, ..settings(Integrator::Whitted, 32, 1) }).unwrap();
        let all = pixels(&film);
        let brightest = all.iter().map(|p| p.max_element()).fold(0.0, f32::max);
        let mean = all.iter().map(|p| p.element_sum() / 3.0).sum::<f32>() / all.len() as f32;
        assert!(brightest <= 1.0 + 1e-4, "{name}: a pixel of {brightest} under a light of 1");
        assert!(mean > 0.97, "{name}: mean {mean}: energy lost");
        if name == "glass in glass" {
            let film = render(&scene.frame(), &deep).unwrap().0;
            let worst = pixels(&film).iter().zip(pixels(&alone)).map(|(a, b)| (*a - b).abs().max_element()).fold(0.0, f32::max);
            let diffs: Vec<(usize, Vec3, Vec3)> = pixels(&film).iter().zip(pixels(&alone)).enumerate().filter(|(_, (a, b))| (**a - *b).abs().max_element() > 1e-3).map(|(i, (a, b))| (i, *a, b)).collect();
            assert!(worst < 1e-3, "{name}: differs from the sphere alone by {worst}: {diffs:?}");
        }
        let (film, _) = render(&scene.frame(), &settings(Integrator::Path, 16, 64)).unwrap();
        let all = pixels(&film);
        let mean = all.iter().map(|p| p.element_sum() / 3.0).sum::<f32>() / all.len() as f32;
        assert!(mean <= 1.01 && mean > 0.95, "{name}, path tracer: mean {mean}");
    }
}

/// Fresnel's equations for unpolarised light from air into index `n` at incidence `cos_i`.
fn fresnel(cos_i: f64, n: f64) -> f64 {
    let sin_t = (1.0 - cos_i * cos_i).sqrt() / n;
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    let rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// Light through a clear glass slab at 0°, 30°, 45°, 60° and 75° from its normal: reflected
/// back and forth inside, the transmitted sum is (1 − R)² Σ R^2k = (1 − R) / (1 + R) for the
/// unpolarised reflectance R at that angle (equal at both faces), within 0.5 %.
#[test]
fn a_glass_slab_transmits_what_fresnel_says_at_every_angle() {
    for degrees in [0.0f32, 30.0, 45.0, 60.0, 75.0] {
        let mut scene = Scene::new();
        let glass = shader(&mut scene, "Glass", &[("ior", ParamValue::Float(1.5))]);
        place(&mut scene, box_mesh(Vec3::new(-50.0, -50.0, -0.5), Vec3::new(50.0, 50.0, 0.5)), glass);
        let wall = shader(&mut scene, "Constant", &[("color", ParamValue::Color(Vec3::ONE))]);
        place(&mut scene, box_mesh(Vec3::new(-5e3, -5e3, -40.0), Vec3::new(5e3, 5e3, -39.0)), wall);
        scene.add_light(Light::Environment { radiance: Vec3::ZERO, map: None, rotate_degrees: 0.0 }).unwrap();
        let angle = degrees.to_radians();
        let eye = Vec3::new(angle.sin(), 0.0, angle.cos()) * 10.0;
        scene.set_camera(Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 0.5).unwrap()).unwrap();
        let (film, _) = render(&scene.frame(), &settings(Integrator::Whitted, 4, 1)).unwrap();
        let r = fresnel(angle.cos() as f64, 1.5);
        let expected = ((1.0 - r) / (1.0 + r)) as f32;
        let seen = film.pixel(2, 2);
        assert!(((seen - Vec3::splat(expected)) / expected).abs().max_element() < 0.005, "{degrees}°: {seen} instead of {expected}");
    }
}

/// NaN and infinite render settings are refused with an error naming the field, not rendered.
#[test]
fn nan_and_infinite_settings_are_refused() {
    let scene = nested(None);
    for radius in [f32::NAN, f32::INFINITY, -0.0] {
        let bad = RenderSettings { filter: Filter::Gaussian { radius }, ..settings(Integrator::Path, 4, 1) };
        let err = render(&scene.frame(), &bad).map(|_: (Film, _)| ()).unwrap_err().to_string();
        assert!(err.contains("filter.radius"), "{err}");
    }
}
