//! A packet's rays prepared eight at a time: the divisions, sign tests and Woop's axis choice of
//! [`PreparedRay::new`] run once across the lanes instead of once per ray (one ray at a time,
//! the three divisions per ray queue up on the divider), and the prepared rays are written from
//! the lanes with two transposes (each half of a [`PreparedRay`] is eight lanes wide).

use std::arch::x86_64::*;
use std::mem::{MaybeUninit, offset_of};

use crate::PACKET_SIZE;
use crate::prepared::{PreparedRay, ROBUST_FAR};
use crate::ray::Ray;

use super::transpose;

// The layouts the transposes read and write.
const _: () = {
    assert!(size_of::<Ray>() == 32 && offset_of!(Ray, tnear) == 12 && offset_of!(Ray, dir) == 16 && offset_of!(Ray, tfar) == 28);
    assert!(size_of::<PreparedRay>() == 64 && offset_of!(PreparedRay, tnear) == 12 && offset_of!(PreparedRay, inv) == 16);
    assert!(offset_of!(PreparedRay, tfar) == 28 && offset_of!(PreparedRay, inv_far) == 32 && offset_of!(PreparedRay, shear) == 44);
    assert!(offset_of!(PreparedRay, k) == 56 && offset_of!(PreparedRay, neg) == 59);
};

/// [`PreparedRay::packet`], bit for bit: the same operations on the same values, lane by lane.
///
/// # Safety
/// The CPU must support AVX2; `rays` must hold one to eight rays.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn prepare_packet(rays: &[Ray]) -> [PreparedRay; PACKET_SIZE] {
    debug_assert!(!rays.is_empty() && rays.len() <= PACKET_SIZE);
    let last = rays.len() - 1;
    // SAFETY: a ray is eight floats (checked above).
    let ray = |i: usize| unsafe { _mm256_loadu_ps((&rays[i.min(last)] as *const Ray).cast::<f32>()) };
    let [ox, oy, oz, tnear, dx, dy, dz, tfar] = transpose(std::array::from_fn(ray));
    let dir = [dx, dy, dz];
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
    let swap = |a: __m256, b: __m256| (_mm256_blendv_ps(a, b, negative), _mm256_blendv_ps(b, a, negative));
    let (first, second) = swap(pick(dir[1], dir[2], dir[0]), pick(dir[2], dir[0], dir[1]));
    let inv_kz = pick(inv[0], inv[1], inv[2]);
    let shear = [_mm256_mul_ps(first, inv_kz), _mm256_mul_ps(second, inv_kz), inv_kz];
    // The axis and sign bytes, four to a float's bits: `k` then `neg[0]`, then `neg[1..]`.
    let index = |i: i32| _mm256_castsi256_ps(_mm256_set1_epi32(i));
    let (kx, ky) = swap(pick(index(1), index(2), index(0)), pick(index(2), index(0), index(1)));
    let kz = pick(index(0), index(1), index(2));
    let sign = inv.map(|i| _mm256_srli_epi32::<31>(_mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(i, zero))));
    let byte = |v: __m256i, at: i32| _mm256_sllv_epi32(v, _mm256_set1_epi32(8 * at));
    let bytes = |v: [__m256i; 4]| _mm256_castsi256_ps(_mm256_or_si256(_mm256_or_si256(v[0], byte(v[1], 1)), _mm256_or_si256(byte(v[2], 2), byte(v[3], 3))));
    let [kx, ky, kz] = [kx, ky, kz].map(|v| _mm256_castps_si256(v));
    let axes = bytes([kx, ky, kz, sign[0]]);
    let signs = bytes([sign[1], sign[2], _mm256_setzero_si256(), _mm256_setzero_si256()]);

    let front = transpose([ox, oy, oz, tnear, inv[0], inv[1], inv[2], tfar]);
    let back = transpose([inv_far[0], inv_far[1], inv_far[2], shear[0], shear[1], shear[2], axes, signs]);
    let mut out = MaybeUninit::<[PreparedRay; PACKET_SIZE]>::uninit();
    let base = out.as_mut_ptr().cast::<f32>();
    for lane in 0..PACKET_SIZE {
        // SAFETY: each prepared ray is 16 floats, 64-byte aligned; both halves are written.
        unsafe {
            _mm256_store_ps(base.add(16 * lane), front[lane]);
            _mm256_store_ps(base.add(16 * lane + 8), back[lane]);
        }
    }
    // SAFETY: every byte was written, the axis bytes with 0 to 2 and the sign bytes with 0 or 1.
    unsafe { out.assume_init() }
}
