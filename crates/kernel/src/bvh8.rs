//! The 8-wide triangle BVH, collapsed from the binary one, traversed with SIMD box and triangle
//! tests. Its nodes are [`crate::wide`]'s; its leaves are blocks of up to eight triangles stored
//! as structure of arrays and tested against the ray all at once.

use std::mem::MaybeUninit;

use rayon::prelude::*;

use crate::aabb::Aabb;
use crate::build::{self, BuildOptions, Scratch};
use crate::bvh2::{Bvh2, Node2Kind};
use crate::isa::Isa;
use crate::memory::huge_page_vec;
use crate::prepared::PreparedRay;
use crate::ray::{Hit, Ray};
use crate::traverse::{self, Tally, WalkCounts};
use crate::triangle::TriangleSource;
use crate::wide::{EMPTY, LEAF, Node8, WIDTH, box_cost, collapse};

/// Rays per packet of [`Bvh8::intersect_packets`].
pub const PACKET_SIZE: usize = 8;

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
    /// Triangles in the block: lanes past the last repeat it.
    pub(crate) fn triangles(&self) -> usize {
        1 + (1..WIDTH).filter(|&lane| self.prim[lane] != self.prim[lane - 1]).count()
    }

    /// Writes triangles `prims` (lanes past the last repeating it) into `block`, in place (a block
    /// built elsewhere and copied in is read back before its stores have settled), and returns the
    /// box around them. Every field is written, so the block's storage need not be initialised
    /// first: a fresh tree's blocks are written once, by the threads that fill them, instead of
    /// cleared by one thread and then overwritten.
    fn fill(block: &mut MaybeUninit<TriBlock>, tris: &(impl TriangleSource + ?Sized), prims: &[u32]) -> Aabb {
        debug_assert!(!prims.is_empty() && prims.len() <= WIDTH);
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        let last = prims.len() - 1;
        let mut lanes = [0u32; WIDTH];
        for (lane, prim) in lanes.iter_mut().enumerate() {
            *prim = prims[lane.min(last)];
        }
        let out = block.as_mut_ptr();
        for (lane, &prim) in lanes.iter().enumerate() {
            let tri = tris.triangle(prim);
            for (vertex, p) in tri.iter().enumerate() {
                for (axis, c) in p.to_array().into_iter().enumerate() {
                    // SAFETY: `out` points to the block's storage; plain floats are written to it
                    // field by field, no reference to the uninitialised block is made.
                    unsafe { (*out).v[3 * vertex + axis][lane] = c };
                    lo[axis] = lo[axis].min(c);
                    hi[axis] = hi[axis].max(c);
                }
            }
        }
        // SAFETY: as above; with this, every field has been written.
        unsafe { (*out).prim = lanes };
        Aabb { min: glam::Vec3::from_array(lo), max: glam::Vec3::from_array(hi) }
    }

    /// The vertices of one lane. (Written out: nested `array::from_fn`s are not inlined into
    /// the leaf test, which asks for the vertices of every hit it accepts.)
    #[inline]
    pub(crate) fn lane(&self, lane: usize) -> [[f32; 3]; 3] {
        let v = &self.v;
        [[v[0][lane], v[1][lane], v[2][lane]], [v[3][lane], v[4][lane], v[5][lane]], [v[6][lane], v[7][lane], v[8][lane]]]
    }
}

/// Blocks filled one after the other by one thread (runs of them go to threads in parallel).
const FILL_RUN: usize = 256;
/// How many blocks ahead the vertices of a block are prefetched (and twice that, its indices).
const PREFETCH_BLOCKS: usize = 2;

/// Makes `blocks` the `len` blocks where block `i` holds the triangles `prims[first..first +
/// count]`, `(first, count) = ranges(i)` (see [`TriBlock::fill`]), reusing its storage, and puts
/// each block's box in `bounds[i]` if asked. The triangles are gathered in tree order, at random
/// in memory, so each run of blocks prefetches the indices and then the vertices of the blocks a
/// little ahead of the one it fills.
fn fill_blocks<T, R>(blocks: &mut Vec<TriBlock>, len: usize, tris: &T, prims: &[u32], ranges: R, bounds: Option<&mut [Aabb]>)
where
    T: TriangleSource + ?Sized,
    R: Fn(usize) -> (usize, usize) + Sync,
{
    blocks.clear();
    blocks.reserve(len);
    let filled = &mut blocks.spare_capacity_mut()[..len];
    let of = |i: usize| {
        let (first, count) = ranges(i);
        &prims[first..first + count]
    };
    let fill_run = |run: usize, blocks: &mut [MaybeUninit<TriBlock>], mut bounds: Option<&mut [Aabb]>| {
        let first = run * FILL_RUN;
        for (j, block) in blocks.iter_mut().enumerate() {
            let i = first + j;
            for (ahead, vertices) in [(2 * PREFETCH_BLOCKS, false), (PREFETCH_BLOCKS, true)] {
                if i + ahead < len {
                    of(i + ahead).iter().for_each(|&p| tris.prefetch(p, vertices));
                }
            }
            let b = TriBlock::fill(block, tris, of(i));
            if let Some(bounds) = bounds.as_deref_mut() {
                bounds[j] = b;
            }
        }
    };
    match bounds {
        Some(bounds) => filled.par_chunks_mut(FILL_RUN).zip(bounds.par_chunks_mut(FILL_RUN)).enumerate().for_each(|(run, (b, out))| fill_run(run, b, Some(out))),
        None => filled.par_chunks_mut(FILL_RUN).enumerate().for_each(|(run, b)| fill_run(run, b, None)),
    }
    // SAFETY: `TriBlock::fill` wrote every one of the first `len` blocks, each run its own.
    unsafe { blocks.set_len(len) };
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
    /// The tree's surface-area cost: the summed surface area of every child box (inner node or
    /// leaf block) over the area of the tree's box, the number of child boxes a random ray
    /// through the tree's box enters (the SAH with unit costs). Lower is better.
    pub sah_cost: f32,
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
    /// The tree's box cost (see `wide::box_cost`) when it was built: what refits are measured
    /// against.
    built_cost: f32,
    isa: Isa,
    /// The last rebuild's working storage, kept for the next (empty unless rebuilt).
    scratch: Scratch,
}

impl Bvh8 {
    /// Builds with binned SAH on the current rayon pool, then collapses to eight lanes.
    pub fn build(tris: &(impl TriangleSource + ?Sized), opts: &BuildOptions) -> Bvh8 {
        Bvh8::from_bvh2(&Bvh2::build(tris, opts), tris)
    }

    /// Rebuilds the tree over `tris` in place, reusing its node and block storage and, from the
    /// second rebuild on, the build's working storage, which the tree keeps from then on (about
    /// 90 bytes a triangle): an object rebuilt every frame then does not fault in fresh pages
    /// each time (for the museum's 64k triangles, the tree's pages were a millisecond, a third
    /// of the rebuild; a Morton-order rebuild of 64k triangles of the sphere scene then still
    /// took 5.2 ms with fresh working vectors and takes 3.2 ms with the kept ones).
    pub fn rebuild(&mut self, tris: &(impl TriangleSource + ?Sized), opts: &BuildOptions) {
        let mut scratch = std::mem::take(&mut self.scratch);
        build::build_in(tris, opts, &mut scratch);
        let bvh2 = Bvh2 { nodes: std::mem::take(&mut scratch.nodes), prims: std::mem::take(&mut scratch.prims) };
        let storage = (std::mem::take(&mut self.nodes), std::mem::take(&mut self.blocks));
        *self = Bvh8::collapsed(&bvh2, tris, storage);
        (scratch.nodes, scratch.prims) = (bvh2.nodes, bvh2.prims);
        self.scratch = scratch;
    }

    /// Collapses a binary BVH into eight lanes (the kernel's `wide` collapse) and copies the
    /// triangles into leaf blocks.
    pub fn from_bvh2(bvh2: &Bvh2, tris: &(impl TriangleSource + ?Sized)) -> Bvh8 {
        Bvh8::collapsed(bvh2, tris, (Vec::new(), Vec::new()))
    }

    /// [`Bvh8::from_bvh2`] into the given node and block vectors, which grow (on huge pages) only
    /// if they are too small.
    fn collapsed(bvh2: &Bvh2, tris: &(impl TriangleSource + ?Sized), (mut nodes, mut blocks): (Vec<Node8>, Vec<TriBlock>)) -> Bvh8 {
        // Every binary leaf becomes one block; every wide node consumes at least one binary inner
        // node, so the binary counts bound both arrays and they never reallocate.
        let leaves = bvh2.nodes.par_iter().with_min_len(4096).filter(|n| matches!(n.kind(), Node2Kind::Leaf { .. })).count();
        let inner = bvh2.nodes.len() - leaves;
        nodes.clear();
        if nodes.capacity() < inner {
            nodes = huge_page_vec(inner);
        }
        if blocks.capacity() < leaves {
            blocks = huge_page_vec(leaves);
        }
        let mut ranges: Vec<(u32, u32)> = Vec::with_capacity(leaves);
        let wide = collapse(&bvh2.nodes, nodes, |first, count| {
            ranges.push((first, count));
            LEAF | (ranges.len() - 1) as u32
        });
        // Gathering the triangles into blocks reads the vertices in tree order, at random in
        // memory: done in parallel, it is no longer the slowest part of a fast build.
        fill_blocks(&mut blocks, ranges.len(), tris, &bvh2.prims, |i| (ranges[i].0 as usize, ranges[i].1 as usize), None);
        let bounds = bvh2.bounds();
        Bvh8 {
            built_cost: box_cost(&wide.nodes, &bounds),
            nodes: wide.nodes,
            blocks,
            root: wide.root,
            bounds,
            depth: wide.depth,
            isa: Isa::best(),
            scratch: Scratch::default(),
        }
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
        self.intersect_prepared(&PreparedRay::new(ray))
    }

    /// [`Bvh8::intersect`] for a ray prepared once for several trees.
    #[inline]
    pub fn intersect_prepared(&self, pre: &PreparedRay) -> Option<Hit> {
        self.intersect_tallied(pre, &mut ())
    }

    /// [`Bvh8::intersect`], adding what the walk did to `counts`: the same walk, step for
    /// step (the statistics the benchmarks report).
    pub fn intersect_counted(&self, ray: &Ray, counts: &mut WalkCounts) -> Option<Hit> {
        counts.rays += 1;
        self.intersect_tallied(&PreparedRay::new(ray), counts)
    }

    /// The closest hit in `(tnear, tfar]` among those `admit` counts: [`Bvh8::intersect`]
    /// where only some hits count (the back of a single-sided surface, the holes of an alpha
    /// cut-out do not), as Embree's intersection filter asks. `admit` sees hits as
    /// [`Bvh8::intersect`] reports them, only those closer than the best counted so far, in no
    /// set order. One walk, where finding the closest hit and walking again past each that does
    /// not count would take one walk per such hit.
    #[inline]
    pub fn intersect_where(&self, pre: &PreparedRay, admit: impl FnMut(&Hit) -> bool) -> Option<Hit> {
        self.intersect_admitted(pre, &mut (), &mut traverse::Where(admit))
    }

    #[inline]
    fn intersect_tallied(&self, pre: &PreparedRay, tally: &mut impl Tally) -> Option<Hit> {
        self.intersect_admitted(pre, tally, &mut ())
    }

    #[inline]
    fn intersect_admitted(&self, pre: &PreparedRay, tally: &mut impl Tally, admit: &mut impl traverse::Admit) -> Option<Hit> {
        match self.isa {
            // SAFETY: `isa` is only ever set to a flavour `is_supported` confirmed on this CPU.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { traverse::avx2::intersect(self, pre, tally, admit) },
            _ => traverse::portable::intersect(self, pre, tally, admit),
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
            let prepared = PreparedRay::packet(rays);
            self.intersect_packet_prepared(&prepared[..rays.len()], hits);
        }
    }

    /// Closest hits of one packet of up to [`PACKET_SIZE`] prepared rays, `hits[i]` for
    /// `rays[i]`: [`Bvh8::intersect_packets`] for rays the caller has already prepared (a two-level
    /// scene prepares them once for its top level and every instance that keeps them as they are).
    ///
    /// # Panics
    /// If `rays` and `hits` differ in length, or hold more than [`PACKET_SIZE`] rays.
    pub fn intersect_packet_prepared(&self, rays: &[PreparedRay], hits: &mut [Option<Hit>]) {
        assert!(rays.len() == hits.len() && rays.len() <= PACKET_SIZE, "one hit slot per ray, at most a packet");
        match self.isa {
            // SAFETY: as in `intersect`.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { traverse::avx2::intersect_packet(self, rays, hits) },
            _ => {
                for (ray, hit) in rays.iter().zip(hits.iter_mut()) {
                    *hit = traverse::portable::intersect(self, ray, &mut (), &mut ());
                }
            }
        }
    }

    /// Whether anything is hit in `(tnear, tfar]`; stops at the first hit found.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_prepared(&PreparedRay::new(ray))
    }

    /// [`Bvh8::occluded`] for a ray prepared once for several trees.
    #[inline]
    pub fn occluded_prepared(&self, pre: &PreparedRay) -> bool {
        self.occluded_tallied(pre, &mut ())
    }

    /// [`Bvh8::occluded`], adding what the walk did to `counts`, as
    /// [`Bvh8::intersect_counted`] does.
    pub fn occluded_counted(&self, ray: &Ray, counts: &mut WalkCounts) -> bool {
        counts.rays += 1;
        self.occluded_tallied(&PreparedRay::new(ray), counts)
    }

    /// Whether a hit in `(tnear, tfar]` is one that `admit` counts: [`Bvh8::occluded`] where
    /// only some hits block (the back of a single-sided surface, the holes of an alpha cut-out
    /// do not), as Embree's occlusion filter asks. `admit` sees hits as [`Bvh8::intersect`]
    /// reports them (distance, barycentrics, normal), in no set order, and may see several; the
    /// walk stops at the first it counts. One walk, where finding the closest hit and walking on
    /// past every hit that does not count would take one walk per such hit.
    #[inline]
    pub fn occluded_where(&self, pre: &PreparedRay, admit: impl FnMut(&Hit) -> bool) -> bool {
        self.occluded_admitted(pre, &mut (), &mut traverse::Where(admit))
    }

    #[inline]
    fn occluded_tallied(&self, pre: &PreparedRay, tally: &mut impl Tally) -> bool {
        self.occluded_admitted(pre, tally, &mut ())
    }

    #[inline]
    fn occluded_admitted(&self, pre: &PreparedRay, tally: &mut impl Tally, admit: &mut impl traverse::Admit) -> bool {
        match self.isa {
            // SAFETY: as in `intersect`.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { traverse::avx2::occluded(self, pre, tally, admit) },
            _ => traverse::portable::occluded(self, pre, tally, admit),
        }
    }

    /// Which of up to [`PACKET_SIZE`] prepared rays hit anything in their segment `(tnear, tfar]`:
    /// bit `i` for `rays[i]`, exactly what [`Bvh8::occluded_prepared`] says of each. Rays that
    /// share their origin and octant (shadow rays traced from a point light to the points it
    /// lights) are traced as one packet; others one by one.
    ///
    /// # Panics
    /// If `rays` holds more than [`PACKET_SIZE`] rays.
    pub fn occluded_packet_prepared(&self, rays: &[PreparedRay]) -> u32 {
        assert!(rays.len() <= PACKET_SIZE, "at most a packet");
        match self.isa {
            // SAFETY: as in `intersect`.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 if !rays.is_empty() => unsafe { traverse::avx2::occluded_packet(self, rays) },
            _ => (0..rays.len()).filter(|&i| traverse::portable::occluded(self, &rays[i], &mut (), &mut ())).fold(0, |m, i| m | 1 << i),
        }
    }

    /// Moves the triangles to their current positions in `tris` (the same triangles, by index,
    /// that the tree was built from, with [`BuildOptions::refittable`]) and refits every box
    /// bottom-up, keeping the tree's topology. Linear in the size of the tree and far cheaper than
    /// a rebuild, but the tree degrades as triangles drift apart.
    ///
    /// Returns the degradation: how much more work a ray does in the refitted tree than in the
    /// freshly built one, as the relative growth of the tree's surface-area cost (the summed
    /// area of all child boxes over the tree's own). It is about zero for rigid motion and grows
    /// as the grouping of triangles stops matching their positions. RT-DEFORM (docs/design/seeds.md
    /// §1.3) measures the same loosening node by node, by each node's area against its children's;
    /// the whole-tree cost also catches children that swell together with their parent, as
    /// scattered triangles make them.
    pub fn refit(&mut self, tris: &(impl TriangleSource + ?Sized)) -> f32 {
        // Each block's box comes with its triangles, so the walk up the tree reads no vertices.
        let mut leaf_bounds = vec![Aabb::EMPTY; self.blocks.len()];
        // The blocks' own triangles, lanes as they are (the last repeated to fill a block).
        let prims: Vec<u32> = self.blocks.iter().flat_map(|b| b.prim).collect();
        fill_blocks(&mut self.blocks, prims.len() / WIDTH, tris, &prims, |i| (WIDTH * i, WIDTH), Some(&mut leaf_bounds));
        if self.root == EMPTY {
            return 0.0;
        }
        self.bounds = self.refit_below(self.root, &leaf_bounds);
        let cost = box_cost(&self.nodes, &self.bounds);
        if self.built_cost > 0.0 { cost / self.built_cost - 1.0 } else { 0.0 }
    }

    /// Refits the subtree under `link`, whose blocks' boxes are `leaf_bounds`; returns its box.
    fn refit_below(&mut self, link: u32, leaf_bounds: &[Aabb]) -> Aabb {
        if link & LEAF != 0 {
            return leaf_bounds[(link & !LEAF) as usize];
        }
        let node = link as usize;
        let mut bounds = Aabb::EMPTY;
        for lane in 0..WIDTH {
            let child = self.nodes[node].child[lane];
            if child != EMPTY {
                let b = self.refit_below(child, leaf_bounds);
                self.nodes[node].set_child(lane, &b, child);
                bounds = bounds.union(b);
            }
        }
        bounds
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
            sah_cost: box_cost(&self.nodes, &self.bounds),
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::Bvh8;
    use crate::build::{BuildOptions, BuildQuality};

    /// A jittered grid of `n`×`n` small triangles, shifted by `shift`.
    fn grid(n: u32, shift: f32) -> Vec<[Vec3; 3]> {
        (0..n * n)
            .map(|i| {
                let z = (i.wrapping_mul(2_654_435_761) >> 20) as f32 / 4096.0;
                let p = Vec3::new((i % n) as f32 + shift * z, (i / n) as f32, z);
                [p, p + Vec3::new(0.9, 0.1, 0.0), p + Vec3::new(0.2, 0.8, 0.3)]
            })
            .collect()
    }

    #[test]
    fn rebuilds_reuse_their_storage_and_equal_fresh_builds() {
        for quality in [BuildQuality::Sah, BuildQuality::Fast] {
            let opts = BuildOptions { quality, refittable: quality == BuildQuality::Fast, ..BuildOptions::default() };
            let (first, moved) = (grid(150, 0.0), grid(150, 3.0));
            let mut tree = Bvh8::build(&first, &opts);
            tree.rebuild(&moved, &opts);
            let storage = (tree.scratch.nodes.as_ptr(), tree.nodes.as_ptr(), tree.blocks.as_ptr());
            tree.rebuild(&first, &opts);
            let fresh = Bvh8::build(&first, &opts);
            assert_eq!(format!("{:?}", (&tree.nodes, &tree.blocks, tree.root, tree.bounds)), format!("{:?}", (&fresh.nodes, &fresh.blocks, fresh.root, fresh.bounds)), "{quality:?}");
            assert_eq!((tree.scratch.nodes.as_ptr(), tree.nodes.as_ptr(), tree.blocks.as_ptr()), storage, "{quality:?}: storage kept");
        }
    }
}
