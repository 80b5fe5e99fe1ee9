//! BVH construction: primitive references, build options, and the builders that turn them into
//! a binary tree ([`crate::Bvh2`]'s nodes), which the wide layout is then collapsed from.
//!
//! - [`sah`]: binned SAH with exact sweeps near the leaves, for static geometry (best trees);
//! - [`lbvh`]: Morton-order splits, an order of magnitude faster, for geometry that changes
//!   every frame;
//! - [`top_level`]: the seed's cheap heuristic for the per-frame tree over instance boxes.

mod lbvh;
mod sah;
mod top_level;

pub(crate) use top_level::build_over_boxes;

use glam::Vec4;
use rayon::prelude::*;

use crate::aabb::Aabb;
use crate::bvh2::Node2;
use crate::triangle::TriangleSource;

/// Largest number of triangles in one leaf: a leaf is one SIMD block of eight lanes.
pub const MAX_LEAF_SIZE: usize = 8;

/// Which builder makes the tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BuildQuality {
    /// Binned surface area heuristic: the best trees, for geometry built once.
    #[default]
    Sah,
    /// Morton-order (LBVH) splits: an order of magnitude faster to build and somewhat slower to
    /// trace, for geometry rebuilt often.
    Fast,
}

/// Tuning of the builders. The defaults are what the benchmark scenes measured best with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildOptions {
    /// Which builder.
    pub quality: BuildQuality,
    /// Keep triangles that can never be hit as they are now (two equal vertices) because their
    /// vertices will move: required for trees that are [refit](crate::Bvh8::refit).
    pub refittable: bool,
    /// Most triangles per leaf, `1..=MAX_LEAF_SIZE`.
    pub max_leaf_size: usize,
    /// SAH cost of visiting an inner node, relative to `intersection_cost`.
    pub traversal_cost: f32,
    /// SAH cost of testing one leaf.
    pub intersection_cost: f32,
    /// Centroid bins per axis of large nodes, `2..=MAX_BINS`; nodes of a few hundred primitives
    /// use fewer (see the SAH builder).
    pub bins: usize,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            quality: BuildQuality::Sah,
            refittable: false,
            max_leaf_size: 8,
            traversal_cost: 1.0,
            intersection_cost: 1.0,
            bins: 32,
        }
    }
}

/// Upper bound for [`BuildOptions::bins`].
pub const MAX_BINS: usize = 32;

/// A primitive reference: its bounds, with the primitive index in the `w` lane of `lo` (as raw
/// bits; `w` never takes part in any bound computation).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(crate) struct PrimRef {
    pub(crate) lo: Vec4,
    pub(crate) hi: Vec4,
}

impl PrimRef {
    pub(crate) fn new(bounds: Aabb, prim: u32) -> Self {
        PrimRef { lo: bounds.min.extend(f32::from_bits(prim)), hi: bounds.max.extend(0.0) }
    }

    pub(crate) fn prim(&self) -> u32 {
        self.lo.w.to_bits()
    }

    /// Twice the centroid (the factor cancels out in binning).
    #[inline(always)]
    pub(crate) fn centroid2(&self) -> Vec4 {
        self.lo + self.hi
    }

    pub(crate) fn bounds(&self) -> Aabb {
        Aabb { min: self.lo.truncate(), max: self.hi.truncate() }
    }
}

/// Bounds of a set of primitives and of their doubled centroids.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SetBounds {
    pub(crate) geometry: Aabb,
    pub(crate) centroids: Aabb,
}

impl SetBounds {
    pub(crate) const EMPTY: SetBounds = SetBounds { geometry: Aabb::EMPTY, centroids: Aabb::EMPTY };

    pub(crate) fn union(self, o: SetBounds) -> SetBounds {
        SetBounds { geometry: self.geometry.union(o.geometry), centroids: self.centroids.union(o.centroids) }
    }

    pub(crate) fn of(refs: &[PrimRef]) -> SetBounds {
        if refs.len() >= PARALLEL_BOUNDS {
            refs.par_chunks(4096)
                .map(|c| c.iter().fold(Growing::EMPTY, Growing::add).bounds())
                .reduce(|| SetBounds::EMPTY, SetBounds::union)
        } else {
            refs.iter().fold(Growing::EMPTY, Growing::add).bounds()
        }
    }
}

/// [`SetBounds`] being grown reference by reference, in the references' own four-lane layout
/// (each update is two SIMD min/max pairs; the `w` lanes hold garbage and are dropped at the end).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Growing {
    lo: Vec4,
    hi: Vec4,
    centroid_lo: Vec4,
    centroid_hi: Vec4,
}

impl Growing {
    pub(crate) const EMPTY: Growing = Growing {
        lo: Vec4::INFINITY,
        hi: Vec4::NEG_INFINITY,
        centroid_lo: Vec4::INFINITY,
        centroid_hi: Vec4::NEG_INFINITY,
    };

    #[inline(always)]
    pub(crate) fn add(self, r: &PrimRef) -> Growing {
        let c = r.centroid2();
        Growing {
            lo: self.lo.min(r.lo),
            hi: self.hi.max(r.hi),
            centroid_lo: self.centroid_lo.min(c),
            centroid_hi: self.centroid_hi.max(c),
        }
    }

    pub(crate) fn bounds(self) -> SetBounds {
        SetBounds {
            geometry: Aabb { min: self.lo.truncate(), max: self.hi.truncate() },
            centroids: Aabb { min: self.centroid_lo.truncate(), max: self.centroid_hi.truncate() },
        }
    }
}

/// Sets at least this large compute their bounds in parallel.
const PARALLEL_BOUNDS: usize = 1 << 16;

/// The output of a build: binary nodes (root at index 0) and the primitive order their leaves
/// index into.
pub(crate) struct Built {
    pub nodes: Vec<Node2>,
    pub prims: Vec<u32>,
}

/// The working storage of a build, and the binary tree it leaves. A tree that is rebuilt keeps
/// one (see `Bvh8::rebuild`), so that every rebuild after the first writes into pages already
/// mapped: in vectors of its own, each Morton-order rebuild of 64k triangles faulted in and
/// zeroed some 1,250 fresh pages.
#[derive(Default)]
pub(crate) struct Scratch {
    /// The primitive references, in leaf order once built.
    refs: Vec<PrimRef>,
    /// The Morton-order builder's keys and codes.
    morton: lbvh::Scratch,
    /// The binary nodes built last (root at index 0).
    pub(crate) nodes: Vec<Node2>,
    /// The primitive order their leaves index into.
    pub(crate) prims: Vec<u32>,
}

/// A copy of a tree starts without working storage: it is no part of the tree's value.
impl Clone for Scratch {
    fn clone(&self) -> Scratch {
        Scratch::default()
    }
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Scratch {{ {} references }}", self.refs.capacity())
    }
}

/// Builds a binary BVH over all triangles that can be hit: triangles with a non-finite coordinate
/// are left out, and so are triangles without area (two equal vertices, or three on a line: see
/// `triangle::is_degenerate`) unless the tree must be refittable.
/// Runs on the current rayon pool.
pub(crate) fn build(tris: &(impl TriangleSource + ?Sized), opts: &BuildOptions) -> Built {
    let mut scratch = Scratch::default();
    build_in(tris, opts, &mut scratch);
    Built { nodes: scratch.nodes, prims: scratch.prims }
}

/// [`build`] into `scratch`'s vectors, which keep their storage: the tree is left in
/// `scratch.nodes` and `scratch.prims`.
pub(crate) fn build_in(tris: &(impl TriangleSource + ?Sized), opts: &BuildOptions, scratch: &mut Scratch) {
    let opts = BuildOptions {
        max_leaf_size: opts.max_leaf_size.clamp(1, MAX_LEAF_SIZE),
        bins: opts.bins.clamp(2, MAX_BINS),
        ..*opts
    };
    let refs = &mut scratch.refs;
    // One reference per triangle, written in place (an indexed collect), with the triangles
    // left out marked by empty bounds and dropped afterwards: collecting a `filter_map` would
    // gather pieces of unknown length and copy them together.
    (0..tris.triangle_count() as u32)
        .into_par_iter()
        .with_min_len(4096)
        .map(|i| {
            let t = tris.triangle(i);
            let b = Aabb::of_triangle(&t);
            let hittable = opts.refittable || !crate::triangle::is_degenerate(&t);
            let finite = t.iter().all(|v| v.is_finite());
            if finite && hittable { PrimRef::new(b, i) } else { PrimRef::new(Aabb::EMPTY, i) }
        })
        .collect_into_vec(refs);
    // Usually every triangle is kept, and a parallel look saves the serial pass of `retain`.
    if refs.par_iter().any(|r| !r.lo.truncate().is_finite()) {
        refs.retain(|r| r.lo.truncate().is_finite());
    }
    scratch.nodes.clear();
    scratch.prims.clear();
    if refs.is_empty() {
        return;
    }
    let set = SetBounds::of(refs);
    match opts.quality {
        BuildQuality::Sah => sah::build(refs, set, &opts, &mut scratch.nodes),
        BuildQuality::Fast => lbvh::build(refs, set, opts.max_leaf_size, &mut scratch.morton, &mut scratch.nodes),
    }
    refs.par_iter().with_min_len(4096).map(PrimRef::prim).collect_into_vec(&mut scratch.prims);
}

// Triangles with two equal vertices are the common degenerate case: the watertight test can
// never hit them (the repeated vertex makes one edge value exactly zero and the other two exact
// negatives of each other, so the determinant is exactly zero for every ray), but leaving them
// out saves their test, which would otherwise always take the slow double-precision path (UV
// spheres have a row of them at each pole). Three distinct vertices on one line can be hit
// (by rounding): leaving them out is what keeps them from being.

/// Appends a subtree built into its own vector, rebasing its child links; returns its root index.
pub(crate) fn splice(out: &mut Vec<Node2>, sub: Vec<Node2>) -> u32 {
    let base = out.len() as u32;
    out.extend(sub.into_iter().map(|n| n.rebased(base)));
    base
}

/// In-place partition: elements satisfying `left` first; returns their number.
pub(crate) fn partition(refs: &mut [PrimRef], left: impl Fn(&PrimRef) -> bool) -> usize {
    let (mut i, mut j) = (0, refs.len());
    loop {
        while i < j && left(&refs[i]) {
            i += 1;
        }
        while i < j && !left(&refs[j - 1]) {
            j -= 1;
        }
        if i >= j {
            return i;
        }
        refs.swap(i, j - 1);
        i += 1;
        j -= 1;
    }
}
