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
}

impl Best {
    /// No hit yet: everything up to the ray's `tfar` (inclusive) is still acceptable.
    pub fn none(tfar: f32) -> Best {
        Best { t: tfar, prim: u32::MAX, u: 0.0, v: 0.0 }
    }

    /// Takes the candidate if it wins under the kernel's deterministic order.
    #[inline(always)]
    pub fn offer(&mut self, t: f32, prim: u32, u: f32, v: f32) {
        if crate::ray::closer(t, prim, self.t, self.prim) {
            *self = Best { t, prim, u, v };
        }
    }

    pub fn into_hit(self) -> Option<crate::ray::Hit> {
        (self.prim != u32::MAX).then_some(crate::ray::Hit { t: self.t, prim: self.prim, u: self.u, v: self.v })
    }
}
