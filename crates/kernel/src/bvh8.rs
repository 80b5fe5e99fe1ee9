//! The 8-wide BVH layout, collapsed from the binary one, traversed with SIMD box and triangle tests.
//!
//! Nodes store their eight child boxes as structure-of-arrays planes, so one AVX2 instruction
//! tests one plane of all eight children. Leaves are blocks of up to eight triangles, also stored
//! as structure of arrays, tested against the ray all at once. Both are 64-byte aligned and laid
//! out in depth-first order, so a traversal step touches few cache lines.

use crate::aabb::Aabb;
use crate::builder::BuildOptions;
use crate::bvh2::{Bvh2, Node2Kind};
use crate::isa::Isa;
use crate::memory::huge_page_vec;
use crate::prepared::PreparedRay;
use crate::ray::{Hit, Ray};
use crate::traverse;
use crate::triangle::TriangleSource;

/// Rays per packet of [`Bvh8::intersect_packets`].
pub const PACKET_SIZE: usize = 8;

/// Lanes per node and per triangle block.
pub(crate) const WIDTH: usize = 8;
/// Child-link flag: the link names a triangle block, not a node.
pub(crate) const LEAF: u32 = 1 << 31;
/// Child link of an unused slot (its box is empty, so no ray ever follows it).
pub(crate) const EMPTY: u32 = u32::MAX;
/// Deepest wide tree the traversal stack is sized for (the builder bounds the binary depth to
/// 40 SAH levels plus at most 32 median levels; collapsing never deepens a tree).
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
    const UNUSED: Node8 = Node8 {
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

    fn set_child(&mut self, lane: usize, bounds: &Aabb, link: u32) {
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        for axis in 0..3 {
            self.planes[2 * axis][lane] = lo[axis];
            self.planes[2 * axis + 1][lane] = hi[axis];
        }
        self.child[lane] = link;
    }
}

/// Up to eight triangles as structure of arrays: `v[3 * vertex + axis][lane]`, and the index of
/// each lane's triangle in the source mesh. Unused lanes repeat the last triangle, which can only
/// produce the same hit again.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct TriBlock {
    pub v: [[f32; WIDTH]; 9],
    pub prim: [u32; WIDTH],
}

impl TriBlock {
    fn new(tris: &(impl TriangleSource + ?Sized), prims: &[u32]) -> TriBlock {
        debug_assert!(!prims.is_empty() && prims.len() <= WIDTH);
        let mut block = TriBlock { v: [[0.0; WIDTH]; 9], prim: [0; WIDTH] };
        for lane in 0..WIDTH {
            let prim = prims[lane.min(prims.len() - 1)];
            let tri = tris.triangle(prim);
            for (vertex, p) in tri.iter().enumerate() {
                for (axis, c) in p.to_array().into_iter().enumerate() {
                    block.v[3 * vertex + axis][lane] = c;
                }
            }
            block.prim[lane] = prim;
        }
        block
    }

    /// The vertices of one lane.
    pub(crate) fn lane(&self, lane: usize) -> [[f32; 3]; 3] {
        std::array::from_fn(|vertex| std::array::from_fn(|axis| self.v[3 * vertex + axis][lane]))
    }
}

/// Shape figures of a wide BVH, for tuning and for the benchmark report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bvh8Stats {
    /// Inner nodes.
    pub nodes: usize,
    /// Leaf blocks.
    pub leaves: usize,
    /// Triangles referenced by the leaves.
    pub triangles: usize,
    /// Deepest leaf (the root is depth 1).
    pub depth: usize,
    /// Mean number of used child slots per node.
    pub mean_children: f32,
    /// Bytes of node and leaf storage.
    pub bytes: usize,
}

/// An 8-wide BVH that owns a copy of its triangles. Queries take only the ray.
#[derive(Clone, Debug)]
pub struct Bvh8 {
    pub(crate) nodes: Vec<Node8>,
    pub(crate) blocks: Vec<TriBlock>,
    /// Link to the root: a node, a single leaf block, or `EMPTY` for an empty tree.
    pub(crate) root: u32,
    bounds: Aabb,
    depth: usize,
    isa: Isa,
}

impl Bvh8 {
    /// Builds with binned SAH on the current rayon pool, then collapses to eight lanes.
    pub fn build(tris: &(impl TriangleSource + ?Sized), opts: &BuildOptions) -> Bvh8 {
        Bvh8::from_bvh2(&Bvh2::build(tris, opts), tris)
    }

    /// Collapses a binary BVH: starting from the two children of each binary node, the child
    /// with the largest surface area is repeatedly replaced by its own two children until eight
    /// slots are used or only leaves remain (the collapse used by Embree's BVH8 builders).
    pub fn from_bvh2(bvh2: &Bvh2, tris: &(impl TriangleSource + ?Sized)) -> Bvh8 {
        // Every binary leaf becomes one block; every wide node consumes at least one binary inner
        // node, so the binary counts bound both arrays and they never reallocate.
        let leaves = bvh2.nodes.iter().filter(|n| matches!(n.kind(), Node2Kind::Leaf { .. })).count();
        let inner = bvh2.nodes.len() - leaves;
        let mut c = Collapse { bvh2, tris, nodes: huge_page_vec(inner), blocks: huge_page_vec(leaves), depth: 0 };
        let root = match bvh2.nodes.first().map(|n| n.kind()) {
            None => EMPTY,
            Some(Node2Kind::Leaf { first, count }) => {
                c.depth = 1;
                c.leaf(first, count)
            }
            Some(Node2Kind::Inner { .. }) => c.node(0, 1),
        };
        assert!(c.depth <= MAX_DEPTH, "BVH depth {} exceeds the traversal stack", c.depth);
        Bvh8 { nodes: c.nodes, blocks: c.blocks, root, bounds: bvh2.bounds(), depth: c.depth, isa: Isa::best() }
    }

    /// The same tree traversed with the given instruction set, or `None` if this CPU lacks it.
    pub fn with_isa(mut self, isa: Isa) -> Option<Bvh8> {
        isa.is_supported().then(|| {
            self.isa = isa;
            self
        })
    }

    /// The instruction set queries run with.
    pub fn isa(&self) -> Isa {
        self.isa
    }

    /// Bounds of all triangles.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The closest hit of `ray`: smallest `t` in `(tnear, tfar]`, ties broken by the smaller
    /// triangle index (so results equal [`crate::brute::intersect`] exactly).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let pre = PreparedRay::new(ray);
        match self.isa {
            // SAFETY: `isa` is only ever set to a flavour `is_supported` confirmed on this CPU.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { traverse::avx2::intersect(self, &pre) },
            _ => traverse::portable::intersect(self, &pre),
        }
    }

    /// Closest hits of many rays at once, `hits[i]` for `rays[i]`: exactly what
    /// [`Bvh8::intersect`] returns for each ray. Consecutive groups of [`PACKET_SIZE`] rays that
    /// share their origin (camera rays of neighbouring pixels, rays traced from a light) and
    /// travel in the same octant are traced as one packet, whose node tests are shared; other
    /// rays are traced one by one. Give coherent rays in packet-sized groups: 4×2 pixels, say.
    ///
    /// # Panics
    /// If `rays` and `hits` differ in length.
    pub fn intersect_packets(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        assert_eq!(rays.len(), hits.len(), "one hit slot per ray");
        for (rays, hits) in rays.chunks(PACKET_SIZE).zip(hits.chunks_mut(PACKET_SIZE)) {
            let prepared: [PreparedRay; PACKET_SIZE] = std::array::from_fn(|i| PreparedRay::new(&rays[i.min(rays.len() - 1)]));
            let prepared = &prepared[..rays.len()];
            match self.isa {
                // SAFETY: as in `intersect`.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2 => unsafe { traverse::avx2::intersect_packet(self, prepared, hits) },
                _ => {
                    for (ray, hit) in prepared.iter().zip(hits.iter_mut()) {
                        *hit = traverse::portable::intersect(self, ray);
                    }
                }
            }
        }
    }

    /// Whether anything is hit in `(tnear, tfar]`; stops at the first hit found.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let pre = PreparedRay::new(ray);
        match self.isa {
            // SAFETY: as in `intersect`.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { traverse::avx2::occluded(self, &pre) },
            _ => traverse::portable::occluded(self, &pre),
        }
    }

    /// Shape figures of the tree.
    pub fn stats(&self) -> Bvh8Stats {
        let used: usize = self.nodes.iter().map(|n| n.child.iter().filter(|&&c| c != EMPTY).count()).sum();
        let triangles = self
            .blocks
            .iter()
            .map(|b| {
                let mut lanes = b.prim.to_vec();
                lanes.dedup();
                lanes.len()
            })
            .sum();
        Bvh8Stats {
            nodes: self.nodes.len(),
            leaves: self.blocks.len(),
            triangles,
            depth: self.depth,
            mean_children: used as f32 / self.nodes.len().max(1) as f32,
            bytes: self.nodes.len() * size_of::<Node8>() + self.blocks.len() * size_of::<TriBlock>(),
        }
    }
}

/// State of one collapse: nodes and blocks are appended in depth-first order.
struct Collapse<'a, T: TriangleSource + ?Sized> {
    bvh2: &'a Bvh2,
    tris: &'a T,
    nodes: Vec<Node8>,
    blocks: Vec<TriBlock>,
    depth: usize,
}

impl<T: TriangleSource + ?Sized> Collapse<'_, T> {
    fn leaf(&mut self, first: u32, count: u32) -> u32 {
        let prims = &self.bvh2.prims[first as usize..(first + count) as usize];
        self.blocks.push(TriBlock::new(self.tris, prims));
        LEAF | (self.blocks.len() - 1) as u32
    }

    /// Emits the wide node for binary inner node `index`; returns its link.
    fn node(&mut self, index: u32, depth: usize) -> u32 {
        let nodes2 = &self.bvh2.nodes;
        let Node2Kind::Inner { left, right } = nodes2[index as usize].kind() else {
            unreachable!("only inner nodes are collapsed")
        };
        let mut kids = vec![left, right];
        while kids.len() < WIDTH {
            let widest = kids
                .iter()
                .enumerate()
                .filter(|(_, k)| matches!(nodes2[**k as usize].kind(), Node2Kind::Inner { .. }))
                .max_by(|a, b| nodes2[*a.1 as usize].bounds.area().total_cmp(&nodes2[*b.1 as usize].bounds.area()));
            let Some((slot, &k)) = widest else { break };
            let Node2Kind::Inner { left, right } = nodes2[k as usize].kind() else { unreachable!() };
            kids[slot] = left;
            kids.push(right);
        }
        let at = self.nodes.len();
        self.nodes.push(Node8::UNUSED);
        for (lane, &k) in kids.iter().enumerate() {
            let n = nodes2[k as usize];
            let link = match n.kind() {
                Node2Kind::Leaf { first, count } => {
                    self.depth = self.depth.max(depth + 1);
                    self.leaf(first, count)
                }
                Node2Kind::Inner { .. } => self.node(k, depth + 1),
            };
            self.nodes[at].set_child(lane, &n.bounds, link);
        }
        at as u32
    }
}
