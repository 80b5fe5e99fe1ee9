//! A packet's rays prepared eight at a time: the divisions, sign tests and Woop's axis choice of
//! [`PreparedRay::new`] run once across the lanes instead of once per ray (one ray at a time,
//! the three divisions per ray queue up on the divider).

use std::arch::x86_64::*;

use crate::PACKET_SIZE;
use crate::prepared::{PreparedRay, ROBUST_FAR};
use crate::ray::Ray;

/// [`PreparedRay::packet`], bit for bit: the same operations on the same values, lane by lane.
///
/// # Safety
/// The CPU must support AVX2; `rays` must hold one to eight rays.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn prepare_packet(rays: &[Ray]) -> [PreparedRay; PACKET_SIZE] {
    debug_assert!(!rays.is_empty() && rays.len() <= PACKET_SIZE);
    let last = rays.len() - 1;
    // Scalar loads, not a gather: the caller has usually just written the rays, and a gather
    // waits for those stores to retire where a scalar load takes its value straight from them.
    let lane = |i: usize| rays[i.min(last)].dir;
    let dir: [__m256; 3] = std::array::from_fn(|axis| {
        let c = |i: usize| lane(i)[axis];
        _mm256_setr_ps(c(0), c(1), c(2), c(3), c(4), c(5), c(6), c(7))
    });
    let zero = _mm256_setzero_ps();
    let inv = dir.map(|d| _mm256_div_ps(_mm256_set1_ps(1.0), d));
    let inv_far = inv.map(|i| _mm256_mul_ps(i, _mm256_set1_ps(ROBUST_FAR)));
    let abs = dir.map(|d| _mm256_andnot_ps(_mm256_set1_ps(-0.0), d));
    // Woop's dominant axis, chosen as `PreparedRay::new` chooses it.
    let x_dominant = _mm256_and_ps(_mm256_cmp_ps::<_CMP_GE_OQ>(abs[0], abs[1]), _mm256_cmp_ps::<_CMP_GE_OQ>(abs[0], abs[2]));
    let y_dominant = _mm256_andnot_ps(x_dominant, _mm256_cmp_ps::<_CMP_GE_OQ>(abs[1], abs[2]));
    let pick = |x: __m256, y: __m256, z: __m256| _mm256_blendv_ps(_mm256_blendv_ps(z, y, y_dominant), x, x_dominant);
    // The two other axes in turn (y, z after x; z, x after y; x, y after z), swapped when the
    // ray runs towards −kz.
    let negative = _mm256_cmp_ps::<_CMP_LT_OQ>(pick(dir[0], dir[1], dir[2]), zero);
    let (first, second) = (pick(dir[1], dir[2], dir[0]), pick(dir[2], dir[0], dir[1]));
    let (first, second) = (_mm256_blendv_ps(first, second, negative), _mm256_blendv_ps(second, first, negative));
    let inv_kz = pick(inv[0], inv[1], inv[2]);
    let shear = [_mm256_mul_ps(first, inv_kz), _mm256_mul_ps(second, inv_kz), inv_kz];

    let lanes = |v: __m256| {
        let mut out = [0f32; PACKET_SIZE];
        // SAFETY: `out` holds eight floats.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), v) };
        out
    };
    let (inv, inv_far, shear) = (inv.map(lanes), inv_far.map(lanes), shear.map(lanes));
    let bits = |m: __m256| _mm256_movemask_ps(m) as u32;
    let (x_dominant, y_dominant, negative) = (bits(x_dominant), bits(y_dominant), bits(negative));
    std::array::from_fn(|lane| {
        let ray = &rays[lane.min(last)];
        let bit = |mask: u32| mask >> lane & 1 != 0;
        let kz = if bit(x_dominant) { 0 } else if bit(y_dominant) { 1 } else { 2 };
        let k = match (kz, bit(negative)) {
            (0, false) => [1, 2, 0],
            (0, true) => [2, 1, 0],
            (1, false) => [2, 0, 1],
            (1, true) => [0, 2, 1],
            (_, false) => [0, 1, 2],
            (_, true) => [1, 0, 2],
        };
        let inv = [inv[0][lane], inv[1][lane], inv[2][lane]];
        PreparedRay {
            org: ray.origin.to_array(),
            inv,
            inv_far: [inv_far[0][lane], inv_far[1][lane], inv_far[2][lane]],
            neg: inv.map(|i| i < 0.0),
            tnear: ray.tnear,
            tfar: ray.tfar,
            k,
            shear: [shear[0][lane], shear[1][lane], shear[2][lane]],
        }
    })
}
