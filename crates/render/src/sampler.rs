//! The pixels' sample sequences: stratified within each pixel and across neighbouring pixels,
//! progressive, and decorrelated between dimensions.
//!
//! Every pair of dimensions is drawn from a (0,2)-sequence in base 2 (the first two Sobol
//! dimensions): any 2^k consecutive, aligned points of it put exactly one point in each of 2^k
//! equal rectangles of the unit square, for every rectangle shape at once. The pixels of a
//! 16 × 16 block share one such sequence: in Morton order, each pixel takes the next aligned
//! run of `2^k` points, `2^k` the frame's samples per pixel rounded up to a power of two
//! (pbrt-v4's `ZSobolSampler`, after Ahmed and Wonka 2020, *Screen-space blue-noise diffusion
//! of Monte Carlo sampling error via hierarchical ordering of pixels*). So a pixel's samples are
//! stratified at every count (any first `2^j` of them too: progressive rendering), and so are
//! the samples of any 2 × 2, 4 × 4, … square of pixels together: neighbouring pixels' errors
//! tend to cancel, and what remains of the noise is at high frequencies, which the eye and any
//! average over an area see least. Each dimension pair of each block gets its own hash-based
//! Owen scrambling of the sequence's order and of its points (Burley 2020, *Practical
//! Hash-based Owen Scrambling*), which keeps those properties while making every point
//! uniformly random (the estimate stays unbiased) and decorrelates pairs of dimensions from each
//! other (the seed's Cook 1986 shuffles jittered samples between dimensions for the same reason,
//! docs/design/seeds.md §1.6). Samples past the frame's count (a progressive accumulation that
//! goes on) start a new, independently scrambled sequence for every further `2^k`.
//! docs/design/sampling.md has the layout and what it changed, measured.

/// Pixels along each side of a block whose samples come from one sequence: `2^BLOCK_BITS`.
/// Its pixels' Morton codes and the bits of 65,536 samples fit the 32 bits of an index.
const BLOCK_BITS: u32 = 4;

/// The samples of one pixel: call [`PixelSampler::next_2d`] for each pair of dimensions a path
/// uses, in the same order for every sample.
#[derive(Clone, Debug)]
pub struct PixelSampler {
    /// The pixel's block, the render's seed and which run of `2^k` samples of the pixel this
    /// one is in, hashed into the block's seed when a first sample is drawn (a pixel of a frame
    /// that needs no random numbers never pays for it).
    block: [u32; 4],
    block_seed: Option<u32>,
    /// The sample's place in its block's sequence, bit-reversed (as every dimension scrambles
    /// it: reversed once here, not once per dimension).
    reversed_index: u32,
    dimension: u32,
}

impl PixelSampler {
    /// The sampler of pixel `(x, y)` of a render with seed `seed` and `samples_per_pixel`
    /// samples per pixel, positioned at sample `index` of the pixel (from 0; any index is
    /// valid, those past `samples_per_pixel` rounded up to a power of two less stratified).
    pub fn new(x: u32, y: u32, seed: u32, index: u32, samples_per_pixel: u32) -> PixelSampler {
        // Bits of a pixel's run of the sequence: 2^k ≥ samples_per_pixel.
        let k = samples_per_pixel.max(1).checked_next_power_of_two().map_or(32, u32::trailing_zeros).min(32 - 2 * BLOCK_BITS);
        let mask = (1u32 << k) - 1;
        let block = [x >> BLOCK_BITS, y >> BLOCK_BITS, seed, (index >> k).wrapping_add(1)];
        let cell = morton_2d(x, y) & ((1 << (2 * BLOCK_BITS)) - 1);
        PixelSampler { block, block_seed: None, reversed_index: (cell << k | index & mask).reverse_bits(), dimension: 0 }
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
        let [x, y, seed, run] = self.block;
        let block_seed = *self.block_seed.get_or_insert_with(|| hash(hash(hash(x ^ hash(seed)) ^ y) ^ run));
        let dimension_seed = DIMENSION_SEEDS.get(self.dimension as usize).copied().unwrap_or_else(|| dimension_seed(self.dimension));
        let seed = hash(block_seed ^ dimension_seed);
        self.dimension += 1;
        (seed, laine_karras(self.reversed_index, seed).reverse_bits())
    }
}

/// What a pair of dimensions mixes into its block's seed: the pair's number, hashed.
const fn dimension_seed(dimension: u32) -> u32 {
    hash(dimension.wrapping_add(0x9e37_79b9))
}

/// [`dimension_seed`] of the first 256 pairs, which a path of 64 bounces stays within: one
/// hash fewer per pair drawn (1 KB).
static DIMENSION_SEEDS: [u32; 256] = {
    let mut seeds = [0; 256];
    let mut dimension = 0;
    while dimension < 256 {
        seeds[dimension] = dimension_seed(dimension as u32);
        dimension += 1;
    }
    seeds
};

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

/// The low 16 bits of `x` and `y` interleaved, `x`'s lowest: the pixel's place in a
/// Z-shaped walk of its block, which visits every aligned square of 2^j × 2^j pixels in one run.
fn morton_2d(x: u32, y: u32) -> u32 {
    let spread = |v: u32| {
        let mut v = v & 0xffff;
        v = (v | v << 8) & 0x00ff_00ff;
        v = (v | v << 4) & 0x0f0f_0f0f;
        v = (v | v << 2) & 0x3333_3333;
        (v | v << 1) & 0x5555_5555
    };
    spread(x) | spread(y) << 1
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

    /// The samples as the textbook computes them, bit by bit and reversal by reversal: pixel
    /// `(x, y)`'s sample `index` of `spp` is point `cell · 2^k + index mod 2^k` of its block's
    /// sequence, `cell` the pixel's Morton code in its 16 × 16 block, `2^k ≥ spp`.
    fn reference_2d((x, y): (u32, u32), seed: u32, index: u32, spp: u32, dimension: u32) -> [f32; 2] {
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
        let k = (0..).find(|&k| 1u64 << k >= spp as u64).unwrap();
        let cell = (0..4).map(|b| (x >> b & 1) << (2 * b) | (y >> b & 1) << (2 * b + 1)).sum::<u32>();
        let point = (cell << k) | (index % (1 << k));
        let block_seed = hash(hash(hash((x / 16) ^ hash(seed)) ^ (y / 16)) ^ (index >> k).wrapping_add(1));
        let seed = hash(block_seed ^ hash(dimension.wrapping_add(0x9e37_79b9)));
        let (x, y) = sobol(owen(point, seed));
        [to_unit(owen(x, hash(seed ^ 0x68bc_21eb))), to_unit(owen(y, hash(seed ^ 0x02e5_be93)))]
    }

    #[test]
    fn samples_are_the_textbook_s_bit_for_bit() {
        for (pixel, spp) in [((5, 9), 1), ((5, 9), 3), ((21, 40), 64), ((1000, 7), 1000), ((15, 15), 65_536)] {
            for index in (0..3000).chain([spp - 1, spp, 2 * spp + 1, u32::MAX, 1 << 31, 0x1234_5678]) {
                let mut sampler = PixelSampler::new(pixel.0, pixel.1, 3, index, spp);
                for dimension in 0..6 {
                    let expected = reference_2d(pixel, 3, index, spp, dimension);
                    if dimension % 2 == 0 {
                        assert_eq!(sampler.next_2d(), expected, "pixel {pixel:?}, sample {index} of {spp}, dimension {dimension}");
                    } else {
                        assert_eq!(sampler.next_1d(), expected[0], "pixel {pixel:?}, sample {index} of {spp}, dimension {dimension}");
                    }
                }
            }
        }
        // Deep paths: the pairs whose seeds are tabulated, and those past the table.
        for index in [0, 5, 63] {
            let mut sampler = PixelSampler::new(21, 40, 3, index, 64);
            for dimension in 0..300 {
                assert_eq!(sampler.next_2d(), reference_2d((21, 40), 3, index, 64, dimension), "sample {index}, dimension {dimension}");
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

    /// Whether `points` (2^m of them) put one point in each cell of every 2^a × 2^b grid with
    /// a + b = m: the (0, m, 2)-net property.
    fn is_net(points: &[[f32; 2]]) -> bool {
        let m = points.len().trailing_zeros();
        (0..=m).all(|a| {
            let cells: std::collections::HashSet<(u32, u32)> = points.iter().map(|p| ((p[0] * (1 << a) as f32) as u32, (p[1] * (1 << (m - a)) as f32) as u32)).collect();
            cells.len() == points.len()
        })
    }

    /// Sample pair `pair` of samples `samples` of the pixels `pixels` of a render of `spp`.
    fn points(pixels: impl Iterator<Item = (u32, u32)> + Clone, samples: std::ops::Range<u32>, spp: u32, pair: u32) -> Vec<[f32; 2]> {
        samples
            .flat_map(|i| {
                pixels.clone().map(move |(x, y)| {
                    let mut sampler = PixelSampler::new(x, y, 7, i, spp);
                    (0..pair).for_each(|_| {
                        sampler.next_2d();
                    });
                    sampler.next_2d()
                })
            })
            .collect()
    }

    #[test]
    fn a_pixel_s_samples_and_their_first_powers_of_two_are_stratified() {
        for pair in [0, 1, 5] {
            assert!(is_net(&points([(3, 4)].into_iter(), 0..64, 64, pair)), "pair {pair}");
            // A progressive render's first passes, and a render of fewer samples than its
            // power of two.
            assert!(is_net(&points([(3, 4)].into_iter(), 0..16, 64, pair)), "pair {pair}");
            assert!(is_net(&points([(3, 4)].into_iter(), 0..32, 48, pair)), "pair {pair}");
            // Samples past the frame's count: another run, stratified in itself.
            assert!(is_net(&points([(3, 4)].into_iter(), 64..128, 64, pair)), "pair {pair}");
        }
    }

    #[test]
    fn squares_of_pixels_are_stratified_together() {
        let square = |x0: u32, y0: u32, side: u32| (0..side * side).map(move |i| (x0 + i % side, y0 + i / side));
        for (spp, pair) in [(1, 0), (4, 0), (4, 3), (16, 1)] {
            for (x0, y0, side) in [(0, 0, 2), (20, 36, 2), (4, 8, 4), (16, 32, 16)] {
                let p = points(square(x0, y0, side), 0..spp, spp, pair);
                assert!(is_net(&p), "{side}×{side} pixels from ({x0}, {y0}), {spp} spp, pair {pair}");
            }
        }
        // Not across blocks' edges: those are scrambled apart.
        assert!(!is_net(&points(square(15, 15, 2), 0..4, 4, 0)));
    }

    #[test]
    fn pixels_blocks_and_runs_get_different_points() {
        let first = |x, y, index| PixelSampler::new(x, y, 7, index, 64).next_2d();
        assert_ne!(first(3, 4, 0), first(4, 3, 0), "pixels of a block");
        assert_ne!(first(3, 4, 0), first(19, 4, 0), "the same place in the next block");
        assert_ne!(first(3, 4, 0), first(3, 4, 64), "the next run of samples");
    }

    #[test]
    fn dimensions_are_decorrelated() {
        // The correlation between dimension pair 0 and pair 1 over many samples is near zero.
        let n = 4096;
        let (mut sum_xy, mut sum_x, mut sum_y) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..n {
            let mut s = PixelSampler::new(1, 1, 0, i, n);
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
