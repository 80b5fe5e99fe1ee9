//! Walks of the box tree: the single-ray node test, with the caller's closure at the leaves.

use std::arch::x86_64::*;
use std::mem::MaybeUninit;

use super::{BoxLanes, Entry, child_hits, near_first};
use crate::boxtree::BoxTree;
use crate::prepared::{PreparedRay, widen};
use crate::wide::{EMPTY, LEAF, STACK_SIZE};

/// Near-first closest-hit walk; see [`BoxTree::closest`].
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn boxes_closest(tree: &BoxTree, ray: &PreparedRay, mut visit: impl FnMut(u32, f32) -> f32) {
    let r = BoxLanes::new(ray);
    let mut tfar = ray.tfar;
    let mut stack = [MaybeUninit::<Entry>::uninit(); STACK_SIZE];
    let mut sp = 0usize;
    let mut link = tree.root;
    loop {
        if link & LEAF == 0 {
            let node = &tree.nodes[link as usize];
            let (mask, tn) = child_hits(node, &r, _mm256_set1_ps(widen(tfar)));
            if mask != 0 {
                link = near_first(node, mask, tn, &mut stack, &mut sp, |_| {});
                continue;
            }
        } else if link != EMPTY {
            tfar = visit(BoxTree::leaf_item(link), tfar);
        }
        loop {
            if sp == 0 {
                return;
            }
            sp -= 1;
            // SAFETY: every entry below `sp` was written before.
            let e = unsafe { stack[sp].assume_init() };
            if e.dist <= widen(tfar) {
                link = e.link;
                break;
            }
        }
    }
}

/// Any-hit walk; see [`BoxTree::any`].
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn boxes_any(tree: &BoxTree, ray: &PreparedRay, mut visit: impl FnMut(u32) -> bool) -> bool {
    let r = BoxLanes::new(ray);
    let tfar_wide = _mm256_set1_ps(widen(ray.tfar));
    let mut stack = [MaybeUninit::<u32>::uninit(); STACK_SIZE];
    stack[0].write(tree.root);
    let mut sp = 1usize;
    while sp > 0 {
        sp -= 1;
        // SAFETY: every entry below `sp` was written before.
        let link = unsafe { stack[sp].assume_init() };
        if link & LEAF == 0 {
            let node = &tree.nodes[link as usize];
            let (mut mask, _) = child_hits(node, &r, tfar_wide);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                stack[sp].write(node.child[lane]);
                sp += 1;
            }
        } else if link != EMPTY && visit(BoxTree::leaf_item(link)) {
            return true;
        }
    }
    false
}
