//! The binary BVH layout: what the SAH builder produces and the wide layout is collapsed from.
//! Its scalar traversal is the readable reference for the wide one.

use crate::aabb::Aabb;
use crate::build::{self, BuildOptions};
use crate::prepared::{PreparedRay, widen};
use crate::ray::{Hit, Ray, closer};
use crate::triangle::{self, TriangleSource};

/// Leaf flag in [`Node2::b`].
const LEAF: u32 = 1 << 31;

/// A binary node: for an inner node `a`, `b` are the child indices; for a leaf, `a` is the first
/// entry in the primitive order and `b` the count with the `LEAF` bit set.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node2 {
    pub bounds: Aabb,
    a: u32,
    b: u32,
}

/// What a binary node is.
pub(crate) enum Node2Kind {
    Inner { left: u32, right: u32 },
    Leaf { first: u32, count: u32 },
}

impl Node2 {
    pub(crate) fn leaf(bounds: Aabb, first: u32, count: u32) -> Node2 {
        Node2 { bounds, a: first, b: count | LEAF }
    }

    pub(crate) fn inner(bounds: Aabb, left: u32, right: u32) -> Node2 {
        Node2 { bounds, a: left, b: right }
    }

    pub(crate) fn kind(&self) -> Node2Kind {
        if self.b & LEAF != 0 {
            Node2Kind::Leaf { first: self.a, count: self.b & !LEAF }
        } else {
            Node2Kind::Inner { left: self.a, right: self.b }
        }
    }

    /// The same node with child links shifted by `base` (leaves are unchanged).
    pub(crate) fn rebased(self, base: u32) -> Node2 {
        match self.kind() {
            Node2Kind::Inner { left, right } => Node2::inner(self.bounds, left + base, right + base),
            Node2Kind::Leaf { .. } => self,
        }
    }
}

/// A binary BVH over a triangle source. It stores no geometry: queries take the same source again.
#[derive(Clone, Debug)]
pub struct Bvh2 {
    pub(crate) nodes: Vec<Node2>,
    /// Triangle indices in leaf order.
    pub(crate) prims: Vec<u32>,
}

impl Bvh2 {
    /// Builds with binned SAH on the current rayon pool.
    pub fn build(tris: &(impl TriangleSource + ?Sized), opts: &BuildOptions) -> Bvh2 {
        let built = build::build(tris, opts);
        Bvh2 { nodes: built.nodes, prims: built.prims }
    }

    /// Bounds of everything in the tree (empty for an empty tree).
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds)
    }

    /// Number of nodes (inner and leaves).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The SAH cost of the tree, with `traversal_cost` per inner node and `intersection_cost` per
    /// triangle, relative to the root's area: the expected cost of a random ray through the root.
    pub fn sah_cost(&self, traversal_cost: f32, intersection_cost: f32) -> f32 {
        let root_area = self.bounds().area();
        if root_area == 0.0 {
            return 0.0;
        }
        let sum: f64 = self
            .nodes
            .iter()
            .map(|n| {
                let c = match n.kind() {
                    Node2Kind::Inner { .. } => traversal_cost,
                    Node2Kind::Leaf { count, .. } => intersection_cost * count as f32,
                };
                (n.bounds.area() * c) as f64
            })
            .sum();
        (sum / root_area as f64) as f32
    }

    /// Closest hit of `ray` among `tris` (which must be the source the tree was built from).
    pub fn intersect(&self, tris: &(impl TriangleSource + ?Sized), ray: &Ray) -> Option<Hit> {
        let pre = PreparedRay::new(ray);
        let mut best: Option<Hit> = None;
        let mut tfar = ray.tfar;
        let mut stack: Vec<(u32, f32)> = Vec::with_capacity(64);
        if let Some(t) = self.nodes.first().and_then(|n| n.bounds.intersect(&pre, tfar)) {
            stack.push((0, t));
        }
        while let Some((index, dist)) = stack.pop() {
            if dist > widen(tfar) {
                continue;
            }
            match self.nodes[index as usize].kind() {
                Node2Kind::Leaf { first, count } => {
                    for &prim in &self.prims[first as usize..(first + count) as usize] {
                        let v = tris.triangle(prim).map(|p| p.to_array());
                        if let Some(h) = triangle::intersect(&pre, &v, tfar)
                            && best.is_none_or(|b| closer(h.t, prim, b.t, b.prim)) {
                                best = Some(Hit { t: h.t, prim, u: h.u, v: h.v, ng: triangle::geometric_normal(&v.map(glam::Vec3::from_array)) });
                                tfar = h.t;
                            }
                    }
                }
                Node2Kind::Inner { left, right } => {
                    let hl = self.nodes[left as usize].bounds.intersect(&pre, tfar);
                    let hr = self.nodes[right as usize].bounds.intersect(&pre, tfar);
                    // Push the farther child first so the nearer one is popped next.
                    let mut pair = [(left, hl), (right, hr)];
                    if let (Some(a), Some(b)) = (hl, hr)
                        && a < b {
                            pair.swap(0, 1);
                        }
                    stack.extend(pair.iter().filter_map(|&(i, h)| h.map(|t| (i, t))));
                }
            }
        }
        best
    }

    /// Whether anything in `tris` is hit by `ray`.
    pub fn occluded(&self, tris: &(impl TriangleSource + ?Sized), ray: &Ray) -> bool {
        let pre = PreparedRay::new(ray);
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        if self.nodes.first().and_then(|n| n.bounds.intersect(&pre, ray.tfar)).is_some() {
            stack.push(0);
        }
        while let Some(index) = stack.pop() {
            match self.nodes[index as usize].kind() {
                Node2Kind::Leaf { first, count } => {
                    let hit = self.prims[first as usize..(first + count) as usize].iter().any(|&prim| {
                        triangle::intersect(&pre, &tris.triangle(prim).map(|p| p.to_array()), ray.tfar).is_some()
                    });
                    if hit {
                        return true;
                    }
                }
                Node2Kind::Inner { left, right } => {
                    for child in [left, right] {
                        if self.nodes[child as usize].bounds.intersect(&pre, ray.tfar).is_some() {
                            stack.push(child);
                        }
                    }
                }
            }
        }
        false
    }
}
