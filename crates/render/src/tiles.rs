//! The tiled frame loop: the image is cut into square tiles, each one task, handed out
//! dynamically by rayon's work stealing.
//!
//! Tiles rather than rows or single pixels: a tile keeps neighbouring rays coherent in the BVH,
//! traced one after the other while the tree's nodes are in cache, and is enough work to
//! amortise its setup. 32×32 tiles are best for a large frame (16×16 made a point-lit 1080p
//! frame 3 % slower), but a frame must offer enough of them to keep many threads busy however
//! unevenly its work is spread (a band of sky next to a band of glass): the tile side is the
//! largest of 32, 16 and 8 that cuts the frame into at least [`MIN_TASKS`] tiles, so that every
//! image of 128×128 or more keeps 64 threads busy with tasks of at most 1/256 of it. Rayon
//! splits the row-major range of tiles in halves, so neighbouring tiles go to the same thread.
//!
//! Each tile writes its own pixels of the accumulation buffers in place, through a mutable view
//! of its row segments ([`TileSums`]: no copies, no locks, no two tasks touching one pixel, as the
//! borrow checker sees), and a band of rows is handed on once its tiles are done.

use glam::Vec3;
use rayon::prelude::*;

use crate::Cancel;
use crate::lights::luminance;

/// The tasks a frame is cut into at least, where its size allows tiles of 8 pixels a side.
pub const MIN_TASKS: u32 = 256;

/// Largest edge length of a tile in pixels; tiles on the right and bottom border may be
/// smaller.
pub const TILE_SIZE: u32 = 32;

/// The edge length of the tiles of a `width × height` frame (see the module documentation).
pub(crate) fn tile_size(width: u32, height: u32) -> u32 {
    [TILE_SIZE, 16, 8].into_iter().find(|&side| width.div_ceil(side) * height.div_ceil(side) >= MIN_TASKS).unwrap_or(8)
}

/// The index, row by row, of the tile of a `width × height` frame that pixel `(x, y)` lies in.
pub(crate) fn tile_of(x: u32, y: u32, width: u32, height: u32) -> usize {
    let side = tile_size(width, height);
    ((y / side) * width.div_ceil(side) + x / side) as usize
}

/// How many tasks the frame loop cuts a `width × height` frame into: what keeps threads busy,
/// reported by the benchmarks.
pub fn tasks(width: u32, height: u32) -> usize {
    let side = tile_size(width, height);
    (width.div_ceil(side) * height.div_ceil(side)) as usize
}

/// One process's share of a frame rendered by several (the MPI ranks of a cluster): the tiles
/// numbered (row by row) `index`, `index + count`, `index + 2·count`… Interleaved rather than one
/// block each, so that a frame whose work sits in one part (glass in the middle, sky at the top)
/// spreads it over every share, and tile by tile rather than band by band (rows of tiles), so
/// that many shares still get nearly equal work: a 1080p frame has 34 bands but 2,040 tiles, so
/// 16 ranks get 2 or 3 bands (the busiest 1.41× the mean, capping their efficiency at 0.71) but
/// 127 or 128 tiles. Whole tiles, so that each pixel is rendered exactly as a whole-frame render
/// renders it (adaptive sampling decides per tile).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Share {
    /// Which share, `0..count`.
    pub index: u32,
    /// How many shares the frame is cut into.
    pub count: u32,
}

impl Share {
    /// The whole frame.
    pub const WHOLE: Share = Share { index: 0, count: 1 };

    /// Whether the tile numbered `tile` (row by row) is in this share.
    pub fn owns_tile(&self, tile: u32) -> bool {
        tile % self.count == self.index
    }

    /// The tiles of a `width × height` frame in this share, row by row: each as its columns
    /// and rows of pixels.
    pub fn tiles(&self, width: u32, height: u32) -> Vec<(std::ops::Range<u32>, std::ops::Range<u32>)> {
        let side = tile_size(width, height);
        let columns = width.div_ceil(side);
        (0..columns * height.div_ceil(side))
            .filter(|&tile| self.owns_tile(tile))
            .map(|tile| {
                let (x0, y0) = (tile % columns * side, tile / columns * side);
                (x0..(x0 + side).min(width), y0..(y0 + side).min(height))
            })
            .collect()
    }

    /// The pixels of a `width × height` frame in this share, tile by tile, row by row within a
    /// tile: the order in which a rank sends them.
    pub fn pixels(&self, width: u32, height: u32) -> impl Iterator<Item = (u32, u32)> {
        self.tiles(width, height).into_iter().flat_map(|(xs, ys)| ys.flat_map(move |y| xs.clone().map(move |x| (x, y))))
    }

    /// How many pixels [`Share::pixels`] gives.
    pub fn pixel_count(&self, width: u32, height: u32) -> usize {
        self.tiles(width, height).iter().map(|(xs, ys)| xs.len() * ys.len()).sum()
    }
}

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

/// A tile's own pixels of the frame's accumulation buffers: its row segments of the sums (and of
/// the squared luminances, if kept), borrowed mutably and disjointly from every other tile's, so
/// that tiles write in place on many threads without locks and without `unsafe`.
pub(crate) struct TileSums<'a> {
    /// The tile's rows of sums of the samples, top to bottom.
    rows: Vec<&'a mut [Vec3]>,
    /// The tile's rows of sums of the squared sample luminances, if the variance is kept.
    squares: Option<Vec<&'a mut [f32]>>,
}

impl TileSums<'_> {
    /// Adds one sample of every pixel of the tile, `samples` in the tile's row-major order, to the
    /// sums (and their squared luminances, if kept); the first pass writes them over the sums
    /// instead.
    ///
    /// The samples are gathered per tile rather than stored pixel by pixel as they are shaded:
    /// a frame's sums are far larger than the caches, and each store that misses them holds up
    /// the stores behind it (the next packet's camera rays, its shading), where row by row the
    /// misses come together.
    pub fn add(&mut self, samples: &[Vec3], first_pass: bool) {
        let width = self.rows.first().map_or(0, |r| r.len());
        assert_eq!(samples.len(), width * self.rows.len(), "a sample per pixel of the tile");
        for (row, samples) in self.rows.iter_mut().zip(samples.chunks(width.max(1))) {
            if first_pass {
                row.copy_from_slice(samples);
            } else {
                row.iter_mut().zip(samples).for_each(|(sum, sample)| *sum += *sample);
            }
        }
        if let Some(squares) = &mut self.squares {
            for (row, samples) in squares.iter_mut().zip(samples.chunks(width.max(1))) {
                for (sum_sq, sample) in row.iter_mut().zip(samples) {
                    let square = luminance(*sample) * luminance(*sample);
                    *sum_sq = if first_pass { square } else { *sum_sq + square };
                }
            }
        }
    }

    /// Whether every pixel of the tile, with `samples` samples, has a standard error of its mean
    /// luminance within `threshold` of the mean (a floor of 10⁻³ keeps black pixels from
    /// dividing by zero).
    pub fn converged(&self, samples: u32, threshold: f32) -> bool {
        let Some(squares) = &self.squares else { return false };
        self.rows.iter().zip(squares).all(|(sums, squares)| {
            sums.iter().zip(squares.iter()).all(|(s, sq)| {
                let mean = luminance(*s) / samples as f32;
                variance_of_mean(*s, *sq, samples).sqrt() <= threshold * mean.max(1e-3)
            })
        })
    }
}

/// The estimated variance of the mean luminance of a pixel whose `samples` samples sum to `sum`
/// and their squared luminances to `sum_sq` (zero below two samples).
pub(crate) fn variance_of_mean(sum: Vec3, sum_sq: f32, samples: u32) -> f32 {
    if samples < 2 {
        return 0.0;
    }
    let n = samples as f32;
    let mean = luminance(sum) / n;
    ((sum_sq / n - mean * mean) * n / (n - 1.0)).max(0.0) / n
}

/// Runs `add` over every tile of `share` of a `width × height` image, each tile a task on the
/// current rayon pool (run it inside `ThreadPool::install` to choose the number of threads),
/// giving it its own pixels of the per-pixel accumulation buffers (row-major, one entry per
/// pixel; the squared sums only if kept) to write into. Once every tile of a band of rows is
/// done, `finished(first_row, sums)` is called with the band's rows of sums.
///
/// The buffers are cut into bands of rows, each a task, and each band into its tiles' row
/// segments, each a task too: every task holds a mutable view of its own pixels only, and a
/// band's task, once its tiles are done, holds the whole band again to hand it on.
///
/// Once `cancel` is cancelled, the tiles not yet started are skipped, and so are the bands they
/// lie in: a cancelled frame's sums are incomplete, and only the caller knows what to do with
/// them (see [`crate::Cancel`]).
pub(crate) fn render_tiles_with(
    width: u32,
    height: u32,
    share: Share,
    sum: &mut [Vec3],
    sum_sq: Option<&mut [f32]>,
    cancel: Option<&Cancel>,
    add: impl Fn(&Tile, &mut TileSums<'_>) + Sync,
    finished: impl Fn(u32, &[Vec3]) + Sync,
) {
    if width == 0 || height == 0 {
        return;
    }
    let n = width as usize * height as usize;
    assert!(sum.len() == n && sum_sq.as_ref().is_none_or(|s| s.len() == n), "one sum per pixel");
    let side = tile_size(width, height);
    let columns = width.div_ceil(side);
    let band_len = side as usize * width as usize;
    let square_bands: Vec<Option<&mut [f32]>> = match sum_sq {
        Some(squares) => squares.chunks_mut(band_len).map(Some).collect(),
        None => (0..height.div_ceil(side)).map(|_| None).collect(),
    };
    let cancelled = || cancel.is_some_and(Cancel::is_cancelled);
    sum.par_chunks_mut(band_len).zip(square_bands).enumerate().for_each(|(band, (band_sums, band_squares))| {
        let y0 = band as u32 * side;
        // The share's tiles of the band only: the others' pixels are left as they are.
        let owned: Vec<u32> = (0..columns).filter(|c| share.owns_tile(band as u32 * columns + c)).collect();
        if owned.is_empty() || cancelled() {
            return;
        }
        let mut tiles: Vec<(Tile, TileSums<'_>)> = owned
            .iter()
            .map(|&c| {
                let x0 = c * side;
                let tile = Tile { x0, y0, width: side.min(width - x0), height: side.min(height - y0) };
                (tile, TileSums { rows: Vec::new(), squares: band_squares.is_some().then(Vec::new) })
            })
            .collect();
        cut_rows(band_sums, width, side, &owned, &mut tiles, |sums, row| sums.rows.push(row));
        if let Some(squares) = band_squares {
            cut_rows(squares, width, side, &owned, &mut tiles, |sums, row| sums.squares.as_mut().expect("kept").push(row));
        }
        tiles.into_par_iter().for_each(|(tile, mut sums)| {
            if !cancelled() {
                add(&tile, &mut sums);
            }
        });
        // A tile skipped for a cancelled frame leaves the band incomplete.
        if !cancelled() {
            finished(y0, band_sums);
        }
    });
}

/// Cuts `band`'s rows (of `width` pixels) at every `side` pixels and hands the segments of the
/// columns `owned` to their tiles, `push(tile's sums, segment)`, top to bottom.
fn cut_rows<'a, T>(band: &'a mut [T], width: u32, side: u32, owned: &[u32], tiles: &mut [(Tile, TileSums<'a>)], push: impl Fn(&mut TileSums<'a>, &'a mut [T])) {
    for row in band.chunks_mut(width as usize) {
        let mut next = owned.iter().zip(tiles.iter_mut()).peekable();
        for (column, segment) in row.chunks_mut(side as usize).enumerate() {
            if let Some((_, (_, sums))) = next.next_if(|(c, _)| **c == column as u32) {
                push(sums, segment);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU32, Ordering};

    use super::*;

    const SIZES: [(u32, u32); 7] = [(1, 1), (16, 16), (17, 16), (16, 33), (35, 7), (160, 90), (3, 250)];

    /// Runs `add` over a fresh `width × height` image; returns the sums.
    fn run(width: u32, height: u32, add: impl Fn(&Tile, &mut TileSums<'_>) + Sync) -> Vec<Vec3> {
        let n = (width * height) as usize;
        let (mut sum, mut sum_sq) = (vec![Vec3::ZERO; n], vec![0.0; n]);
        render_tiles_with(width, height, Share::WHOLE, &mut sum, Some(&mut sum_sq), None, add, |_, _| {});
        sum
    }

    #[test]
    fn every_pixel_is_visited_exactly_once_and_written_in_place() {
        for (width, height) in SIZES {
            let calls: Vec<AtomicU32> = (0..width * height).map(|_| AtomicU32::new(0)).collect();
            let sum = run(width, height, |tile, sums| {
                let samples: Vec<Vec3> = (0..tile.len()).map(|i| tile.pixel(i)).map(|(x, y)| Vec3::new(x as f32, y as f32, 1.0)).collect();
                for i in 0..tile.len() {
                    let (x, y) = tile.pixel(i);
                    calls[(y * width + x) as usize].fetch_add(1, Ordering::Relaxed);
                }
                sums.add(&samples, true);
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
            render_tiles_with(width, height, Share::WHOLE, &mut sum, Some(&mut sum_sq), None, |tile, sums| {
                let samples: Vec<Vec3> = (0..tile.len()).map(|i| sample(tile.pixel(i).0, tile.pixel(i).1)).collect();
                sums.add(&samples, pass == 0);
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
        // 2040 tiles of 32 at 1080p; a 67 × 33 image gets tiles of 8 (9 × 5 of them).
        assert_eq!((tile_size(1920, 1080), tasks(1920, 1080)), (32, 60 * 34));
        assert_eq!((tile_size(256, 256), tasks(256, 256)), (16, 256));
        assert_eq!(tile_size(67, 33), 8);
        run(67, 33, |tile, _| tiles.lock().unwrap().push(*tile));
        let mut tiles = tiles.into_inner().unwrap();
        tiles.sort_by_key(|t| (t.y0, t.x0));
        assert_eq!(tiles.len(), 9 * 5);
        assert_eq!(tiles[8], Tile { x0: 64, y0: 0, width: 3, height: 8 });
        assert_eq!(tiles[44], Tile { x0: 64, y0: 32, width: 3, height: 1 });
    }

    /// Every band of rows is handed on once, whole, after all its tiles are written.
    #[test]
    fn each_band_is_finished_once_with_its_final_rows() {
        let (width, height) = (100, 75);
        let bands = std::sync::Mutex::new(Vec::new());
        let mut sum = vec![Vec3::ZERO; (width * height) as usize];
        render_tiles_with(width, height, Share::WHOLE, &mut sum, None, None, |tile, sums| sums.add(&vec![Vec3::ONE; tile.len()], true), |y0, rows| {
            assert!(rows.iter().all(|&p| p == Vec3::ONE), "band at {y0} complete");
            bands.lock().unwrap().push((y0, rows.len() as u32 / width));
        });
        let mut bands = bands.into_inner().unwrap();
        bands.sort_unstable();
        let side = tile_size(width, height);
        let expected: Vec<(u32, u32)> = (0..height).step_by(side as usize).map(|y0| (y0, side.min(height - y0))).collect();
        assert_eq!(bands, expected);
    }

    #[test]
    fn a_cancelled_frame_starts_no_more_tiles_and_finishes_no_band() {
        let cancel = Cancel::new();
        let started = AtomicU32::new(0);
        let (width, height) = (256, 256);
        let mut sum = vec![Vec3::ZERO; (width * height) as usize];
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        pool.install(|| {
            render_tiles_with(width, height, Share::WHOLE, &mut sum, None, Some(&cancel), |_, _| {
                // The first tile cancels the frame: on one thread, no other tile starts.
                started.fetch_add(1, Ordering::Relaxed);
                cancel.cancel();
            }, |y0, _| panic!("band at {y0} finished although its tiles were skipped"));
        });
        assert_eq!(started.into_inner(), 1);
    }

    #[test]
    fn an_empty_image_renders_nothing() {
        run(0, 5, |_, _| unreachable!("no tiles to shade"));
    }

    #[test]
    fn runs_on_the_callers_pool() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let sum = pool.install(|| {
            run(40, 40, |tile, sums| sums.add(&vec![Vec3::splat(rayon::current_num_threads() as f32); tile.len()], true))
        });
        assert_eq!(sum[0], Vec3::ONE);
    }
}
