//! The tiled frame loop: the image is cut into square tiles that rayon renders in parallel.
//!
//! Tiles rather than rows or single pixels: a 16×16 tile is enough work to amortise scheduling,
//! there are enough of them (8,160 at 1920×1080) for rayon's work stealing to balance cheap sky
//! tiles against expensive geometry tiles, and neighbouring rays stay coherent in the BVH.

use glam::Vec3;
use rayon::prelude::*;

use crate::Film;

/// Edge length of a tile in pixels; tiles on the right and bottom border may be smaller.
pub const TILE_SIZE: u32 = 16;

/// A rectangle of pixels: `x0..x0 + width` × `y0..y0 + height`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

impl Tile {
    /// Number of pixels.
    pub fn len(&self) -> usize {
        (self.width * self.height) as usize
    }

    /// Whether the tile has no pixels.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Image coordinates of the pixel at `index` in the tile's row-major order.
    pub fn pixel(&self, index: usize) -> (u32, u32) {
        (self.x0 + index as u32 % self.width, self.y0 + index as u32 / self.width)
    }
}

/// The tiles covering a `width × height` image, row of tiles by row of tiles.
fn tiles(width: u32, height: u32) -> Vec<Tile> {
    (0..height.div_ceil(TILE_SIZE))
        .flat_map(|ty| (0..width.div_ceil(TILE_SIZE)).map(move |tx| (tx * TILE_SIZE, ty * TILE_SIZE)))
        .map(|(x0, y0)| Tile { x0, y0, width: TILE_SIZE.min(width - x0), height: TILE_SIZE.min(height - y0) })
        .collect()
}

/// Fills every pixel of `film`, tiles in parallel on the current rayon pool: run it inside
/// `ThreadPool::install` to choose the number of threads. `shade_tile(tile, pixels)` writes the
/// tile's pixels (linear RGB) into `pixels`, row-major, one per pixel; a whole tile at a time, so
/// that the shader can trace neighbouring pixels' rays together.
///
/// Each tile is shaded into a buffer of its own and then copied into the film, so threads never
/// share a pixel and need no locks; the copy is a few milliseconds for a full-HD frame.
pub fn render_tiles(film: &mut Film, shade_tile: impl Fn(&Tile, &mut [Vec3]) + Sync) {
    let rendered: Vec<(Tile, Vec<Vec3>)> = tiles(film.width(), film.height())
        .into_par_iter()
        .map(|tile| {
            let mut pixels = vec![Vec3::ZERO; tile.len()];
            shade_tile(&tile, &mut pixels);
            (tile, pixels)
        })
        .collect();
    for (tile, pixels) in rendered {
        for (row, y) in pixels.chunks_exact(tile.width as usize).zip(tile.y0..) {
            film.row_mut(y)[tile.x0 as usize..(tile.x0 + tile.width) as usize].copy_from_slice(row);
        }
    }
}

/// Runs `add` over the tiles of a `width × height` image in parallel, giving each a private copy
/// of its part of two per-pixel accumulation buffers (row-major, one entry per pixel) and
/// writing the copies back: the progressive renderer's loop.
pub(crate) fn render_tiles_with(
    width: u32,
    height: u32,
    sum: &mut [Vec3],
    sum_sq: &mut [f32],
    add: impl Fn(&Tile, &mut [Vec3], &mut [f32]) + Sync,
) {
    let (shared_sum, shared_sq) = (&*sum, &*sum_sq);
    let done: Vec<(Tile, Vec<Vec3>, Vec<f32>)> = tiles(width, height)
        .into_par_iter()
        .map(|tile| {
            let index = |i: usize| {
                let (x, y) = tile.pixel(i);
                (y * width + x) as usize
            };
            let mut s: Vec<Vec3> = (0..tile.len()).map(|i| shared_sum[index(i)]).collect();
            let mut q: Vec<f32> = (0..tile.len()).map(|i| shared_sq[index(i)]).collect();
            add(&tile, &mut s, &mut q);
            (tile, s, q)
        })
        .collect();
    for (tile, s, q) in done {
        for i in 0..tile.len() {
            let (x, y) = tile.pixel(i);
            let at = (y * width + x) as usize;
            sum[at] = s[i];
            sum_sq[at] = q[i];
        }
    }
}

/// Adapts a per-pixel shader `shade(x, y)` to [`render_tiles`].
pub fn per_pixel(shade: impl Fn(u32, u32) -> Vec3 + Sync) -> impl Fn(&Tile, &mut [Vec3]) + Sync {
    move |tile, pixels| {
        for (i, p) in pixels.iter_mut().enumerate() {
            let (x, y) = tile.pixel(i);
            *p = shade(x, y);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU32, Ordering};

    use super::*;

    const SIZES: [(u32, u32); 7] = [(1, 1), (16, 16), (17, 16), (16, 33), (35, 7), (160, 90), (3, 250)];

    #[test]
    fn every_pixel_is_shaded_exactly_once() {
        for (width, height) in SIZES {
            let calls: Vec<AtomicU32> = (0..width * height).map(|_| AtomicU32::new(0)).collect();
            let mut film = Film::new(width, height);
            render_tiles(
                &mut film,
                per_pixel(|x, y| {
                    calls[(y * width + x) as usize].fetch_add(1, Ordering::Relaxed);
                    Vec3::ZERO
                }),
            );
            assert!(calls.iter().all(|c| c.load(Ordering::Relaxed) == 1), "{width}×{height}");
        }
    }

    #[test]
    fn every_pixel_gets_its_own_value() {
        for (width, height) in SIZES {
            let mut film = Film::new(width, height);
            render_tiles(&mut film, per_pixel(|x, y| Vec3::new(x as f32, y as f32, 1.0)));
            for y in 0..height {
                for x in 0..width {
                    assert_eq!(film.pixel(x, y), Vec3::new(x as f32, y as f32, 1.0), "{width}×{height} at ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn border_tiles_are_clipped_to_the_image() {
        let t = tiles(35, 17);
        assert_eq!(t.len(), 3 * 2);
        assert_eq!(t[2], Tile { x0: 32, y0: 0, width: 3, height: 16 });
        assert_eq!(t[5], Tile { x0: 32, y0: 16, width: 3, height: 1 });
    }

    #[test]
    fn an_empty_film_renders_nothing() {
        let mut film = Film::new(0, 5);
        render_tiles(&mut film, |_, _| unreachable!("no tiles to shade"));
    }

    #[test]
    fn runs_on_the_callers_pool() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let mut film = Film::new(40, 40);
        pool.install(|| render_tiles(&mut film, per_pixel(|_, _| Vec3::splat(rayon::current_num_threads() as f32))));
        assert_eq!(film.pixel(39, 39), Vec3::ONE);
    }
}
