//! Single-ray traversal: near-first, one ray at a time.

use std::arch::x86_64::*;
use std::mem::MaybeUninit;

use super::{BoxLanes, LeafLanes, block_any, block_closest, child_hits, prefetch, sort_farthest_first, written};
use crate::bvh8::Bvh8;
use crate::wide::{EMPTY, LEAF, STACK_SIZE, WIDTH};
use crate::prepared::{PreparedRay, widen};
use crate::ray::Hit;
use crate::traverse::Best;

/// A deferred child: its link and entry distance.
#[derive(Clone, Copy)]
struct Entry {
    link: u32,
    dist: f32,
}

/// Closest hit, near-first (the Embree BVH8 single-ray scheme: one hit child is followed
/// directly, two are ordered by one comparison, more are pushed and sorted by distance).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn intersect(bvh: &Bvh8, ray: &PreparedRay) -> Option<Hit> {
    closest_below(bvh, ray, bvh.root, Best::none(ray.tfar)).into_hit()
}

/// The best hit in the subtree under `link`, starting from (and never worse than) `best`. A
/// packet hands rays over to this when too few of them share the rest of the walk.
#[target_feature(enable = "avx2,fma")]
pub(super) fn closest_below(bvh: &Bvh8, ray: &PreparedRay, link: u32, best: Best) -> Best {
    let r = BoxLanes::new(ray);
    let leaf = LeafLanes::new(ray);
    let mut best = best;
    let mut tfar_wide = _mm256_set1_ps(widen(best.t));
    let mut stack = [MaybeUninit::<Entry>::uninit(); STACK_SIZE];
    let mut sp = 0usize;
    let mut link = link;
    loop {
        if link & LEAF == 0 {
            // SAFETY: inner links written by the collapse are valid node indices.
            let node = unsafe { bvh.nodes.get_unchecked(link as usize) };
            let (mask, tn) = child_hits(node, &r, tfar_wide);
            if mask != 0 {
                let mut dist = [0f32; WIDTH];
                unsafe { _mm256_storeu_ps(dist.as_mut_ptr(), tn) };
                let c0 = mask.trailing_zeros() as usize;
                let rest = mask & (mask - 1);
                if rest == 0 {
                    link = node.child[c0];
                    continue;
                }
                let c1 = rest.trailing_zeros() as usize;
                let mut rest = rest & (rest - 1);
                if rest == 0 {
                    let (near, far) = if dist[c0] <= dist[c1] { (c0, c1) } else { (c1, c0) };
                    prefetch(bvh, node.child[far]);
                    stack[sp].write(Entry { link: node.child[far], dist: dist[far] });
                    sp += 1;
                    link = node.child[near];
                    continue;
                }
                // Three or more: push all, insertion-sort them farthest-first, take the nearest.
                let base = sp;
                for lane in [c0, c1] {
                    prefetch(bvh, node.child[lane]);
                    stack[sp].write(Entry { link: node.child[lane], dist: dist[lane] });
                    sp += 1;
                }
                while rest != 0 {
                    let lane = rest.trailing_zeros() as usize;
                    rest &= rest - 1;
                    prefetch(bvh, node.child[lane]);
                    stack[sp].write(Entry { link: node.child[lane], dist: dist[lane] });
                    sp += 1;
                }
                // SAFETY: entries base..sp were just written.
                let pushed = unsafe { written(&mut stack[base..sp]) };
                sort_farthest_first(pushed, |e| e.dist);
                sp -= 1;
                link = pushed[pushed.len() - 1].link;
                continue;
            }
        } else if link != EMPTY {
            // SAFETY: leaf links written by the collapse are valid block indices.
            let block = unsafe { bvh.blocks.get_unchecked((link & !LEAF) as usize) };
            block_closest(block, ray, &leaf, &mut best);
            tfar_wide = _mm256_set1_ps(widen(best.t));
        }
        // Pop the nearest deferred child that can still hold a closer hit.
        loop {
            if sp == 0 {
                return best;
            }
            sp -= 1;
            // SAFETY: every entry below `sp` was written before.
            let e = unsafe { stack[sp].assume_init() };
            if e.dist <= widen(best.t) {
                link = e.link;
                break;
            }
        }
    }
}

/// Any hit; stops at the first one. Children are visited in slot order: ordering buys little
/// when the query ends at any hit.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn occluded(bvh: &Bvh8, ray: &PreparedRay) -> bool {
    occluded_below(bvh, ray, bvh.root)
}

/// Whether anything in the subtree under `link` is hit. A packet hands rays over to this when
/// too few of them share the rest of the walk.
#[target_feature(enable = "avx2,fma")]
pub(super) fn occluded_below(bvh: &Bvh8, ray: &PreparedRay, link: u32) -> bool {
    let r = BoxLanes::new(ray);
    let leaf = LeafLanes::new(ray);
    let tfar_wide = _mm256_set1_ps(widen(ray.tfar));
    let mut stack = [MaybeUninit::<u32>::uninit(); STACK_SIZE];
    stack[0].write(link);
    let mut sp = 1usize;
    while sp > 0 {
        sp -= 1;
        // SAFETY: every entry below `sp` was written before.
        let link = unsafe { stack[sp].assume_init() };
        if link & LEAF == 0 {
            // SAFETY: as in `intersect`.
            let node = unsafe { bvh.nodes.get_unchecked(link as usize) };
            let (mut mask, _) = child_hits(node, &r, tfar_wide);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                stack[sp].write(node.child[lane]);
                sp += 1;
            }
        } else if link != EMPTY {
            // SAFETY: as in `intersect`.
            let block = unsafe { bvh.blocks.get_unchecked((link & !LEAF) as usize) };
            if block_any(block, ray, &leaf) {
                return true;
            }
        }
    }
    false
}
