//! Traversal kernels of the wide BVH, one module per instruction set. All flavours visit children
//! near-first, use the same box and triangle arithmetic, and return bit-identical results.

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
pub(crate) mod portable;

use crate::bvh8::TriBlock;

/// What single-ray walks of a tree did, summed over rays: the traversal statistics MLRTA's
/// Table 2 reports (seed 000), counted by [`Bvh8::intersect_counted`](crate::Bvh8::intersect_counted)
/// and [`Bvh8::occluded_counted`](crate::Bvh8::occluded_counted) as the tree's kernel (AVX2 or
/// portable) takes its steps. The kernels' any-hit walks take the same steps; their closest-hit
/// walks may order children at equal distances differently.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WalkCounts {
    /// Rays walked.
    pub rays: u64,
    /// Inner nodes whose eight child boxes were tested.
    pub nodes: u64,
    /// Leaves (blocks of up to eight triangles) tested.
    pub leaves: u64,
    /// Triangles in those leaves.
    pub triangles: u64,
}

impl std::ops::AddAssign for WalkCounts {
    fn add_assign(&mut self, o: WalkCounts) {
        self.rays += o.rays;
        self.nodes += o.nodes;
        self.leaves += o.leaves;
        self.triangles += o.triangles;
    }
}

/// Where a walk tells the steps it takes: [`WalkCounts`] counts them, `()` ignores them, so
/// the walk that is not counted compiles to what it was without the calls.
pub(crate) trait Tally {
    /// An inner node's child boxes were tested.
    fn node(&mut self);
    /// A leaf's triangles were tested.
    fn leaf(&mut self, block: &TriBlock);
}

impl Tally for () {
    #[inline(always)]
    fn node(&mut self) {}
    #[inline(always)]
    fn leaf(&mut self, _: &TriBlock) {}
}

impl Tally for WalkCounts {
    #[inline]
    fn node(&mut self) {
        self.nodes += 1;
    }
    #[inline]
    fn leaf(&mut self, block: &TriBlock) {
        self.leaves += 1;
        self.triangles += block.triangles() as u64;
    }
}

/// Which hits an any-hit walk counts: `()` every hit (the plain walk, which a leaf answers
/// with one test of its eight triangles), [`Where`] those a caller's filter accepts (asked hit
/// by hit).
pub(crate) trait Admit {
    /// Every hit counts: the leaf need not list its hits.
    const ALL: bool;
    /// Whether `hit` counts.
    fn admit(&mut self, hit: &crate::ray::Hit) -> bool;
}

impl Admit for () {
    const ALL: bool = true;
    #[inline(always)]
    fn admit(&mut self, _: &crate::ray::Hit) -> bool {
        true
    }
}

/// The hits a filter accepts.
pub(crate) struct Where<F>(pub F);

impl<F: FnMut(&crate::ray::Hit) -> bool> Admit for Where<F> {
    const ALL: bool = false;
    #[inline(always)]
    fn admit(&mut self, hit: &crate::ray::Hit) -> bool {
        (self.0)(hit)
    }
}

/// The hit at distance `t`, barycentrics `(u, v)`, of triangle `prim` with vertices `tri`: as
/// a closest-hit walk reports it ([`Best::offer`]).
#[inline(always)]
pub(crate) fn lane_hit(t: f32, prim: u32, u: f32, v: f32, tri: &[[f32; 3]; 3]) -> crate::ray::Hit {
    crate::ray::Hit { t, prim, u, v, ng: crate::triangle::geometric_normal(&tri.map(glam::Vec3::from_array)) }
}

/// The best hit found so far during a closest-hit traversal.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Best {
    pub t: f32,
    pub prim: u32,
    pub u: f32,
    pub v: f32,
    pub ng: glam::Vec3,
}

impl Best {
    /// No hit yet: everything up to the ray's `tfar` (inclusive) is still acceptable.
    pub fn none(tfar: f32) -> Best {
        Best { t: tfar, prim: u32::MAX, u: 0.0, v: 0.0, ng: glam::Vec3::ZERO }
    }

    /// Takes the candidate if it wins under the kernel's deterministic order and `admit`
    /// counts it; `tri` gives its vertices, asked for only then.
    #[inline(always)]
    pub fn offer<A: Admit>(&mut self, t: f32, prim: u32, u: f32, v: f32, tri: impl FnOnce() -> [[f32; 3]; 3], admit: &mut A) {
        if crate::ray::closer(t, prim, self.t, self.prim) {
            let hit = lane_hit(t, prim, u, v, &tri());
            if A::ALL || admit.admit(&hit) {
                *self = Best { t, prim, u, v, ng: hit.ng };
            }
        }
    }

    pub fn into_hit(self) -> Option<crate::ray::Hit> {
        (self.prim != u32::MAX).then_some(crate::ray::Hit { t: self.t, prim: self.prim, u: self.u, v: self.v, ng: self.ng })
    }
}
