//! Single-ray traversal: near-first, one ray at a time.

use std::arch::x86_64::*;
use std::mem::MaybeUninit;

use super::{BoxLanes, Entry, LeafLanes, block_any, block_closest, child_hits, near_first, prefetch};
use crate::bvh8::Bvh8;
use crate::wide::{EMPTY, LEAF, STACK_SIZE};
use crate::prepared::{PreparedRay, widen};
use crate::ray::Hit;
use crate::traverse::{Admit, Best, Tally};

/// Closest hit, near-first (the Embree BVH8 single-ray scheme: one hit child is followed
/// directly, two are ordered by one comparison, more are pushed and sorted by distance).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn intersect(bvh: &Bvh8, ray: &PreparedRay, tally: &mut impl Tally, admit: &mut impl Admit) -> Option<Hit> {
    closest_below(bvh, ray, bvh.root, Best::none(ray.tfar), tally, admit).into_hit()
}

/// The best hit in the subtree under `link`, starting from (and never worse than) `best`, each
/// step told to `tally`. A packet hands rays over to this when too few of them share the rest
/// of the walk.
#[target_feature(enable = "avx2,fma")]
pub(super) fn closest_below(bvh: &Bvh8, ray: &PreparedRay, link: u32, best: Best, tally: &mut impl Tally, admit: &mut impl Admit) -> Best {
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
            tally.node();
            let (mask, tn) = child_hits(node, &r, tfar_wide);
            if mask != 0 {
                link = near_first(node, mask, tn, &mut stack, &mut sp, |link| prefetch(bvh, link));
                continue;
            }
        } else if link != EMPTY {
            // SAFETY: leaf links written by the collapse are valid block indices.
            let block = unsafe { bvh.blocks.get_unchecked((link & !LEAF) as usize) };
            tally.leaf(block);
            block_closest(block, ray, &leaf, &mut best, admit);
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
pub(crate) unsafe fn occluded(bvh: &Bvh8, ray: &PreparedRay, tally: &mut impl Tally, admit: &mut impl Admit) -> bool {
    occluded_below(bvh, ray, bvh.root, tally, admit)
}

/// Whether anything in the subtree under `link` is hit that `admit` counts, each step told to
/// `tally`. A packet hands rays over to this when too few of them share the rest of the walk.
#[target_feature(enable = "avx2,fma")]
pub(super) fn occluded_below(bvh: &Bvh8, ray: &PreparedRay, link: u32, tally: &mut impl Tally, admit: &mut impl Admit) -> bool {
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
            tally.node();
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
            tally.leaf(block);
            if block_any(block, ray, &leaf, admit) {
                return true;
            }
        }
    }
    false
}
