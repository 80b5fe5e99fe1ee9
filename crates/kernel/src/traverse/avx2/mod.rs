//! AVX2 traversal: one instruction tests a plane of all eight children, or one coordinate of all
//! eight triangles of a leaf block.
//!
//! Every function here carries `#[target_feature(enable = "avx2,fma")]` so that the intrinsics
//! inline into one loop; callers must have checked `Isa::Avx2.is_supported()`.
//! The arithmetic is the portable kernel's, operation for operation (no FMA contraction in the box
//! or triangle tests), so results are bit-identical.
//!
//! This module holds the node and leaf tests; `single` walks the tree with one ray, `packet` with
//! a packet of rays that share an origin, `boxes` walks a box tree for a caller's closure, and
//! `prepare` computes a packet's per-ray constants across the lanes.

mod boxes;
mod packet;
mod prepare;
mod single;

pub(crate) use boxes::{boxes_any, boxes_closest};
pub(crate) use packet::{boxes_occluded, boxes_touched, intersect_packet, occluded_packet};
pub(crate) use prepare::prepare_packet;
pub(crate) use single::{intersect, occluded};

use std::arch::x86_64::*;
use std::mem::MaybeUninit;

use super::{Admit, Best, lane_hit};
use crate::bvh8::{Bvh8, TriBlock};
use crate::wide::{LEAF, Node8, WIDTH};
use crate::prepared::PreparedRay;
use crate::triangle;

/// One ray's box-test constants broadcast to all eight lanes (eight children of a node).
struct BoxLanes {
    org: [__m256; 3],
    inv: [__m256; 3],
    inv_far: [__m256; 3],
    tnear: __m256,
    /// Row of the near and far plane of each axis in `Node8::planes`.
    near: [usize; 3],
    far: [usize; 3],
}

impl BoxLanes {
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn new(ray: &PreparedRay) -> BoxLanes {
        BoxLanes {
            org: splat3(ray.org),
            inv: splat3(ray.inv),
            inv_far: splat3(ray.inv_far),
            tnear: _mm256_set1_ps(ray.tnear),
            near: plane_rows(ray.neg, false),
            far: plane_rows(ray.neg, true),
        }
    }
}

/// Each of three numbers in all eight lanes. (Written out: `array::map` with an intrinsic
/// in the closure is not inlined into the traversal, and costs a call per ray.)
#[target_feature(enable = "avx2,fma")]
#[inline]
fn splat3(v: [f32; 3]) -> [__m256; 3] {
    [_mm256_set1_ps(v[0]), _mm256_set1_ps(v[1]), _mm256_set1_ps(v[2])]
}

/// Rows of `Node8::planes` holding each axis's near (or far) plane for a ray with these signs.
#[inline]
fn plane_rows(neg: [bool; 3], far: bool) -> [usize; 3] {
    std::array::from_fn(|a| 2 * a + (neg[a] != far) as usize)
}

/// One ray's triangle-test constants broadcast to all eight lanes (eight triangles of a block):
/// origin and shear of the watertight test, in its permuted frame.
struct LeafLanes {
    korg: [__m256; 3],
    shear: [__m256; 3],
    tnear: __m256,
}

impl LeafLanes {
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn new(ray: &PreparedRay) -> LeafLanes {
        LeafLanes {
            korg: splat3(ray.axes().map(|k| ray.org[k])),
            shear: splat3(ray.shear),
            tnear: _mm256_set1_ps(ray.tnear),
        }
    }
}

/// Bit mask of the children the segment `(tnear, tfar]` touches, and their entry distances;
/// `tfar_wide` is the segment's end already widened (see `prepared::ROBUST_FAR`).
#[target_feature(enable = "avx2,fma")]
#[inline]
fn child_hits(node: &Node8, r: &BoxLanes, tfar_wide: __m256) -> (u32, __m256) {
    let plane = |row: usize| unsafe { _mm256_load_ps(node.planes.as_ptr().add(row).cast::<f32>()) };
    // `maxps`/`minps` return their second operand when either is NaN: the slab goes first, so a
    // NaN slab (ray lying in that plane) leaves the running bound unchanged.
    let mut tn = r.tnear;
    let mut tf = tfar_wide;
    for axis in 0..3 {
        tn = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(plane(r.near[axis]), r.org[axis]), r.inv[axis]), tn);
        tf = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(plane(r.far[axis]), r.org[axis]), r.inv_far[axis]), tf);
    }
    (_mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tn, tf)) as u32, tn)
}

/// The watertight test on all eight lanes of a block, up to the edge functions.
struct BlockEdges {
    /// Lanes whose three edge values share a sign (or are zero).
    inside: u32,
    /// Lanes with an edge value of exactly zero: decided by the scalar test's double fallback.
    degenerate: u32,
    u: __m256,
    v: __m256,
    w: __m256,
    /// Permuted z of the three vertices relative to the origin.
    z: [__m256; 3],
}

#[target_feature(enable = "avx2,fma")]
#[inline]
fn block_edges(block: &TriBlock, ray: &PreparedRay, r: &LeafLanes) -> BlockEdges {
    let [kx, ky, kz] = ray.axes();
    let row = |i: usize| unsafe { _mm256_load_ps(block.v.as_ptr().add(i).cast::<f32>()) };
    // Vertex `i` relative to the origin, sheared: (x, y, z) in the ray's frame.
    let vertex = |i: usize| {
        let x = _mm256_sub_ps(row(3 * i + kx), r.korg[0]);
        let y = _mm256_sub_ps(row(3 * i + ky), r.korg[1]);
        let z = _mm256_sub_ps(row(3 * i + kz), r.korg[2]);
        (_mm256_sub_ps(x, _mm256_mul_ps(r.shear[0], z)), _mm256_sub_ps(y, _mm256_mul_ps(r.shear[1], z)), z)
    };
    let (ax, ay, az) = vertex(0);
    let (bx, by, bz) = vertex(1);
    let (cx, cy, cz) = vertex(2);
    let u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
    let v = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
    let w = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
    let zero = _mm256_setzero_ps();
    let any_neg = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(u, zero), _mm256_cmp_ps::<_CMP_LT_OQ>(v, zero)),
        _mm256_cmp_ps::<_CMP_LT_OQ>(w, zero),
    );
    let any_pos = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(u, zero), _mm256_cmp_ps::<_CMP_GT_OQ>(v, zero)),
        _mm256_cmp_ps::<_CMP_GT_OQ>(w, zero),
    );
    let any_zero = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps::<_CMP_EQ_OQ>(u, zero), _mm256_cmp_ps::<_CMP_EQ_OQ>(v, zero)),
        _mm256_cmp_ps::<_CMP_EQ_OQ>(w, zero),
    );
    let mixed = _mm256_movemask_ps(_mm256_and_ps(any_neg, any_pos)) as u32;
    let degenerate = _mm256_movemask_ps(any_zero) as u32;
    BlockEdges { inside: !mixed & 0xff & !degenerate, degenerate, u, v, w, z: [az, bz, cz] }
}

/// Distances `T / det` of all lanes and the mask of those in `(tnear, tfar]` among `lanes`.
#[target_feature(enable = "avx2,fma")]
#[inline]
fn block_distances(e: &BlockEdges, r: &LeafLanes, lanes: u32, tfar: f32) -> (u32, __m256, __m256) {
    let det = _mm256_add_ps(_mm256_add_ps(e.u, e.v), e.w);
    let sz = r.shear[2];
    let t_num = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(e.u, _mm256_mul_ps(sz, e.z[0])), _mm256_mul_ps(e.v, _mm256_mul_ps(sz, e.z[1]))),
        _mm256_mul_ps(e.w, _mm256_mul_ps(sz, e.z[2])),
    );
    let t = _mm256_div_ps(t_num, det);
    let ok = _mm256_and_ps(
        _mm256_and_ps(_mm256_cmp_ps::<_CMP_NEQ_OQ>(det, _mm256_setzero_ps()), _mm256_cmp_ps::<_CMP_GT_OQ>(t, r.tnear)),
        _mm256_cmp_ps::<_CMP_LE_OQ>(t, _mm256_set1_ps(tfar)),
    );
    (_mm256_movemask_ps(ok) as u32 & lanes, t, det)
}

/// A block's hit lanes laid out for one lane at a time: distance, and the numerators and
/// denominator of the barycentrics.
struct LaneHits {
    t: [f32; WIDTH],
    v: [f32; WIDTH],
    w: [f32; WIDTH],
    det: [f32; WIDTH],
}

impl LaneHits {
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn of(e: &BlockEdges, t: __m256, det: __m256) -> LaneHits {
        let mut h = LaneHits { t: [0.0; WIDTH], v: [0.0; WIDTH], w: [0.0; WIDTH], det: [0.0; WIDTH] };
        // SAFETY: each array holds the eight lanes stored.
        unsafe {
            _mm256_storeu_ps(h.t.as_mut_ptr(), t);
            _mm256_storeu_ps(h.v.as_mut_ptr(), e.v);
            _mm256_storeu_ps(h.w.as_mut_ptr(), e.w);
            _mm256_storeu_ps(h.det.as_mut_ptr(), det);
        }
        h
    }

    /// Lane `lane`'s distance and barycentrics `(u, v)`.
    #[inline(always)]
    fn at(&self, lane: usize) -> (f32, f32, f32) {
        (self.t[lane], self.v[lane] / self.det[lane], self.w[lane] / self.det[lane])
    }
}

/// Offers every hit of the block to `best`, which takes those `admit` counts.
#[target_feature(enable = "avx2,fma")]
#[inline]
fn block_closest(block: &TriBlock, ray: &PreparedRay, r: &LeafLanes, best: &mut Best, admit: &mut impl Admit) {
    let e = block_edges(block, ray, r);
    if e.inside != 0 {
        let (mut hits, t, det) = block_distances(&e, r, e.inside, best.t);
        if hits != 0 {
            let lanes = LaneHits::of(&e, t, det);
            while hits != 0 {
                let lane = hits.trailing_zeros() as usize;
                hits &= hits - 1;
                let (t, u, v) = lanes.at(lane);
                best.offer(t, block.prim[lane], u, v, || block.lane(lane), admit);
            }
        }
    }
    let mut degenerate = e.degenerate;
    while degenerate != 0 {
        let lane = degenerate.trailing_zeros() as usize;
        degenerate &= degenerate - 1;
        let tri = block.lane(lane);
        if let Some(h) = triangle::intersect(ray, &tri, best.t) {
            best.offer(h.t, block.prim[lane], h.u, h.v, || tri, admit);
        }
    }
}

/// Whether any lane of the block is hit that `admit` counts (each hit as
/// [`block_closest`] would offer it).
#[target_feature(enable = "avx2,fma")]
#[inline]
fn block_any<A: Admit>(block: &TriBlock, ray: &PreparedRay, r: &LeafLanes, admit: &mut A) -> bool {
    let e = block_edges(block, ray, r);
    if e.inside != 0 {
        let (mut hits, t, det) = block_distances(&e, r, e.inside, ray.tfar);
        if A::ALL {
            if hits != 0 {
                return true;
            }
        } else if hits != 0 {
            let lanes = LaneHits::of(&e, t, det);
            while hits != 0 {
                let lane = hits.trailing_zeros() as usize;
                hits &= hits - 1;
                let (t, u, v) = lanes.at(lane);
                if admit.admit(&lane_hit(t, block.prim[lane], u, v, &block.lane(lane))) {
                    return true;
                }
            }
        }
    }
    let mut degenerate = e.degenerate;
    while degenerate != 0 {
        let lane = degenerate.trailing_zeros() as usize;
        degenerate &= degenerate - 1;
        let tri = block.lane(lane);
        if triangle::intersect(ray, &tri, ray.tfar).is_some_and(|h| A::ALL || admit.admit(&lane_hit(h.t, block.prim[lane], h.u, h.v, &tri))) {
            return true;
        }
    }
    false
}

/// A deferred child of a single-ray walk: its link and entry distance.
#[derive(Clone, Copy)]
struct Entry {
    link: u32,
    dist: f32,
}

/// The near-first step of a single-ray closest-hit walk at `node`, whose children `mask` (not
/// empty) the ray enters at distances `tn` (the Embree BVH8 single-ray scheme): returns the
/// child to visit next; the others go on `stack` above `sp`, farthest deepest. One hit child is
/// followed directly, two are ordered by one comparison, more are pushed and insertion-sorted.
/// `pushed` sees every link pushed (to prefetch it, say).
#[target_feature(enable = "avx2,fma")]
#[inline]
fn near_first(node: &Node8, mask: u32, tn: __m256, stack: &mut [MaybeUninit<Entry>], sp: &mut usize, mut pushed: impl FnMut(u32)) -> u32 {
    let mut dist = [0f32; WIDTH];
    unsafe { _mm256_storeu_ps(dist.as_mut_ptr(), tn) };
    let c0 = mask.trailing_zeros() as usize;
    let rest = mask & (mask - 1);
    if rest == 0 {
        return node.child[c0];
    }
    let c1 = rest.trailing_zeros() as usize;
    let mut rest = rest & (rest - 1);
    if rest == 0 {
        let (near, far) = if dist[c0] <= dist[c1] { (c0, c1) } else { (c1, c0) };
        pushed(node.child[far]);
        stack[*sp].write(Entry { link: node.child[far], dist: dist[far] });
        *sp += 1;
        return node.child[near];
    }
    // Three or more: push all, insertion-sort them farthest-first, take the nearest.
    let base = *sp;
    let mut push = |lane: usize| {
        pushed(node.child[lane]);
        stack[*sp].write(Entry { link: node.child[lane], dist: dist[lane] });
        *sp += 1;
    };
    push(c0);
    push(c1);
    while rest != 0 {
        let lane = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        push(lane);
    }
    // SAFETY: entries base..sp were just written.
    let entries = unsafe { written(&mut stack[base..*sp]) };
    sort_farthest_first(entries, |e| e.dist);
    *sp -= 1;
    entries[entries.len() - 1].link
}

/// Insertion sort, farthest first: the handful of children just pushed, so that the nearest one
/// is on top of the stack.
#[inline]
fn sort_farthest_first<T: Copy>(pushed: &mut [T], dist: impl Fn(&T) -> f32) {
    for i in 1..pushed.len() {
        let e = pushed[i];
        let mut j = i;
        while j > 0 && dist(&pushed[j - 1]) < dist(&e) {
            pushed[j] = pushed[j - 1];
            j -= 1;
        }
        pushed[j] = e;
    }
}

/// The entries of a stack slice that have all been written.
///
/// # Safety
/// Every element of `entries` must be initialised.
#[inline]
unsafe fn written<T>(entries: &mut [MaybeUninit<T>]) -> &mut [T] {
    // SAFETY: `MaybeUninit<T>` has `T`'s layout, and the caller vouches for initialisation.
    unsafe { &mut *(entries as *mut [MaybeUninit<T>] as *mut [T]) }
}

/// Every float of up to eight prepared rays across the lanes: row `f` holds float `f` of each
/// ray (`offset_of!` a component ÷ 4), ray `i` in lane `i`, lanes past the last ray repeating
/// the first. Each ray's two halves are loaded whole and the two 8×8 blocks transposed: a
/// gather per field costs several times more, and its single-float loads wait on the wide
/// stores that wrote the rays.
///
/// # Safety
/// The CPU must support AVX2; `rays` must hold one to eight rays.
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn ray_fields(rays: &[PreparedRay]) -> [__m256; 16] {
    const _: () = assert!(size_of::<PreparedRay>() == 64 && align_of::<PreparedRay>() == 64, "a prepared ray is two aligned halves");
    debug_assert!(!rays.is_empty() && rays.len() <= 8);
    let ray = |i: usize| if i < rays.len() { &rays[i] } else { &rays[0] };
    // SAFETY: each prepared ray is sixteen floats, 64-byte aligned.
    let half = |i: usize, h: usize| unsafe { _mm256_load_ps((ray(i) as *const PreparedRay).cast::<f32>().add(8 * h)) };
    let front = transpose(std::array::from_fn(|i| half(i, 0)));
    let back = transpose(std::array::from_fn(|i| half(i, 1)));
    std::array::from_fn(|f| if f < 8 { front[f] } else { back[f - 8] })
}

/// Eight rows of eight floats transposed: row `i` of the result holds lane `i` of every row.
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) fn transpose(r: [__m256; 8]) -> [__m256; 8] {
    // Pairs, then quads within each 128-bit half, then the halves.
    let pairs = [0, 2, 4, 6].map(|i| (_mm256_unpacklo_ps(r[i], r[i + 1]), _mm256_unpackhi_ps(r[i], r[i + 1])));
    let quads = |a: (__m256, __m256), b: (__m256, __m256)| {
        [_mm256_shuffle_ps::<0x44>(a.0, b.0), _mm256_shuffle_ps::<0xEE>(a.0, b.0), _mm256_shuffle_ps::<0x44>(a.1, b.1), _mm256_shuffle_ps::<0xEE>(a.1, b.1)]
    };
    let (low, high) = (quads(pairs[0], pairs[1]), quads(pairs[2], pairs[3]));
    std::array::from_fn(|i| if i < 4 { _mm256_permute2f128_ps::<0x20>(low[i], high[i]) } else { _mm256_permute2f128_ps::<0x31>(low[i - 4], high[i - 4]) })
}

/// Starts loading a deferred child into L1 (Embree prefetches every child it will visit): by the
/// time it is popped, its lines are usually there.
#[target_feature(enable = "avx2,fma")]
#[inline]
fn prefetch(bvh: &Bvh8, link: u32) {
    let (start, bytes) = if link & LEAF == 0 {
        (bvh.nodes.as_ptr().wrapping_add(link as usize).cast::<i8>(), size_of::<Node8>())
    } else {
        (bvh.blocks.as_ptr().wrapping_add((link & !LEAF) as usize).cast::<i8>(), size_of::<TriBlock>())
    };
    for line in (0..bytes).step_by(64) {
        // Prefetching is a hint: an address outside the arrays (the EMPTY link) is harmless.
        _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(line));
    }
}

