//! Per-ray constants computed once per query and shared by the box and triangle tests.

use crate::PACKET_SIZE;
use crate::ray::Ray;

/// Widening factor of the far end of every box test, `1 + 2·γ(4)` with `γ(n) = n·ε/(1 − n·ε)`
/// and `ε = 2⁻²⁴` (Ize, *Robust BVH Ray Traversal*, JCGT 2013).
///
/// A near distance is computed with three roundings (`plane − origin`, the reciprocal, the
/// product), so it exceeds the exact value by at most a factor `(1 + ε)³`. A far distance uses the
/// reciprocal premultiplied by this factor (one more rounding, four in all), so it falls short of
/// `ROBUST_FAR ×` the exact value by at most `(1 − ε)⁴`. Since `ROBUST_FAR·(1 − ε)⁴ ≥ (1 + ε)³`, a
/// box the exact segment touches, even in a single point, always passes: a triangle lying on its
/// box's face (every triangle touches its leaf's box) is never culled by rounding. The ray's own
/// `tfar` is widened by the same factor, so a triangle at exactly the current closest distance,
/// which may win the tie on its index, is still reached. Folding the factor into the reciprocal
/// keeps the multiplication off the traversal's critical path.
pub(crate) const ROBUST_FAR: f32 = 1.0 + 2.0 * GAMMA4;
const GAMMA4: f32 = 4.0 * f32::EPSILON * 0.5 / (1.0 - 4.0 * f32::EPSILON * 0.5);

/// `t` widened for comparison with a near distance: see [`ROBUST_FAR`].
#[inline(always)]
pub(crate) fn widen(t: f32) -> f32 {
    t * ROBUST_FAR
}

/// A ray with its per-query constants: reciprocal direction for the slab test and the shear
/// transform of the watertight triangle test (Woop, Benthin, Wald 2013). Preparing costs a few
/// divisions; a caller that traces the same ray through several trees (the instances of a
/// two-level scene that share world space, say) prepares it once.
///
/// The fields are laid out in two halves of 32 bytes, one cache line in all: the origin, `tnear`,
/// the reciprocal and `tfar`, then the widened reciprocal, the shear and the axis and sign bytes,
/// so that a packet's rays can be written from its lanes with two transposes.
#[repr(C, align(64))]
#[derive(Clone, Copy, Debug)]
pub struct PreparedRay {
    /// Origin components.
    pub(crate) org: [f32; 3],
    /// Start of the segment.
    pub(crate) tnear: f32,
    /// Exact IEEE reciprocal of the direction: `±∞` for a `±0` component. The box tests then
    /// follow Williams et al. 2005 (docs/design/seeds.md §3.1): the sign of the reciprocal picks
    /// the near plane, so `+0` and `−0` are told apart, and a ray lying exactly in a slab plane
    /// produces `0 · ∞ = NaN` for that plane, which the tests' NaN-ignoring `min`/`max` skip,
    /// leaving the axis unconstrained: such a ray counts as inside the slab for every `t`, as
    /// it is.
    pub(crate) inv: [f32; 3],
    /// End of the segment as given by the caller.
    pub(crate) tfar: f32,
    /// The reciprocal widened by [`ROBUST_FAR`], for far distances.
    pub(crate) inv_far: [f32; 3],
    /// Woop's shear constants `Sx = dx/dz`, `Sy = dy/dz`, `Sz = 1/dz` in the permuted frame
    /// (`dx·(1/dz)`, rounded twice).
    pub(crate) shear: [f32; 3],
    /// Woop's axis permutation: `kz` is the dominant direction axis, `kx`, `ky` the others,
    /// swapped when `dir[kz] < 0` to keep the triangle winding (see [`PreparedRay::axes`]).
    pub(crate) k: [u8; 3],
    /// Per axis: does the ray travel towards −∞ (then a box's near plane is its max)?
    pub(crate) neg: [bool; 3],
}

impl PreparedRay {
    /// Up to [`PACKET_SIZE`] rays prepared for a packet, lanes past the last ray repeating it
    /// (so that every lane holds a valid ray). Each is written in place, which matters: a
    /// prepared ray built elsewhere and copied in is read back before its bytes have settled.
    ///
    /// # Panics
    /// If `rays` is empty or longer than a packet.
    #[inline]
    pub fn packet(rays: &[Ray]) -> [PreparedRay; PACKET_SIZE] {
        assert!(!rays.is_empty() && rays.len() <= PACKET_SIZE, "one to a packet of rays");
        #[cfg(target_arch = "x86_64")]
        if crate::Isa::best() == crate::Isa::Avx2 {
            // SAFETY: `best` only picks AVX2 where the CPU has it; the packet size was checked.
            return unsafe { crate::traverse::avx2::prepare_packet(rays) };
        }
        PreparedRay::packet_one_by_one(rays)
    }

    /// [`PreparedRay::packet`] without SIMD: each lane through [`PreparedRay::new`].
    pub(crate) fn packet_one_by_one(rays: &[Ray]) -> [PreparedRay; PACKET_SIZE] {
        let last = rays.len() - 1;
        let mut prepared = [PreparedRay::new(&rays[0]); PACKET_SIZE];
        for (i, lane) in prepared.iter_mut().enumerate().skip(1) {
            *lane = PreparedRay::new(&rays[i.min(last)]);
        }
        prepared
    }

    /// Precomputes the per-ray constants.
    #[inline(always)]
    pub fn new(ray: &Ray) -> PreparedRay {
        let org = ray.origin.to_array();
        let dir = ray.dir.to_array();
        let inv = dir.map(|d| 1.0 / d);
        let inv_far = inv.map(|i| i * ROBUST_FAR);
        let neg = inv.map(|i| i < 0.0);
        let abs = [dir[0].abs(), dir[1].abs(), dir[2].abs()];
        let kz = if abs[0] >= abs[1] && abs[0] >= abs[2] {
            0
        } else if abs[1] >= abs[2] {
            1
        } else {
            2
        };
        // The next two axes in turn, swapped when the ray runs towards −kz; each case names its
        // components directly (indexing by a computed axis goes through memory). Multiplying by
        // the reciprocal rather than dividing twice more: any shear is watertight as long as
        // every triangle of the query uses the same one.
        let (k, shear) = match (kz, negative_along(dir, kz)) {
            (0, false) => ([1, 2, 0], [dir[1] * inv[0], dir[2] * inv[0], inv[0]]),
            (0, true) => ([2, 1, 0], [dir[2] * inv[0], dir[1] * inv[0], inv[0]]),
            (1, false) => ([2, 0, 1], [dir[2] * inv[1], dir[0] * inv[1], inv[1]]),
            (1, true) => ([0, 2, 1], [dir[0] * inv[1], dir[2] * inv[1], inv[1]]),
            (_, false) => ([0, 1, 2], [dir[0] * inv[2], dir[1] * inv[2], inv[2]]),
            (_, true) => ([1, 0, 2], [dir[1] * inv[2], dir[0] * inv[2], inv[2]]),
        };
        PreparedRay { org, inv, inv_far, neg, tnear: ray.tnear, tfar: ray.tfar, k, shear }
    }

    /// Woop's axis permutation `[kx, ky, kz]` as indices.
    #[inline(always)]
    pub(crate) fn axes(&self) -> [usize; 3] {
        self.k.map(usize::from)
    }

    /// The same ray with its segment ending at `tfar` instead.
    #[inline]
    pub fn with_tfar(self, tfar: f32) -> PreparedRay {
        PreparedRay { tfar, ..self }
    }

    /// A ray in the same direction from `origin` over `(tnear, tfar]`: exactly
    /// [`PreparedRay::new`] of that ray, without computing again what only the direction
    /// decides (rays towards a distant light share it).
    #[inline]
    pub fn moved(self, origin: glam::Vec3, tnear: f32, tfar: f32) -> PreparedRay {
        PreparedRay { org: origin.to_array(), tnear, tfar, ..self }
    }
}

/// Whether `dir` runs towards −∞ along `axis`.
#[inline(always)]
fn negative_along(dir: [f32; 3], axis: usize) -> bool {
    match axis {
        0 => dir[0] < 0.0,
        1 => dir[1] < 0.0,
        _ => dir[2] < 0.0,
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use proptest::prelude::*;

    use super::*;

    /// Every field of a prepared ray as bits, to compare two exactly.
    fn bits(p: &PreparedRay) -> Vec<u32> {
        let floats = p.org.iter().chain(&p.inv).chain(&p.inv_far).chain(&p.shear).chain([&p.tnear, &p.tfar]);
        floats.map(|v| v.to_bits()).chain(p.neg.map(u32::from)).chain(p.k.map(|k| k as u32)).collect()
    }

    /// A direction component: any float, or one of the values that make the axis choice tie
    /// or the signs subtle (±0, ±1, ±2).
    fn component() -> impl Strategy<Value = f32> {
        prop_oneof![-1e6f32..1e6, prop::sample::select(vec![0.0f32, -0.0, 1.0, -1.0, 2.0, -2.0, 1e-30, -1e-30])]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2048, ..ProptestConfig::default() })]

        /// A packet prepared eight at a time is, lane for lane and bit for bit, each ray
        /// prepared alone, for full packets and short ones.
        #[test]
        fn a_prepared_packet_is_its_rays_prepared_one_by_one(
            rays in prop::collection::vec(((-10.0f32..10.0, -10.0f32..10.0, -10.0f32..10.0), (component(), component(), component()), 0.0f32..1.0, 1.0f32..1e3), 1..=PACKET_SIZE),
        ) {
            let rays: Vec<Ray> = rays
                .iter()
                .map(|&((ox, oy, oz), (dx, dy, dz), tnear, tfar)| {
                    let dir = Vec3::new(dx, dy, dz);
                    Ray::segment(Vec3::new(ox, oy, oz), if dir == Vec3::ZERO { Vec3::NEG_Y } else { dir }, tnear, tfar)
                })
                .collect();
            let (packet, one_by_one) = (PreparedRay::packet(&rays), PreparedRay::packet_one_by_one(&rays));
            for (lane, (a, b)) in packet.iter().zip(&one_by_one).enumerate() {
                prop_assert_eq!(bits(a), bits(b), "lane {}", lane);
            }
        }
    }
}
