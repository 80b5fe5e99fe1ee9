//! Packet traversal: up to eight rays that share an origin (camera rays of neighbouring pixels,
//! shadow rays traced from a light) walk the tree together.
//!
//! Each node is first tested once against the packet's *frustum*: per axis, the interval spanned
//! by the rays' reciprocal directions (interval arithmetic, in the spirit of the frustum
//! traversal of the multi-level ray tracing seed, MLRTA, docs/design/seeds.md §1.4). Rounding is
//! monotonic, so the interval bounds enclose every ray's own rounded slab distances and no child
//! any ray would visit is dropped. Only the children the frustum hits are then tested ray by ray,
//! one ray per lane, with exactly the single-ray box arithmetic; a child is deferred with the mask
//! of rays that hit it and their entry distances, so every ray skips whatever its own closest hit
//! has culled. Triangles are tested per ray with the single-ray block test. Hits are therefore
//! bit-identical to tracing the rays one by one, while the node tests, the serial part of
//! single-ray traversal, are shared by the packet. When no more than `FEW` rays need a subtree,
//! they finish it as single rays (the hybrid scheme of Embree's packet kernels).
//!
//! The any-hit walk ([`occluded_packet`]) shares node tests the same way; a ray leaves the
//! packet at its first hit, and the walk ends when every ray is blocked. Shadow rays traced
//! from a point light towards the points it lights share the light as their origin.

use std::arch::x86_64::*;
use std::mem::{MaybeUninit, offset_of};

use super::single::{closest_below, occluded_below};
use super::{LeafLanes, block_any, block_closest, plane_rows, ray_fields, prefetch, sort_farthest_first, splat3, written};
use crate::boxtree::BoxTree;
use crate::bvh8::Bvh8;
use crate::wide::{EMPTY, LEAF, Node8, STACK_SIZE, WIDTH};
use crate::prepared::{PreparedRay, widen};
use crate::ray_packet::Entries;
use crate::ray::Hit;
use crate::traverse::Best;

/// Rays per packet: one per AVX2 lane.
const PACKET: usize = crate::bvh8::PACKET_SIZE;

/// A subtree needed by no more than this many rays of a packet is finished by them alone.
const FEW: u32 = 1;

/// Whether the rays can travel as one packet: a common origin (camera rays, rays from a point
/// light) or a common direction (rays towards a distant light), the same direction sign on
/// every axis, and no zero direction component (whose infinite reciprocal has no useful
/// interval). `Some(parallel)` if they can, `parallel` when their origins differ: the walks
/// are compiled for each case, so that shared-origin packets keep the frustum's registers for
/// one origin.
///
/// Each ray's two halves are compared with the first ray's bit for bit in two wide registers
/// (origin, reciprocal; the sign bytes), instead of field by field.
#[target_feature(enable = "avx2")]
#[inline]
fn packet_kind(rays: &[PreparedRay]) -> Option<bool> {
    let first = rays.first()?;
    // SAFETY: a prepared ray is two aligned halves of eight floats (see `prepare`).
    let halves = |r: &PreparedRay| unsafe {
        let p = (r as *const PreparedRay).cast::<__m256i>();
        (_mm256_load_si256(p), _mm256_load_si256(p.add(1)))
    };
    let (front0, back0) = halves(first);
    let (mut front_differs, mut back_differs) = (_mm256_setzero_si256(), _mm256_setzero_si256());
    let mut unbounded = _mm256_setzero_ps();
    let infinity = _mm256_set1_ps(f32::INFINITY);
    for r in rays {
        let (front, back) = halves(r);
        front_differs = _mm256_or_si256(front_differs, _mm256_xor_si256(front, front0));
        back_differs = _mm256_or_si256(back_differs, _mm256_xor_si256(back, back0));
        // The widened reciprocal is at least the reciprocal: if one is infinite, so is it.
        let magnitude = _mm256_andnot_ps(_mm256_set1_ps(-0.0), _mm256_castsi256_ps(back));
        unbounded = _mm256_or_ps(unbounded, _mm256_cmp_ps::<_CMP_NLT_UQ>(magnitude, infinity));
    }
    // Bytes 59..62 of a prepared ray, the sign bytes, are bytes 3..6 of the back's last 8.
    let signs_differ = _mm256_extract_epi64::<3>(back_differs) as u64 & 0x0000_FFFF_FF00_0000 != 0;
    // The widened reciprocal is in lanes 0..2 of the back.
    if signs_differ || _mm256_movemask_ps(unbounded) & 0b0111 != 0 {
        return None;
    }
    let equal = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(front_differs, _mm256_setzero_si256())));
    let (same_origin, same_direction) = (equal & 0b0111 == 0b0111, equal & 0b0111_0000 == 0b0111_0000);
    (rays.len() <= PACKET && (same_origin || same_direction)).then_some(!same_origin)
}

/// The packet's frustum broadcast to the eight children lanes of a node: per axis, the origin
/// its near and its far planes are measured from, and the smallest and largest reciprocal
/// direction (and its widened twin for far planes).
///
/// Every ray's own distances to a box's planes lie between the frustum's: with a common origin
/// the products of a plane's offset with the reciprocals' ends bound those with each ray's
/// reciprocal; with a common direction the offsets from the origins' extremes bound each ray's
/// own (the near plane's from the origin farthest along the ray, the far plane's from the one
/// farthest back), and rounding keeps both orders.
struct Frustum {
    org_near: [__m256; 3],
    org_far: [__m256; 3],
    inv_lo: [__m256; 3],
    inv_hi: [__m256; 3],
    far_lo: [__m256; 3],
    far_hi: [__m256; 3],
    tnear: __m256,
    near: [usize; 3],
    far: [usize; 3],
}

impl Frustum {
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn new<const PARALLEL: bool>(rays: &[PreparedRay]) -> Frustum {
        // A frustum is set up for every packet that enters an instance, which for small objects
        // costs as much as the walk: each ray's two halves are folded into the lowest and
        // highest of every field at once, one wide minimum and maximum per half and ray.
        // SAFETY: a prepared ray is two aligned halves of eight floats (see `ray_fields`).
        let halves = |r: &PreparedRay| unsafe {
            let p = (r as *const PreparedRay).cast::<f32>();
            (_mm256_load_ps(p), _mm256_load_ps(p.add(8)))
        };
        let (front, back) = halves(&rays[0]);
        let (mut front_lo, mut front_hi, mut back_lo, mut back_hi) = (front, front, back, back);
        for r in &rays[1..] {
            let (front, back) = halves(r);
            front_lo = _mm256_min_ps(front_lo, front);
            front_hi = _mm256_max_ps(front_hi, front);
            back_lo = _mm256_min_ps(back_lo, back);
            back_hi = _mm256_max_ps(back_hi, back);
        }
        // The lowest and the highest of every float of a prepared ray.
        let store = |front: __m256, back: __m256| {
            let mut out = [0.0f32; 16];
            unsafe {
                _mm256_storeu_ps(out.as_mut_ptr(), front);
                _mm256_storeu_ps(out.as_mut_ptr().add(8), back);
            }
            out
        };
        let (lo, hi) = (store(front_lo, back_lo), store(front_hi, back_hi));
        let at = |floats: &[f32; 16], offset: usize| -> [f32; 3] { std::array::from_fn(|a| floats[offset / 4 + a]) };
        let (org, inv, inv_far) = (offset_of!(PreparedRay, org), offset_of!(PreparedRay, inv), offset_of!(PreparedRay, inv_far));
        // (A packet of a common origin has one origin, its lowest and highest.)
        let (org_lo, org_hi) = (at(&lo, org), at(&hi, org));
        let (inv_lo, inv_hi) = (at(&lo, inv), at(&hi, inv));
        let (far_lo, far_hi) = (at(&lo, inv_far), at(&hi, inv_far));
        let tnear = lo[offset_of!(PreparedRay, tnear) / 4];
        // Along an axis the rays travel towards +∞ on, the near plane is nearest from the
        // origin farthest up and the far plane farthest from the one farthest down.
        let neg = rays[0].neg;
        let pick = |up: [f32; 3], down: [f32; 3]| std::array::from_fn(|a| if neg[a] { down[a] } else { up[a] });
        Frustum {
            org_near: splat3(pick(org_hi, org_lo)),
            org_far: splat3(pick(org_lo, org_hi)),
            inv_lo: splat3(inv_lo),
            inv_hi: splat3(inv_hi),
            far_lo: splat3(far_lo),
            far_hi: splat3(far_hi),
            tnear: _mm256_set1_ps(tnear),
            near: plane_rows(neg, false),
            far: plane_rows(neg, true),
        }
    }

    /// Children of `node` that the frustum's segment `(tnear, tfar]` may touch, and lower bounds
    /// of their entry distances.
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn child_hits<const PARALLEL: bool>(&self, node: &Node8, tfar_wide: __m256) -> (u32, __m256) {
        let plane = |row: usize| unsafe { _mm256_load_ps(node.planes.as_ptr().add(row).cast::<f32>()) };
        let mut tn = self.tnear;
        let mut tf = tfar_wide;
        for axis in 0..3 {
            // All reciprocals are finite, so no product is NaN, and every ray's own rounded
            // product lies between the products with the interval's ends.
            let d = _mm256_sub_ps(plane(self.near[axis]), self.org_near[axis]);
            tn = _mm256_max_ps(_mm256_min_ps(_mm256_mul_ps(d, self.inv_lo[axis]), _mm256_mul_ps(d, self.inv_hi[axis])), tn);
            let d = _mm256_sub_ps(plane(self.far[axis]), if PARALLEL { self.org_far[axis] } else { self.org_near[axis] });
            tf = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(d, self.far_lo[axis]), _mm256_mul_ps(d, self.far_hi[axis])), tf);
        }
        (_mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tn, tf)) as u32, tn)
    }
}

/// The rays across the lanes (one ray per lane), for testing one box against all of them.
struct RayLanes {
    /// The first ray's origin, shared by all in a packet of a common origin.
    org: [f32; 3],
    /// Every ray's origin.
    orgs: [__m256; 3],
    near: [usize; 3],
    far: [usize; 3],
    inv: [__m256; 3],
    inv_far: [__m256; 3],
    tnear: __m256,
}

impl RayLanes {
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn new<const PARALLEL: bool>(rays: &[PreparedRay]) -> RayLanes {
        // Lanes past the last ray repeat the first; they are masked out of every result.
        // SAFETY: a packet holds one to eight rays.
        let fields = unsafe { ray_fields(rays) };
        let component = |field: usize, a: usize| fields[field / 4 + a];
        let (org, inv, inv_far) = (offset_of!(PreparedRay, org), offset_of!(PreparedRay, inv), offset_of!(PreparedRay, inv_far));
        RayLanes {
            org: rays[0].org,
            // Only parallel rays have origins of their own.
            orgs: [0, 1, 2].map(|a| if PARALLEL { component(org, a) } else { _mm256_setzero_ps() }),
            near: plane_rows(rays[0].neg, false),
            far: plane_rows(rays[0].neg, true),
            inv: [0, 1, 2].map(|a| component(inv, a)),
            inv_far: [0, 1, 2].map(|a| component(inv_far, a)),
            tnear: component(offset_of!(PreparedRay, tnear), 0),
        }
    }

    /// The rays whose own segment `(tnear, tfar]` touches the box in lane `lane` of `node`, and
    /// their entry distances: the single-ray test's arithmetic, one ray per lane.
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn hit_child<const PARALLEL: bool>(&self, node: &Node8, lane: usize, tfar_wide: __m256) -> (u32, __m256) {
        let mut tn = self.tnear;
        let mut tf = tfar_wide;
        for axis in 0..3 {
            let (near, far) = (node.planes[self.near[axis]][lane], node.planes[self.far[axis]][lane]);
            let (near, far) = if PARALLEL {
                (_mm256_sub_ps(_mm256_set1_ps(near), self.orgs[axis]), _mm256_sub_ps(_mm256_set1_ps(far), self.orgs[axis]))
            } else {
                (_mm256_set1_ps(near - self.org[axis]), _mm256_set1_ps(far - self.org[axis]))
            };
            tn = _mm256_max_ps(_mm256_mul_ps(near, self.inv[axis]), tn);
            tf = _mm256_min_ps(_mm256_mul_ps(far, self.inv_far[axis]), tf);
        }
        (_mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tn, tf)) as u32, tn)
    }
}

/// A deferred child: its link, the frustum's lower bound of its entry distance (for ordering),
/// and the rays that hit its box with their own entry distances.
#[derive(Clone, Copy)]
struct Entry {
    link: u32,
    dist: f32,
    rays: u32,
    entry: __m256,
}

/// One lane set, the rest clear: selects lane `i` in a blend.
const LANE: [[u32; PACKET]; PACKET] = {
    let mut m = [[0; PACKET]; PACKET];
    let mut i = 0;
    while i < PACKET {
        m[i][i] = u32::MAX;
        i += 1;
    }
    m
};

/// The per-ray state of a packet walk: best hits and, in lanes, their widened distances.
struct Rays {
    best: [Best; PACKET],
    tfar: __m256,
}

impl Rays {
    /// The rays of `e` whose own entry distance is still within their own best.
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn live(&self, e: &Entry) -> u32 {
        e.rays & _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(e.entry, self.tfar)) as u32
    }

    /// Records ray `i`'s new best hit.
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn settle(&mut self, i: usize, best: Best) {
        self.best[i] = best;
        let lane = unsafe { _mm256_loadu_ps(LANE[i].as_ptr().cast::<f32>()) };
        self.tfar = _mm256_blendv_ps(self.tfar, _mm256_set1_ps(widen(best.t)), lane);
    }

    /// The largest widened distance of any ray: the frustum's far bound.
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn farthest(&self) -> __m256 {
        let m = _mm256_max_ps(self.tfar, _mm256_permute2f128_ps::<1>(self.tfar, self.tfar));
        let m = _mm256_max_ps(m, _mm256_shuffle_ps::<0b01_00_11_10>(m, m));
        _mm256_max_ps(m, _mm256_shuffle_ps::<0b10_11_00_01>(m, m))
    }
}

/// Closest hits of a packet of rays, written to `out` (one per ray). Rays that do not form a
/// packet (see `packet_kind`) are traced one by one.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn intersect_packet(bvh: &Bvh8, rays: &[PreparedRay], out: &mut [Option<Hit>]) {
    match packet_kind(rays) {
        None => {
            for (ray, hit) in rays.iter().zip(out.iter_mut()) {
                *hit = unsafe { super::intersect(bvh, ray, &mut (), &mut ()) };
            }
        }
        Some(false) => unsafe { intersect_beam::<false>(bvh, rays, out) },
        Some(true) => unsafe { intersect_beam::<true>(bvh, rays, out) },
    }
}

/// [`intersect_packet`] of a packet of a common origin, or of `PARALLEL` rays.
#[target_feature(enable = "avx2,fma")]
unsafe fn intersect_beam<const PARALLEL: bool>(bvh: &Bvh8, rays: &[PreparedRay], out: &mut [Option<Hit>]) {
    let frustum = Frustum::new::<PARALLEL>(rays);
    let lanes = RayLanes::new::<PARALLEL>(rays);
    let best: [Best; PACKET] = std::array::from_fn(|i| Best::none(rays.get(i).map_or(f32::NEG_INFINITY, |r| r.tfar)));
    let widened: [f32; PACKET] = std::array::from_fn(|i| widen(best[i].t));
    let mut state = Rays { best, tfar: unsafe { _mm256_loadu_ps(widened.as_ptr()) } };

    let mut stack = [MaybeUninit::<Entry>::uninit(); STACK_SIZE];
    let mut sp = 0usize;
    let mut current = Some(Entry {
        link: bvh.root,
        dist: 0.0,
        rays: (1u32 << rays.len()) - 1,
        entry: _mm256_set1_ps(f32::NEG_INFINITY),
    });
    while let Some(e) = current.take() {
        let live = state.live(&e);
        if live.count_ones() <= FEW {
            // Too few rays left to share the walk: they finish this subtree alone.
            for i in Lanes(live) {
                let b = closest_below(bvh, &rays[i], e.link, state.best[i], &mut (), &mut ());
                state.settle(i, b);
            }
        } else if e.link & LEAF == 0 {
            // SAFETY: inner links written by the collapse are valid node indices.
            let node = unsafe { bvh.nodes.get_unchecked(e.link as usize) };
            let (mask, tn) = frustum.child_hits::<PARALLEL>(node, state.farthest());
            let mut dist = [0f32; WIDTH];
            unsafe { _mm256_storeu_ps(dist.as_mut_ptr(), tn) };
            let base = sp;
            for lane in Lanes(mask) {
                let (hit, entry) = lanes.hit_child::<PARALLEL>(node, lane, state.tfar);
                if hit & live != 0 {
                    prefetch(bvh, node.child[lane]);
                    stack[sp].write(Entry { link: node.child[lane], dist: dist[lane], rays: hit & live, entry });
                    sp += 1;
                }
            }
            // Farthest first onto the stack, so that the nearest child comes off next.
            // SAFETY: entries base..sp were just written.
            sort_farthest_first(unsafe { written(&mut stack[base..sp]) }, |e| e.dist);
        } else if e.link != EMPTY {
            // SAFETY: leaf links written by the collapse are valid block indices.
            let block = unsafe { bvh.blocks.get_unchecked((e.link & !LEAF) as usize) };
            for i in Lanes(live) {
                let mut b = state.best[i];
                block_closest(block, &rays[i], &LeafLanes::new(&rays[i]), &mut b, &mut ());
                state.settle(i, b);
            }
        }
        // Next: the nearest deferred child that some ray still needs.
        while sp > 0 {
            sp -= 1;
            // SAFETY: every entry below `sp` was written before.
            let next = unsafe { stack[sp].assume_init() };
            if state.live(&next) != 0 {
                current = Some(next);
                break;
            }
        }
    }
    for (hit, b) in out.iter_mut().zip(state.best) {
        *hit = b.into_hit();
    }
}

/// Which rays of a packet hit anything in their segment `(tnear, tfar]`: bit `i` for `rays[i]`,
/// exactly as [`super::occluded`] finds ray by ray. Rays that do not form a packet (see
/// `packet_kind`) are traced one by one. Children are visited in slot order, as by single rays.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn occluded_packet(bvh: &Bvh8, rays: &[PreparedRay]) -> u32 {
    match packet_kind(rays) {
        None => (0..rays.len()).filter(|&i| occluded_below(bvh, &rays[i], bvh.root, &mut (), &mut ())).fold(0, |m, i| m | 1 << i),
        Some(false) => unsafe { occluded_beam::<false>(bvh, rays) },
        Some(true) => unsafe { occluded_beam::<true>(bvh, rays) },
    }
}

/// [`occluded_packet`] of a packet of a common origin, or of `PARALLEL` rays.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
unsafe fn occluded_beam<const PARALLEL: bool>(bvh: &Bvh8, rays: &[PreparedRay]) -> u32 {
    let finish = |link: u32, live: u32| {
        if live.count_ones() <= FEW {
            Some(Lanes(live).filter(|&i| occluded_below(bvh, &rays[i], link, &mut (), &mut ())).fold(0, |m, i| m | 1 << i))
        } else if link & LEAF == 0 {
            None
        } else if link == EMPTY {
            Some(0)
        } else {
            // SAFETY: leaf links written by the collapse are valid block indices.
            let block = unsafe { bvh.blocks.get_unchecked((link & !LEAF) as usize) };
            Some(Lanes(live).filter(|&i| block_any(block, &rays[i], &LeafLanes::new(&rays[i]), &mut ())).fold(0, |m, i| m | 1 << i))
        }
    };
    unsafe { walk_any::<PARALLEL>(&bvh.nodes, bvh.root, rays, finish) }
}

/// The any-hit walk of a packet down `nodes` from `root` (an object's tree),
/// carrying the rays still open: `finish(link, rays)` is offered every subtree the open rays
/// among `rays` reach, and either finishes it, returning the rays it blocks, or leaves it to
/// the walk (`None`, for an inner node). Ends once every ray is blocked; returns the blocked.
///
/// # Safety
/// The CPU must support AVX2 and FMA; inner links must be valid indices into `nodes`.
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn walk_any<const PARALLEL: bool>(nodes: &[Node8], root: u32, rays: &[PreparedRay], mut finish: impl FnMut(u32, u32) -> Option<u32>) -> u32 {
    let all = (1u32 << rays.len()) - 1;
    let frustum = Frustum::new::<PARALLEL>(rays);
    let lanes = RayLanes::new::<PARALLEL>(rays);
    let widened: [f32; PACKET] = std::array::from_fn(|i| rays.get(i).map_or(f32::NEG_INFINITY, |r| widen(r.tfar)));
    let tfar = unsafe { _mm256_loadu_ps(widened.as_ptr()) };
    let farthest = _mm256_set1_ps(widened.iter().copied().fold(f32::NEG_INFINITY, f32::max));
    // Rays not blocked yet.
    let mut open = all;
    // Deferred children with the rays that hit their boxes.
    let mut stack = [MaybeUninit::<(u32, u32)>::uninit(); STACK_SIZE];
    stack[0].write((root, all));
    let mut sp = 1usize;
    while sp > 0 && open != 0 {
        sp -= 1;
        // SAFETY: every entry below `sp` was written before.
        let (link, needing) = unsafe { stack[sp].assume_init() };
        let live = needing & open;
        if live == 0 {
            continue;
        }
        if let Some(blocked) = finish(link, live) {
            open &= !blocked;
            continue;
        }
        // SAFETY: the caller vouches for inner links.
        let node = unsafe { nodes.get_unchecked(link as usize) };
        let (mask, _) = frustum.child_hits::<PARALLEL>(node, farthest);
        for lane in Lanes(mask) {
            let (hit, _) = lanes.hit_child::<PARALLEL>(node, lane, tfar);
            if hit & live != 0 {
                stack[sp].write((node.child[lane], hit & live));
                sp += 1;
            }
        }
    }
    all & !open
}

/// [`BoxTree::occluded_by`] of rays that travel as a packet (see `packet_kind`); `None` for
/// others, which the caller walks one by one.
///
/// # Safety
/// The CPU must support AVX2 and FMA; the tree's root must be a node.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn boxes_occluded(tree: &BoxTree, rays: &[PreparedRay], block: &mut impl FnMut(u32, u32) -> u32) -> Option<u32> {
    let reach = |item: u32, rays: u32, _: __m256| block(item, rays);
    match packet_kind(rays)? {
        false => Some(unsafe { walk_boxes::<false>(tree, rays, reach) }),
        true => Some(unsafe { walk_boxes::<true>(tree, rays, reach) }),
    }
}

/// [`BoxTree::touched`] of rays that travel as a packet (see `packet_kind`); returns `false`,
/// having visited nothing, for others, which the caller walks one by one.
///
/// # Safety
/// The CPU must support AVX2 and FMA; the tree's root must be a node.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn boxes_touched(tree: &BoxTree, rays: &[PreparedRay], visit: &mut impl FnMut(u32, &Entries)) -> bool {
    // Nothing is ever blocked: every box the rays touch is visited.
    let reach = |item: u32, rays: u32, entry: __m256| {
        let mut entries = Entries { rays, entry: [0.0; PACKET] };
        // Lane `i` all ones if bit `i` of `rays` is set.
        let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        let mask = _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(rays as i32), bits), bits));
        unsafe { _mm256_storeu_ps(entries.entry.as_mut_ptr(), _mm256_blendv_ps(_mm256_set1_ps(f32::INFINITY), entry, mask)) };
        visit(item, &entries);
        0
    };
    match packet_kind(rays) {
        None => return false,
        Some(false) => unsafe { walk_boxes::<false>(tree, rays, reach) },
        Some(true) => unsafe { walk_boxes::<true>(tree, rays, reach) },
    };
    true
}

/// The walk of a packet down a box tree, carrying the rays still open. Each box is handed to
/// `reach(item, rays, entry)` as soon as the node holding it has been tested, with exactly the
/// open rays whose segment touches it and (in their lanes) where each enters it: every box of
/// the tree is nested in its parent's, so a ray that touches a box touched every box above it,
/// and the single-ray test of its lane is [`crate::Aabb::intersect`]'s arithmetic. `reach`
/// returns the rays the box blocks. Ends once every ray is blocked; returns the blocked.
///
/// # Safety
/// The CPU must support AVX2 and FMA; the tree's root must be a node.
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn walk_boxes<const PARALLEL: bool>(tree: &BoxTree, rays: &[PreparedRay], mut reach: impl FnMut(u32, u32, __m256) -> u32) -> u32 {
    let all = (1u32 << rays.len()) - 1;
    let frustum = Frustum::new::<PARALLEL>(rays);
    let lanes = RayLanes::new::<PARALLEL>(rays);
    let widened: [f32; PACKET] = std::array::from_fn(|i| rays.get(i).map_or(f32::NEG_INFINITY, |r| widen(r.tfar)));
    let tfar = unsafe { _mm256_loadu_ps(widened.as_ptr()) };
    let farthest = _mm256_set1_ps(widened.iter().copied().fold(f32::NEG_INFINITY, f32::max));
    // Rays not blocked yet.
    let mut open = all;
    // Deferred nodes with the rays that touch their boxes.
    let mut stack = [MaybeUninit::<(u32, u32)>::uninit(); STACK_SIZE];
    stack[0].write((tree.root, all));
    let mut sp = 1usize;
    while sp > 0 && open != 0 {
        sp -= 1;
        // SAFETY: every entry below `sp` was written before.
        let (link, needing) = unsafe { stack[sp].assume_init() };
        if needing & open == 0 {
            continue;
        }
        // SAFETY: the root and every link pushed are inner links, valid node indices.
        let node = unsafe { tree.nodes.get_unchecked(link as usize) };
        let (mask, _) = frustum.child_hits::<PARALLEL>(node, farthest);
        for lane in Lanes(mask) {
            let (hit, entry) = lanes.hit_child::<PARALLEL>(node, lane, tfar);
            let reached = hit & needing & open;
            let child = node.child[lane];
            if reached == 0 || child == EMPTY {
                continue;
            }
            if child & LEAF == 0 {
                stack[sp].write((child, reached));
                sp += 1;
            } else {
                open &= !reach(BoxTree::leaf_item(child), reached, entry);
            }
        }
    }
    all & !open
}

/// The set bits of a mask, lowest first.
struct Lanes(u32);

impl Iterator for Lanes {
    type Item = usize;

    fn next(&mut self) -> Option<usize> {
        (self.0 != 0).then(|| {
            let lane = self.0.trailing_zeros() as usize;
            self.0 &= self.0 - 1;
            lane
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::{PACKET_SIZE, Ray};

    /// `packet_kind` field by field, as the comparisons read in prose.
    fn kind_field_by_field(rays: &[PreparedRay]) -> Option<bool> {
        let first = rays.first()?;
        let bits = |v: [f32; 3]| v.map(f32::to_bits);
        let mut same = (true, true);
        for r in rays {
            let finite = (0..3).all(|a| r.inv[a].is_finite() && r.inv_far[a].is_finite());
            if r.neg != first.neg || !finite {
                return None;
            }
            same.0 &= bits(r.org) == bits(first.org);
            same.1 &= bits(r.inv) == bits(first.inv);
        }
        (rays.len() <= PACKET && (same.0 || same.1)).then_some(!same.0)
    }

    /// The wide comparison tells every packet apart as the field-by-field one does: shared
    /// origins or directions, one ray off, flipped signs, zero components (infinite reciprocals)
    /// and a subnormal one whose reciprocal is finite but widens to infinity, short packets.
    #[test]
    fn packet_kinds_are_told_apart_as_field_by_field() {
        if !crate::Isa::Avx2.is_supported() {
            return;
        }
        let mut next = crate::unit_floats(0x9E37_79B9_7F4A_7C15);
        let mut kinds = [0usize; 3];
        for round in 0..20_000 {
            let n = 1 + round % PACKET_SIZE;
            let origin = Vec3::new(next(), next(), next());
            let dir = Vec3::new(next() - 0.3, next() - 0.3, -1.0);
            let odd = (next() * 16.0) as usize;
            let rays: Vec<Ray> = (0..n)
                .map(|i| {
                    let (mut o, mut d) = (origin, dir);
                    match (round / PACKET_SIZE) % 4 {
                        0 => d += Vec3::new(next(), next(), 0.0) * 0.1,
                        1 => o += Vec3::new(next(), next(), next()),
                        _ => {}
                    }
                    if i == odd {
                        match round % 7 {
                            0 => d.x = -d.x,
                            1 => d.y = 0.0,
                            5 => d.z = 0.0,
                            6 => d.z = -f32::from_bits(0x0020_0001),
                            // A reciprocal that is finite, widened to infinity.
                            2 => d.x = f32::from_bits(0x0020_0001),
                            3 => o.z += 1.0,
                            _ => d.y += 0.5,
                        }
                    }
                    Ray::segment(o, d, 0.0, f32::INFINITY)
                })
                .collect();
            let prepared: Vec<PreparedRay> = rays.iter().map(PreparedRay::new).collect();
            let expected = kind_field_by_field(&prepared);
            // SAFETY: AVX2 was checked above.
            assert_eq!(unsafe { packet_kind(&prepared) }, expected, "round {round}");
            kinds[match expected { None => 0, Some(false) => 1, Some(true) => 2 }] += 1;
        }
        assert!(kinds.iter().all(|&k| k > 1000), "every kind often: {kinds:?}");
    }
}
