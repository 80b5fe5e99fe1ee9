//! A clearcoat on a dark, rough paint: the coat adds its own sharp highlight where the light is
//! mirrored, and takes from the paint under it only what it reflects.

mod common;

use common::{render_with, sphere_scene};
use glam::Vec3;
use raystage_render::Integrator;
use raystage_scene::{Light, ParamValue};

/// A dark red rough dielectric sphere lit by a point light beside the camera, with a coat of
/// weight `coat` (roughness 0.3).
fn paint(coat: f32) -> raystage_scene::Scene {
    let mut scene = sphere_scene(
        "PhysicallyBased",
        &[
            ("base_color", ParamValue::Color(Vec3::new(0.5, 0.02, 0.02))),
            ("metallic", ParamValue::Float(0.0)),
            ("roughness", ParamValue::Float(1.0)),
            ("clearcoat", ParamValue::Float(coat)),
            ("clearcoat_roughness", ParamValue::Float(0.3)),
        ],
    );
    scene.add_light(Light::Point { position: Vec3::new(0.0, 0.0, 4.0), intensity: Vec3::splat(10.0) }).unwrap();
    scene
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
