//! A packet's per-hit values four lanes at a time, in glam's SSE-backed `Vec4`: the packet
//! shading loops written over quads run the same correctly rounded operations as one by one,
//! where the compiler left to itself mixes packed and scalar square roots and divisions.

use glam::{BVec4A, Vec4};
use raystage_kernel::PACKET_SIZE;

/// The first lane of each quad of a packet.
pub(crate) fn quads() -> std::iter::StepBy<std::ops::Range<usize>> {
    (0..PACKET_SIZE).step_by(4)
}

/// Lanes `lane..lane + 4` of `values`.
pub(crate) fn quad(values: &[f32; PACKET_SIZE], lane: usize) -> Vec4 {
    Vec4::from_slice(&values[lane..])
}

/// Lanes `lane..lane + 4` of `flags`, as a mask.
pub(crate) fn pack(flags: &[bool; PACKET_SIZE], lane: usize) -> BVec4A {
    BVec4A::new(flags[lane], flags[lane + 1], flags[lane + 2], flags[lane + 3])
}

/// Writes `mask` over lanes `lane..lane + 4` of `flags`.
pub(crate) fn unpack(mask: BVec4A, flags: &mut [bool; PACKET_SIZE], lane: usize) {
    let bits = mask.bitmask();
    for (i, flag) in flags[lane..lane + 4].iter_mut().enumerate() {
        *flag = bits & (1 << i) != 0;
    }
}
