//! Cancelling renders: a cancelled render stops at its next tile or sample, hands on no band
//! it did not finish, returns `Error::Cancelled`, and leaves a progressive accumulation empty.

use std::sync::atomic::{AtomicU32, Ordering};

use raystage_render::{Cancel, Error, Integrator, Progressive, RenderSettings, render, render_rows};

fn settings() -> RenderSettings {
    RenderSettings { width: 96, height: 64, integrator: Integrator::Path, samples_per_pixel: 4, ..RenderSettings::default() }
}

#[test]
fn a_render_cancelled_before_it_starts_renders_nothing() {
    let scene = raystage_demo::shading::cornell_room().unwrap();
    let cancel = Cancel::new();
    cancel.cancel();
    let bands = AtomicU32::new(0);
    let result = render_rows(&scene.frame(), &settings(), Some(&cancel), |_| {
        bands.fetch_add(1, Ordering::Relaxed);
    });
    assert!(matches!(result, Err(Error::Cancelled)), "{:?}", result.map(|_| ()));
    assert_eq!(bands.into_inner(), 0);
    // Adaptive renders take their samples in passes: each pass stops too.
    let adaptive = RenderSettings { noise_threshold: Some(0.1), samples_per_pixel: 64, ..settings() };
    assert!(matches!(render_rows(&scene.frame(), &adaptive, Some(&cancel), |_| {}), Err(Error::Cancelled)));
}

#[test]
fn a_render_cancelled_midway_stops_there() {
    let scene = raystage_demo::shading::cornell_room().unwrap();
    let cancel = Cancel::new();
    let bands = AtomicU32::new(0);
    // One thread: tiles go in order, so nothing after the first band's last tile starts.
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let result = pool.install(|| {
        render_rows(&scene.frame(), &settings(), Some(&cancel), |_| {
            bands.fetch_add(1, Ordering::Relaxed);
            cancel.cancel();
        })
    });
    assert!(matches!(result, Err(Error::Cancelled)));
    assert_eq!(bands.into_inner(), 1, "only the band finished before the cancel is handed on");
    // A token that nobody cancels changes nothing.
    let (film, _) = render_rows(&scene.frame(), &settings(), Some(&Cancel::new()), |_| {}).unwrap();
    let (expected, _) = render(&scene.frame(), &settings()).unwrap();
    assert_eq!(film.to_rgba8(), expected.to_rgba8());
}

#[test]
fn a_cancelled_pass_empties_the_accumulation_and_the_next_starts_over() {
    let scene = raystage_demo::shading::cornell_room().unwrap();
    let frame = scene.frame();
    let mut progressive = Progressive::new(settings()).unwrap();
    progressive.add(&frame, 2);
    let cancel = Cancel::new();
    cancel.cancel();
    assert!(matches!(progressive.add_cancellable(&frame, 2, &cancel), Err(Error::Cancelled)));
    assert_eq!(progressive.samples(), 0);
    progressive.add_cancellable(&frame, 2, &Cancel::new()).unwrap();
    let mut fresh = Progressive::new(settings()).unwrap();
    fresh.add(&frame, 2);
    assert_eq!(progressive.film().to_rgba8(), fresh.film().to_rgba8());
}
