//! Arithmetic on eight values side by side, for the renderer's packets of hits, with exactly
//! the rounding of the scalar operations it replaces.

/// `1 / sqrt(x)` of eight lanes, each exactly as `1.0 / x.sqrt()` rounds it (IEEE square roots
/// and divisions are correctly rounded either way), computed four at a time: the compiler often
/// does them one by one, each waiting on the last.
#[inline]
pub fn reciprocal_sqrt8(x: [f32; 8]) -> [f32; 8] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_div_ps, _mm_loadu_ps, _mm_set1_ps, _mm_sqrt_ps, _mm_storeu_ps};
        let mut out = [0.0f32; 8];
        for half in 0..2 {
            // SAFETY: SSE is part of every x86-64 CPU; the loads and stores stay inside the
            // arrays (four lanes from 0 or 4).
            unsafe {
                let v = _mm_loadu_ps(x.as_ptr().add(4 * half));
                _mm_storeu_ps(out.as_mut_ptr().add(4 * half), _mm_div_ps(_mm_set1_ps(1.0), _mm_sqrt_ps(v)));
            }
        }
        out
    }
    #[cfg(not(target_arch = "x86_64"))]
    x.map(|v| 1.0 / v.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reciprocal_square_roots_round_as_the_scalar_ones() {
        let x = [1.0, 2.0, 0.0, -0.0, f32::INFINITY, 1e-40, 3.0e38, f32::NAN];
        let lanes = reciprocal_sqrt8(x);
        for (v, r) in x.iter().zip(lanes) {
            assert_eq!(r.to_bits(), (1.0 / v.sqrt()).to_bits(), "1/sqrt({v})");
        }
        let mut seed = 0x9E37_79B9u32;
        for _ in 0..1000 {
            let x: [f32; 8] = std::array::from_fn(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 17;
                seed ^= seed << 5;
                f32::from_bits(seed & 0x7fff_ffff)
            });
            let lanes = reciprocal_sqrt8(x);
            for (v, r) in x.iter().zip(lanes) {
                assert_eq!(r.to_bits(), (1.0 / v.sqrt()).to_bits(), "1/sqrt({v})");
            }
        }
    }
}
