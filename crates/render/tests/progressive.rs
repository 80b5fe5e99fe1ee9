//! Progressive accumulation: passes continue each pixel's sample sequence, a reset starts a new
//! image, and a frame written into a reused buffer shows nothing of the image that was there.

use raystage_render::{Integrator, Progressive, RenderSettings, render};

fn settings(integrator: Integrator, samples_per_pixel: u32) -> RenderSettings {
    RenderSettings { width: 41, height: 29, integrator, samples_per_pixel, ..RenderSettings::default() }
}

fn bits(film: &raystage_render::Film) -> Vec<[u32; 3]> {
    (0..film.height()).flat_map(|y| (0..film.width()).map(move |x| film.pixel(x, y).to_array().map(f32::to_bits))).collect()
}

#[test]
fn passes_add_up_to_one_render_of_all_their_samples() {
    let scene = raystage_demo::shading::cornell_room().unwrap();
    let frame = scene.frame();
    // (A first pass of one sample looks through the pixel centres, as a one-sample frame
    // does; from two samples on, samples spread over the pixel.)
    let mut progressive = Progressive::new(settings(Integrator::Path, 1)).unwrap();
    progressive.add(&frame, 2);
    progressive.add(&frame, 1);
    let (whole, _) = render(&frame, &settings(Integrator::Path, 3)).unwrap();
    assert_eq!(bits(&progressive.film()), bits(&whole));
}

#[test]
fn a_reset_starts_a_new_image() {
    let scene = raystage_demo::shading::cornell_room().unwrap();
    let frame = scene.frame();
    let mut progressive = Progressive::new(settings(Integrator::Path, 1)).unwrap();
    progressive.add(&frame, 4);
    progressive.reset();
    assert!(bits(&progressive.film()).iter().all(|p| *p == [0; 3]), "no samples: black");
    progressive.add(&frame, 1);
    let (fresh, _) = render(&frame, &settings(Integrator::Path, 1)).unwrap();
    assert_eq!(bits(&progressive.film()), bits(&fresh));
    assert!(progressive.variance().iter().all(|v| *v == 0.0), "one sample: no variance yet");
}

#[test]
fn a_frame_in_a_reused_buffer_shows_nothing_of_the_last_image() {
    let (cornell, materials) = (raystage_demo::shading::cornell_room().unwrap(), raystage_demo::shading::materials().unwrap());
    let (expected, _) = render(&materials.frame(), &settings(Integrator::EyeLight, 1)).unwrap();
    let expected = bits(&expected);
    for _ in 0..3 {
        // The Cornell room's film is dropped, and its buffer is the next frame's.
        drop(render(&cornell.frame(), &settings(Integrator::Path, 2)).unwrap());
        let (film, _) = render(&materials.frame(), &settings(Integrator::EyeLight, 1)).unwrap();
        assert_eq!(bits(&film), expected);
    }
}

/// Every pixel's samples are its own (seeded by the pixel and the sample's number), so a frame
/// is bit for bit the same however many threads render its tiles, and in whatever order.
#[test]
fn frames_are_the_same_on_any_number_of_threads() {
    let scene = raystage_demo::shading::materials().unwrap();
    let frame = scene.frame();
    for integrator in [Integrator::Whitted, Integrator::Path] {
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| bits(&render(&frame, &RenderSettings { width: 150, height: 70, ..settings(integrator, 2) }).unwrap().0))
        };
        let one = on(1);
        assert_eq!(one, on(2), "{integrator:?}");
        assert_eq!(one, on(7), "{integrator:?}");
    }
}
