//! A frame cut into shares (one per MPI rank in a cluster) and put back together is the very
//! frame one process renders, bit for bit, for every integrator and with adaptive sampling.

use raystage_render::{Film, Integrator, RenderSettings, Share, render, render_share};

fn assembled(scene: &raystage_scene::Scene, settings: &RenderSettings, count: u32) -> Film {
    let frame = scene.frame();
    let (w, h) = (settings.width, settings.height);
    let mut assembled = Film::from_pixels(w, h, vec![glam::Vec3::splat(f32::NAN); (w * h) as usize]);
    for index in 0..count {
        let share = Share { index, count };
        let (film, _) = render_share(&frame, settings, share).unwrap();
        // As a rank sends its share and rank 0 puts it in.
        assert!(assembled.set_share_values(share, &film.share_values(share)));
        assert!(!assembled.set_share_values(share, &[0.0; 3]), "a share of the wrong size is refused");
    }
    assembled
}

#[test]
fn shares_put_together_are_the_whole_frame_bit_for_bit() {
    let scenes = [raystage_demo::shading::materials().unwrap(), raystage_demo::shading::cornell_room().unwrap()];
    for scene in &scenes {
        for integrator in Integrator::ALL {
            for (spp, noise_threshold) in [(4, None), (32, Some(0.2))] {
                let settings = RenderSettings { width: 67, height: 45, integrator, samples_per_pixel: spp, noise_threshold, max_depth: 6, seed: 3, ..RenderSettings::default() };
                let (whole, _) = render(&scene.frame(), &settings).unwrap();
                for count in [2, 3, 7] {
                    let parts = assembled(scene, &settings, count);
                    // Bits, not values: NaN from a row no share covered would fail too.
                    let bits = |f: &Film| f.pixels().iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
                    assert!(bits(&parts) == bits(&whole), "{integrator:?}, {spp} spp, threshold {noise_threshold:?}, {count} shares");
                }
            }
        }
    }
}

#[test]
fn every_pixel_is_in_exactly_one_share_and_the_rest_stays_black() {
    for (w, h) in [(1, 1), (67, 45), (640, 360), (8, 1000), (1920, 1080)] {
        for count in [1, 2, 3, 16] {
            let mut seen = vec![0u8; (w * h) as usize];
            let mut counts = Vec::new();
            for index in 0..count {
                let share = Share { index, count };
                share.pixels(w, h).for_each(|(x, y)| seen[(y * w + x) as usize] += 1);
                counts.push(share.tiles(w, h).len());
                assert_eq!(share.pixel_count(w, h), share.pixels(w, h).count());
            }
            assert!(seen.iter().all(|&n| n == 1), "{w}x{h}, {count} shares");
            // Tile by tile: the shares' tile counts differ by one at most.
            assert!(counts.iter().max().unwrap() - counts.iter().min().unwrap() <= 1, "{w}x{h}, {count} shares: {counts:?}");
        }
    }
    let scene = raystage_demo::shading::cornell_room().unwrap();
    let settings = RenderSettings { width: 32, height: 64, integrator: Integrator::Whitted, ..RenderSettings::default() };
    let share = Share { index: 1, count: 2 };
    let (film, _) = render_share(&scene.frame(), &settings, share).unwrap();
    let owned: Vec<(u32, u32)> = share.pixels(32, 64).collect();
    for y in 0..64 {
        for x in 0..32 {
            if !owned.contains(&(x, y)) {
                assert_eq!(film.pixel(x, y), glam::Vec3::ZERO, "({x}, {y}) is not the share's");
            }
        }
    }
    assert!(render_share(&scene.frame(), &settings, Share { index: 2, count: 2 }).is_err());
}
