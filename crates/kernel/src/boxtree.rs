//! A wide BVH over boxes whose leaves the caller intersects: the top level of a two-level scene,
//! rebuilt every frame over the instances' world boxes.

use crate::aabb::Aabb;
use crate::build::build_over_boxes;
use crate::isa::Isa;
use crate::prepared::PreparedRay;
use crate::ray_packet::Entries;
use crate::traverse;
use crate::wide::{LEAF, Node8, collapse};

/// A tree over boxes, built with the seed's fast top-level heuristic (see `build::top_level`)
/// and collapsed to eight lanes. Each leaf holds one box, and its link names the box by its
/// index in the slice the tree was built from (`LEAF | index`), so that a walk reaches the box
/// without a further load; what is inside a box (an instance of an object, say) the caller
/// intersects itself.
#[derive(Clone, Debug)]
pub struct BoxTree {
    pub(crate) nodes: Vec<Node8>,
    pub(crate) root: u32,
    /// The boxes the tree was built over, by index (the packet walks' answers are exact to
    /// them).
    boxes: Vec<Aabb>,
    /// Boxes in the tree.
    len: usize,
    bounds: Aabb,
    isa: Isa,
}

impl BoxTree {
    /// Bytes a tree holds per box, for memory budgets: the box's copy and its share of the
    /// 8-wide nodes (leaves hold up to eight boxes and inner nodes add about one in seven more,
    /// so a node per six boxes).
    pub const BYTES_PER_BOX: usize = size_of::<Aabb>() + size_of::<Node8>() / 6;

    /// Builds the tree over `boxes`; empty or non-finite boxes are left out (no ray reaches them).
    ///
    /// # Panics
    /// If there are 2³¹ − 1 boxes or more (their indices would not fit a leaf link).
    pub fn build(boxes: &[Aabb]) -> BoxTree {
        assert!(boxes.len() < (!LEAF) as usize, "too many boxes for leaf links");
        let built = build_over_boxes(boxes, 1);
        let wide = collapse(&built.nodes, Vec::new(), |first, count| {
            assert_eq!(count, 1, "the top-level builder makes leaves of one box");
            LEAF | built.prims[first as usize]
        });
        let bounds = built.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds);
        BoxTree { nodes: wide.nodes, root: wide.root, boxes: boxes.to_vec(), len: built.prims.len(), bounds, isa: Isa::best() }
    }

    /// The same tree traversed with the given instruction set, or `None` if this CPU lacks it.
    pub fn with_isa(mut self, isa: Isa) -> Option<BoxTree> {
        isa.is_supported().then(|| {
            self.isa = isa;
            self
        })
    }

    /// Bounds of all boxes in the tree.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Number of boxes in the tree.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the tree holds no box.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// A closest-hit walk, near-first: `visit(item, tfar)` is called for every box the ray's
    /// segment `(tnear, tfar]` touches, with `tfar` the closest hit found so far, and returns
    /// the new closest distance (`tfar` itself if it found nothing closer). Boxes that start
    /// beyond the closest hit are skipped, with the kernel's conservative rounding (a box that
    /// starts exactly at `tfar` is still visited, so ties can be resolved by the caller).
    pub fn closest(&self, ray: &PreparedRay, visit: impl FnMut(u32, f32) -> f32) {
        match self.isa {
            // SAFETY: `isa` is only ever set to a flavour `is_supported` confirmed on this CPU.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { traverse::avx2::boxes_closest(self, ray, visit) },
            _ => traverse::portable::boxes_closest(self, ray, visit),
        }
    }

    /// An any-hit walk: `visit(item)` is called for the boxes the ray's segment touches until it
    /// returns `true`; returns whether it did.
    pub fn any(&self, ray: &PreparedRay, visit: impl FnMut(u32) -> bool) -> bool {
        match self.isa {
            // SAFETY: as in `closest`.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { traverse::avx2::boxes_any(self, ray, visit) },
            _ => traverse::portable::boxes_any(self, ray, visit),
        }
    }

    /// The boxes that the segments of up to [`crate::PACKET_SIZE`] rays touch: `visit(item,
    /// entries)` for each, in no particular order, with exactly the rays (bit `i` for
    /// `rays[i]`) whose segment touches box `item` and where each enters it (what
    /// [`Aabb::intersect`] says of each). Rays that share an origin or a direction and an
    /// octant (camera rays of neighbouring pixels, shadow rays towards a light) walk the tree as
    /// one packet, naming each box once; others walk it one by one, and a box can come once per
    /// ray. Returns whether every box was named at most once.
    ///
    /// # Panics
    /// If `rays` holds more than [`crate::PACKET_SIZE`] rays.
    pub fn touched(&self, rays: &[PreparedRay], mut visit: impl FnMut(u32, &Entries)) -> bool {
        assert!(rays.len() <= crate::PACKET_SIZE, "at most a packet");
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `isa` is only ever set to a flavour `is_supported` confirmed on this CPU; the
        // root of a tree of two boxes or more is a node.
        if self.isa == Isa::Avx2 && self.root & LEAF == 0 && !rays.is_empty() && unsafe { traverse::avx2::boxes_touched(self, rays, &mut visit) } {
            return true;
        }
        for (i, ray) in rays.iter().enumerate() {
            self.any(ray, |item| {
                if let Some(entry) = self.boxes[item as usize].intersect(ray, ray.tfar) {
                    let mut entries = Entries { rays: 1 << i, ..Entries::NONE };
                    entries.entry[i] = entry;
                    visit(item, &entries);
                }
                false
            });
        }
        rays.len() <= 1
    }

    /// An any-hit walk for up to [`crate::PACKET_SIZE`] rays at once: `block(item, rays)` is
    /// called with exactly the rays (bit `i` for `rays[i]`), not blocked yet, whose segment
    /// touches box `item`, and returns those it blocks; the walk skips the rest of the tree for
    /// blocked rays and ends once all are. Returns the blocked rays. Rays that travel as a
    /// packet (see [`BoxTree::touched`]) walk the tree together; others one by one.
    ///
    /// # Panics
    /// If `rays` holds more than [`crate::PACKET_SIZE`] rays.
    pub fn occluded_by(&self, rays: &[PreparedRay], mut block: impl FnMut(u32, u32) -> u32) -> u32 {
        assert!(rays.len() <= crate::PACKET_SIZE, "at most a packet");
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as in `touched`.
        if self.isa == Isa::Avx2
            && self.root & LEAF == 0
            && !rays.is_empty()
            && let Some(blocked) = unsafe { traverse::avx2::boxes_occluded(self, rays, &mut block) }
        {
            return blocked;
        }
        let touches = |item: u32, ray: &PreparedRay| self.boxes[item as usize].intersect(ray, ray.tfar).is_some();
        if self.boxes.len() == 1 {
            // A tree of one box is a leaf, which the walk below takes ray by ray: the rays that
            // touch it go to `block` together instead (a scene of one instance's shadow packets
            // then cross it as a packet).
            let live = (0..rays.len()).filter(|&i| touches(0, &rays[i])).fold(0, |m, i| m | 1 << i);
            return if live == 0 { 0 } else { block(0, live) };
        }
        (0..rays.len()).filter(|&i| self.any(&rays[i], |item| touches(item, &rays[i]) && block(item, 1 << i) != 0)).fold(0, |m, i| m | 1 << i)
    }

    /// The box a leaf link (not `EMPTY`) names.
    #[inline]
    pub(crate) fn leaf_item(link: u32) -> u32 {
        link & !LEAF
    }
}
