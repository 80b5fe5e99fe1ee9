//! Sheen (glTF's KHR_materials_sheen) on a dark blue ball lit from the camera: the fibres add a
//! rim of their colour where the surface turns away, little head-on, and take that light from
//! the ball under them.

mod common;

use common::{lit_from_the_camera, render_with};
use glam::Vec3;
use raystage_render::Integrator;
use raystage_scene::ParamValue;

/// A dark blue rough dielectric sphere lit by a point light at the camera, with red fibres.
fn cloth(sheen: Vec3) -> raystage_scene::Scene {
    lit_from_the_camera(&[
        ("base_color", ParamValue::Color(Vec3::new(0.02, 0.02, 0.5))),
        ("metallic", ParamValue::Float(0.0)),
        ("roughness", ParamValue::Float(1.0)),
        ("sheen_color", ParamValue::Color(sheen)),
        ("sheen_roughness", ParamValue::Float(0.3)),
    ])
}

#[test]
fn sheen_adds_a_rim_of_its_colour_and_takes_it_from_the_base() {
    let (w, h) = (48, 48);
    let bare = render_with(&cloth(Vec3::ZERO), Integrator::Path, w, h, 64).0;
    let red = render_with(&cloth(Vec3::new(1.0, 0.0, 0.0)), Integrator::Path, w, h, 64).0;
    let (centre_bare, centre_red) = (bare.pixel(w / 2, h / 2), red.pixel(w / 2, h / 2));
    let (rim_bare, rim_red) = (bare.pixel(w / 2 + 18, h / 2), red.pixel(w / 2 + 18, h / 2));
    // Near the silhouette the fibres' red outshines the blue ball; head-on they add little.
    assert!(rim_red.x > rim_red.z && rim_red.x > 5.0 * rim_bare.x.max(1e-3), "the rim: {rim_red} against {rim_bare}");
    assert!(centre_red.x - centre_bare.x < 0.5 * (rim_red.x - rim_bare.x), "head-on: {centre_red} against {centre_bare}");
    // What the fibres reflect the ball under them does not: its blue dims.
    assert!(rim_red.z < rim_bare.z && centre_red.z <= centre_bare.z * 1.02, "the base: {rim_red} against {rim_bare}");
    // The other integrators light the fibres too, finite.
    for integrator in [Integrator::EyeLight, Integrator::Whitted, Integrator::Distribution] {
        let (film, stats) = render_with(&cloth(Vec3::new(1.0, 0.0, 0.0)), integrator, 48, 48, 4);
        assert!(film.pixels().iter().all(|p| p.is_finite()) && stats.non_finite == 0, "{integrator:?}");
        if integrator != Integrator::EyeLight {
            assert!(film.pixel(w / 2 + 18, h / 2).x > film.pixel(w / 2 + 18, h / 2).z, "{integrator:?}: a red rim");
        }
    }
}
