//! One frame, end to end: primary rays through every pixel, eye-light shading, statistics.

use std::time::Instant;

use raystage_kernel::{Bvh8, IndexedMesh, PACKET_SIZE, Ray, TriangleSource};

use crate::tiles::Tile;
use crate::{Camera, EyeLight, Film, render_tiles};

/// The triangles a frame is traced against and the BVH built over them.
///
/// A stand-in for the retained scene: when `raystage-scene` exists, it takes this pair's place.
#[derive(Clone, Copy, Debug)]
pub struct Geometry<'a> {
    /// The triangles, for shading: the BVH reports hits by triangle index.
    pub triangles: IndexedMesh<'a>,
    /// The BVH built from `triangles`.
    pub bvh: &'a Bvh8,
}

/// What a frame cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// Rays traced (primary rays only in an eye-light frame: one per pixel).
    pub rays: u64,
    /// Wall-clock time of tracing and shading, in seconds (excludes encoding).
    pub seconds: f64,
}

impl FrameStats {
    /// Throughput in millions of rays per second.
    pub fn mrays_per_second(&self) -> f64 {
        self.rays as f64 / self.seconds / 1e6
    }
}

/// Renders a `width × height` eye-light frame of `geometry` seen by `camera`, in parallel on the
/// current rayon pool.
pub fn render_frame(
    geometry: &Geometry<'_>,
    camera: &impl Camera,
    shader: &EyeLight,
    width: u32,
    height: u32,
) -> (Film, FrameStats) {
    let mut film = Film::new(width, height);
    let start = Instant::now();
    render_tiles(&mut film, |tile, pixels| {
        // Neighbouring primary rays travel together as packets (see `Bvh8::intersect_packets`).
        let order = packet_order(tile);
        let rays: Vec<Ray> = order
            .iter()
            .map(|&i| {
                let (x, y) = tile.pixel(i);
                camera.primary_ray(x, y, width, height)
            })
            .collect();
        let mut hits = vec![None; rays.len()];
        geometry.bvh.intersect_packets(&rays, &mut hits);
        for ((&i, ray), hit) in order.iter().zip(&rays).zip(&hits) {
            pixels[i] = match hit {
                Some(hit) => shader.shade_hit(ray.dir, hit, &geometry.triangles.triangle(hit.prim)),
                None => shader.sky(ray.dir),
            };
        }
    });
    let stats = FrameStats { rays: u64::from(width) * u64::from(height), seconds: start.elapsed().as_secs_f64() };
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
    use glam::Vec3;
    use raystage_kernel::BuildOptions;

    use super::*;

    /// An orthographic camera looking down −z over `[-1, 1]²`.
    struct Orthographic;

    impl Camera for Orthographic {
        fn primary_ray(&self, x: u32, y: u32, width: u32, height: u32) -> Ray {
            let u = (x as f32 + 0.5) / width as f32 * 2.0 - 1.0;
            let v = 1.0 - (y as f32 + 0.5) / height as f32 * 2.0;
            Ray::new(Vec3::new(u, v, 1.0), Vec3::NEG_Z)
        }
    }

    #[test]
    fn packet_order_visits_every_pixel_once_in_4x2_blocks() {
        for (width, height) in [(16, 16), (5, 3), (1, 1), (7, 16)] {
            let tile = Tile { x0: 3, y0: 5, width, height };
            let mut order = packet_order(&tile);
            order.sort_unstable();
            assert_eq!(order, (0..tile.len()).collect::<Vec<_>>(), "{width}×{height}");
        }
        // A full tile: the first packet is the 4×2 block at the tile's top-left corner.
        let order = packet_order(&Tile { x0: 0, y0: 0, width: 16, height: 16 });
        assert_eq!(&order[..8], &[0, 1, 2, 3, 16, 17, 18, 19]);
    }

    #[test]
    fn a_square_in_front_of_the_sky() {
        // Two triangles covering [-0.5, 0.5]² at z = 0, each its own colour group.
        let vertices = [
            Vec3::new(-0.5, -0.5, 0.0),
            Vec3::new(0.5, -0.5, 0.0),
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::new(-0.5, 0.5, 0.0),
        ];
        let indices = [[0, 1, 2], [0, 2, 3]];
        let triangles = IndexedMesh { vertices: &vertices, indices: &indices };
        let bvh = Bvh8::build(&triangles, &BuildOptions::default());
        let shader = EyeLight { group_size: 1, plain_from: u32::MAX };

        let (film, stats) = render_frame(&Geometry { triangles, bvh: &bvh }, &Orthographic, &shader, 20, 20);

        assert_eq!(stats.rays, 400);
        assert!(stats.seconds > 0.0 && stats.mrays_per_second() > 0.0);
        // Head-on hits get the full base colour; (14, 8) is below the diagonal, in triangle 0.
        assert_eq!(film.pixel(14, 8), shader.base_colour(0));
        assert_eq!(film.pixel(6, 12), shader.base_colour(1));
        assert_eq!(film.pixel(0, 0), shader.sky(Vec3::NEG_Z));
    }
}
