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
    // Samples are laid out for the accumulation's samples per pixel (neighbouring pixels share
    // their sequence): passes that bring it to that count make the render of that count.
    let scene = raystage_demo::shading::cornell_room().unwrap();
    let frame = scene.frame();
    // (A first pass of one sample looks through the pixel centres, as a one-sample frame
    // does; from two samples on, samples spread over the pixel.)
    let mut progressive = Progressive::new(settings(Integrator::Path, 3)).unwrap();
    progressive.add(&frame, 2);
    progressive.add(&frame, 1);
    let (whole, _) = render(&frame, &settings(Integrator::Path, 3)).unwrap();
    assert_eq!(bits(&progressive.film()), bits(&whole));
}

/// A stream takes a sample per pass up to its `max_samples`: told that count, its passes lay
/// their samples out as the render of that many does, and make that render.
#[test]
fn passes_planned_for_more_samples_add_up_to_the_render_of_that_many() {
    let scene = raystage_demo::shading::cornell_room().unwrap();
    let frame = scene.frame();
    let (whole, _) = render(&frame, &settings(Integrator::Path, 8)).unwrap();
    let passes = |planned: Option<u32>| {
        let mut progressive = Progressive::new(RenderSettings { planned_samples: planned, ..settings(Integrator::Path, 1) }).unwrap();
        for samples in [2, 1, 5] {
            progressive.add(&frame, samples);
        }
        bits(&progressive.film())
    };
    assert_eq!(passes(Some(8)), bits(&whole));
    // Laid out for one sample, the same passes take other samples.
    assert_ne!(passes(None), bits(&whole));
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

/// Adaptive sampling: tiles of a flat, noiseless backdrop stop after the minimum while the
/// path-traced room goes on, and the image is the one a full render converges to.
#[test]
fn adaptive_sampling_spends_samples_where_the_noise_is() {
    let mut scene = raystage_demo::shading::cornell_room().unwrap();
    // Half the view looks past the room at a flat backdrop.
    let camera = raystage_scene::Camera::look_at(glam::Vec3::new(2.5, 1.0, 4.0), glam::Vec3::new(0.0, 1.0, 0.0), glam::Vec3::Y, 60.0).unwrap();
    scene.set_camera(camera).unwrap();
    scene.set_background(Some(raystage_scene::Background::Color(glam::Vec3::splat(0.5)))).unwrap();
    let frame = scene.frame();
    let adaptive = RenderSettings { width: 64, height: 48, noise_threshold: Some(0.05), ..settings(Integrator::Path, 128) };
    let mut progressive = Progressive::new(adaptive).unwrap();
    let mut stats = progressive.add(&frame, 16);
    while progressive.samples() < 128 {
        stats.merge(&progressive.add(&frame, progressive.samples()));
    }
    let mean = progressive.mean_samples();
    assert!(mean > 16.0 && mean < 100.0, "{mean} samples per pixel on average");
    assert!(stats.rays.primary < 64 * 48 * 100, "{} camera rays", stats.rays.primary);
    // The same image as every pixel at 128 samples, within the noise.
    let (full, _) = render(&frame, &RenderSettings { noise_threshold: None, ..adaptive }).unwrap();
    let film = progressive.film();
    let (mut diff, mut sum) = (0.0, 0.0);
    for y in 0..48 {
        for x in 0..64 {
            diff += (film.pixel(x, y) - full.pixel(x, y)).abs().element_sum();
            sum += full.pixel(x, y).element_sum();
        }
    }
    assert!(diff / sum < 0.05, "relative difference {}", diff / sum);
    // `render` with a threshold takes its passes itself.
    let (once, once_stats) = render(&frame, &adaptive).unwrap();
    assert_eq!(bits(&once), bits(&film));
    assert_eq!(once_stats.rays.primary, stats.rays.primary);
}
