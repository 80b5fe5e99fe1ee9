//! Binned SAH construction (Wald 2007; the RTRT core's SAH build, docs/design/seeds.md §1.4).
//!
//! Top-down: at each node, primitive centroids are binned along all three axes, the split plane
//! with the lowest surface-area-heuristic cost is chosen, and the primitive references are
//! partitioned in place; nodes of a few primitives are split by an exact sweep instead. Large
//! nodes bin in parallel and both halves of a split are built as independent rayon tasks, each
//! subtree of a few thousand primitives into its own node vector, put together with the others
//! once at the end; small subtrees run sequentially so that no task is smaller than that.

use glam::Vec4;
use rayon::prelude::*;

use super::{BuildOptions, Growing, MAX_BINS, PrimRef, SetBounds, splice};
use crate::aabb::Aabb;
use crate::bvh2::Node2;

/// Builds the tree over `refs` (reordered in place into leaf order) into `nodes` (emptied first,
/// its storage reused); root at index 0, nodes in depth-first order.
pub(super) fn build(refs: &mut [PrimRef], set: SetBounds, opts: &BuildOptions, nodes: &mut Vec<Node2>) {
    nodes.clear();
    let task = Task { refs, offset: 0, set, depth: 0 };
    if rayon::current_num_threads() == 1 {
        // One thread builds the same tree straight into one vector: the parts would only be
        // copied together again.
        nodes.reserve(node_capacity(task.refs.len(), opts));
        build_into(task, opts, nodes);
        return;
    }
    let part = build_part(task, opts);
    nodes.reserve(part.len());
    part.flatten_into(nodes);
}

/// Below this depth the builder stops looking for SAH splits and halves nodes at the object
/// median instead, so the tree depth (and the traversal stack) stays bounded even for inputs on
/// which the SAH peels off one primitive per level.
const SAH_DEPTH_LIMIT: u32 = 40;
/// Nodes with at most this many primitives are split by a full SAH sweep over their sorted
/// centroids instead of by binning.
const SWEEP_BELOW: usize = 32;
/// Nodes with at least this many primitives bin in parallel.
const PARALLEL_BINNING: usize = 1 << 16;
/// Nodes with at least this many primitives build their two halves as separate tasks.
const PARALLEL_SUBTREES: usize = 1 << 12;

/// A node still to be built: its primitive references (a sub-slice of the global array starting
/// at `offset`), their bounds and its depth.
struct Task<'a> {
    refs: &'a mut [PrimRef],
    offset: u32,
    set: SetBounds,
    depth: u32,
}

/// A subtree as the parallel tasks leave it: nodes built by one task into one vector, or an inner
/// node whose halves were built by separate tasks. The parts are put together once, at the end:
/// splicing each task's vector into its parent's, as the tasks returned, copied the top of the
/// tree once per level, each time into fresh pages (5 % of the sphere scene's build on one
/// thread).
enum Part {
    Nodes(Vec<Node2>),
    Split { bounds: Aabb, halves: Box<(Part, Part)> },
}

impl Part {
    /// Number of nodes.
    fn len(&self) -> usize {
        match self {
            Part::Nodes(nodes) => nodes.len(),
            Part::Split { halves, .. } => 1 + halves.0.len() + halves.1.len(),
        }
    }

    /// Appends the part's nodes to `out` in depth-first order; returns its root's index.
    fn flatten_into(self, out: &mut Vec<Node2>) -> u32 {
        match self {
            Part::Nodes(nodes) => splice(out, nodes),
            Part::Split { bounds, halves } => {
                let index = out.len();
                out.push(Node2::leaf(bounds, 0, 0));
                let (left, right) = *halves;
                let l = left.flatten_into(out);
                let r = right.flatten_into(out);
                out[index] = Node2::inner(bounds, l, r);
                index as u32
            }
        }
    }
}

/// Room for the nodes over `n` references in leaves of half `max_leaf_size` on average (the
/// benchmark scenes' leaves average 7.2 and 7.4 of 8), so that the vector rarely grows and
/// copies itself; pages reserved but never written are never mapped.
fn node_capacity(n: usize, opts: &BuildOptions) -> usize {
    4 * n / opts.max_leaf_size + 1
}

/// Builds the subtree of `task`, its halves as separate tasks while they are large.
fn build_part(task: Task<'_>, opts: &BuildOptions) -> Part {
    if task.refs.len() < PARALLEL_SUBTREES {
        let mut nodes = Vec::with_capacity(node_capacity(task.refs.len(), opts));
        build_into(task, opts, &mut nodes);
        return Part::Nodes(nodes);
    }
    let bounds = task.set.geometry;
    let (offset, count) = (task.offset, task.refs.len() as u32);
    match split(task, opts) {
        None => Part::Nodes(vec![Node2::leaf(bounds, offset, count)]),
        Some((left, right)) => {
            let halves = rayon::join(|| build_part(left, opts), || build_part(right, opts));
            Part::Split { bounds, halves: Box::new(halves) }
        }
    }
}

/// Builds the subtree of `task` into `out` on this thread and returns its root index.
fn build_into(task: Task<'_>, opts: &BuildOptions, out: &mut Vec<Node2>) -> u32 {
    let index = out.len();
    let bounds = task.set.geometry;
    let (offset, count) = (task.offset, task.refs.len() as u32);
    out.push(Node2::leaf(bounds, offset, count));
    let Some((left, right)) = split(task, opts) else {
        return index as u32;
    };
    let l = build_into(left, opts, out);
    let r = build_into(right, opts, out);
    out[index] = Node2::inner(bounds, l, r);
    index as u32
}

/// One centroid bin: bounds of the primitives that fell into it, and their number.
#[derive(Clone, Copy)]
struct Bin {
    lo: Vec4,
    hi: Vec4,
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin { lo: Vec4::INFINITY, hi: Vec4::NEG_INFINITY, count: 0 };

    fn merge(self, o: Bin) -> Bin {
        Bin { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi), count: self.count + o.count }
    }

    fn area(&self) -> f32 {
        Aabb { min: self.lo.truncate(), max: self.hi.truncate() }.area()
    }
}

/// Maps doubled centroids to bin indices along all three axes at once.
#[derive(Clone, Copy)]
struct BinMapping {
    origin: Vec4,
    scale: Vec4,
    last: i32,
}

impl BinMapping {
    fn new(centroids: &Aabb, bins: usize) -> Self {
        let extent = centroids.extent();
        // Slightly below `bins / extent` so that the maximum centroid maps to the last bin.
        let s = |e: f32| if e > 0.0 { bins as f32 * (1.0 - 1e-5) / e } else { 0.0 };
        BinMapping {
            origin: centroids.min.extend(0.0),
            scale: Vec4::new(s(extent.x), s(extent.y), s(extent.z), 0.0),
            last: bins as i32 - 1,
        }
    }

    /// The bins of `r` along the three axes, as the first three bytes of a word (the fourth is
    /// garbage). Clamping in floating point first lets the three conversions be one truncating
    /// SIMD instruction instead of Rust's saturating scalar casts, and packing the three lanes
    /// to bytes in registers gives the binning loop one store per reference: extracting each lane
    /// went through the stack, and the reload of a lane from the vector just stored there was
    /// the binning loop's most sampled instruction after the wait for the reference itself (the
    /// packing took 6 % off the sphere scene's and the soup's one-thread builds: medians of 20
    /// and 12 paired runs, the same trees).
    #[inline(always)]
    fn bins_of(&self, r: &PrimRef) -> [u8; 4] {
        let f = ((r.centroid2() - self.origin) * self.scale).clamp(Vec4::ZERO, Vec4::splat(self.last as f32));
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_cvtsi128_si32, _mm_cvttps_epi32, _mm_packs_epi32, _mm_packus_epi16};
            // SAFETY: these are SSE2 instructions, which every x86_64 CPU has. The indices are
            // in `0..MAX_BINS`, so neither pack saturates them.
            unsafe {
                let i = _mm_cvttps_epi32(f.into());
                let bytes = _mm_packus_epi16(_mm_packs_epi32(i, i), _mm_packs_epi32(i, i));
                _mm_cvtsi128_si32(bytes).to_le_bytes()
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            [f.x as u8, f.y as u8, f.z as u8, 0]
        }
    }

    /// Whether `r` falls into a bin below `pos` along `axis`, for `1 <= pos < bins`: the same as
    /// `bins_of(r)[axis] < pos` (the truncation and the clamping cannot change which side of an
    /// integer a value lies on), without the conversion. All three axes are compared at once
    /// and the axis's bit picked from the mask: picking the axis's lane first went through the
    /// stack and a jump table on every reference.
    #[inline(always)]
    fn below(&self, r: &PrimRef, axis: usize, pos: usize) -> bool {
        let f = (r.centroid2() - self.origin) * self.scale;
        f.cmplt(Vec4::splat(pos as f32)).bitmask() >> axis & 1 != 0
    }
}

/// Bins per axis for a node of `n` references: `4 + n / 20`, at most `bins` (Embree's rule). A
/// small node gains little from fine bins (most would be empty) but pays for each one when the
/// split is evaluated; on one thread this took the sphere scene's build from 0.31 s to 0.29 s and
/// lowered the soup's SAH cost (181.93 to 181.83), the sphere's staying 1.3033.
fn bins_for(n: usize, bins: usize) -> usize {
    bins.min(4 + n / 20)
}

/// The box of one centroid bin: kept apart from the counts, 32 bytes aligned to 32, so that no
/// box straddles two cache lines.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct BinBox {
    lo: Vec4,
    hi: Vec4,
}

impl BinBox {
    const EMPTY: BinBox = BinBox { lo: Vec4::INFINITY, hi: Vec4::NEG_INFINITY };

    #[inline(always)]
    fn add(&mut self, r: &PrimRef) {
        self.lo = self.lo.min(r.lo);
        self.hi = self.hi.max(r.hi);
    }
}

/// Centroid bins along the three axes: their boxes and their reference counts.
#[derive(Clone, Copy)]
struct Bins {
    boxes: [[BinBox; MAX_BINS]; 3],
    counts: [[u32; MAX_BINS]; 3],
}

impl Bins {
    const EMPTY: Bins = Bins { boxes: [[BinBox::EMPTY; MAX_BINS]; 3], counts: [[0; MAX_BINS]; 3] };

    /// Bin `i` along `axis`.
    #[inline(always)]
    fn bin(&self, axis: usize, i: usize) -> Bin {
        let b = &self.boxes[axis][i];
        Bin { lo: b.lo, hi: b.hi, count: self.counts[axis][i] }
    }

    /// Merges the bins of `o` into these.
    fn merge(&mut self, o: &Bins) {
        for axis in 0..3 {
            for (a, b) in self.boxes[axis].iter_mut().zip(&o.boxes[axis]) {
                a.lo = a.lo.min(b.lo);
                a.hi = a.hi.max(b.hi);
            }
            for (a, b) in self.counts[axis].iter_mut().zip(&o.counts[axis]) {
                *a += b;
            }
        }
    }
}

const _: () = assert!(MAX_BINS.is_power_of_two() && MAX_BINS <= 256, "bin indices are masked into range and fit a byte");

/// References whose bin indices are computed at a time, before their bins are grown. Computing
/// each reference's indices just before its updates left the bin loads waiting on that chain
/// (subtraction, scaling, conversion, lane extraction) and the updates of neighbouring references
/// could hardly overlap; with the indices read from a small buffer (and the bins' boxes apart
/// from their counts), binning a node of 16k references took two thirds of the time. Filling two
/// sets of bins in turn, which cut the chains from one update of a bin to the next, then gained
/// nothing.
const INDEX_RUN: usize = 64;

/// Bins the references sequentially. Masking the indices (already in range: `bins_of` clamps
/// them) drops three bounds checks per reference.
fn bin_refs(refs: &[PrimRef], map: &BinMapping) -> Bins {
    let mut bins = Bins::EMPTY;
    // Four bytes a reference (the last unused): one store each, where three bytes made binning
    // slower than it was without the buffer.
    let mut indices = [[0u8; 4]; INDEX_RUN];
    for run in refs.chunks(INDEX_RUN) {
        for (index, r) in indices.iter_mut().zip(run) {
            *index = map.bins_of(r);
        }
        for (r, index) in run.iter().zip(&indices) {
            for (axis, &i) in index[..3].iter().enumerate() {
                let i = usize::from(i) & (MAX_BINS - 1);
                bins.boxes[axis][i].add(r);
                bins.counts[axis][i] += 1;
            }
        }
    }
    bins
}

fn bin_all(refs: &[PrimRef], map: &BinMapping) -> Bins {
    if refs.len() < PARALLEL_BINNING {
        return bin_refs(refs, map);
    }
    refs.par_chunks(16384)
        .map(|c| bin_refs(c, map))
        .reduce_with(|mut a, b| {
            a.merge(&b);
            a
        })
        .expect("at least one chunk")
}

/// The SAH cost of a leaf of `count` primitives: up to `max_leaf_size` of them are tested at once
/// (one 8-lane block of triangles, or one box of a box tree), so it counts such groups. Evaluated
/// for every candidate split; a power-of-two leaf size (the default 8) makes the group count a
/// shift instead of a division (with the bins on the stack, a sixth off the sphere scene's build
/// on one thread).
#[derive(Clone, Copy)]
struct LeafCost {
    intersection_cost: f32,
    max_leaf_size: u32,
    /// `log2(max_leaf_size)` when it is a power of two.
    shift: Option<u32>,
}

impl LeafCost {
    fn new(opts: &BuildOptions) -> LeafCost {
        let size = opts.max_leaf_size as u32;
        LeafCost { intersection_cost: opts.intersection_cost, max_leaf_size: size, shift: size.is_power_of_two().then(|| size.trailing_zeros()) }
    }

    #[inline(always)]
    fn of(&self, count: u32) -> f32 {
        let groups = match self.shift {
            Some(shift) => (count + (self.max_leaf_size - 1)) >> shift,
            None => count.div_ceil(self.max_leaf_size),
        };
        self.intersection_cost * groups as f32
    }
}

/// The best split found: axis, where the right side starts (a bin for binning, a position in
/// centroid order for a sweep), and SAH cost (in units of `intersection_cost × parent area`,
/// without the traversal term).
struct BinSplit {
    axis: usize,
    pos: usize,
    cost: f32,
}

fn best_bin_split(bins: &Bins, n_bins: usize, map: &BinMapping, leaf_cost: LeafCost) -> Option<BinSplit> {
    let mut best: Option<BinSplit> = None;
    for axis in 0..3 {
        if map.scale[axis] == 0.0 {
            continue;
        }
        // Right-to-left accumulation: cost contribution of bins[i..].
        let mut right_cost = [0.0f32; MAX_BINS];
        let mut right_count = [0u32; MAX_BINS];
        let mut acc = Bin::EMPTY;
        for i in (1..n_bins).rev() {
            acc = acc.merge(bins.bin(axis, i));
            right_cost[i] = acc.area() * leaf_cost.of(acc.count);
            right_count[i] = acc.count;
        }
        let mut left = Bin::EMPTY;
        for pos in 1..n_bins {
            left = left.merge(bins.bin(axis, pos - 1));
            if left.count == 0 || right_count[pos] == 0 {
                continue;
            }
            let cost = left.area() * leaf_cost.of(left.count) + right_cost[pos];
            if best.as_ref().is_none_or(|b| cost < b.cost) {
                best = Some(BinSplit { axis, pos, cost });
            }
        }
    }
    best
}

/// The exact best SAH split of a few primitives: along each axis, sorted by centroid, every
/// position between two primitives is evaluated. `pos` is the size of the left side; the keys
/// returned are the split axis's sort keys, whose low halves are the indices of `refs` in order.
fn best_sweep_split(refs: &[PrimRef], leaf_cost: LeafCost) -> Option<(BinSplit, [u64; SWEEP_BELOW])> {
    let n = refs.len();
    debug_assert!(n <= SWEEP_BELOW);
    let mut best: Option<(BinSplit, [u64; SWEEP_BELOW])> = None;
    let mut best_cost = f32::INFINITY;
    let mut right_cost = [0.0f32; SWEEP_BELOW];
    for axis in 0..3 {
        // Sorting packed (centroid key, index) words instead of the 32-byte references themselves
        // took the sphere scene's build from 0.45 s to 0.39 s on one thread; the index breaks
        // ties deterministically.
        let mut keys = [0u64; SWEEP_BELOW];
        for (i, (k, r)) in keys.iter_mut().zip(refs).enumerate() {
            *k = (u64::from(order_key(r.centroid2()[axis])) << 32) | i as u64;
        }
        keys[..n].sort_unstable();
        if keys[0] >> 32 == keys[n - 1] >> 32 {
            continue;
        }
        let at = |i: usize| &refs[keys[i] as u32 as usize];
        let (mut lo, mut hi) = (Vec4::INFINITY, Vec4::NEG_INFINITY);
        for i in (1..n).rev() {
            (lo, hi) = (lo.min(at(i).lo), hi.max(at(i).hi));
            right_cost[i] = box_area(lo, hi) * leaf_cost.of((n - i) as u32);
        }
        let (mut lo, mut hi) = (Vec4::INFINITY, Vec4::NEG_INFINITY);
        let mut best_pos = None;
        for (pos, &right) in right_cost[..n].iter().enumerate().skip(1) {
            (lo, hi) = (lo.min(at(pos - 1).lo), hi.max(at(pos - 1).hi));
            let cost = box_area(lo, hi) * leaf_cost.of(pos as u32) + right;
            if cost < best_cost {
                (best_cost, best_pos) = (cost, Some(pos));
            }
        }
        if let Some(pos) = best_pos {
            best = Some((BinSplit { axis, pos, cost: best_cost }, keys));
        }
    }
    best
}

/// A key whose unsigned order is the order of finite floats.
fn order_key(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 { !bits } else { bits | 1 << 31 }
}

/// Surface area of the non-empty box `lo..hi` (the `w` lanes are ignored).
#[inline(always)]
fn box_area(lo: Vec4, hi: Vec4) -> f32 {
    let d = hi - lo;
    2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
}

/// Decides how to split `task`: `None` makes it a leaf.
fn split<'a>(task: Task<'a>, opts: &BuildOptions) -> Option<(Task<'a>, Task<'a>)> {
    let n = task.refs.len();
    if n <= 1 {
        return None;
    }
    let fits_leaf = n <= opts.max_leaf_size;
    let leaf_cost = LeafCost::new(opts);
    if task.depth >= SAH_DEPTH_LIMIT {
        return (!fits_leaf).then(|| median_split(task));
    }
    // A split costs at least the traversal step: a node that fits a leaf whose test costs no more
    // is a leaf without looking at its primitives. With the default costs that is every node of
    // at most `max_leaf_size`; sweeping them took the sphere scene's build from 0.36 s to 0.39 s.
    if fits_leaf && opts.traversal_cost >= leaf_cost.of(n as u32) {
        return None;
    }
    let area = task.set.geometry.area().max(f32::MIN_POSITIVE);
    let worth_splitting = |cost: f32| !fits_leaf || opts.traversal_cost + cost / area < leaf_cost.of(n as u32);
    let (mid, sides) = if n <= SWEEP_BELOW {
        // Few primitives: sorting them is cheaper than binning and finds the exact best plane.
        let Some((best, keys)) = best_sweep_split(task.refs, leaf_cost) else {
            return (!fits_leaf).then(|| median_split(task));
        };
        if !worth_splitting(best.cost) {
            return None;
        }
        let unsorted: [PrimRef; SWEEP_BELOW] = std::array::from_fn(|i| task.refs[i.min(n - 1)]);
        for (r, &key) in task.refs.iter_mut().zip(&keys) {
            *r = unsorted[key as u32 as usize];
        }
        (best.pos, None)
    } else {
        let n_bins = bins_for(n, opts.bins);
        let map = BinMapping::new(&task.set.centroids, n_bins);
        let bins = bin_all(task.refs, &map);
        let Some(best) = best_bin_split(&bins, n_bins, &map, leaf_cost) else {
            // All centroids coincide: no plane separates them.
            return (!fits_leaf).then(|| median_split(task));
        };
        if !worth_splitting(best.cost) {
            return None;
        }
        let (mid, left, right) = partition_bins(task.refs, &map, best.axis, best.pos);
        (mid, Some((left, right)))
    };
    if mid == 0 || mid == n {
        return (!fits_leaf).then(|| median_split(task));
    }
    Some(halves(task, mid, sides))
}

/// Partitions the references in place, those whose bin along `axis` lies below `pos` first;
/// returns the size of the left side and the bounds of both sides. The side test must stay cheap:
/// taking it from `bins_of` (an index spilled to the stack and read back by axis) made this loop
/// slower than a pass of its own.
///
/// Blocks of references at each end are classified without branches first (the block partition
/// of Edelkamp and Weiß's BlockQuicksort), then the misplaced ones of the two blocks swapped
/// pairwise. A loop that branched on each reference's side mispredicted about every second
/// reference of the triangle soup, whose neighbours in memory lie anywhere in space: this took
/// the soup's one-thread build from 0.50 s to 0.36 s (CPU time), the sphere scene's staying
/// within 4 %. Each side's bounds are grown from a block once it holds only that side, while it
/// is still in the L1 cache (as Embree does, this saves a pass over the children's references);
/// the last two blocks or fewer are partitioned one reference at a time.
fn partition_bins(refs: &mut [PrimRef], map: &BinMapping, axis: usize, pos: usize) -> (usize, SetBounds, SetBounds) {
    let is_left = |r: &PrimRef| map.below(r, axis, pos);
    let (mut left, mut right) = (Growing::EMPTY, Growing::EMPTY);
    let (mut i, mut j) = (0, refs.len());
    // Offsets of the misplaced references of the current block at each end (from `i` upwards,
    // from `j - 1` downwards), and how many of them are swapped already and in all.
    let (mut misplaced_left, mut misplaced_right) = ([0u8; BLOCK], [0u8; BLOCK]);
    let (mut swapped_left, mut found_left, mut swapped_right, mut found_right) = (0, 0, 0, 0);
    while j - i >= 2 * BLOCK {
        if swapped_left == found_left {
            (swapped_left, found_left) = (0, 0);
            for (k, r) in refs[i..i + BLOCK].iter().enumerate() {
                misplaced_left[found_left] = k as u8;
                found_left += usize::from(!is_left(r));
            }
        }
        if swapped_right == found_right {
            (swapped_right, found_right) = (0, 0);
            for (k, r) in refs[j - BLOCK..j].iter().rev().enumerate() {
                misplaced_right[found_right] = k as u8;
                found_right += usize::from(is_left(r));
            }
        }
        let pairs = (found_left - swapped_left).min(found_right - swapped_right);
        for (&a, &b) in misplaced_left[swapped_left..][..pairs].iter().zip(&misplaced_right[swapped_right..][..pairs]) {
            refs.swap(i + a as usize, j - 1 - b as usize);
        }
        swapped_left += pairs;
        swapped_right += pairs;
        if swapped_left == found_left {
            left = refs[i..i + BLOCK].iter().fold(left, Growing::add);
            i += BLOCK;
        }
        if swapped_right == found_right {
            right = refs[j - BLOCK..j].iter().fold(right, Growing::add);
            j -= BLOCK;
        }
    }
    // The references of a block only partly sorted out are still in `i..j`, and are grown into
    // their side's bounds here.
    loop {
        while i < j && is_left(&refs[i]) {
            left = left.add(&refs[i]);
            i += 1;
        }
        while i < j && !is_left(&refs[j - 1]) {
            right = right.add(&refs[j - 1]);
            j -= 1;
        }
        if i >= j {
            return (i, left.bounds(), right.bounds());
        }
        refs.swap(i, j - 1);
        left = left.add(&refs[i]);
        right = right.add(&refs[j - 1]);
        i += 1;
        j -= 1;
    }
}

/// References classified at a time at each end by [`partition_bins`] (offsets fit a byte).
const BLOCK: usize = 32;

/// Splits the task's references at `mid` into two child tasks, with the sides' bounds if they
/// are known (computed here otherwise).
fn halves(task: Task<'_>, mid: usize, sides: Option<(SetBounds, SetBounds)>) -> (Task<'_>, Task<'_>) {
    let large = task.refs.len() >= PARALLEL_BINNING;
    let (l, r) = task.refs.split_at_mut(mid);
    let (ls, rs) = match sides {
        Some(sides) => sides,
        None if large => rayon::join(|| SetBounds::of(l), || SetBounds::of(r)),
        None => (SetBounds::of(l), SetBounds::of(r)),
    };
    let depth = task.depth + 1;
    (
        Task { refs: l, offset: task.offset, set: ls, depth },
        Task { refs: r, offset: task.offset + mid as u32, set: rs, depth },
    )
}

/// Splits at the object median along the widest centroid axis.
fn median_split(task: Task<'_>) -> (Task<'_>, Task<'_>) {
    let e = task.set.centroids.extent();
    let axis = if e.x >= e.y && e.x >= e.z { 0 } else if e.y >= e.z { 1 } else { 2 };
    let mid = task.refs.len() / 2;
    task.refs.select_nth_unstable_by(mid, |a, b| a.centroid2()[axis].total_cmp(&b.centroid2()[axis]));
    halves(task, mid, None)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use proptest::prelude::*;

    use super::{BinMapping, bin_refs, partition_bins};
    use crate::aabb::Aabb;
    use crate::build::{BuildOptions, MAX_BINS, PrimRef, SetBounds, build};
    use crate::bvh2::{Node2, Node2Kind};

    /// Small triangles on a jittered grid, enough of them for parallel binning and tasks.
    fn grid(n: u32) -> Vec<[Vec3; 3]> {
        (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f32, (i / n) as f32);
                let z = (i.wrapping_mul(2_654_435_761) >> 20) as f32 / 4096.0;
                let p = Vec3::new(x, y, z);
                [p, p + Vec3::new(0.9, 0.1, 0.0), p + Vec3::new(0.2, 0.8, 0.3)]
            })
            .collect()
    }

    /// Checks that the subtree at `index` is laid out depth-first (each inner node followed by its
    /// left subtree, then its right); returns the index just past it.
    fn depth_first(nodes: &[Node2], index: usize) -> usize {
        match nodes[index].kind() {
            Node2Kind::Leaf { .. } => index + 1,
            Node2Kind::Inner { left, right } => {
                assert_eq!(left as usize, index + 1, "left child of node {index} follows it");
                let end = depth_first(nodes, index + 1);
                assert_eq!(right as usize, end, "right child of node {index} follows its left subtree");
                depth_first(nodes, end)
            }
        }
    }

    /// References of random boxes, `n` of them, from `seed`.
    fn random_refs(n: usize, seed: u64) -> Vec<PrimRef> {
        let mut state = seed.wrapping_mul(6_364_136_223_846_793_005) | 1;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..n as u32)
            .map(|i| {
                let lo = Vec3::new(next(), next(), next()) * 10.0;
                PrimRef::new(Aabb { min: lo, max: lo + Vec3::new(next(), next(), next()) }, i)
            })
            .collect()
    }

    /// The bin of `r` along `axis` computed one axis at a time with scalar arithmetic: what
    /// `BinMapping::bins_of` computes for the three axes at once.
    fn scalar_bin(map: &BinMapping, r: &PrimRef, axis: usize) -> usize {
        ((r.centroid2()[axis] - map.origin[axis]) * map.scale[axis]).clamp(0.0, map.last as f32) as usize
    }

    proptest! {
        /// Binning through the buffer of packed indices grows each bin by exactly the references
        /// whose centroids fall into it by scalar arithmetic.
        #[test]
        fn binning_matches_scalar_bins(n in 0usize..300, seed in any::<u64>(), n_bins in 2usize..=MAX_BINS) {
            let refs = random_refs(n, seed);
            let map = BinMapping::new(&SetBounds::of(&refs).centroids, n_bins);
            let bins = bin_refs(&refs, &map);
            for axis in 0..3 {
                for i in 0..MAX_BINS {
                    let inside: Vec<PrimRef> = refs.iter().filter(|r| scalar_bin(&map, r, axis) == i).copied().collect();
                    let bin = bins.bin(axis, i);
                    prop_assert_eq!(bin.count as usize, inside.len());
                    let expected = SetBounds::of(&inside).geometry;
                    prop_assert_eq!((bin.lo.truncate(), bin.hi.truncate()), (expected.min, expected.max));
                }
            }
        }

        /// The block partition puts exactly the references on the left that the side test puts
        /// there, keeps every reference, and grows each side's bounds over exactly its own.
        #[test]
        fn block_partition_matches_the_side_test(n in 0usize..400, seed in any::<u64>(), axis in 0usize..3, pos in 1usize..16, sorted in any::<bool>()) {
            let mut refs = random_refs(n, seed);
            if sorted {
                // Spatially ordered input, as meshes are: long runs on each side.
                refs.sort_by(|a, b| a.centroid2()[axis].total_cmp(&b.centroid2()[axis]));
            }
            let map = BinMapping::new(&SetBounds::of(&refs).centroids, 16);
            let mut parted = refs.clone();
            let (mid, left, right) = partition_bins(&mut parted, &map, axis, pos);
            let expected_left: Vec<u32> = refs.iter().filter(|r| scalar_bin(&map, r, axis) < pos).map(PrimRef::prim).collect();
            prop_assert_eq!(mid, expected_left.len());
            prop_assert!(parted[..mid].iter().all(|r| scalar_bin(&map, r, axis) < pos));
            prop_assert!(parted[mid..].iter().all(|r| scalar_bin(&map, r, axis) >= pos));
            let mut prims: Vec<u32> = parted.iter().map(PrimRef::prim).collect();
            prims.sort_unstable();
            prop_assert_eq!(prims, (0..n as u32).collect::<Vec<_>>());
            for (side, bounds) in [(&parted[..mid], left), (&parted[mid..], right)] {
                let expected = SetBounds::of(side);
                prop_assert_eq!(format!("{:?}", bounds), format!("{:?}", expected));
            }
        }
    }

    #[test]
    fn parallel_parts_make_one_depth_first_tree_whatever_the_threads() {
        let tris = grid(300);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
            pool.install(|| build(&tris, &BuildOptions::default()))
        };
        let one = on(1);
        assert_eq!(depth_first(&one.nodes, 0), one.nodes.len(), "every node is reached once");
        let three = on(3);
        assert_eq!(format!("{:?}", one.nodes), format!("{:?}", three.nodes));
        assert_eq!(one.prims, three.prims);
    }
}
