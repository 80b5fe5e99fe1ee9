//! Traversal kernels of the wide BVH, one module per instruction set. All flavours visit children
//! near-first, use the same box and triangle arithmetic, and return bit-identical results.

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
pub(crate) mod portable;

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

    /// Takes the candidate if it wins under the kernel's deterministic order; `tri` gives its
    /// vertices, asked for only then.
    #[inline(always)]
    pub fn offer(&mut self, t: f32, prim: u32, u: f32, v: f32, tri: impl FnOnce() -> [[f32; 3]; 3]) {
        if crate::ray::closer(t, prim, self.t, self.prim) {
            *self = Best { t, prim, u, v, ng: crate::triangle::geometric_normal(&tri().map(glam::Vec3::from_array)) };
        }
    }

    pub fn into_hit(self) -> Option<crate::ray::Hit> {
        (self.prim != u32::MAX).then_some(crate::ray::Hit { t: self.t, prim: self.prim, u: self.u, v: self.v, ng: self.ng })
    }
}
