//! The 8-wide node layout, and the collapse of a binary tree into it. Shared by the triangle BVH
//! ([`crate::Bvh8`]) and the box tree of the top level ([`crate::BoxTree`]).
//!
//! Nodes store their eight child boxes as structure-of-arrays planes, so one AVX2 instruction
//! tests one plane of all eight children. They are 64-byte aligned and laid out in depth-first
//! order, so a traversal step touches few cache lines.

use crate::aabb::Aabb;
use crate::bvh2::{Node2, Node2Kind};

/// Lanes per node and per triangle block.
pub(crate) const WIDTH: usize = 8;
/// Child-link flag: the link names a leaf (a triangle block, or a range of boxes), not a node.
pub(crate) const LEAF: u32 = 1 << 31;
/// Child link of an unused slot (its box is empty, so no ray ever follows it).
pub(crate) const EMPTY: u32 = u32::MAX;
/// Deepest wide tree the traversal stack is sized for (the builders bound the binary depth to
/// 40 heuristic levels plus at most 32 median levels; collapsing never deepens a tree).
pub(crate) const MAX_DEPTH: usize = 73;
/// Traversal stack entries: each level leaves at most seven siblings behind.
pub(crate) const STACK_SIZE: usize = (WIDTH - 1) * MAX_DEPTH + 1;

/// An 8-wide node: child boxes as planes `[lo_x, hi_x, lo_y, hi_y, lo_z, hi_z][lane]`, then the
/// child links (node index, `LEAF | block index`, or `EMPTY`).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct Node8 {
    pub planes: [[f32; WIDTH]; 6],
    pub child: [u32; WIDTH],
}

impl Node8 {
    pub(crate) const UNUSED: Node8 = Node8 {
        planes: [
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [EMPTY; WIDTH],
    };

    pub(crate) fn set_child(&mut self, lane: usize, bounds: &Aabb, link: u32) {
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        for axis in 0..3 {
            self.planes[2 * axis][lane] = lo[axis];
            self.planes[2 * axis + 1][lane] = hi[axis];
        }
        self.child[lane] = link;
    }
}

impl Node8 {
    /// The box of child `lane` (empty for an unused slot).
    pub(crate) fn child_bounds(&self, lane: usize) -> Aabb {
        let p = &self.planes;
        Aabb {
            min: glam::Vec3::new(p[0][lane], p[2][lane], p[4][lane]),
            max: glam::Vec3::new(p[1][lane], p[3][lane], p[5][lane]),
        }
    }
}

/// The result of collapsing a binary tree: wide nodes in depth-first order, the root's link and
/// the depth of the deepest leaf.
pub(crate) struct Collapsed {
    pub nodes: Vec<Node8>,
    pub root: u32,
    pub depth: usize,
}

/// The surface-area cost of a tree: the summed surface area of every child box, relative to the
/// area of the whole tree's box. For uniformly distributed rays through the tree's box it is the
/// expected number of child boxes entered, the SAH's measure of how much work a ray does; refits
/// raise it as the boxes loosen around moving triangles.
pub(crate) fn box_cost(nodes: &[Node8], bounds: &Aabb) -> f32 {
    let area = bounds.area();
    if area <= 0.0 {
        return 0.0;
    }
    let sum: f64 = nodes
        .iter()
        .flat_map(|n| (0..WIDTH).filter(|&lane| n.child[lane] != EMPTY).map(|lane| f64::from(n.child_bounds(lane).area())))
        .sum();
    (sum / f64::from(area)) as f32
}

/// Collapses binary nodes (root at 0): starting from the two children of each binary node, the
/// child with the largest surface area is repeatedly replaced by its own two children until
/// eight slots are used or only leaves remain (the collapse of Embree's BVH8 builders). `leaf`
/// turns a binary leaf (first, count) into a child link; `nodes` is where the wide nodes go.
pub(crate) fn collapse(nodes2: &[Node2], mut nodes: Vec<Node8>, mut leaf: impl FnMut(u32, u32) -> u32) -> Collapsed {
    let mut c = Collapsing { nodes2, nodes: &mut nodes, leaf: &mut leaf, depth: 0 };
    let root = match nodes2.first().map(|n| n.kind()) {
        None => EMPTY,
        Some(Node2Kind::Leaf { first, count }) => {
            c.depth = 1;
            (c.leaf)(first, count)
        }
        Some(Node2Kind::Inner { .. }) => c.node(0, 1),
    };
    assert!(c.depth <= MAX_DEPTH, "BVH depth {} exceeds the traversal stack", c.depth);
    let depth = c.depth;
    Collapsed { nodes, root, depth }
}

struct Collapsing<'a, F: FnMut(u32, u32) -> u32> {
    nodes2: &'a [Node2],
    nodes: &'a mut Vec<Node8>,
    leaf: &'a mut F,
    depth: usize,
}

impl<F: FnMut(u32, u32) -> u32> Collapsing<'_, F> {
    /// Emits the wide node for binary inner node `index`; returns its link.
    fn node(&mut self, index: u32, depth: usize) -> u32 {
        let nodes2 = self.nodes2;
        let Node2Kind::Inner { left, right } = nodes2[index as usize].kind() else {
            unreachable!("only inner nodes are collapsed")
        };
        // On the stack: a vector per wide node was an allocation per node.
        let mut slots = [0u32; WIDTH];
        (slots[0], slots[1]) = (left, right);
        let mut used = 2;
        while used < WIDTH {
            let widest = slots[..used]
                .iter()
                .enumerate()
                .filter(|(_, k)| matches!(nodes2[**k as usize].kind(), Node2Kind::Inner { .. }))
                .max_by(|a, b| nodes2[*a.1 as usize].bounds.area().total_cmp(&nodes2[*b.1 as usize].bounds.area()));
            let Some((slot, &k)) = widest else { break };
            let Node2Kind::Inner { left, right } = nodes2[k as usize].kind() else { unreachable!() };
            slots[slot] = left;
            slots[used] = right;
            used += 1;
        }
        let kids = &slots[..used];
        let at = self.nodes.len();
        self.nodes.push(Node8::UNUSED);
        for (lane, &k) in kids.iter().enumerate() {
            let n = nodes2[k as usize];
            let link = match n.kind() {
                Node2Kind::Leaf { first, count } => {
                    self.depth = self.depth.max(depth + 1);
                    (self.leaf)(first, count)
                }
                Node2Kind::Inner { .. } => self.node(k, depth + 1),
            };
            self.nodes[at].set_child(lane, &n.bounds, link);
        }
        at as u32
    }
}
