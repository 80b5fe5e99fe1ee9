//! Per-pixel sample sequences: stratified, progressive, and decorrelated between pixels and
//! between dimensions.
//!
//! Every pair of dimensions of a pixel's samples is a (0,2)-sequence in base 2 (the first two
//! Sobol dimensions): any 2^k consecutive samples put exactly one point in each of 2^k equal
//! rectangles of the unit square, for every rectangle shape at once, so the samples are
//! stratified at every count and adding samples never breaks the stratification (progressive
//! rendering). Each pixel and each dimension pair gets its own hash-based Owen scrambling, which
//! keeps those properties while making the points random, and its own shuffle of the sample
//! order, so that pairs of dimensions are not correlated with each other (Burley 2020, *Practical
//! Hash-based Owen Scrambling*; the seed's Cook 1986 shuffles jittered samples between
//! dimensions for the same reason, DIGEST §1.6).

/// The samples of one pixel: call [`PixelSampler::next_2d`] for each pair of dimensions a path
/// uses, in the same order for every sample.
#[derive(Clone, Debug)]
pub struct PixelSampler {
    /// The pixel and the render's seed, hashed into the pixel's seed when a first sample is
    /// drawn (a pixel of a frame that needs no random numbers never pays for it).
    pixel: (u32, u32, u32),
    pixel_seed: Option<u32>,
    index: u32,
    dimension: u32,
}

impl PixelSampler {
    /// The sampler of pixel `(x, y)` of a render with seed `seed`, positioned at sample `index`.
    pub fn new(x: u32, y: u32, seed: u32, index: u32) -> PixelSampler {
        PixelSampler { pixel: (x, y, seed), pixel_seed: None, index, dimension: 0 }
    }

    /// The next two dimensions of the current sample, each in `[0, 1)`.
    pub fn next_2d(&mut self) -> [f32; 2] {
        let (x, y, seed) = self.pixel;
        let pixel_seed = *self.pixel_seed.get_or_insert_with(|| hash(hash(x ^ hash(seed)) ^ y));
        let seed = hash(pixel_seed ^ hash(self.dimension.wrapping_add(0x9e37_79b9)));
        self.dimension += 1;
        let shuffled = owen_scramble(self.index, seed);
        let (x, y) = sobol_02(shuffled);
        [to_unit(owen_scramble(x, hash(seed ^ 0x68bc_21eb))), to_unit(owen_scramble(y, hash(seed ^ 0x02e5_be93)))]
    }

    /// The next dimension of the current sample, in `[0, 1)`.
    pub fn next_1d(&mut self) -> f32 {
        self.next_2d()[0]
    }
}

/// The first two dimensions of the Sobol sequence as 32-bit fixed-point fractions: the
/// van der Corput sequence and its partner, a (0,2)-sequence in base 2.
fn sobol_02(index: u32) -> (u32, u32) {
    let x = index.reverse_bits();
    let mut y = 0u32;
    let mut v = 1u32 << 31;
    let mut i = index;
    while i != 0 {
        if i & 1 != 0 {
            y ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    (x, y)
}

/// Owen scrambling of a 32-bit fixed-point fraction by a hash (Laine and Karras 2011, constants
/// from Burley 2020): every bit is flipped depending on the bits above it, so the scrambled
/// points keep the sequence's stratification.
fn owen_scramble(x: u32, seed: u32) -> u32 {
    let mut v = x.reverse_bits();
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v.reverse_bits()
}

/// A 32-bit integer hash (the lowbias32 finaliser).
pub(crate) fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// A fixed-point fraction as a float in `[0, 1)` (24 bits, so 1 is never reached).
fn to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sobol_pairs_are_stratified_in_every_elementary_interval() {
        // 16 points: one in each of the 16 cells of every 2^a × 2^b grid with a + b = 4.
        let points: Vec<(u32, u32)> = (0..16).map(sobol_02).collect();
        for a in 0..=4u32 {
            let b = 4 - a;
            let mut seen = std::collections::HashSet::new();
            for &(x, y) in &points {
                assert!(seen.insert((x as u64 >> (32 - a), y as u64 >> (32 - b))), "a = {a}");
            }
        }
    }

    #[test]
    fn scrambled_samples_stay_stratified_and_differ_between_pixels() {
        let samples = |x, y| {
            let mut s: Vec<[f32; 2]> = (0..64).map(|i| PixelSampler::new(x, y, 7, i).next_2d()).collect();
            s.sort_by(|a, b| a[0].total_cmp(&b[0]));
            s
        };
        let a = samples(3, 4);
        // One point in each of the 64 vertical strips.
        for (k, p) in a.iter().enumerate() {
            assert_eq!((p[0] * 64.0) as usize, k, "{p:?}");
        }
        assert_ne!(a, samples(4, 3), "pixels get different points");
    }

    #[test]
    fn dimensions_are_decorrelated() {
        // The correlation between dimension pair 0 and pair 1 over many samples is near zero.
        let n = 4096;
        let (mut sum_xy, mut sum_x, mut sum_y) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..n {
            let mut s = PixelSampler::new(1, 1, 0, i);
            let (a, b) = (s.next_2d()[0] as f64, s.next_2d()[0] as f64);
            sum_xy += a * b;
            sum_x += a;
            sum_y += b;
        }
        let n = n as f64;
        let covariance = sum_xy / n - (sum_x / n) * (sum_y / n);
        assert!(covariance.abs() < 0.005, "covariance {covariance}");
    }
}
