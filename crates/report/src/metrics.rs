//! How far an image is from the reference, in the measures rendering uses.
//!
//! Absolute RMSE over all pixels is dominated by the brightest edges (a light's outline) and
//! says nothing of the dark parts where noise shows most, so the report's main measure is a
//! *relative* RMSE: each difference divided by the reference value (plus ε, 10 % of the
//! reference's mean, so that black pixels do not divide by zero), over the pixels that are not
//! emitters or background (they are the light, not the lighting), on means of 4×4 pixel blocks
//! (what the eye sees of fine noise) and per pixel. Per-channel mean ratios show a brightness
//! or colour bias at once; the repeats of a setting split its error into bias and noise.

use glam::Vec3;
use raystage_render::Film;

/// The side of the blocks the main error measure averages over.
pub const BLOCK: u32 = 4;

/// ε of the relative errors, as a fraction of the reference's mean value.
const EPSILON: f64 = 0.1;

/// The reference prepared for comparisons: its block means, which blocks count (no emitter or
/// background pixel in them) and ε.
#[derive(Clone, Debug)]
pub struct Comparison {
    width: u32,
    height: u32,
    reference: Film,
    blocks: Vec<Vec3>,
    /// Per pixel: measured (not an emitter or background).
    measured: Vec<bool>,
    /// Per block: every pixel measured.
    measured_blocks: Vec<bool>,
    epsilon: f64,
    reference_mean: [f64; 3],
}

impl Comparison {
    /// Prepares `reference`; `emitters` marks the pixels that see a light or the background
    /// directly (the same size). If that leaves no pixel, every pixel is measured.
    pub fn new(reference: &Film, emitters: &[bool]) -> Comparison {
        let (width, height) = (reference.width(), reference.height());
        assert_eq!(emitters.len(), reference.pixels().len(), "a mask of the reference's size");
        let mut measured: Vec<bool> = emitters.iter().map(|e| !e).collect();
        if !measured.contains(&true) {
            measured.fill(true);
        }
        let blocks = block_means(reference);
        let (bw, bh) = (width.div_ceil(BLOCK), height.div_ceil(BLOCK));
        let mut measured_blocks = vec![true; (bw * bh) as usize];
        for y in 0..height {
            for x in 0..width {
                if !measured[(y * width + x) as usize] {
                    measured_blocks[((y / BLOCK) * bw + x / BLOCK) as usize] = false;
                }
            }
        }
        if !measured_blocks.contains(&true) {
            measured_blocks.fill(true);
        }
        let reference_mean = channel_means(reference.pixels(), &measured);
        let epsilon = EPSILON * (reference_mean.iter().sum::<f64>() / 3.0).max(1e-12);
        Comparison { width, height, reference: reference.clone(), blocks, measured, measured_blocks, epsilon, reference_mean }
    }

    /// The share of pixels measured (the rest see emitters or the background).
    pub fn measured_share(&self) -> f64 {
        self.measured.iter().filter(|&&m| m).count() as f64 / self.measured.len() as f64
    }

    /// The reference's per-channel mean over the measured pixels.
    pub fn reference_mean(&self) -> [f64; 3] {
        self.reference_mean
    }

    /// An image's 4×4 block means, all that [`Comparison::split`] needs of it (a sixteenth of
    /// the image, so that a report can keep every render's).
    pub fn blocks(&self, image: &Film) -> Vec<Vec3> {
        block_means(image)
    }

    /// Compares one image (of the reference's size) with the reference.
    pub fn errors(&self, image: &Film) -> Errors {
        assert_eq!((image.width(), image.height()), (self.width, self.height), "images of one size");
        let blocks = block_means(image);
        let relative = |a: &[Vec3], r: &[Vec3], keep: &[bool]| {
            let (mut sum, mut n) = (0.0, 0usize);
            for ((a, r), _) in a.iter().zip(r).zip(keep).filter(|(_, k)| **k) {
                for c in 0..3 {
                    let (a, r) = (a[c] as f64, r[c] as f64);
                    sum += (a - r).powi(2) / (r * r + self.epsilon * self.epsilon);
                    n += 1;
                }
            }
            (sum / n.max(1) as f64).sqrt()
        };
        let absolute = {
            let sum: f64 = image.pixels().iter().zip(self.reference.pixels()).map(|(a, r)| (*a - *r).as_dvec3().length_squared()).sum();
            (sum / (3 * self.measured.len()) as f64).sqrt()
        };
        let mean = channel_means(image.pixels(), &self.measured);
        Errors {
            relative_blocks: relative(&blocks, &self.blocks, &self.measured_blocks),
            relative_pixels: relative(image.pixels(), self.reference.pixels(), &self.measured),
            rmse: absolute,
            mean_ratio: std::array::from_fn(|c| mean[c] / self.reference_mean[c].max(1e-30)),
        }
    }

    /// Splits the error of repeated renders of one setting (independent seeds) into bias and
    /// noise, on the block means: per block and channel, the repeats' mean against the
    /// reference is the bias (less the part of it that is the mean's own noise) and their
    /// spread the noise, both relative as in [`Errors::relative_blocks`]. Needs two images or
    /// more, as their [`Comparison::blocks`].
    pub fn split(&self, blocks: &[Vec<Vec3>]) -> Split {
        let k = blocks.len();
        assert!(k >= 2, "two repeats or more");
        let (mut bias2, mut noise2, mut n) = (0.0, 0.0, 0usize);
        for (b, r) in self.blocks.iter().enumerate().filter(|(b, _)| self.measured_blocks[*b]) {
            for c in 0..3 {
                let values = blocks.iter().map(|img| img[b][c] as f64);
                let mean = values.clone().sum::<f64>() / k as f64;
                let variance = values.map(|v| (v - mean).powi(2)).sum::<f64>() / (k - 1) as f64;
                let w = 1.0 / ((r[c] as f64).powi(2) + self.epsilon * self.epsilon);
                // The squared distance of the mean from the reference is bias² plus the mean's
                // variance, variance / k: subtract that to keep the bias estimate unbiased.
                bias2 += w * ((mean - r[c] as f64).powi(2) - variance / k as f64);
                noise2 += w * variance;
                n += 1;
            }
        }
        let n = n.max(1) as f64;
        Split { bias: (bias2 / n).max(0.0).sqrt(), noise: (noise2 / n).sqrt() }
    }
}

/// One image's errors against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    /// Relative RMSE of the 4×4 block means over blocks without emitter pixels: the report's
    /// main measure.
    pub relative_blocks: f64,
    /// Relative RMSE per pixel over the pixels that are not emitters.
    pub relative_pixels: f64,
    /// Absolute RMSE over every pixel and channel (the measure of earlier reports).
    pub rmse: f64,
    /// Per channel, the image's mean over the measured pixels over the reference's.
    pub mean_ratio: [f64; 3],
}

/// Error of one render split into its two causes, in the units of
/// [`Errors::relative_blocks`]: bias² + noise² is the expected squared error of one render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    /// What more samples do not remove: the renders' mean against the reference.
    pub bias: f64,
    /// What more samples remove: the renders' spread about their mean.
    pub noise: f64,
}

impl Split {
    /// The share of the squared error that is bias, in `[0, 1]`.
    pub fn bias_share(&self) -> f64 {
        let total = self.bias * self.bias + self.noise * self.noise;
        if total > 0.0 { self.bias * self.bias / total } else { 0.0 }
    }
}

/// Means of `BLOCK`×`BLOCK` pixel blocks, row by row (partial blocks at the right and bottom
/// edges average the pixels they have).
fn block_means(film: &Film) -> Vec<Vec3> {
    let (w, h) = (film.width(), film.height());
    let (bw, bh) = (w.div_ceil(BLOCK), h.div_ceil(BLOCK));
    let mut sums = vec![(Vec3::ZERO, 0u32); (bw * bh) as usize];
    for y in 0..h {
        for x in 0..w {
            let s = &mut sums[((y / BLOCK) * bw + x / BLOCK) as usize];
            s.0 += film.pixel(x, y);
            s.1 += 1;
        }
    }
    sums.into_iter().map(|(sum, n)| sum / n as f32).collect()
}

/// Per-channel means of the pixels where `keep` holds.
fn channel_means(pixels: &[Vec3], keep: &[bool]) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    let mut n = 0usize;
    for (p, _) in pixels.iter().zip(keep).filter(|(_, k)| **k) {
        (0..3).for_each(|c| sum[c] += p[c] as f64);
        n += 1;
    }
    sum.map(|s| s / n.max(1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film(values: impl Fn(u32, u32) -> Vec3) -> Film {
        Film::from_pixels(8, 8, (0..64).map(|i| values(i % 8, i / 8)).collect())
    }

    #[test]
    fn a_scaled_image_has_that_mean_ratio_and_relative_error() {
        let reference = film(|x, y| Vec3::splat(1.0 + (x + y) as f32 * 0.01));
        let comparison = Comparison::new(&reference, &[false; 64]);
        let scaled = Film::from_pixels(8, 8, reference.pixels().iter().map(|p| *p * 0.9).collect());
        let e = comparison.errors(&scaled);
        for ratio in e.mean_ratio {
            assert!((ratio - 0.9).abs() < 1e-6, "{ratio}");
        }
        // Every value is 10 % low, relative to itself plus ε (10 % of the mean, about 1.07).
        assert!((e.relative_blocks - 0.1).abs() < 0.002, "{}", e.relative_blocks);
        assert_eq!(comparison.errors(&reference).relative_pixels, 0.0);
    }

    #[test]
    fn emitter_pixels_and_their_blocks_are_left_out() {
        let reference = film(|x, _| Vec3::splat(if x == 0 { 100.0 } else { 1.0 }));
        let emitters: Vec<bool> = (0..64).map(|i| i % 8 == 0).collect();
        let comparison = Comparison::new(&reference, &emitters);
        // The light's column is wrong, everything else exact: no error is measured.
        let image = film(|x, _| Vec3::splat(if x == 0 { 50.0 } else { 1.0 }));
        let e = comparison.errors(&image);
        assert_eq!((e.relative_blocks, e.relative_pixels, e.mean_ratio), (0.0, 0.0, [1.0; 3]));
        assert!(e.rmse > 1.0, "the absolute RMSE still sees every pixel");
        assert_eq!(comparison.measured_share(), 7.0 / 8.0);
    }

    /// Three renders with independent noise of σ = 0.1 about the reference: the split finds
    /// that noise and no bias, although the three renders' mean is itself off by σ/√3 per block.
    #[test]
    fn independent_noise_is_not_taken_for_bias() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut gaussian = || {
            let mut uniform = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            let (u1, u2) = (uniform().max(1e-300), uniform());
            ((-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()) as f32
        };
        let (w, h) = (256, 256);
        let reference = Film::from_pixels(w, h, vec![Vec3::ONE; (w * h) as usize]);
        let comparison = Comparison::new(&reference, &vec![false; (w * h) as usize]);
        // Noise per block (σ 0.1 for the block mean): each pixel gets 4 × that, as 16 pixels average.
        let renders: Vec<Vec<Vec3>> = (0..3)
            .map(|_| {
                let film = Film::from_pixels(w, h, (0..w * h).map(|_| Vec3::new(1.0 + 0.4 * gaussian(), 1.0 + 0.4 * gaussian(), 1.0 + 0.4 * gaussian())).collect());
                comparison.blocks(&film)
            })
            .collect();
        let split = comparison.split(&renders);
        assert!((split.noise - 0.1 / 1.01f64.sqrt()).abs() < 0.005, "{split:?}");
        assert!(split.bias < 0.015, "no bias, only the mean's own noise (σ/√3 ≈ 0.058): {split:?}");
    }

    #[test]
    fn repeats_split_bias_from_noise() {
        let reference = film(|_, _| Vec3::ONE);
        let comparison = Comparison::new(&reference, &[false; 64]);
        // Unbiased noise: ±0.01 about the reference, alternating between two repeats.
        let plus = film(|x, y| Vec3::splat(if (x / 4 + y / 4) % 2 == 0 { 1.01 } else { 0.99 }));
        let minus = film(|x, y| Vec3::splat(if (x / 4 + y / 4) % 2 == 0 { 0.99 } else { 1.01 }));
        let split = comparison.split(&[block_means(&plus), block_means(&minus)]);
        assert!(split.bias < 1e-6, "{split:?}");
        assert!(split.noise > 0.01, "{split:?}");
        // The same two, 5 % high everywhere: the bias shows, the noise is unchanged.
        let high = |f: &Film| Film::from_pixels(8, 8, f.pixels().iter().map(|p| *p + Vec3::splat(0.05)).collect());
        let biased = comparison.split(&[block_means(&high(&plus)), block_means(&high(&minus))]);
        assert!((biased.bias - 0.05 / (1.0f64 + 0.01).sqrt()).abs() < 2e-3, "{biased:?}");
        assert!((biased.noise - split.noise).abs() < 1e-6, "f32 rounding only");
        assert!(biased.bias_share() > 0.0 && biased.bias_share() < 1.0);
    }
}
