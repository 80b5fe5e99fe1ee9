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
//! dimensions for the same reason, docs/design/seeds.md §1.6).

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
    #[inline]
    pub fn next_2d(&mut self) -> [f32; 2] {
        let (seed, shuffled) = self.next_dimension();
        let y = sobol_second_reversed(shuffled);
        [to_unit(laine_karras(shuffled, hash(seed ^ 0x68bc_21eb)).reverse_bits()), to_unit(laine_karras(y, hash(seed ^ 0x02e5_be93)).reverse_bits())]
    }

    /// The next dimension of the current sample, in `[0, 1)`: the first of
    /// [`PixelSampler::next_2d`]'s pair (the pair's second is not computed).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let (seed, shuffled) = self.next_dimension();
        to_unit(laine_karras(shuffled, hash(seed ^ 0x68bc_21eb)).reverse_bits())
    }

    /// The seed of the next pair of dimensions, and the sample's index shuffled for it (Owen
    /// scrambled) in bit-reversed order, which is the pair's first Sobol dimension as
    /// `laine_karras` takes it. Scrambling works on reversed bits: computing in that order
    /// throughout takes three of the seven bit reversals the textbook order needs (a reversal
    /// is a dozen instructions on x86).
    #[inline]
    fn next_dimension(&mut self) -> (u32, u32) {
        let (x, y, seed) = self.pixel;
        let pixel_seed = *self.pixel_seed.get_or_insert_with(|| hash(hash(x ^ hash(seed)) ^ y));
        let seed = hash(pixel_seed ^ hash(self.dimension.wrapping_add(0x9e37_79b9)));
        self.dimension += 1;
        (seed, laine_karras(self.index.reverse_bits(), seed).reverse_bits())
    }
}

/// The second Sobol dimension of `index`, bit-reversed: the XOR of the direction numbers of
/// `index`'s set bits, a byte at a time from [`SOBOL_SECOND`].
#[inline]
fn sobol_second_reversed(index: u32) -> u32 {
    let t = &SOBOL_SECOND;
    t[0][(index & 0xff) as usize] ^ t[1][(index >> 8 & 0xff) as usize] ^ t[2][(index >> 16 & 0xff) as usize] ^ t[3][(index >> 24) as usize]
}

/// For each byte of an index and each value of it, the XOR of the bit-reversed direction
/// numbers of the second Sobol dimension for the bits set in it: bit `k` of the index has
/// direction number `v_k = v_(k−1) ^ (v_(k−1) >> 1)` from `v_0 = 2^31`, and reversed
/// `r_k = r_(k−1) ^ (r_(k−1) << 1)` from `r_0 = 1`. (4 KB: four lookups instead of a loop over
/// 32 bits.)
static SOBOL_SECOND: [[u32; 256]; 4] = {
    let mut directions = [0u32; 32];
    let mut r = 1u32;
    let mut k = 0;
    while k < 32 {
        directions[k] = r;
        r ^= r << 1;
        k += 1;
    }
    let mut table = [[0u32; 256]; 4];
    let mut byte = 0;
    while byte < 4 {
        let mut value = 0;
        while value < 256 {
            let mut xor = 0u32;
            let mut bit = 0;
            while bit < 8 {
                if value >> bit & 1 != 0 {
                    xor ^= directions[byte * 8 + bit];
                }
                bit += 1;
            }
            table[byte][value] = xor;
            value += 1;
        }
        byte += 1;
    }
    table
};

/// The first two dimensions of the Sobol sequence as 32-bit fixed-point fractions: the
/// van der Corput sequence and its partner, a (0,2)-sequence in base 2.
#[cfg(test)]
fn sobol_02(index: u32) -> (u32, u32) {
    (index.reverse_bits(), sobol_second_reversed(index).reverse_bits())
}

/// Laine and Karras's (2011) scrambling of bit-reversed fixed-point fractions (constants from
/// Burley 2020): every bit is flipped depending on the bits below it, which, read reversed, is
/// Owen scrambling: the scrambled points keep the sequence's stratification.
#[inline]
fn laine_karras(mut v: u32, seed: u32) -> u32 {
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v
}

/// A 32-bit integer hash (the lowbias32 finaliser), shared with the scene's alpha test.
pub(crate) use raystage_scene::hash;

/// A fixed-point fraction as a float in `[0, 1)` (24 bits, so 1 is never reached).
fn to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The samples as the textbook computes them, bit by bit and reversal by reversal.
    fn reference_2d(pixel: (u32, u32, u32), index: u32, dimension: u32) -> [f32; 2] {
        let owen = |x: u32, seed: u32| laine_karras(x.reverse_bits(), seed).reverse_bits();
        let sobol = |index: u32| {
            let (mut y, mut v, mut i) = (0u32, 1u32 << 31, index);
            while i != 0 {
                if i & 1 != 0 {
                    y ^= v;
                }
                i >>= 1;
                v ^= v >> 1;
            }
            (index.reverse_bits(), y)
        };
        let (x, y, seed) = pixel;
        let pixel_seed = hash(hash(x ^ hash(seed)) ^ y);
        let seed = hash(pixel_seed ^ hash(dimension.wrapping_add(0x9e37_79b9)));
        let (x, y) = sobol(owen(index, seed));
        [to_unit(owen(x, hash(seed ^ 0x68bc_21eb))), to_unit(owen(y, hash(seed ^ 0x02e5_be93)))]
    }

    #[test]
    fn samples_are_the_textbook_s_bit_for_bit() {
        for index in (0..5000).chain([u32::MAX, 1 << 31, 0x1234_5678]) {
            let mut sampler = PixelSampler::new(5, 9, 3, index);
            for dimension in 0..6 {
                let expected = reference_2d((5, 9, 3), index, dimension);
                if dimension % 2 == 0 {
                    assert_eq!(sampler.next_2d(), expected, "sample {index}, dimension {dimension}");
                } else {
                    assert_eq!(sampler.next_1d(), expected[0], "sample {index}, dimension {dimension}");
                }
            }
        }
    }

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
