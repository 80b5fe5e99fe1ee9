//! The per-frame builder of the top level over instance boxes, after the seed's fast top-level
//! construction (Wald, *Handling Dynamic Scenes*, §5; docs/design/seeds.md §1.3):
//!
//! 1. split the node along its axis of largest extent (else the next largest);
//! 2. consider only planes at the borders of the boxes it holds;
//! 3. take the border closest to the node's centre on the side that holds more boxes, so that the
//!    plane lies between the spatial centre and the object median.
//!
//! No cost function is evaluated, so thousands of instances build in about a millisecond. The
//! seed splits space (a kd-tree); here boxes go to the side their centre is on (a BVH), and when
//! no border separates the centres the node is halved at the object median instead.
//!
//! Up to [`SAH_BELOW`] boxes, binned SAH builds the tree instead, as the seed recommends for few
//! instances (§5.1): it is still well under a millisecond there, and it isolates boxes that
//! overlap everything (a city or a ground plane under many small moving parts) near the root,
//! where the centre heuristic would bury them under nodes as large as the scene.

use super::sah;
use super::{BuildOptions, Built, PrimRef, SetBounds, partition};
use crate::aabb::Aabb;
use crate::bvh2::Node2;

/// Depth past which nodes are halved at the object median, bounding the tree's depth.
const HEURISTIC_DEPTH_LIMIT: u32 = 40;

/// Box counts below which the top level is built with binned SAH.
pub const SAH_BELOW: usize = 4096;

/// Builds a binary tree over the non-empty, finite boxes (`prims` are box indices), with at most
/// `max_leaf_size` boxes per leaf.
pub(crate) fn build_over_boxes(boxes: &[Aabb], max_leaf_size: usize) -> Built {
    let mut refs: Vec<PrimRef> = boxes
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.is_empty() && b.min.is_finite() && b.max.is_finite())
        .map(|(i, b)| PrimRef::new(*b, i as u32))
        .collect();
    let max_leaf_size = max_leaf_size.max(1);
    let nodes = if refs.is_empty() {
        Vec::new()
    } else if refs.len() < SAH_BELOW {
        let opts = BuildOptions { max_leaf_size, ..BuildOptions::default() };
        let set = SetBounds::of(&refs);
        let mut nodes = Vec::new();
        sah::build(&mut refs, set, &opts, &mut nodes);
        nodes
    } else {
        let mut nodes = Vec::with_capacity(2 * refs.len());
        emit(&mut refs, 0, 0, max_leaf_size, &mut nodes);
        nodes
    };
    Built { nodes, prims: refs.iter().map(PrimRef::prim).collect() }
}

/// Emits the subtree over `refs` (at position `offset` of the whole order); returns its index.
fn emit(refs: &mut [PrimRef], offset: u32, depth: u32, max_leaf_size: usize, out: &mut Vec<Node2>) -> u32 {
    let index = out.len() as u32;
    let bounds = refs.iter().fold(Aabb::EMPTY, |b, r| b.union(r.bounds()));
    if refs.len() <= max_leaf_size {
        out.push(Node2::leaf(bounds, offset, refs.len() as u32));
        return index;
    }
    out.push(Node2::leaf(bounds, offset, 0));
    let mid = if depth < HEURISTIC_DEPTH_LIMIT { border_split(refs, &bounds) } else { None };
    let mid = mid.unwrap_or_else(|| median_split(refs, &bounds));
    let (left, right) = refs.split_at_mut(mid);
    let l = emit(left, offset, depth + 1, max_leaf_size, out);
    let r = emit(right, offset + mid as u32, depth + 1, max_leaf_size, out);
    out[index as usize] = Node2::inner(bounds, l, r);
    index
}

/// The seed's split: partitions `refs` in place and returns the size of the left side, or `None`
/// if no box border separates their centres.
fn border_split(refs: &mut [PrimRef], bounds: &Aabb) -> Option<usize> {
    let extent = bounds.extent().to_array();
    let mut axes = [0, 1, 2];
    axes.sort_by(|&a, &b| extent[b].total_cmp(&extent[a]));
    for axis in axes {
        let centre2 = bounds.min[axis] + bounds.max[axis];
        let left_of_centre = refs.iter().filter(|r| r.centroid2()[axis] < centre2).count();
        let more_left = 2 * left_of_centre > refs.len();
        // Borders (doubled, to compare with doubled centres) on the fuller side, nearest the centre.
        let plane2 = refs
            .iter()
            .flat_map(|r| [2.0 * r.lo[axis], 2.0 * r.hi[axis]])
            .filter(|&p| if more_left { p < centre2 } else { p >= centre2 })
            .reduce(|a, b| if more_left { a.max(b) } else { a.min(b) });
        let Some(plane2) = plane2 else { continue };
        let mid = partition(refs, |r| r.centroid2()[axis] < plane2);
        if mid > 0 && mid < refs.len() {
            return Some(mid);
        }
    }
    None
}

/// Halves `refs` at the object median along the widest axis; returns the left size.
fn median_split(refs: &mut [PrimRef], bounds: &Aabb) -> usize {
    let e = bounds.extent();
    let axis = if e.x >= e.y && e.x >= e.z { 0 } else if e.y >= e.z { 1 } else { 2 };
    let mid = refs.len() / 2;
    refs.select_nth_unstable_by(mid, |a, b| a.centroid2()[axis].total_cmp(&b.centroid2()[axis]));
    mid
}
