//! The tiled frame loop: the image is cut into square tiles, rendered in parallel band by band.
//!
//! Tiles rather than rows or single pixels: a 32×32 tile keeps neighbouring rays coherent in the
//! BVH, traced one after the other while the tree's nodes are in cache (16×16 tiles made a
//! point-lit 1080p frame 3 % slower), and is enough work to amortise its setup. The tiles of
//! one band of 32 rows go to one thread in turn, and the bands (34 at 1080p) are shared out by
//! rayon's work stealing, which
//! balances cheap sky bands against expensive geometry bands. A band is a contiguous run of the
//! image's rows, so each thread writes its pixels in place: no copies, no locks.

use glam::Vec3;
use rayon::prelude::*;

/// Edge length of a tile in pixels; tiles on the right and bottom border may be smaller.
pub const TILE_SIZE: u32 = 32;

/// A rectangle of pixels: `x0..x0 + width` × `y0..y0 + height`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Tile {
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

    /// Where pixel `(x, y)` of the image is in the tile's row-major order.
    pub fn index(&self, x: u32, y: u32) -> usize {
        ((y - self.y0) * self.width + (x - self.x0)) as usize
    }

    /// Image coordinates of the pixel at `index` in the tile's row-major order.
    #[cfg(test)]
    pub fn pixel(&self, index: usize) -> (u32, u32) {
        (self.x0 + index as u32 % self.width, self.y0 + index as u32 / self.width)
    }
}

/// One band's part of the per-pixel accumulation buffers: whole image rows from `y0` on.
pub(crate) struct Band<'a> {
    /// Sum of the samples, per pixel.
    pub sum: &'a mut [Vec3],
    /// Sum of the squared sample luminances, per pixel, if the variance is kept.
    pub sum_sq: Option<&'a mut [f32]>,
    width: u32,
    y0: u32,
}

impl Band<'_> {
    /// Where pixel `(x, y)` of the image is in the band's buffers.
    pub fn index(&self, x: u32, y: u32) -> usize {
        ((y - self.y0) * self.width + x) as usize
    }

    /// Adds one sample of every pixel of `tile`, `samples` in the tile's row-major order, to the
    /// band's sums (and their squared luminances, if kept); the first pass writes them over the
    /// sums instead.
    ///
    /// The samples are gathered per tile rather than stored pixel by pixel as they are shaded:
    /// a frame's sums are far larger than the caches, and each store that misses them holds up
    /// the stores behind it (the next packet's camera rays, its shading), where row by row the
    /// misses come together.
    pub fn add_tile(&mut self, tile: &Tile, samples: &[Vec3], first_pass: bool) {
        assert_eq!(samples.len(), tile.len(), "a sample per pixel of the tile");
        let width = tile.width as usize;
        for (row, samples) in samples.chunks(width).enumerate() {
            let at = self.index(tile.x0, tile.y0 + row as u32);
            let sum = &mut self.sum[at..at + width];
            if first_pass {
                sum.copy_from_slice(samples);
            } else {
                sum.iter_mut().zip(samples).for_each(|(sum, sample)| *sum += *sample);
            }
            if let Some(sum_sq) = self.sum_sq.as_deref_mut() {
                for (sum_sq, sample) in sum_sq[at..at + width].iter_mut().zip(samples) {
                    let square = luminance(*sample) * luminance(*sample);
                    *sum_sq = if first_pass { square } else { *sum_sq + square };
                }
            }
        }
    }
}

/// Relative luminance of linear RGB (Rec. 709).
pub(crate) fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Runs `add` over every tile of a `width × height` image, bands of tiles in parallel on the
/// current rayon pool (run it inside `ThreadPool::install` to choose the number of threads),
/// giving it the band of the per-pixel accumulation buffers (row-major, one entry per pixel;
/// the squared sums only if kept) its tile lies in. Once every tile of a band is done,
/// `finished(first_row, sums)` is called with the band's rows of sums, on the thread that
/// rendered them.
pub(crate) fn render_tiles_with(
    width: u32,
    height: u32,
    sum: &mut [Vec3],
    sum_sq: Option<&mut [f32]>,
    add: impl Fn(&Tile, &mut Band<'_>) + Sync,
    finished: impl Fn(u32, &[Vec3]) + Sync,
) {
    if width == 0 || height == 0 {
        return;
    }
    let band_len = (width * TILE_SIZE) as usize;
    let bands = sum.len().div_ceil(band_len);
    let sum_sq_bands: Vec<Option<&mut [f32]>> = match sum_sq {
        Some(sum_sq) => sum_sq.chunks_mut(band_len).map(Some).collect(),
        None => (0..bands).map(|_| None).collect(),
    };
    sum.par_chunks_mut(band_len).zip(sum_sq_bands).enumerate().for_each(|(b, (sum, sum_sq))| {
        let y0 = b as u32 * TILE_SIZE;
        let rows = TILE_SIZE.min(height - y0);
        let mut band = Band { sum, sum_sq, width, y0 };
        for x0 in (0..width).step_by(TILE_SIZE as usize) {
            add(&Tile { x0, y0, width: TILE_SIZE.min(width - x0), height: rows }, &mut band);
        }
        finished(y0, band.sum);
    });
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU32, Ordering};

    use super::*;

    const SIZES: [(u32, u32); 7] = [(1, 1), (16, 16), (17, 16), (16, 33), (35, 7), (160, 90), (3, 250)];

    /// Runs `add` over a fresh `width × height` image; returns the sums.
    fn run(width: u32, height: u32, add: impl Fn(&Tile, &mut Band<'_>) + Sync) -> Vec<Vec3> {
        let n = (width * height) as usize;
        let (mut sum, mut sum_sq) = (vec![Vec3::ZERO; n], vec![0.0; n]);
        render_tiles_with(width, height, &mut sum, Some(&mut sum_sq), add, |_, _| {});
        sum
    }

    #[test]
    fn every_pixel_is_visited_exactly_once_and_written_in_place() {
        for (width, height) in SIZES {
            let calls: Vec<AtomicU32> = (0..width * height).map(|_| AtomicU32::new(0)).collect();
            let sum = run(width, height, |tile, band| {
                for i in 0..tile.len() {
                    let (x, y) = tile.pixel(i);
                    calls[(y * width + x) as usize].fetch_add(1, Ordering::Relaxed);
                    let at = band.index(x, y);
                    band.sum[at] = Vec3::new(x as f32, y as f32, 1.0);
                }
            });
            assert!(calls.iter().all(|c| c.load(Ordering::Relaxed) == 1), "{width}×{height}");
            for (i, p) in sum.iter().enumerate() {
                assert_eq!(*p, Vec3::new((i as u32 % width) as f32, (i as u32 / width) as f32, 1.0), "{width}×{height}");
            }
        }
    }

    #[test]
    fn a_tile_s_samples_are_written_then_added_with_their_squares() {
        let (width, height) = (70, 40);
        let n = (width * height) as usize;
        let (mut sum, mut sum_sq) = (vec![Vec3::splat(9.0); n], vec![9.0; n]);
        let sample = |x: u32, y: u32| Vec3::new(x as f32, y as f32, 1.0);
        for pass in 0..2 {
            render_tiles_with(width, height, &mut sum, Some(&mut sum_sq), |tile, band| {
                let samples: Vec<Vec3> = (0..tile.len()).map(|i| sample(tile.pixel(i).0, tile.pixel(i).1)).collect();
                band.add_tile(tile, &samples, pass == 0);
            }, |_, _| {});
        }
        for (i, (s, sq)) in sum.iter().zip(&sum_sq).enumerate() {
            let one = sample(i as u32 % width, i as u32 / width);
            assert_eq!(*s, 2.0 * one, "pixel {i}");
            assert_eq!(*sq, 2.0 * luminance(one) * luminance(one), "pixel {i}");
        }
    }

    #[test]
    fn border_tiles_are_clipped_to_the_image() {
        let tiles = std::sync::Mutex::new(Vec::new());
        let t = TILE_SIZE;
        run(2 * t + 3, t + 1, |tile, _| tiles.lock().unwrap().push(*tile));
        let mut tiles = tiles.into_inner().unwrap();
        tiles.sort_by_key(|t| (t.y0, t.x0));
        assert_eq!(tiles.len(), 3 * 2);
        assert_eq!(tiles[2], Tile { x0: 2 * t, y0: 0, width: 3, height: t });
        assert_eq!(tiles[5], Tile { x0: 2 * t, y0: t, width: 3, height: 1 });
    }

    #[test]
    fn an_empty_image_renders_nothing() {
        run(0, 5, |_, _| unreachable!("no tiles to shade"));
    }

    #[test]
    fn runs_on_the_callers_pool() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let sum = pool.install(|| {
            run(40, 40, |tile, band| {
                let (x, y) = tile.pixel(0);
                let at = band.index(x, y);
                band.sum[at] = Vec3::splat(rayon::current_num_threads() as f32);
            })
        });
        assert_eq!(sum[0], Vec3::ONE);
    }
}
