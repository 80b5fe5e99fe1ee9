//! Every layout and every instruction set against the brute-force reference, on random and
//! adversarial inputs: random soups, grids of axis-aligned triangles hit through their shared
//! edges and vertices, rays along triangle edges, rays with ±0 direction components and rays
//! lying in the planes of the boxes. "Equal" means bit-identical: same primitive, same distance,
//! same barycentrics.

use glam::Vec3;
use proptest::prelude::*;
use raystage_kernel::{Aabb, BoxTree, BuildOptions, BuildQuality, Bvh2, Bvh8, Hit, Isa, PACKET_SIZE, PreparedRay, Ray, WalkCounts, brute};

/// Checks one ray against every layout and instruction set, closest and any hit.
fn check_ray(tris: &Vec<[Vec3; 3]>, bvh2: &Bvh2, bvh8s: &[Bvh8], ray: &Ray) -> Result<(), TestCaseError> {
    let expected = brute::intersect(tris, ray);
    let expected_any = brute::occluded(tris, ray);
    prop_assert_eq!(expected.is_some(), expected_any, "brute force disagrees with itself for {:?}", ray);
    prop_assert_eq!(bvh2.intersect(tris, ray), expected, "Bvh2 closest hit, ray {:?}", ray);
    prop_assert_eq!(bvh2.occluded(tris, ray), expected_any, "Bvh2 any hit, ray {:?}", ray);
    for bvh in bvh8s {
        prop_assert_eq!(bvh.intersect(ray), expected, "Bvh8/{} closest hit, ray {:?}", bvh.isa().name(), ray);
        prop_assert_eq!(bvh.occluded(ray), expected_any, "Bvh8/{} any hit, ray {:?}", bvh.isa().name(), ray);
        let mut counts = WalkCounts::default();
        prop_assert_eq!(bvh.intersect_counted(ray, &mut counts), expected, "Bvh8/{} counted closest hit, ray {:?}", bvh.isa().name(), ray);
        prop_assert_eq!(bvh.occluded_counted(ray, &mut counts), expected_any, "Bvh8/{} counted any hit, ray {:?}", bvh.isa().name(), ray);
        check_filtered(tris, bvh, ray)?;
    }
    Ok(())
}

/// [`Bvh8::intersect_where`] and [`Bvh8::occluded_where`] with a filter that counts front
/// faces of two triangles in three: the closest hit is the closest such hit (ties to the
/// smaller index), blocked exactly when one exists, and every hit a filter is shown is the one
/// brute force finds on that triangle alone, bit for bit.
fn check_filtered(tris: &[[Vec3; 3]], bvh: &Bvh8, ray: &Ray) -> Result<(), TestCaseError> {
    let alone = |prim: u32| brute::intersect(&[tris[prim as usize]][..], ray).map(|h| Hit { prim, ..h });
    let counts = |h: &Hit| h.ng.dot(ray.dir) < 0.0 && !h.prim.is_multiple_of(3);
    // In index order, a later hit wins only if strictly closer: the kernel's tie rule.
    let expected = (0..tris.len() as u32).filter_map(alone).filter(counts).fold(None, |best: Option<Hit>, h| match best {
        Some(b) if b.t <= h.t => Some(b),
        _ => Some(h),
    });
    let mut shown = Vec::new();
    let pre = PreparedRay::new(ray);
    let closest = bvh.intersect_where(&pre, |h| {
        shown.push(*h);
        counts(h)
    });
    prop_assert_eq!(closest, expected, "Bvh8/{} filtered closest hit, ray {:?}", bvh.isa().name(), ray);
    let blocked = bvh.occluded_where(&pre, |h| {
        shown.push(*h);
        counts(h)
    });
    prop_assert_eq!(blocked, expected.is_some(), "Bvh8/{} filtered any hit, ray {:?}", bvh.isa().name(), ray);
    for h in shown {
        prop_assert_eq!(Some(h), alone(h.prim), "Bvh8/{} filtered hit shown, ray {:?}", bvh.isa().name(), ray);
    }
    Ok(())
}

/// What `rays`' closest-hit and any-hit walks of `bvh` did.
fn walk_counts(bvh: &Bvh8, rays: &[Ray]) -> (WalkCounts, WalkCounts) {
    let (mut closest, mut any) = (WalkCounts::default(), WalkCounts::default());
    for ray in rays {
        bvh.intersect_counted(ray, &mut closest);
        bvh.occluded_counted(ray, &mut any);
    }
    (closest, any)
}

/// Builds every layout over `tris` with the given leaf size: the binary SAH tree, and the wide
/// tree from both builders in every instruction set.
fn layouts(tris: &Vec<[Vec3; 3]>, max_leaf_size: usize) -> (Bvh2, Vec<Bvh8>) {
    let opts = BuildOptions { max_leaf_size, ..BuildOptions::default() };
    let bvh2 = Bvh2::build(tris, &opts);
    let fast = Bvh8::build(tris, &BuildOptions { quality: BuildQuality::Fast, ..opts });
    let all = [Bvh8::from_bvh2(&bvh2, tris), fast]
        .into_iter()
        .flat_map(|bvh8| Isa::all().filter_map(move |isa| bvh8.clone().with_isa(isa)))
        .collect();
    (bvh2, all)
}

/// Uniform floats in `[lo, hi)` on a grid of 2²⁴ steps (proptest's own float ranges trip an
/// internal assertion on some bounds).
fn uniform(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    (0u32..1 << 24).prop_map(move |i| lo + (hi - lo) * (i as f32 / (1u32 << 24) as f32))
}

fn coord() -> impl Strategy<Value = f32> {
    uniform(-10.0, 10.0)
}

fn point() -> impl Strategy<Value = Vec3> {
    (coord(), coord(), coord()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A direction component: mostly random, sometimes exactly +0.0 or −0.0.
fn component() -> impl Strategy<Value = f32> {
    prop_oneof![6 => uniform(-1.0, 1.0), 1 => Just(0.0f32), 1 => Just(-0.0f32)]
}

fn direction() -> impl Strategy<Value = Vec3> {
    (component(), component(), component())
        .prop_filter("non-zero direction", |(x, y, z)| *x != 0.0 || *y != 0.0 || *z != 0.0)
        .prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A ray with random segment bounds: unbounded, or cut short so that some hits fall outside.
fn ray() -> impl Strategy<Value = Ray> {
    (point(), direction(), prop_oneof![Just(f32::INFINITY), uniform(0.1, 30.0)], prop_oneof![Just(0.0f32), uniform(0.0, 2.0)])
        .prop_map(|(o, d, tfar, tnear)| Ray::segment(o, d, tnear, tfar.max(tnear)))
}

/// Small random triangles scattered through the volume, plus a few big ones cutting through it.
fn soup() -> impl Strategy<Value = Vec<[Vec3; 3]>> {
    let small = (point(), point(), point()).prop_map(|(c, a, b)| [c, c + a * 0.15, c + b * 0.15]);
    let big = (point(), point(), point()).prop_map(|(a, b, c)| [a, b, c]);
    (prop::collection::vec(small, 1..300), prop::collection::vec(big, 0..4)).prop_map(|(mut s, b)| {
        s.extend(b);
        s
    })
}

/// Unit squares (two triangles each) on the integer planes x = i, y = j, z = k of an n³ lattice:
/// every square shares its edges and corners with neighbours, and many are coplanar with the
/// planes of their boxes.
fn lattice(n: i32, keep: &[bool]) -> Vec<[Vec3; 3]> {
    let mut tris = Vec::new();
    let mut index = 0;
    for a in 0..n {
        for b in 0..n {
            for c in 0..=n {
                for axis in 0..3 {
                    let k = index;
                    index += 1;
                    if !keep[k % keep.len()] {
                        continue;
                    }
                    let p = |u: i32, v: i32| {
                        let q = [(a + u) as f32, (b + v) as f32, c as f32];
                        match axis {
                            0 => Vec3::new(q[2], q[0], q[1]),
                            1 => Vec3::new(q[0], q[2], q[1]),
                            _ => Vec3::new(q[0], q[1], q[2]),
                        }
                    };
                    tris.push([p(0, 0), p(1, 0), p(1, 1)]);
                    tris.push([p(0, 0), p(1, 1), p(0, 1)]);
                }
            }
        }
    }
    tris
}

/// Rays that start on lattice points or half-points and travel along lattice lines, face
/// diagonals or space diagonals, with ±0 components: they run along shared edges, through shared
/// vertices and inside the planes of node boxes.
fn lattice_ray() -> impl Strategy<Value = Ray> {
    let o = (-1i32..9, -1i32..9, -1i32..9, 0u8..4).prop_map(|(x, y, z, half)| {
        let h = |bit: u8| if half & bit != 0 { 0.5 } else { 0.0 };
        Vec3::new(x as f32 + h(1), y as f32 + h(2), z as f32 + h(1) * h(2) * 2.0)
    });
    let d = (prop::sample::select(vec![-1.0f32, -0.0, 0.0, 1.0, 0.5, -2.0]), prop::sample::select(vec![-1.0f32, -0.0, 0.0, 1.0, 3.0]), prop::sample::select(vec![-1.0f32, -0.0, 0.0, 1.0, -0.25]))
        .prop_filter("non-zero", |(x, y, z)| *x != 0.0 || *y != 0.0 || *z != 0.0)
        .prop_map(|(x, y, z)| Vec3::new(x, y, z));
    (o, d).prop_map(|(o, d)| Ray::new(o, d))
}

/// Checks packets of rays against brute force, ray by ray: closest hits, and occlusion (bit
/// `i` of a packet's mask for its ray `i`).
fn check_packets(tris: &Vec<[Vec3; 3]>, bvh8s: &[Bvh8], rays: &[Ray]) -> Result<(), TestCaseError> {
    let expected: Vec<Option<Hit>> = rays.iter().map(|r| brute::intersect(tris, r)).collect();
    for bvh in bvh8s {
        let mut hits = vec![None; rays.len()];
        bvh.intersect_packets(rays, &mut hits);
        prop_assert_eq!(&hits, &expected, "Bvh8/{} packets", bvh.isa().name());
        for packet in rays.chunks(8) {
            let prepared: Vec<PreparedRay> = packet.iter().map(PreparedRay::new).collect();
            let blocked = bvh.occluded_packet_prepared(&prepared);
            let expected = packet.iter().enumerate().filter(|(_, r)| brute::occluded(tris, r)).fold(0u32, |m, (i, _)| m | 1 << i);
            prop_assert_eq!(blocked, expected, "Bvh8/{} occluded packets", bvh.isa().name());
        }
    }
    Ok(())
}

/// Rays from one origin in a cone around a random direction: real packets, with now and then
/// a ray that breaks the packet (another octant, a zero component), and empty segments (the
/// rays of a two-level packet that miss an instance), which a packet leaves out.
fn coherent_rays() -> impl Strategy<Value = Vec<Ray>> {
    let offset = (uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0), prop::bool::weighted(0.2))
        .prop_map(|(x, y, z, empty)| (Vec3::new(x, y, z), empty));
    (point(), direction(), prop_oneof![Just(0.0f32), uniform(0.0, 0.05), uniform(0.0, 0.6)], prop::collection::vec(offset, 1..=20), prop_oneof![3 => Just(f32::INFINITY), 1 => uniform(1.0, 20.0)])
        .prop_map(|(o, d, spread, offsets, tfar)| {
            offsets.iter().map(|&(e, empty)| Ray::segment(o, d + e * spread, 0.0, if empty { 0.0 } else { tfar })).collect()
        })
}

/// Parallel rays from origins scattered around a point, towards a random direction (shadow
/// rays towards a distant light from neighbouring hits): packets of a common direction, with
/// now and then a ray that breaks the packet (another direction) or an empty segment.
fn parallel_rays() -> impl Strategy<Value = Vec<Ray>> {
    let origin = (uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0), prop::bool::weighted(0.1), prop::bool::weighted(0.2))
        .prop_map(|(x, y, z, other, empty)| (Vec3::new(x, y, z), other, empty));
    (point(), direction(), direction(), prop_oneof![Just(0.0f32), uniform(0.0, 0.05), uniform(0.0, 2.0), uniform(0.0, 8.0)], prop::collection::vec(origin, 1..=20), prop_oneof![3 => Just(f32::INFINITY), 1 => uniform(1.0, 20.0)])
        .prop_map(|(o, d, other_d, spread, origins, tfar)| {
            origins.iter().map(|&(e, other, empty)| Ray::segment(o + e * spread, if other { other_d } else { d }, 0.0, if empty { 0.0 } else { tfar })).collect()
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn packets_equal_single_rays(tris in soup(), rays in coherent_rays(), leaf in 1usize..=8) {
        let (_, bvh8s) = layouts(&tris, leaf);
        check_packets(&tris, &bvh8s, &rays)?;
    }

    #[test]
    fn parallel_packets_equal_single_rays(tris in soup(), rays in parallel_rays(), leaf in 1usize..=8) {
        let (_, bvh8s) = layouts(&tris, leaf);
        check_packets(&tris, &bvh8s, &rays)?;
    }

    #[test]
    fn refitted_trees_equal_brute_force_on_the_moved_triangles(
        tris in soup(),
        moves in prop::collection::vec(point(), 1..64),
        rays in prop::collection::vec(ray(), 32),
        fast in any::<bool>(),
    ) {
        let quality = if fast { BuildQuality::Fast } else { BuildQuality::Sah };
        let opts = BuildOptions { quality, refittable: true, ..BuildOptions::default() };
        let built = Bvh8::build(&tris, &opts);
        // Move every triangle by a displacement from the list, some a lot, some not at all.
        let moved: Vec<[Vec3; 3]> = tris.iter().enumerate().map(|(i, t)| {
            let d = moves[i % moves.len()] * if i % 3 == 0 { 0.0 } else { 0.3 };
            t.map(|v| v + d)
        }).collect();
        for isa in Isa::all() {
            let Some(mut bvh) = built.clone().with_isa(isa) else { continue };
            let degradation = bvh.refit(&moved);
            prop_assert!(degradation.is_finite());
            for r in &rays {
                prop_assert_eq!(bvh.intersect(r), brute::intersect(&moved, r), "refitted {} closest, ray {:?}", isa.name(), r);
                prop_assert_eq!(bvh.occluded(r), brute::occluded(&moved, r));
            }
        }
    }

    #[test]
    fn box_trees_reach_every_box_a_ray_needs(tris in soup(), rays in prop::collection::vec(ray(), 32)) {
        // One box per triangle; the walk intersects the triangle itself at each leaf.
        let boxes: Vec<Aabb> = tris.iter().map(|t| Aabb::from_points(t)).collect();
        for isa in Isa::all() {
            let Some(tree) = BoxTree::build(&boxes).with_isa(isa) else { continue };
            prop_assert_eq!(tree.len(), tris.len());
            for r in &rays {
                let mut best: Option<Hit> = None;
                tree.closest(&PreparedRay::new(r), |item, tfar| {
                    let one = [tris[item as usize]];
                    let seg = Ray::segment(r.origin, r.dir, r.tnear, tfar);
                    match brute::intersect(&one[..], &seg) {
                        Some(h) if best.is_none_or(|b| h.t < b.t || (h.t == b.t && item < b.prim)) => {
                            best = Some(Hit { prim: item, ..h });
                            h.t
                        }
                        _ => tfar,
                    }
                });
                prop_assert_eq!(best, brute::intersect(&tris, r), "{} box tree closest, ray {:?}", isa.name(), r);
                let any = tree.any(&PreparedRay::new(r), |item| brute::occluded(&[tris[item as usize]][..], r));
                prop_assert_eq!(any, brute::occluded(&tris, r));
            }
        }
    }

    #[test]
    fn box_tree_packets_name_exactly_the_boxes_each_ray_touches(tris in soup(), coherent in coherent_rays(), parallel in parallel_rays()) {
        // One box per triangle (a tree of one box now and then).
        let boxes: Vec<Aabb> = tris.iter().map(|t| Aabb::from_points(t)).collect();
        for isa in Isa::all() {
            let Some(tree) = BoxTree::build(&boxes).with_isa(isa) else { continue };
            for rays in coherent.chunks(PACKET_SIZE).chain(parallel.chunks(PACKET_SIZE)) {
                let prepared: Vec<PreparedRay> = rays.iter().map(PreparedRay::new).collect();
                // Every (box, ray) pair named, with its entry.
                let mut named: Vec<(u32, usize, u32)> = Vec::new();
                let mut boxes_named: Vec<u32> = Vec::new();
                let once = tree.touched(&prepared, |item, entries| {
                    boxes_named.push(item);
                    for i in 0..PACKET_SIZE {
                        if entries.rays & (1 << i) != 0 {
                            named.push((item, i, entries.entry[i].to_bits()));
                        } else {
                            assert_eq!(entries.entry[i], f32::INFINITY, "lanes of other rays");
                        }
                    }
                });
                named.sort_unstable();
                let entry = |item: u32, i: usize| boxes[item as usize].intersect(&prepared[i], rays[i].tfar);
                let expected: Vec<(u32, usize, u32)> =
                    (0..boxes.len() as u32).flat_map(|item| (0..rays.len()).filter_map(move |i| Some((item, i, entry(item, i)?.to_bits())))).collect();
                prop_assert_eq!(&named, &expected, "{} touched, rays {:?}", isa.name(), rays);
                if once {
                    let count = boxes_named.len();
                    boxes_named.sort_unstable();
                    boxes_named.dedup();
                    prop_assert_eq!(boxes_named.len(), count, "each box named once");
                }
                // Each triangle blocks the rays it occludes, and is offered only rays that touch
                // its box.
                let blocked = tree.occluded_by(&prepared, |item, offered| {
                    let mut blocks = 0;
                    for (i, r) in rays.iter().enumerate().filter(|&(i, _)| offered & (1 << i) != 0) {
                        assert!(entry(item, i).is_some(), "offered a ray that misses the box");
                        if brute::occluded(&[tris[item as usize]][..], r) {
                            blocks |= 1 << i;
                        }
                    }
                    blocks
                });
                let expected = rays.iter().enumerate().filter(|(_, r)| brute::occluded(&tris, r)).fold(0, |m, (i, _)| m | 1 << i);
                prop_assert_eq!(blocked, expected, "{} occluded_by, rays {:?}", isa.name(), rays);
            }
        }
    }

    #[test]
    fn lattice_packets(keep in prop::collection::vec(any::<bool>(), 1..16), rays in prop::collection::vec(lattice_ray(), 1..24)) {
        let tris = lattice(4, &keep);
        prop_assume!(!tris.is_empty());
        let (_, bvh8s) = layouts(&tris, 3);
        // Same origin for all: a packet whenever the directions agree in sign and have no zeros.
        let o = rays[0].origin;
        let rays: Vec<Ray> = rays.iter().map(|r| Ray::new(o, r.dir)).collect();
        check_packets(&tris, &bvh8s, &rays)?;
    }

    #[test]
    fn every_instruction_set_takes_the_same_walk_steps(tris in soup(), rays in prop::collection::vec(ray(), 64), leaf in 1usize..=8) {
        let bvh = Bvh8::build(&tris, &BuildOptions { max_leaf_size: leaf, ..BuildOptions::default() });
        let stats = bvh.stats();
        let (closest, any) = walk_counts(&bvh, &rays);
        for counts in [closest, any] {
            prop_assert_eq!(counts.rays, rays.len() as u64);
            prop_assert!(counts.nodes <= counts.rays * stats.nodes as u64, "{:?} in {:?}", counts, stats);
            prop_assert!(counts.leaves <= counts.triangles && counts.triangles <= 8 * counts.leaves, "{:?}", counts);
        }
        // Any-hit walks visit children in slot order, so every kernel takes the same steps;
        // closest-hit walks order children by distance, and kernels may break ties otherwise.
        for other in Isa::all().filter_map(|isa| bvh.clone().with_isa(isa)) {
            prop_assert_eq!(walk_counts(&other, &rays).1, any, "Bvh8/{} against Bvh8/{}", other.isa().name(), bvh.isa().name());
        }
    }

    #[test]
    fn random_soups(tris in soup(), rays in prop::collection::vec(ray(), 64), leaf in 1usize..=8) {
        let (bvh2, bvh8s) = layouts(&tris, leaf);
        for r in &rays {
            check_ray(&tris, &bvh2, &bvh8s, r)?;
        }
    }

    #[test]
    fn lattices_through_edges_and_vertices(
        keep in prop::collection::vec(any::<bool>(), 1..16),
        rays in prop::collection::vec(lattice_ray(), 96),
        leaf in 1usize..=8,
    ) {
        let tris = lattice(4, &keep);
        prop_assume!(!tris.is_empty());
        let (bvh2, bvh8s) = layouts(&tris, leaf);
        for r in &rays {
            check_ray(&tris, &bvh2, &bvh8s, r)?;
        }
    }

    #[test]
    fn rays_along_triangle_edges(tris in soup(), picks in prop::collection::vec((any::<prop::sample::Index>(), 0usize..3, uniform(-1.0, 2.0)), 48)) {
        let (bvh2, bvh8s) = layouts(&tris, 4);
        for (pick, edge, s) in picks {
            let t = tris[pick.index(tris.len())];
            let (a, b) = (t[edge], t[(edge + 1) % 3]);
            prop_assume!(a != b);
            // Start on the edge's line (before, on or beyond the edge) and run along it.
            let origin = a + (b - a) * s;
            check_ray(&tris, &bvh2, &bvh8s, &Ray::new(origin, b - a))?;
            check_ray(&tris, &bvh2, &bvh8s, &Ray::new(origin, a - b))?;
            // Aim exactly at the edge's end points from elsewhere.
            check_ray(&tris, &bvh2, &bvh8s, &Ray::new(Vec3::new(0.3, 11.0, -0.7), b - Vec3::new(0.3, 11.0, -0.7)))?;
        }
    }

    #[test]
    fn flat_boxes_and_parallel_rays(z in uniform(-5.0, 5.0), rays in prop::collection::vec((point(), 0usize..3, any::<bool>()), 64)) {
        // A wall of triangles in the plane z = const: every box is flat in z.
        let tris: Vec<[Vec3; 3]> = (0..8).flat_map(|i| (0..8).flat_map(move |j| {
            let p = |x: i32, y: i32| Vec3::new(x as f32 - 4.0, y as f32 - 4.0, z);
            [[p(i, j), p(i + 1, j), p(i + 1, j + 1)], [p(i, j), p(i + 1, j + 1), p(i, j + 1)]]
        })).collect();
        let (bvh2, bvh8s) = layouts(&tris, 2);
        for (o, axis, neg) in rays {
            let s = if neg { -1.0 } else { 1.0 };
            // Parallel to the wall (in its plane when o.z == z), and perpendicular through it.
            let along = [Vec3::new(s, 0.0, 0.0), Vec3::new(0.0, s, -0.0), Vec3::new(s, s, 0.0)][axis];
            check_ray(&tris, &bvh2, &bvh8s, &Ray::new(Vec3::new(o.x, o.y, z), along))?;
            check_ray(&tris, &bvh2, &bvh8s, &Ray::new(o, along))?;
            check_ray(&tris, &bvh2, &bvh8s, &Ray::new(o, Vec3::new(0.0, -0.0, s)))?;
        }
    }
}

#[test]
fn empty_and_degenerate_inputs_never_hit() {
    let empty: Vec<[Vec3; 3]> = Vec::new();
    let bvh = Bvh8::build(&empty, &BuildOptions::default());
    assert_eq!(bvh.intersect(&Ray::new(Vec3::ZERO, Vec3::X)), None);
    assert!(!bvh.occluded(&Ray::new(Vec3::ZERO, Vec3::X)));

    let p = Vec3::new(1.0, 0.0, 0.0);
    let degenerate = vec![
        [p, p, p],                                                         // a point
        [p, p + Vec3::Y, p + 2.0 * Vec3::Y],                               // collinear
        [Vec3::NAN, p, p + Vec3::Y],                                       // not finite: left out
        [p, Vec3::INFINITY, p + Vec3::Y],                                  // not finite: left out
    ];
    for bvh in layouts(&degenerate, 4).1 {
        for d in [Vec3::X, Vec3::new(1.0, 0.5, 0.0), Vec3::new(1.0, 0.0, 1e-9), Vec3::NEG_X] {
            for o in [Vec3::new(0.0, 0.5, 0.0), Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, -1.0, 0.0)] {
                let ray = Ray::new(o, d);
                assert_eq!(bvh.intersect(&ray), None, "{} hit a degenerate triangle with {:?}", bvh.isa().name(), ray);
                assert!(!bvh.occluded(&ray));
            }
        }
    }
}

#[test]
fn coincident_triangles_resolve_to_the_smaller_index() {
    let t = [Vec3::new(-1.0, -1.0, 3.0), Vec3::new(1.0, -1.0, 3.0), Vec3::new(0.0, 1.0, 3.0)];
    // Eight copies of the same triangle, plus noise around them, in a shuffled build order.
    let mut tris: Vec<[Vec3; 3]> = (0..40).map(|i| {
        let o = Vec3::new(i as f32 * 0.37 % 5.0, 2.0 + i as f32 * 0.11, 4.0 + i as f32);
        [o, o + Vec3::X, o + Vec3::Y]
    }).collect();
    for k in 0..8 {
        tris.insert(5 * k + 3, t);
    }
    let first = tris.iter().position(|x| *x == t).unwrap() as u32;
    for bvh in layouts(&tris, 3).1 {
        for x in [-0.5f32, 0.0, 0.25] {
            let ray = Ray::new(Vec3::new(x, -0.2, 0.0), Vec3::new(0.01, 0.02, 1.0));
            let hit = bvh.intersect(&ray).expect("hit");
            assert_eq!(hit.prim, first, "{}", bvh.isa().name());
            assert_eq!(Some(hit), brute::intersect(&tris, &ray));
        }
    }
}

/// Packets on a scene large enough for deep trees, long stacks and packets that break up: a
/// field of 40,000 small random triangles seen through a pinhole camera, every ray compared with
/// its single-ray result (which the property tests hold to brute force).
#[test]
fn packets_equal_single_rays_on_a_large_scene() {
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    let tris: Vec<[Vec3; 3]> = (0..40_000)
        .map(|_| {
            let c = Vec3::new(next() * 20.0 - 10.0, next() * 4.0, -next() * 30.0);
            let mut v = || c + Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * 0.6;
            [v(), v(), v()]
        })
        .collect();
    for bvh in layouts(&tris, 8).1 {
        let (w, h) = (96u32, 64u32);
        let rays: Vec<Ray> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| {
                let d = Vec3::new(x as f32 / w as f32 - 0.5, 0.3 - y as f32 / h as f32 * 0.6, -1.0);
                Ray::new(Vec3::new(0.1, 2.0, 3.0), d)
            })
            .collect();
        let mut packed = vec![None; rays.len()];
        bvh.intersect_packets(&rays, &mut packed);
        for (ray, hit) in rays.iter().zip(&packed) {
            assert_eq!(*hit, bvh.intersect(ray), "{} packet vs single for {:?}", bvh.isa().name(), ray);
        }
        assert!(packed.iter().flatten().count() > rays.len() / 2, "the camera sees the field");
        // Shadow rays from a light above the field to the points seen, as the renderer traces
        // them: from the light, ending short of each point.
        let light = Vec3::new(-3.0, 9.0, -8.0);
        let shadows: Vec<Ray> = rays
            .iter()
            .zip(&packed)
            .map(|(ray, hit)| {
                let target = hit.map_or(ray.at(10.0), |h| ray.at(h.t));
                Ray::segment(light, target - light, 1e-4, 1.0 - 1e-4)
            })
            .collect();
        let mut blocked = 0;
        for packet in shadows.chunks(8) {
            let prepared: Vec<PreparedRay> = packet.iter().map(PreparedRay::new).collect();
            let mask = bvh.occluded_packet_prepared(&prepared);
            for (i, ray) in packet.iter().enumerate() {
                assert_eq!(mask & (1 << i) != 0, bvh.occluded(ray), "{} shadow packet vs single for {:?}", bvh.isa().name(), ray);
            }
            blocked += mask.count_ones();
        }
        assert!(blocked > 0 && (blocked as usize) < shadows.len(), "some points are lit, some in shadow: {blocked}");
    }
}

#[test]
fn walk_counts_count_the_steps_of_a_known_walk() {
    // Two triangles far apart: the root holds two leaves.
    let tris = vec![
        [Vec3::new(-1.0, -1.0, 5.0), Vec3::new(1.0, -1.0, 5.0), Vec3::new(0.0, 1.0, 5.0)],
        [Vec3::new(-1.0, -1.0, 50.0), Vec3::new(1.0, -1.0, 50.0), Vec3::new(0.0, 1.0, 50.0)],
    ];
    for bvh in Isa::all().filter_map(|isa| Bvh8::build(&tris, &BuildOptions { max_leaf_size: 1, ..BuildOptions::default() }).with_isa(isa)) {
        assert_eq!(bvh.stats().nodes, 1, "one root over two leaves");
        let mut counts = WalkCounts::default();
        // Down the axis: both leaves' boxes are entered, the nearer one first, and its hit
        // culls the farther one.
        assert_eq!(bvh.intersect_counted(&Ray::new(Vec3::ZERO, Vec3::Z), &mut counts).map(|h| h.prim), Some(0));
        assert_eq!(counts, WalkCounts { rays: 1, nodes: 1, leaves: 1, triangles: 1 }, "{}", bvh.isa().name());
        // Beside them: the root's children are tested, no leaf.
        let mut missed = WalkCounts::default();
        assert!(bvh.intersect_counted(&Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::Z), &mut missed).is_none());
        assert_eq!(missed, WalkCounts { rays: 1, nodes: 1, leaves: 0, triangles: 0 }, "{}", bvh.isa().name());
    }
}
