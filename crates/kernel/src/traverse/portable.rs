//! The portable traversal: the same algorithm as the SIMD kernels, one lane at a time. It is the
//! fallback for CPUs without AVX2 and the readable statement of what the SIMD code computes.

use super::{Admit, Best, Tally, lane_hit};
use crate::boxtree::BoxTree;
use crate::bvh8::{Bvh8, TriBlock};
use crate::wide::{EMPTY, LEAF, Node8, STACK_SIZE, WIDTH};
use crate::prepared::{PreparedRay, widen};
use crate::ray::Hit;
use crate::triangle;

/// Entry distances of the children the ray segment `(tnear, tfar]` touches, `None` elsewhere.
#[inline]
fn child_hits(node: &Node8, ray: &PreparedRay, tfar: f32) -> [Option<f32>; WIDTH] {
    std::array::from_fn(|lane| {
        let mut tn = ray.tnear;
        let mut tf = widen(tfar);
        for axis in 0..3 {
            let (near, far) = if ray.neg[axis] { (2 * axis + 1, 2 * axis) } else { (2 * axis, 2 * axis + 1) };
            tn = ((node.planes[near][lane] - ray.org[axis]) * ray.inv[axis]).max(tn);
            tf = ((node.planes[far][lane] - ray.org[axis]) * ray.inv_far[axis]).min(tf);
        }
        (tn <= tf).then_some(tn)
    })
}

fn block_closest(block: &TriBlock, ray: &PreparedRay, best: &mut Best, admit: &mut impl Admit) {
    for lane in 0..WIDTH {
        let tri = block.lane(lane);
        if let Some(h) = triangle::intersect(ray, &tri, best.t) {
            best.offer(h.t, block.prim[lane], h.u, h.v, || tri, admit);
        }
    }
}

fn block_any<A: Admit>(block: &TriBlock, ray: &PreparedRay, admit: &mut A) -> bool {
    (0..WIDTH).any(|lane| {
        let tri = block.lane(lane);
        triangle::intersect(ray, &tri, ray.tfar).is_some_and(|h| A::ALL || admit.admit(&lane_hit(h.t, block.prim[lane], h.u, h.v, &tri)))
    })
}

/// Closest hit, near-first, each step told to `tally`.
pub(crate) fn intersect(bvh: &Bvh8, ray: &PreparedRay, tally: &mut impl Tally, admit: &mut impl Admit) -> Option<Hit> {
    let mut best = Best::none(ray.tfar);
    let mut stack = [(0u32, 0f32); STACK_SIZE];
    let mut sp = 0;
    let mut next = Some(bvh.root);
    while let Some(link) = next.take() {
        if link & LEAF == 0 {
            let node = &bvh.nodes[link as usize];
            tally.node();
            let base = sp;
            for (lane, d) in child_hits(node, ray, best.t).into_iter().enumerate() {
                if let Some(d) = d {
                    stack[sp] = (node.child[lane], d);
                    sp += 1;
                }
            }
            // Farthest first onto the stack, so that the nearest child comes off next.
            stack[base..sp].sort_unstable_by(|a, b| b.1.total_cmp(&a.1));
        } else if link != EMPTY {
            let block = &bvh.blocks[(link & !LEAF) as usize];
            tally.leaf(block);
            block_closest(block, ray, &mut best, admit);
        }
        while sp > 0 {
            sp -= 1;
            let (link, dist) = stack[sp];
            if dist <= widen(best.t) {
                next = Some(link);
                break;
            }
        }
    }
    best.into_hit()
}

/// Any hit that `admit` counts; stops at the first one. Each step is told to `tally`.
pub(crate) fn occluded(bvh: &Bvh8, ray: &PreparedRay, tally: &mut impl Tally, admit: &mut impl Admit) -> bool {
    let mut stack = [0u32; STACK_SIZE];
    stack[0] = bvh.root;
    let mut sp = 1;
    while sp > 0 {
        sp -= 1;
        let link = stack[sp];
        if link & LEAF == 0 {
            let node = &bvh.nodes[link as usize];
            tally.node();
            for (lane, d) in child_hits(node, ray, ray.tfar).into_iter().enumerate() {
                if d.is_some() {
                    stack[sp] = node.child[lane];
                    sp += 1;
                }
            }
        } else if link != EMPTY {
            let block = &bvh.blocks[(link & !LEAF) as usize];
            tally.leaf(block);
            if block_any(block, ray, admit) {
                return true;
            }
        }
    }
    false
}

/// Near-first closest-hit walk of a box tree; see [`BoxTree::closest`].
pub(crate) fn boxes_closest(tree: &BoxTree, ray: &PreparedRay, mut visit: impl FnMut(u32, f32) -> f32) {
    let mut tfar = ray.tfar;
    let mut stack = [(0u32, 0f32); STACK_SIZE];
    let mut sp = 0;
    let mut next = Some(tree.root);
    while let Some(link) = next.take() {
        if link & LEAF == 0 {
            let node = &tree.nodes[link as usize];
            let base = sp;
            for (lane, d) in child_hits(node, ray, tfar).into_iter().enumerate() {
                if let Some(d) = d {
                    stack[sp] = (node.child[lane], d);
                    sp += 1;
                }
            }
            stack[base..sp].sort_unstable_by(|a, b| b.1.total_cmp(&a.1));
        } else if link != EMPTY {
            tfar = visit(BoxTree::leaf_item(link), tfar);
        }
        while sp > 0 {
            sp -= 1;
            let (link, dist) = stack[sp];
            if dist <= widen(tfar) {
                next = Some(link);
                break;
            }
        }
    }
}

/// Any-hit walk of a box tree; see [`BoxTree::any`].
pub(crate) fn boxes_any(tree: &BoxTree, ray: &PreparedRay, mut visit: impl FnMut(u32) -> bool) -> bool {
    let mut stack = [0u32; STACK_SIZE];
    stack[0] = tree.root;
    let mut sp = 1;
    while sp > 0 {
        sp -= 1;
        let link = stack[sp];
        if link & LEAF == 0 {
            let node = &tree.nodes[link as usize];
            for (lane, d) in child_hits(node, ray, ray.tfar).into_iter().enumerate() {
                if d.is_some() {
                    stack[sp] = node.child[lane];
                    sp += 1;
                }
            }
        } else if link != EMPTY && visit(BoxTree::leaf_item(link)) {
            return true;
        }
    }
    false
}
