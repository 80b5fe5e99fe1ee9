//! One frame of the retained scene, end to end: primary rays in 4×2 blocks, preview shading,
//! statistics.

use std::time::Instant;

use raystage_kernel::{PACKET_SIZE, Ray};
use raystage_scene::{Frame, FrameWork};

use crate::lambert::{self, RayCounts};
use crate::tiles::Tile;
use crate::{Film, render_tiles, sky};

/// What a frame cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// Rays traced, by kind.
    pub rays: RayCounts,
    /// Wall-clock time of tracing and shading, in seconds (excludes encoding).
    pub seconds: f64,
    /// Seconds spent placing instances and building the top level.
    pub top_level_seconds: f64,
    /// Object trees built, refitted or skipped while tracing.
    pub work: FrameWork,
}

impl FrameStats {
    /// Tracing throughput in millions of rays (all kinds) per second, not counting the time the
    /// frame spent in lazy object builds.
    pub fn mrays_per_second(&self) -> f64 {
        let tracing = (self.seconds - self.work.build_seconds).max(self.seconds * 1e-3);
        (self.rays.primary + self.rays.shadow) as f64 / tracing / 1e6
    }
}

/// Renders a `width × height` frame of the scene as `frame` froze it, seen by its camera, in
/// parallel on the current rayon pool.
pub fn render_frame(frame: &Frame<'_>, width: u32, height: u32) -> (Film, FrameStats) {
    let mut film = Film::new(width, height);
    let start = Instant::now();
    let counts = std::sync::Mutex::new(RayCounts::default());
    let camera = *frame.camera();
    render_tiles(&mut film, |tile, pixels| {
        // Neighbouring primary rays go to the scene together, in 4×2 blocks.
        let order = packet_order(tile);
        let rays: Vec<Ray> = order
            .iter()
            .map(|&i| {
                let (x, y) = tile.pixel(i);
                camera.ray(x as f32 + 0.5, y as f32 + 0.5, width, height)
            })
            .collect();
        let mut hits = vec![None; rays.len()];
        frame.intersect_many(&rays, &mut hits, 0.0);
        let mut tile_counts = RayCounts { primary: rays.len() as u64, shadow: 0 };
        for ((&i, ray), hit) in order.iter().zip(&rays).zip(&hits) {
            pixels[i] = match hit {
                Some(hit) => lambert::shade(frame, ray, hit, &mut tile_counts),
                None => sky(ray.dir),
            };
        }
        *counts.lock().unwrap_or_else(|e| e.into_inner()) += tile_counts;
    });
    let stats = FrameStats {
        rays: counts.into_inner().unwrap_or_else(|e| e.into_inner()),
        seconds: start.elapsed().as_secs_f64(),
        top_level_seconds: frame.top_level_seconds(),
        work: frame.work(),
    };
    (film, stats)
}

/// The tile's pixel indices grouped in blocks of 4×2 pixels (fewer at the tile's edges), so that
/// every [`PACKET_SIZE`] consecutive rays are neighbours.
fn packet_order(tile: &Tile) -> Vec<usize> {
    const BLOCK: (u32, u32) = (4, 2);
    const _: () = assert!((BLOCK.0 * BLOCK.1) as usize == PACKET_SIZE);
    let (w, h) = (tile.width, tile.height);
    let mut order = Vec::with_capacity(tile.len());
    for by in (0..h).step_by(BLOCK.1 as usize) {
        for bx in (0..w).step_by(BLOCK.0 as usize) {
            for y in by..(by + BLOCK.1).min(h) {
                order.extend((bx..(bx + BLOCK.0).min(w)).map(|x| (y * w + x) as usize));
            }
        }
    }
    order
}

#[cfg(test)]
mod tests {
    use glam::{Affine3A, Vec3};
    use raystage_scene::{Camera, Light, Mesh, ObjectKind, ParamValue, Scene};

    use super::*;

    #[test]
    fn packet_order_visits_every_pixel_once_in_4x2_blocks() {
        for (width, height) in [(16, 16), (5, 3), (1, 1), (7, 16)] {
            let tile = Tile { x0: 3, y0: 5, width, height };
            let mut order = packet_order(&tile);
            order.sort_unstable();
            assert_eq!(order, (0..tile.len()).collect::<Vec<_>>(), "{width}×{height}");
        }
        let order = packet_order(&Tile { x0: 0, y0: 0, width: 16, height: 16 });
        assert_eq!(&order[..8], &[0, 1, 2, 3, 16, 17, 18, 19]);
    }

    /// A unit square at z = 0 facing +z, seen from (0, 0, 3), lit from the camera side.
    fn square_scene(light: Option<Light>) -> Scene {
        let mut scene = Scene::new();
        let red = scene.add_shader("Diffuse").unwrap();
        scene.set_param(red, "diffuse", ParamValue::Color(Vec3::new(1.0, 0.0, 0.0))).unwrap();
        let mesh = Mesh::new(
            vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, 0.0)],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .with_shader(red);
        let square = scene.add_object(ObjectKind::Static, mesh).unwrap();
        scene.add_instance(square, Affine3A::IDENTITY).unwrap();
        scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 60.0).unwrap()).unwrap();
        if let Some(light) = light {
            scene.add_light(light).unwrap();
        }
        scene
    }

    #[test]
    fn a_lit_square_in_front_of_the_sky() {
        let light = Light::Directional { direction: -Vec3::Z, intensity: Vec3::splat(std::f32::consts::PI) };
        let scene = square_scene(Some(light));
        let frame = scene.frame();
        let (film, stats) = render_frame(&frame, 32, 32);
        // Facing the light head-on with E = π: radiance = albedo · E · cos / π = albedo.
        let centre = film.pixel(16, 16);
        assert!((centre - Vec3::new(1.0, 0.0, 0.0)).abs().max_element() < 1e-4, "{centre}");
        assert_eq!(film.pixel(0, 0), sky(frame.camera().ray(0.5, 0.5, 32, 32).dir));
        assert_eq!(stats.rays.primary, 32 * 32);
        assert!(stats.rays.shadow > 0 && stats.rays.shadow < 32 * 32);
        assert_eq!(stats.work.built, 1);
    }

    #[test]
    fn no_lights_means_eye_light_and_no_shadow_rays() {
        let scene = square_scene(None);
        let (film, stats) = render_frame(&scene.frame(), 16, 16);
        assert_eq!(stats.rays.shadow, 0);
        assert!(film.pixel(8, 8).x > 0.9, "seen head-on under the eye light");
    }
}
