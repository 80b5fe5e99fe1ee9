//! Morton codes and the radix sort that orders by them: what the fast builder sorts primitives
//! by (Lauterbach et al. 2009), and what a tracer that batches rays by where they start sorts
//! rays by (Bikker's RayGrid, seed 003). Cells that are near each other in space are near each
//! other in Morton order at every scale, so any run of the order covers a compact region.

/// Bits per axis of a Morton code: 1024 cells along each axis, a code in 30 bits.
pub const BITS: u32 = 10;

/// The Morton code of cell `(x, y, z)` of a `2^BITS`-cell grid (the low [`BITS`] bits of each
/// coordinate): their bits interleaved, x's lowest.
#[inline]
pub fn code(x: u32, y: u32, z: u32) -> u32 {
    interleave(x) | interleave(y) << 1 | interleave(z) << 2
}

/// Spreads the low 10 bits of `v` to every third bit.
fn interleave(v: u32) -> u32 {
    let mut x = v & 0x3ff;
    x = (x | x << 16) & 0x0300_00ff;
    x = (x | x << 8) & 0x0300_f00f;
    x = (x | x << 4) & 0x030c_30c3;
    (x | x << 2) & 0x0924_9249
}

/// Stable least-significant-digit radix sort on the 30-bit keys, 10 bits per pass (the three
/// digits' counts taken in one read of the keys), with `spare` as the second buffer: linear in
/// the number of items, where a comparison sort is not.
pub fn radix_sort<T: Copy>(items: &mut Vec<(u32, T)>, spare: &mut Vec<(u32, T)>) {
    const DIGITS: usize = 1 << 10;
    let digit = |key: u32, pass: usize| ((key >> (10 * pass)) & 0x3ff) as usize;
    let mut offsets = vec![[0usize; 3]; DIGITS + 1];
    for (key, _) in items.iter() {
        for pass in 0..3 {
            offsets[digit(*key, pass) + 1][pass] += 1;
        }
    }
    for d in 1..offsets.len() {
        let below = offsets[d - 1];
        offsets[d].iter_mut().zip(below).for_each(|(o, b)| *o += b);
    }
    spare.clear();
    spare.extend_from_slice(items);
    for pass in 0..3 {
        for item in items.iter() {
            let slot = &mut offsets[digit(item.0, pass)][pass];
            spare[*slot] = *item;
            *slot += 1;
        }
        std::mem::swap(items, spare);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_interleave_the_coordinates_bits() {
        assert_eq!(interleave(0b1), 0b1);
        assert_eq!(interleave(0b11), 0b1001);
        assert_eq!(interleave(0x3ff), 0x0924_9249);
        assert_eq!(code(1, 0, 0), 0b001);
        assert_eq!(code(0, 1, 0), 0b010);
        assert_eq!(code(0, 0, 1), 0b100);
        assert_eq!(code(0x3ff, 0x3ff, 0x3ff), 0x3fff_ffff);
    }

    #[test]
    fn radix_sort_is_a_stable_sort() {
        let items: Vec<(u32, usize)> = (0..5000).map(|i| ((i * 7919 % 4093) as u32 & 0x3fff_ffff, i)).collect();
        let mut expected = items.clone();
        expected.sort_by_key(|(k, _)| *k);
        let (mut sorted, mut spare) = (items, vec![(7, 7)]);
        radix_sort(&mut sorted, &mut spare);
        assert_eq!(sorted, expected);
    }
}
