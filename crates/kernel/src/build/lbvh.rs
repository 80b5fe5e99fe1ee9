//! The fast builder: Morton-order splits (a linear BVH, Lauterbach et al. 2009).
//!
//! Primitive centroids are quantised to a 1024³ grid over their bounds and sorted by the Morton
//! code of their cell (a radix sort, linear in the number of primitives). Every node then splits
//! its range where the highest bit that differs between its first and last code changes, which is
//! a spatial median split along the axis that bit encodes. No cost function is evaluated, so the
//! build is an order of magnitude faster than binned SAH; the trees trace somewhat slower. That is
//! the right trade for geometry whose tree is rebuilt every few frames (RT-DEFORM rebuilds with a
//! spatial-median builder for the same reason, docs/design/seeds.md §1.3).

use super::{PrimRef, SetBounds};
use crate::aabb::Aabb;
use crate::bvh2::Node2;
use crate::morton::{self, BITS, radix_sort};

/// The Morton-order builder's working storage, kept across rebuilds (see `build::Scratch`).
#[derive(Default)]
pub(super) struct Scratch {
    /// (code, position) pairs, sorted by code.
    keyed: Vec<(u32, u32)>,
    /// The radix sort's second buffer.
    spare: Vec<(u32, u32)>,
    /// The references in their order before the sort.
    unsorted: Vec<PrimRef>,
    /// The sorted codes.
    codes: Vec<u32>,
}

/// Builds the tree over `refs` (reordered in place into Morton order) into `nodes` (emptied
/// first, its storage reused); root at index 0.
pub(super) fn build(refs: &mut [PrimRef], set: SetBounds, max_leaf_size: usize, scratch: &mut Scratch, nodes: &mut Vec<Node2>) {
    sort_by_morton_code(refs, &set.centroids, scratch);
    nodes.clear();
    nodes.reserve(2 * refs.len() / max_leaf_size + 1);
    emit(refs, &scratch.codes, 0, max_leaf_size, nodes);
}

/// Sorts `refs` by the Morton code of their centroid within `centroids` (the bounds of the
/// doubled centroids) and leaves the codes, in the new order, in `scratch.codes`.
fn sort_by_morton_code(refs: &mut [PrimRef], centroids: &Aabb, scratch: &mut Scratch) {
    let cells = (1u32 << BITS) as f32;
    let extent = centroids.extent();
    let scale = |e: f32| if e > 0.0 { cells * (1.0 - 1e-6) / e } else { 0.0 };
    let (sx, sy, sz) = (scale(extent.x), scale(extent.y), scale(extent.z));
    // Sort (code, position) pairs, eight bytes each, then move the references once.
    scratch.keyed.clear();
    scratch.keyed.extend(refs.iter().enumerate().map(|(i, r)| {
        let c = r.centroid2().truncate() - centroids.min;
        let q = |v: f32, s: f32| ((v * s) as u32).min((1 << BITS) - 1);
        (morton::code(q(c.x, sx), q(c.y, sy), q(c.z, sz)), i as u32)
    }));
    radix_sort(&mut scratch.keyed, &mut scratch.spare);
    scratch.unsorted.clear();
    scratch.unsorted.extend_from_slice(refs);
    for (slot, &(_, i)) in refs.iter_mut().zip(&scratch.keyed) {
        *slot = scratch.unsorted[i as usize];
    }
    scratch.codes.clear();
    scratch.codes.extend(scratch.keyed.iter().map(|&(code, _)| code));
}

/// Emits the subtree over `refs` (whose codes are `codes`, sorted), starting at position
/// `offset` of the whole primitive order; returns its root index and bounds.
fn emit(refs: &[PrimRef], codes: &[u32], offset: u32, max_leaf_size: usize, out: &mut Vec<Node2>) -> (u32, Aabb) {
    let index = out.len() as u32;
    let n = refs.len();
    if n <= max_leaf_size {
        let bounds = refs.iter().fold(Aabb::EMPTY, |b, r| b.union(r.bounds()));
        out.push(Node2::leaf(bounds, offset, n as u32));
        return (index, bounds);
    }
    out.push(Node2::leaf(Aabb::EMPTY, 0, 0));
    let mid = split_position(codes);
    let (l, lb) = emit(&refs[..mid], &codes[..mid], offset, max_leaf_size, out);
    let (r, rb) = emit(&refs[mid..], &codes[mid..], offset + mid as u32, max_leaf_size, out);
    let bounds = lb.union(rb);
    out[index as usize] = Node2::inner(bounds, l, r);
    (index, bounds)
}

/// Where a sorted range of codes splits: the first position whose code has the highest bit that
/// differs between the range's ends set, or the middle if all codes are equal.
fn split_position(codes: &[u32]) -> usize {
    let (first, last) = (codes[0], codes[codes.len() - 1]);
    if first == last {
        return codes.len() / 2;
    }
    // Every code in the range agrees with both ends above that bit, so the codes without it
    // come first.
    let bit = 1u32 << (31 - (first ^ last).leading_zeros());
    codes.partition_point(|&c| c & bit == 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_where_the_highest_differing_bit_changes() {
        assert_eq!(split_position(&[0b000, 0b001, 0b100, 0b101]), 2);
        assert_eq!(split_position(&[0b010, 0b011, 0b011, 0b111]), 3);
        assert_eq!(split_position(&[5, 5, 5, 5]), 2);
    }
}
