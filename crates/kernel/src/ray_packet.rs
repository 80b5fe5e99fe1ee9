//! A packet of prepared rays laid across SIMD lanes, for testing boxes against all of its rays at
//! once: the instance boxes a two-level scene's packet meets one after the other, where eight
//! single-ray slab tests per box cost more than the walk of a small instance's own tree.

use crate::PACKET_SIZE;
use crate::aabb::Aabb;
use crate::isa::Isa;
use crate::prepared::{PreparedRay, widen};

/// Which rays of a packet touch a box, and where each enters it: what the packet box tests
/// ([`RayPacket::touching`], [`crate::BoxTree::touched`]) find.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Entries {
    /// Bit `i` for each ray `i` whose segment touches the box.
    pub rays: u32,
    /// `entry[i]`: where the segment of ray `i` in `rays` enters the box (what
    /// [`Aabb::intersect`] returns for it); +∞ in the lanes of other rays.
    pub entry: [f32; PACKET_SIZE],
}

impl Entries {
    /// No ray touches the box.
    pub const NONE: Entries = Entries { rays: 0, entry: [f32::INFINITY; PACKET_SIZE] };

    /// The nearest entry of any ray (+∞ if none touches the box).
    #[inline]
    pub fn nearest(&self) -> f32 {
        self.entry.iter().copied().fold(f32::INFINITY, f32::min)
    }

    /// The rays that still touch the box once the segment of each ray `i` ends at `tfar[i]`,
    /// no later than the end it was tested with: those that enter the box by then (after the
    /// widening of [`Aabb::intersect`], which this answers exactly as a new test would).
    #[inline]
    pub fn within(&self, tfar: &[f32; PACKET_SIZE]) -> u32 {
        (0..PACKET_SIZE).fold(0, |rays, i| rays | u32::from(self.entry[i] <= widen(tfar[i])) << i) & self.rays
    }
}

/// Up to [`PACKET_SIZE`] prepared rays, component by component.
#[derive(Clone, Debug)]
pub struct RayPacket {
    org: [[f32; PACKET_SIZE]; 3],
    inv: [[f32; PACKET_SIZE]; 3],
    inv_far: [[f32; PACKET_SIZE]; 3],
    /// All bits set in lane `i` of axis `a` if ray `i` travels towards −∞ on it.
    neg: [[u32; PACKET_SIZE]; 3],
    tnear: [f32; PACKET_SIZE],
    /// Bit `i` for each ray there is.
    rays: u32,
    isa: Isa,
}

impl RayPacket {
    /// The packet of `rays`.
    ///
    /// # Panics
    /// If there are more than [`PACKET_SIZE`] rays.
    pub fn new(rays: &[PreparedRay]) -> RayPacket {
        assert!(rays.len() <= PACKET_SIZE, "at most a packet");
        let isa = Isa::best();
        match isa {
            // SAFETY: `isa` is a flavour `is_supported` confirmed on this CPU.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 if rays.len() == PACKET_SIZE => unsafe { RayPacket::transposed(rays.try_into().expect("a full packet"), isa) },
            _ => RayPacket::lane_by_lane(rays, isa),
        }
    }

    /// [`RayPacket::new`], one lane at a time.
    fn lane_by_lane(rays: &[PreparedRay], isa: Isa) -> RayPacket {
        let mut p = RayPacket {
            org: [[0.0; PACKET_SIZE]; 3],
            inv: [[0.0; PACKET_SIZE]; 3],
            inv_far: [[0.0; PACKET_SIZE]; 3],
            neg: [[0; PACKET_SIZE]; 3],
            tnear: [0.0; PACKET_SIZE],
            rays: (1u32 << rays.len()) - 1,
            isa,
        };
        for (lane, r) in rays.iter().enumerate() {
            for a in 0..3 {
                p.org[a][lane] = r.org[a];
                p.inv[a][lane] = r.inv[a];
                p.inv_far[a][lane] = r.inv_far[a];
                p.neg[a][lane] = if r.neg[a] { u32::MAX } else { 0 };
            }
            p.tnear[lane] = r.tnear;
        }
        p
    }

    /// [`RayPacket::new`] of a full packet, the rays' fields transposed into lanes and stored
    /// whole (lane-by-lane stores would make the box tests' wide loads wait for them).
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn transposed(rays: &[PreparedRay; PACKET_SIZE], isa: Isa) -> RayPacket {
        use std::arch::x86_64::*;
        // SAFETY: the packet is full.
        let fields = unsafe { crate::traverse::avx2::ray_fields(rays) };
        let field = |offset: usize| fields[offset / 4];
        let store = |v: __m256| {
            let mut out = [0.0f32; PACKET_SIZE];
            unsafe { _mm256_storeu_ps(out.as_mut_ptr(), v) };
            out
        };
        let (org, inv, inv_far) = (std::mem::offset_of!(PreparedRay, org), std::mem::offset_of!(PreparedRay, inv), std::mem::offset_of!(PreparedRay, inv_far));
        let inv_lanes = [0, 1, 2].map(|a| field(inv + 4 * a));
        RayPacket {
            org: [0, 1, 2].map(|a| store(field(org + 4 * a))),
            inv: inv_lanes.map(store),
            inv_far: [0, 1, 2].map(|a| store(field(inv_far + 4 * a))),
            // `PreparedRay::neg` is `inv < 0`.
            neg: inv_lanes.map(|v| store(_mm256_cmp_ps::<_CMP_LT_OQ>(v, _mm256_setzero_ps())).map(f32::to_bits)),
            tnear: store(field(std::mem::offset_of!(PreparedRay, tnear))),
            rays: (1u32 << PACKET_SIZE) - 1,
            isa,
        }
    }

    /// The rays among `candidates` (bit `i` for ray `i`) whose segment `(tnear, tfar[i]]` touches
    /// `b`, and where each enters it: exactly what [`Aabb::intersect`] says of each.
    pub fn touching(&self, b: &Aabb, tfar: &[f32; PACKET_SIZE], candidates: u32) -> Entries {
        let candidates = candidates & self.rays;
        match self.isa {
            // SAFETY: `isa` is only ever a flavour `is_supported` confirmed on this CPU.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { self.touching_avx2(b, tfar, candidates) },
            _ => self.touching_portable(b, tfar, candidates),
        }
    }

    /// [`RayPacket::touching`], lane by lane.
    fn touching_portable(&self, b: &Aabb, tfar: &[f32; PACKET_SIZE], candidates: u32) -> Entries {
        let mut found = Entries::NONE;
        for lane in (0..PACKET_SIZE).filter(|&lane| candidates & (1 << lane) != 0) {
            let ray = |a: usize| (self.org[a][lane], self.inv[a][lane], self.inv_far[a][lane], self.neg[a][lane] != 0);
            let (mut tn, mut tf) = (self.tnear[lane], widen(tfar[lane]));
            for a in 0..3 {
                let (org, inv, inv_far, neg) = ray(a);
                let (near, far) = if neg { (b.max[a], b.min[a]) } else { (b.min[a], b.max[a]) };
                tn = ((near - org) * inv).max(tn);
                tf = ((far - org) * inv_far).min(tf);
            }
            if tn <= tf {
                found.rays |= 1 << lane;
                found.entry[lane] = tn;
            }
        }
        found
    }

    /// [`RayPacket::touching`] of all lanes at once: the slab test's arithmetic, one ray per
    /// lane. (`max`/`min` return their second
    /// operand for a NaN, a ray in a slab's plane, as `f32::max`/`min` return the other
    /// operand.)
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn touching_avx2(&self, b: &Aabb, tfar: &[f32; PACKET_SIZE], candidates: u32) -> Entries {
        use std::arch::x86_64::*;
        let load = |v: &[f32; PACKET_SIZE]| unsafe { _mm256_loadu_ps(v.as_ptr()) };
        let (mut tn, mut tf) = (load(&self.tnear), _mm256_mul_ps(load(tfar), _mm256_set1_ps(crate::prepared::ROBUST_FAR)));
        for a in 0..3 {
            let (lo, hi) = (_mm256_set1_ps(b.min[a]), _mm256_set1_ps(b.max[a]));
            let neg = unsafe { _mm256_castsi256_ps(_mm256_loadu_si256(self.neg[a].as_ptr().cast())) };
            let (near, far) = (_mm256_blendv_ps(lo, hi, neg), _mm256_blendv_ps(hi, lo, neg));
            let org = load(&self.org[a]);
            tn = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(near, org), load(&self.inv[a])), tn);
            tf = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(far, org), load(&self.inv_far[a])), tf);
        }
        let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        let wanted = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(candidates as i32), bits), bits);
        let hit = _mm256_and_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tn, tf), _mm256_castsi256_ps(wanted));
        let mut found = Entries { rays: _mm256_movemask_ps(hit) as u32, entry: [0.0; PACKET_SIZE] };
        unsafe { _mm256_storeu_ps(found.entry.as_mut_ptr(), _mm256_blendv_ps(_mm256_set1_ps(f32::INFINITY), tn, hit)) };
        found
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::Ray;

    /// Every lane's answer is the single-ray slab test's (with either instruction set), on boxes
    /// the rays hit, miss, graze and lie in the faces of, with ±0 direction components.
    #[test]
    fn lanes_answer_as_single_rays_do() {
        let mut unit = crate::unit_floats(0x2545_F491_4F6C_DD1D);
        let mut next = move || unit() * 4.0 - 2.0;
        let pick = |x: f32| if x.abs() < 0.3 { if x < 0.0 { -0.0 } else { 0.0 } } else { x };
        let (mut hits, mut misses) = (0, 0);
        for round in 0..2000 {
            let n = 1 + round % PACKET_SIZE;
            // A box, flat now and then, and rays from around it towards points near it, some
            // along axes or in its faces' planes.
            let lo = Vec3::new(next().round() * 0.5, next(), next());
            let depth = if next() > 1.0 { 0.0 } else { next().abs() };
            let b = Aabb { min: lo, max: lo + Vec3::new(next().abs(), next().abs(), depth) };
            let rays: Vec<PreparedRay> = (0..n)
                .map(|_| {
                    let o = Vec3::new(next().round() * 0.5, next(), next()) * 2.0;
                    let target = b.min + (b.max - b.min) * Vec3::new(next(), next(), next()).abs() * 0.7;
                    let d = target - o;
                    let d = Vec3::new(pick(d.x), pick(d.y), pick(d.z));
                    let d = if d == Vec3::ZERO { Vec3::X } else { d };
                    PreparedRay::new(&Ray::segment(o, d, next().abs() * 0.1, if next() > 1.5 { 0.5 } else { f32::INFINITY }))
                })
                .collect();
            let tfar: [f32; PACKET_SIZE] = std::array::from_fn(|i| rays.get(i).map_or(0.0, |r| r.tfar));
            let packet = RayPacket::new(&rays);
            let by_lane = RayPacket::lane_by_lane(&rays, packet.isa);
            let bits = |p: &RayPacket| -> Vec<u32> { p.org.iter().chain(&p.inv).chain(&p.inv_far).chain([&p.tnear]).flatten().map(|v| v.to_bits()).collect() };
            assert_eq!((bits(&packet), packet.neg, packet.rays), (bits(&by_lane), by_lane.neg, by_lane.rays), "round {round}: transposed lanes");
            let candidates = (next().abs() * 1000.0) as u32 | 1;
            let found = packet.touching(&b, &tfar, candidates);
            let mut expected = Entries::NONE;
            for (i, r) in rays.iter().enumerate().filter(|&(i, _)| candidates & (1 << i) != 0) {
                if let Some(t) = b.intersect(r, tfar[i]) {
                    expected.rays |= 1 << i;
                    expected.entry[i] = t;
                }
            }
            let bits = |e: &Entries| (e.rays, e.entry.map(f32::to_bits));
            assert_eq!(bits(&found), bits(&expected), "round {round}");
            assert_eq!(bits(&packet.touching_portable(&b, &tfar, candidates & packet.rays)), bits(&found), "round {round}: the portable lanes");
            // Shortened segments: `within` answers as a new test.
            let shorter: [f32; PACKET_SIZE] = std::array::from_fn(|i| if next() > 0.0 { tfar[i] } else { tfar[i].min(found.entry[i].max(0.0) * (1.0 + next() * 0.01)) });
            assert_eq!(found.within(&shorter), packet.touching(&b, &shorter, candidates).rays, "round {round}: within shortened segments");
            hits += found.rays.count_ones();
            misses += (candidates & ((1 << n) - 1) & !found.rays).count_ones();
        }
        assert!(hits > 500 && misses > 500, "{hits} hits, {misses} misses");
    }
}
