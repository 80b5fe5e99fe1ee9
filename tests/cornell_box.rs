//! The classic Cornell box (`raystage_demo::cornell_box`), imported from its glTF file and path
//! traced, against Mitsuba 3's rendering of the same file (`tests/references/cornell_box.pfm`,
//! 64×64 at 32,768 samples per pixel, made by `scripts/references/cornell_box.py`). The room is
//! lit by its emissive quad only: no default light may join it, and the light is counted once
//! however a path finds it.
//!
//! The comparison is on means: each colour channel's mean over the pixels that are not the light
//! (within 2 %), the light's own pixels (within 2 %), and the relative RMSE of 4×4-pixel block
//! means, which averages the noise of a test-sized sample count down while keeping where the
//! light falls. Broken variants fail it: paths cut short, a light that emits from its back,
//! the light counted twice where it is seen. (So do a path tracer that counts the light a
//! bounce finds in full besides sampling it, channel means 1.8× the reference's, and one that
//! counts the light the camera sees twice, the light's pixels 2×: both measured by changing
//! the code.)

use glam::Vec3;
use raystage_gltf_import::Limits;
use raystage_render::{Film, Integrator, RenderSettings, render};
use raystage_demo::cornell_box::Comparison;
use raystage_scene::{ObjectKind, Scene};

/// The image side of the reference and of the test's renders.
const SIZE: u32 = 64;
/// Samples per pixel of the test's renders.
const SPP: u32 = 256;
/// Largest relative RMSE of 4×4 block means the comparison accepts: a little above the noise
/// of `SPP` samples per pixel.
const BLOCK_TOLERANCE: f32 = 0.03;
/// Largest relative difference of channel means, and of the light's pixels.
const MEAN_TOLERANCE: f32 = 0.02;

/// Mitsuba's image, row by row from the top.
fn reference() -> Vec<Vec3> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/references/cornell_box.pfm");
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let film = Film::from_pfm(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!((film.width(), film.height()), (SIZE, SIZE));
    film.pixels().to_vec()
}

/// The room as raystage imports it.
fn room() -> Scene {
    let import = raystage_gltf_import::read(raystage_demo::cornell_box::gltf().as_bytes(), None, &Limits::default()).unwrap();
    assert!(import.lights().is_empty(), "the file has no punctual light");
    import.into_scene().unwrap()
}

/// `scene` path traced as the reference was: box filter, paths of up to `max_depth` segments.
fn render_room(scene: &Scene, max_depth: u32) -> Vec<Vec3> {
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        integrator: Integrator::Path,
        samples_per_pixel: SPP,
        max_depth,
        ..RenderSettings::default()
    };
    let (film, stats) = render(&scene.frame(), &settings).unwrap();
    assert!(!stats.default_lights, "the emissive quad lights the room");
    assert_eq!(stats.non_finite, 0);
    film.pixels().to_vec()
}

/// `image` against the reference.
fn compare(image: &[Vec3], reference: &[Vec3]) -> Comparison {
    Comparison::of(image, reference, SIZE as usize)
}

/// Whether a comparison is within the test's tolerances.
fn passes(c: &Comparison) -> bool {
    (c.channel_ratio - Vec3::ONE).abs().max_element() <= MEAN_TOLERANCE && (c.light_ratio - 1.0).abs() <= MEAN_TOLERANCE && c.block_rmse <= BLOCK_TOLERANCE
}

#[test]
fn the_path_traced_room_matches_mitsuba() {
    let reference = reference();
    let comparison = compare(&render_room(&room(), 64), &reference);
    eprintln!("raystage: {comparison:?}");
    assert!(passes(&comparison), "{comparison:?}");
}

#[test]
fn the_comparison_fails_broken_rooms() {
    let reference = reference();
    // Paths cut short: the light of the fourth bounce on is missing.
    let short = compare(&render_room(&room(), 4), &reference);
    eprintln!("paths of 4 segments: {short:?}");
    assert!(!passes(&short), "{short:?}");
    // The light's one side mistaken: it emits from its back, up into the ceiling.
    let mut flipped = room();
    for id in flipped.object_ids().collect::<Vec<_>>() {
        let mut mesh = flipped.mesh(id).unwrap().clone();
        for (prim, triangle) in mesh.indices.iter_mut().enumerate() {
            if flipped.shader(mesh.shaders[prim]).unwrap().color("emissive").max_element() > 0.0 {
                triangle.swap(1, 2);
            }
        }
        flipped.define_object(id, ObjectKind::Static, mesh).unwrap();
    }
    let upside_down = compare(&render_room(&flipped, 64), &reference);
    eprintln!("the light's back lit: {upside_down:?}");
    assert!(!passes(&upside_down), "{upside_down:?}");
    // The light counted twice where the camera sees it (the bug of a frame loop and an
    // integrator both adding it): its pixels read double.
    let mut doubled = render_room(&room(), 64);
    doubled.iter_mut().zip(&reference).filter(|(_, r)| r.dot(Vec3::new(0.2126, 0.7152, 0.0722)) > 1.0).for_each(|(c, _)| *c *= 2.0);
    let doubled = compare(&doubled, &reference);
    assert!(!passes(&doubled), "{doubled:?}");
}
