//! A clearcoat on a dark, rough paint: the coat adds its own sharp highlight where the light is
//! mirrored, and takes from the paint under it only what it reflects.

mod common;

use common::{lit_from_the_camera, render_with, sphere_scene};
use glam::Vec3;
use raystage_render::Integrator;
use raystage_scene::ParamValue;

/// A dark red rough dielectric sphere lit by a point light beside the camera, with a coat of
/// weight `coat` (roughness 0.3).
fn paint(coat: f32) -> raystage_scene::Scene {
    lit_from_the_camera(&[
        ("base_color", ParamValue::Color(Vec3::new(0.5, 0.02, 0.02))),
        ("metallic", ParamValue::Float(0.0)),
        ("roughness", ParamValue::Float(1.0)),
        ("clearcoat", ParamValue::Float(coat)),
        ("clearcoat_roughness", ParamValue::Float(0.3)),
    ])
}

#[test]
fn a_coat_adds_its_highlight_and_dims_the_paint_by_what_it_reflects() {
    let (w, h) = (48, 48);
    let bare = render_with(&paint(0.0), Integrator::Path, w, h, 64).0;
    let coated = render_with(&paint(1.0), Integrator::Path, w, h, 64).0;
    // At the centre the light is mirrored back to the camera: the coat's highlight, white.
    let (b, c) = (bare.pixel(w / 2, h / 2), coated.pixel(w / 2, h / 2));
    assert!(c.y > b.y + 0.2 && c.z > b.z + 0.2, "the coat's highlight: {c} against {b}");
    // Away from the highlight the paint shows through, a little darker (the coat reflects
    // about 4 % each way there), and as red.
    let (b, c) = (bare.pixel(w / 2 + 9, h / 2 + 9), coated.pixel(w / 2 + 9, h / 2 + 9));
    assert!(c.x < b.x && c.x > 0.8 * b.x, "the paint under the coat: {c} against {b}");
    assert!(c.x > 4.0 * c.y, "still red: {c}");
    // The other integrators render the paint under it, finite.
    for integrator in [Integrator::Whitted, Integrator::Distribution] {
        let (film, stats) = render_with(&paint(1.0), integrator, 16, 16, 4);
        assert!(film.pixels().iter().all(|p| p.is_finite()) && stats.non_finite == 0, "{integrator:?}");
    }
}

/// Whitted's and Cook's recursions reflect the scene in the coat: a black paint before a white
/// wall (behind the camera) shows the wall in its coat, as the path tracer does.
#[test]
fn the_recursive_integrators_reflect_the_scene_in_the_coat() {
    let scene = |coat: f32| {
        let mut scene = sphere_scene(
            "PhysicallyBased",
            &[
                ("base_color", ParamValue::Color(Vec3::splat(0.0))),
                ("metallic", ParamValue::Float(0.0)),
                ("roughness", ParamValue::Float(1.0)),
                ("specular", ParamValue::Float(0.0)),
                ("clearcoat", ParamValue::Float(coat)),
                ("clearcoat_roughness", ParamValue::Float(0.0)),
            ],
        );
        let white = common::shader(&mut scene, "Constant", &[("color", ParamValue::Color(Vec3::ONE))]);
        common::place(&mut scene, raystage_demo::shading::box_mesh(Vec3::new(-20.0, -20.0, 9.0), Vec3::new(20.0, 20.0, 10.0)), white);
        scene
    };
    // The path tracer picks the coat's lobe in a tenth of its samples: enough of them to see 4 %.
    let centre = |integrator: Integrator, coat: f32| {
        let spp = if integrator == Integrator::Path { 1024 } else { 16 };
        render_with(&scene(coat), integrator, 9, 9, spp).0.pixel(4, 4)
    };
    for integrator in [Integrator::Whitted, Integrator::Distribution, Integrator::Path] {
        let (bare, coated) = (centre(integrator, 0.0), centre(integrator, 1.0));
        // Head-on, the coat reflects 4 % of the white wall.
        assert!(bare.max_element() < 0.005 && (coated - Vec3::splat(0.04)).abs().max_element() < 0.01, "{integrator:?}: {coated} against {bare}");
    }
}
