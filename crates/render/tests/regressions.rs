//! Image regressions: small renders of the demo scenes compared with references the project
//! rendered at many samples per pixel and checked in (`tests/references/`). Renders are noisy,
//! so the comparison is the root-mean-square error of the 8-bit sRGB images, with a tolerance a
//! little above the noise of the sample count used here; a shading change that moves the image
//! (a light twice as bright, a lost bounce, a colour channel swapped) exceeds it many times.
//!
//! `RAYSTAGE_BLESS=1 cargo test -p raystage-render --release --test regressions` re-renders the
//! references.

use std::path::PathBuf;

use raystage_render::{Film, Integrator, RenderSettings, render};
use raystage_scene::Scene;

/// One regression case.
struct Case {
    name: &'static str,
    scene: fn() -> Scene,
    integrator: Integrator,
    width: u32,
    height: u32,
    /// Samples per pixel of the test render, and of the reference.
    spp: u32,
    reference_spp: u32,
    /// Largest RMSE (8-bit sRGB, as a fraction of full scale) the test accepts.
    tolerance: f32,
}

const CASES: &[Case] = &[
    Case {
        name: "cornell-path",
        scene: || raystage_demo::shading::cornell_room().unwrap(),
        integrator: Integrator::Path,
        width: 64,
        height: 48,
        spp: 64,
        reference_spp: 8192,
        tolerance: 0.045,
    },
    Case {
        name: "materials-distribution",
        scene: || raystage_demo::shading::materials().unwrap(),
        integrator: Integrator::Distribution,
        width: 80,
        height: 50,
        spp: 32,
        reference_spp: 4096,
        tolerance: 0.025,
    },
    Case {
        name: "materials-whitted",
        scene: || raystage_demo::shading::materials().unwrap(),
        integrator: Integrator::Whitted,
        width: 80,
        height: 50,
        spp: 16,
        reference_spp: 1024,
        // Renders of six seeds measured 0.019-0.023 (2026-12-06).
        tolerance: 0.025,
    },
];

fn reference_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/references").join(format!("{name}.png"))
}

fn render_case(case: &Case, spp: u32, seed: u32) -> Film {
    let scene = (case.scene)();
    let settings = RenderSettings {
        width: case.width,
        height: case.height,
        integrator: case.integrator,
        samples_per_pixel: spp,
        max_depth: 8,
        seed,
        ..RenderSettings::default()
    };
    render(&scene.frame(), &settings).unwrap().0
}

/// RMSE between two RGBA8 images, over the colour channels, as a fraction of full scale.
fn rmse(a: &[u8], b: &[u8]) -> f32 {
    assert_eq!(a.len(), b.len());
    let (sum, n) = a
        .chunks_exact(4)
        .zip(b.chunks_exact(4))
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] as f32 - q[c] as f32) / 255.0))
        .fold((0.0, 0), |(s, n), d| (s + d * d, n + 1));
    (sum / n as f32).sqrt()
}

#[test]
fn renders_match_their_references() {
    let bless = std::env::var_os("RAYSTAGE_BLESS").is_some();
    let mut failures = Vec::new();
    for case in CASES {
        let path = reference_path(case.name);
        if bless {
            render_case(case, case.reference_spp, 7).write_png(&path).unwrap();
        }
        let reference = image::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgba8();
        assert_eq!((reference.width(), reference.height()), (case.width, case.height), "{}", case.name);
        let rendered = render_case(case, case.spp, 1).to_rgba8();
        let error = rmse(&rendered, reference.as_raw());
        eprintln!("{}: RMSE {error:.4} (tolerance {})", case.name, case.tolerance);
        if error > case.tolerance {
            let out = std::env::temp_dir().join(format!("raystage-{}.png", case.name));
            image::RgbaImage::from_raw(case.width, case.height, rendered).unwrap().save(&out).unwrap();
            failures.push(format!("{}: RMSE {error:.4} > {} (render written to {})", case.name, case.tolerance, out.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The comparison would notice a real change: the same scene with its light at half the power
/// is far outside the tolerance.
#[test]
fn the_tolerance_catches_a_dimmer_light() {
    let case = &CASES[2];
    let normal = render_case(case, case.spp, 2).to_rgba8();
    let mut scene = (case.scene)();
    let lights: Vec<_> = scene.lights().map(|(id, l)| (id, *l)).collect();
    for (id, light) in lights {
        let dimmer = match light {
            raystage_scene::Light::Environment { radiance, map, rotate_degrees } => raystage_scene::Light::Environment { radiance: radiance * 0.5, map, rotate_degrees },
            other => other,
        };
        scene.set_light(id, dimmer).unwrap();
    }
    let settings = RenderSettings { width: case.width, height: case.height, integrator: case.integrator, samples_per_pixel: case.spp, max_depth: 8, seed: 1, ..RenderSettings::default() };
    let dim = render(&scene.frame(), &settings).unwrap().0.to_rgba8();
    let error = rmse(&dim, &normal);
    assert!(error > 3.0 * case.tolerance, "RMSE {error}");
}
