//! Numerically hard cases for the kernel (docs/design/hard-cases.md): closed meshes hit
//! through their shared edges and vertices at every scale and far from the origin, degenerate
//! and sliver triangles, coincident triangles, a tiny object in a huge scene, and the corner
//! cases of the ray/box test that the property tests in `against_brute_force.rs` do not reach.
//!
//! The long variants are `#[ignore]`d: `cargo test --release -p raystage-kernel --test
//! hard_cases -- --ignored`.

mod shapes;

use glam::Vec3;
use rayon::prelude::*;
use raystage_kernel::{Aabb, BoxTree, BuildOptions, BuildQuality, Bvh8, Hit, Isa, PACKET_SIZE, PreparedRay, Ray, brute};
use shapes::{Rng, Shape, cube, icosphere, torus};

/// Every tree the kernel can make over `tris`: both builders, every instruction set (SAH trees
/// first).
fn trees(tris: &Vec<[Vec3; 3]>) -> Vec<Bvh8> {
    [BuildQuality::Sah, BuildQuality::Fast]
        .into_iter()
        .flat_map(|quality| {
            let bvh = Bvh8::build(tris, &BuildOptions { quality, ..BuildOptions::default() });
            Isa::all().filter_map(move |isa| bvh.clone().with_isa(isa))
        })
        .collect()
}

/// A two-level version of the same triangles: consecutive runs of `chunk` triangles, each with
/// its own tree, under a [`BoxTree`] walked with [`Bvh8::intersect_prepared`] (what the scene
/// does with instances placed by the identity). Returns hits with indices into `tris`.
struct TwoLevel {
    chunks: Vec<(u32, Bvh8)>,
    top: BoxTree,
}

impl TwoLevel {
    fn new(tris: &[[Vec3; 3]], chunk: usize, isa: Isa) -> Option<TwoLevel> {
        let chunks: Vec<(u32, Bvh8)> = tris
            .chunks(chunk)
            .enumerate()
            .map(|(k, c)| ((k * chunk) as u32, Bvh8::build(c, &BuildOptions::default()).with_isa(isa).expect("supported")))
            .collect();
        let boxes: Vec<Aabb> = chunks.iter().map(|(_, b)| b.bounds()).collect();
        Some(TwoLevel { chunks, top: BoxTree::build(&boxes).with_isa(isa)? })
    }

    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let pre = PreparedRay::new(ray);
        let mut best: Option<Hit> = None;
        self.top.closest(&pre, |item, tfar| {
            let (first, bvh) = &self.chunks[item as usize];
            if let Some(h) = bvh.intersect_prepared(&pre.with_tfar(tfar)) {
                let h = Hit { prim: first + h.prim, ..h };
                if best.is_none_or(|b| h.t < b.t || (h.t == b.t && h.prim < b.prim)) {
                    best = Some(h);
                }
            }
            best.map_or(tfar, |b| b.t)
        });
        best
    }

    fn occluded(&self, ray: &Ray) -> bool {
        let pre = PreparedRay::new(ray);
        self.top.any(&pre, |item| self.chunks[item as usize].1.occluded_prepared(&pre))
    }
}

/// A point on the surface to aim at, the direction it faces, and the half-angle of the cone
/// around that direction from which a ray aimed at it enters the solid there.
#[derive(Clone, Copy, Debug)]
struct Target {
    point: Vec3,
    normal: Vec3,
}

/// Half-angle of the cone of ray directions around a target's normal. A cube's corner admits
/// rays into the solid from within 35° of its diagonal; 25° keeps every ray clearly inside.
const CONE: f32 = 25.0 * std::f32::consts::PI / 180.0;

/// Every vertex, and points on every edge (its midpoint and a random point), sorted by the
/// direction they face so that neighbours in the list face alike. Edge points keep a tenth of
/// the edge from its ends: far from the origin a point closer to a vertex rounds onto it, where
/// the edge's normal no longer says which rays enter (at a vertex on the cube's rim, a ray
/// within the cone of one face's normal may only touch the rim and leave).
fn targets(shape: &Shape, rng: &mut Rng) -> Vec<Target> {
    let mut list: Vec<Target> = shape.vertices.iter().zip(shape.vertex_normals()).map(|(&point, normal)| Target { point, normal }).collect();
    for (a, b, normal) in shape.edges() {
        let (a, b) = (shape.vertices[a as usize], shape.vertices[b as usize]);
        for s in [0.5, rng.range(0.1, 0.9)] {
            list.push(Target { point: a + (b - a) * s, normal });
        }
    }
    let key = |t: &Target| (t.normal * 6.0).round().to_array().map(|c| c as i32);
    list.sort_by_key(key);
    list
}

/// One configuration of the watertightness test: a shape placed at some scale and offset.
struct Placement {
    name: &'static str,
    shape: Shape,
    /// Size of the shape's smallest feature a leaking ray would have to cross to hit the
    /// surface again (the cube's width, the torus's tube): a hit further than this beyond the
    /// aimed-at point is a ray that went through the surface.
    feature: f32,
    convex: bool,
}

/// The shapes at scales 1e-4, 1 and 1e4, each at the origin, a few of its sizes away, and as
/// far out as its vertices keep at least 2⁻⁷ of its size in precision (up to 1e5).
fn placements() -> Vec<Placement> {
    let bases: [(&str, Shape, f32, bool); 3] =
        [("icosphere", icosphere(3), 1.0, true), ("cube", cube(4), 1.0, true), ("torus", torus(1.0, 0.35, 48, 24), 0.35, false)];
    let mut out = Vec::new();
    for (name, shape, feature, convex) in bases {
        shape.assert_closed();
        for scale in [1e-4f32, 1.0, 1e4] {
            let far = (scale * 131_072.0).min(1e5);
            for offset in [Vec3::ZERO, Vec3::new(2.5, -1.5, 0.5) * scale, Vec3::new(0.6, -0.64, 0.48) * far] {
                out.push(Placement { name, shape: shape.mapped(|v| v * scale + offset), feature: feature * scale, convex });
            }
        }
    }
    out
}

/// What went wrong for one ray, if anything.
fn check_aimed(p: &Placement, ray: &Ray, hit: Option<Hit>) -> Result<(), String> {
    let Some(hit) = hit else { return Err(format!("{}: ray {ray:?} aimed at the surface hit nothing", p.name)) };
    let len = ray.dir.length();
    // How far beyond the aimed-at point (t = 1) a hit may be found: rounding of the ray only,
    // never a whole feature.
    let beyond = (hit.t - 1.0) * len;
    if beyond > 0.2 * p.feature {
        return Err(format!("{}: ray {ray:?} went through the surface: hit {:.3e} beyond the aimed-at point", p.name, beyond));
    }
    if p.convex && -beyond > 0.2 * p.feature {
        return Err(format!("{}: ray {ray:?} hit {:.3e} before the surface of a convex shape", p.name, -beyond));
    }
    Ok(())
}

/// Runs about `rays` rays aimed at the vertices and edges of closed meshes at every placement;
/// every ray through every tree, every instruction set, as single rays, prepared rays under a
/// box tree, any-hit queries and packets of eight. Returns the number of distinct rays.
fn watertightness(rays: usize, seed: u64) -> usize {
    let placements = placements();
    let per = rays.div_ceil(placements.len()).div_ceil(PACKET_SIZE);
    let counts: Vec<usize> = placements
        .par_iter()
        .enumerate()
        .map(|(k, p)| {
            let tris = p.shape.triangles();
            let trees = trees(&tris);
            let two_level: Vec<TwoLevel> = Isa::all().filter_map(|isa| TwoLevel::new(&tris, 97, isa)).collect();
            let mut rng = Rng(seed ^ (k as u64) << 32);
            let targets = targets(&p.shape, &mut rng);
            let size = (p.shape.vertices[0] - p.shape.centre).length();
            let mut count = 0;
            for packet in 0..per {
                // One origin per packet, outside, in the cone of a target; up to seven more
                // targets seen from there inside their own cones.
                let first = rng.below(targets.len());
                let t0 = targets[first];
                let origin = t0.point + rng.in_cone(t0.normal, CONE) * size * rng.range(0.3, 3.0);
                // (target, whether it is seen from inside its cone)
                let mut aimed = vec![(t0.point, true)];
                for t in targets.iter().skip(first + 1).take(256) {
                    if aimed.len() == PACKET_SIZE {
                        break;
                    }
                    if (origin - t.point).normalize().dot(t.normal) >= CONE.cos() && rng.f32() < 0.5 {
                        aimed.push((t.point, true));
                    }
                }
                while aimed.len() < PACKET_SIZE {
                    aimed.push((targets[(first + aimed.len() * 7) % targets.len()].point, false));
                }
                let rays: Vec<Ray> = aimed.iter().map(|&(t, _)| Ray::new(origin, t - origin)).collect();
                count += rays.len();
                for (ray, &(_, aimed_well)) in rays.iter().zip(&aimed) {
                    let expected = trees[0].intersect(ray);
                    // Filler rays aimed at targets outside their cone may graze the surface:
                    // for them only check that every layout agrees.
                    if aimed_well && let Err(message) = check_aimed(p, ray, expected) {
                        panic!("{message}");
                    }
                    // The SAH trees (the first of each instruction set) see every ray, the
                    // fast builder's every fourth packet.
                    let all = if packet % 4 == 0 { trees.len() } else { trees.len() / 2 };
                    for bvh in &trees[1..all] {
                        assert_eq!(bvh.intersect(ray), expected, "{}/{}: {ray:?}", p.name, bvh.isa().name());
                    }
                    for bvh in &trees[..all] {
                        assert_eq!(bvh.occluded(ray), expected.is_some(), "{} any hit: {ray:?}", p.name);
                    }
                    if packet % 4 == 0 {
                        for two in &two_level {
                            assert_eq!(two.intersect(ray), expected, "{} two-level: {ray:?}", p.name);
                            assert_eq!(two.occluded(ray), expected.is_some(), "{} two-level any hit: {ray:?}", p.name);
                        }
                    }
                    if packet % 64 == 0 {
                        assert_eq!(brute::intersect(&tris, ray), expected, "{} brute force: {ray:?}", p.name);
                    }
                }
                let expected: Vec<Option<Hit>> = rays.iter().map(|r| trees[0].intersect(r)).collect();
                let mut hits = vec![None; rays.len()];
                let all = if packet % 4 == 0 { trees.len() } else { trees.len() / 2 };
                for bvh in &trees[..all] {
                    bvh.intersect_packets(&rays, &mut hits);
                    assert_eq!(hits, expected, "{} packet through {}", p.name, bvh.isa().name());
                }
            }
            count
        })
        .collect();
    counts.iter().sum()
}

/// Woop, Benthin and Wald, *Watertight Ray/Triangle Intersection* (JCGT 2(1), 2013): a ray
/// aimed at a vertex or an edge of a closed mesh hits the mesh there, never slips through
/// between the triangles that share it. An icosphere, a finely split cube and a torus at scales
/// 1e-4, 1 and 1e4, up to 1e5 from the origin; about a million rays here, ten million in
/// [`watertight_ten_million_rays`].
#[test]
fn watertight_a_million_rays() {
    let n = watertightness(1_000_000, 0x5EED_0001);
    assert!(n >= 1_000_000, "{n} rays");
}

/// The long variant of [`watertight_a_million_rays`]: `cargo test --release -p
/// raystage-kernel --test hard_cases -- --ignored`.
#[test]
#[ignore = "ten million rays: run with --release -- --ignored"]
fn watertight_ten_million_rays() {
    let n = watertightness(10_000_000, 0x5EED_0002);
    assert!(n >= 10_000_000, "{n} rays");
}

/// Checks one ray against every layout and the brute-force reference, and that any hit is a
/// proper one: finite, inside the segment, barycentrics in the triangle.
fn check_against_brute(tris: &Vec<[Vec3; 3]>, trees: &[Bvh8], ray: &Ray) -> Option<Hit> {
    let expected = brute::intersect(tris, ray);
    for bvh in trees {
        assert_eq!(bvh.intersect(ray), expected, "{}: {ray:?}", bvh.isa().name());
        assert_eq!(bvh.occluded(ray), expected.is_some(), "{} any hit: {ray:?}", bvh.isa().name());
    }
    if let Some(h) = expected {
        assert!(h.t.is_finite() && h.t > ray.tnear && h.t <= ray.tfar, "{h:?} for {ray:?}");
        assert!(h.u.is_finite() && h.v.is_finite() && h.u >= 0.0 && h.v >= 0.0 && h.u + h.v <= 1.0 + 1e-6, "{h:?} for {ray:?}");
    }
    expected
}

/// Degenerate triangles (Woop et al. 2013, §3: a zero determinant is a miss): points, two equal
/// vertices, and exactly collinear vertices in any direction never hit, whatever the ray;
/// slivers 1e-7 wide hit only where a ray goes through them, and never give a NaN or an infinite
/// distance.
#[test]
fn degenerate_triangles_never_hit_and_slivers_stay_finite() {
    let mut rng = Rng(0x5EED_0003);
    let mut collinear: Vec<[Vec3; 3]> = Vec::new();
    for k in 0..64 {
        // Integer points on a line through an integer point: exactly collinear in floats too.
        let a = Vec3::new(rng.below(20) as f32 - 10.0, rng.below(20) as f32 - 10.0, rng.below(20) as f32 - 10.0);
        let d = Vec3::new(rng.below(7) as f32 - 3.0, rng.below(7) as f32 - 3.0, rng.below(7) as f32 - 3.0);
        let d = if d == Vec3::ZERO { Vec3::X } else { d };
        let s = [1.0, 2f32.powi(-20), 2f32.powi(20)][k % 3];
        collinear.push([a * s, (a + d) * s, (a + 3.0 * d) * s]);
        collinear.push([(a + 3.0 * d) * s, a * s, (a + d) * s]);
        collinear.push([a * s, a * s, (a + d) * s]);
        collinear.push([a * s, a * s, a * s]);
    }
    let trees_c = trees(&collinear);
    let mut slivers: Vec<[Vec3; 3]> = Vec::new();
    for _ in 0..64 {
        let a = Vec3::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
        let b = a + rng.unit() * rng.range(0.5, 3.0);
        let across = (b - a).any_orthonormal_vector();
        let width = [1e-7, 1e-6, 1e-8][rng.below(3)];
        slivers.push([a, b, (a + b) * 0.5 + across * width]);
    }
    let trees_s = trees(&slivers);
    let mut sliver_hits = 0;
    for _ in 0..20_000 {
        // Aim at a point on a random triangle's longest side, from anywhere, or run along it.
        for (degenerate, tris, trees) in [(true, &collinear, &trees_c), (false, &slivers, &trees_s)] {
            let t = tris[rng.below(tris.len())];
            let on = t[0] + (t[1] - t[0]) * rng.range(-0.2, 1.2);
            let origin = on + rng.unit() * rng.range(0.1, 20.0);
            let rays = [Ray::new(origin, on - origin), Ray::new(on, t[1] - t[0]), Ray::new(t[0] - (t[1] - t[0]), t[1] - t[0]), Ray::new(origin, rng.unit())];
            for ray in rays {
                if ray.dir == Vec3::ZERO {
                    continue;
                }
                let hit = check_against_brute(tris, trees, &ray);
                if degenerate {
                    assert_eq!(hit, None, "a degenerate triangle was hit by {ray:?}");
                } else {
                    sliver_hits += hit.is_some() as u32;
                }
            }
        }
    }
    assert!(sliver_hits > 0, "the rays aimed at slivers never hit one");
}

/// The kernel's tie rule (`ray.rs`, `closer`): of hits at exactly the same distance the smaller
/// triangle index wins, in every layout and instruction set, so coincident geometry (a decal
/// on a wall, a mesh exported twice, two faces with opposite windings) resolves the same way
/// however the tree is built and walked.
#[test]
fn coincident_and_overlapping_triangles_resolve_deterministically() {
    let mut rng = Rng(0x5EED_0004);
    // A tilted plane through (1, 2, 3) with overlapping triangles in it, exact duplicates and
    // reversed windings of some, and unrelated clutter around.
    let (o, e1, e2) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 0.25, -0.5), Vec3::new(-0.25, 1.0, 0.75));
    let mut tris: Vec<[Vec3; 3]> = Vec::new();
    for _ in 0..60 {
        let p = |rng: &mut Rng| o + e1 * rng.range(-2.0, 2.0) + e2 * rng.range(-2.0, 2.0);
        let t = [p(&mut rng), p(&mut rng), p(&mut rng)];
        tris.push(t);
        match rng.below(3) {
            0 => tris.push(t),
            1 => tris.push([t[0], t[2], t[1]]),
            _ => {
                let c = o + Vec3::new(rng.range(-4.0, 4.0), rng.range(-4.0, 4.0), rng.range(-4.0, 4.0));
                tris.push([c, c + rng.unit() * 0.3, c + rng.unit() * 0.3]);
            }
        }
    }
    let trees = trees(&tris);
    let normal = e1.cross(e2).normalize();
    let mut ties = 0;
    for _ in 0..20_000 {
        let target = o + e1 * rng.range(-2.0, 2.0) + e2 * rng.range(-2.0, 2.0);
        let side = if rng.f32() < 0.5 { 1.0 } else { -1.0 };
        let origin = target + (normal * side + rng.unit() * 0.8) * rng.range(0.5, 10.0);
        let ray = Ray::new(origin, target - origin);
        let Some(hit) = check_against_brute(&tris, &trees, &ray) else { continue };
        // Every other triangle hit at exactly the same distance has a larger index.
        for (k, tri) in tris.iter().enumerate() {
            if let Some(h) = brute::intersect(&[*tri][..], &ray)
                && h.t == hit.t
                && k as u32 != hit.prim
            {
                assert!(k as u32 > hit.prim, "triangle {k} ties at t = {} with the winner {}", h.t, hit.prim);
                ties += 1;
            }
        }
    }
    assert!(ties > 100, "only {ties} ties: the test does not exercise the rule");
}

/// The "teapot in a stadium" (Haines, *Ray Tracing News* 1988): a 1e-3 object 60 units from the
/// origin inside a 1e5 stadium is hit exactly as when it is alone: same triangle, bit-identical
/// distance and barycentrics, however deep the tree around it.
#[test]
fn a_teapot_in_a_stadium_is_hit_as_in_isolation() {
    let centre = Vec3::new(37.1, 2.3, -51.7);
    let teapot: Vec<[Vec3; 3]> = icosphere(3).mapped(|v| v * 1e-3 + centre).triangles().into_iter().chain(torus(1.2e-3, 3e-4, 32, 12).mapped(|v| v + centre).triangles()).collect();
    let mut stadium = teapot.clone();
    // The stadium: an inward-facing box 1e5 across, a ground plane, and tiers of boxes.
    stadium.extend(cube(8).mapped(|v| v * 5e4).triangles().iter().map(|t| [t[0], t[2], t[1]]));
    stadium.extend(cube(1).mapped(|v| v * Vec3::new(5e4, 1.0, 5e4) - Vec3::Y * 2.0).triangles());
    let mut rng = Rng(0x5EED_0005);
    for _ in 0..400 {
        let c = Vec3::new(rng.range(-4e4, 4e4), rng.range(0.0, 100.0), rng.range(-4e4, 4e4));
        let size = rng.range(1.0, 500.0);
        stadium.extend(cube(1).mapped(|v| v * size + c).triangles());
    }
    let alone = trees(&teapot);
    let inside = trees(&stadium);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..20_000 {
        let eye = centre + rng.unit() * rng.range(2e-3, 1e-2);
        let aim = centre + rng.unit() * 1.5e-3;
        let ray = Ray::new(eye, aim - eye);
        let isolated = alone[0].intersect(&ray);
        for bvh in &alone[1..] {
            assert_eq!(bvh.intersect(&ray), isolated);
        }
        for bvh in &inside {
            let found = bvh.intersect(&ray);
            match isolated {
                Some(h) => assert_eq!(found, Some(h), "{}: {ray:?}", bvh.isa().name()),
                None => assert!(found.is_none_or(|f| f.prim as usize >= teapot.len()), "{ray:?} hit the teapot only in the stadium"),
            }
        }
        if isolated.is_some() { hits += 1 } else { misses += 1 }
    }
    assert!(hits > 1000 && misses > 1000, "{hits} hits, {misses} misses");
}

/// Williams, Barrus, Morley and Shirley, *An Efficient and Robust Ray-Box Intersection
/// Algorithm* (2005): ±0 direction components select the near plane by the sign of the
/// reciprocal, and a ray lying exactly in a slab plane is inside the slab. The property tests
/// cover the triangle trees; here the box tree of the top level, and segments that end exactly
/// on a triangle (`t = tfar` counts, `t = tnear` does not), on a lattice of unit squares hit
/// through shared edges and vertices by rays along lattice lines and diagonals.
#[test]
fn box_trees_and_exact_segment_ends_on_a_lattice() {
    // Unit squares on the integer planes of a 4³ lattice, every other one left out.
    let mut tris: Vec<[Vec3; 3]> = Vec::new();
    for a in 0..4i32 {
        for b in 0..4i32 {
            for c in 0..=4i32 {
                for axis in 0..3usize {
                    if (a + 2 * b + 3 * c + axis as i32) % 3 == 0 {
                        continue;
                    }
                    let p = |u: i32, v: i32| {
                        let q = [(a + u) as f32, (b + v) as f32, c as f32];
                        [Vec3::new(q[2], q[0], q[1]), Vec3::new(q[0], q[2], q[1]), Vec3::new(q[0], q[1], q[2])][axis]
                    };
                    tris.push([p(0, 0), p(1, 0), p(1, 1)]);
                    tris.push([p(0, 0), p(1, 1), p(0, 1)]);
                }
            }
        }
    }
    let trees = trees(&tris);
    let boxes: Vec<Aabb> = tris.iter().map(|t| Aabb::from_points(t)).collect();
    let box_trees: Vec<BoxTree> = Isa::all().filter_map(|isa| BoxTree::build(&boxes).with_isa(isa)).collect();
    let components = [-1.0f32, -0.0, 0.0, 1.0, 0.5, -2.0];
    let mut checked = 0;
    for x in -1i32..6 {
        for y in -1i32..6 {
            for z in -1i32..6 {
                for half in 0..4u8 {
                    let h = |bit: u8| if half & bit != 0 { 0.5 } else { 0.0 };
                    let origin = Vec3::new(x as f32 + h(1), y as f32 + h(2), z as f32);
                    for (i, &dx) in components.iter().enumerate() {
                        for (j, &dy) in components.iter().enumerate() {
                            let dz = components[(i * 7 + j * 3 + (x + y + z + 3) as usize) % components.len()];
                            let dir = Vec3::new(dx, dy, dz);
                            if dir == Vec3::ZERO {
                                continue;
                            }
                            let ray = Ray::new(origin, dir);
                            let expected = check_against_brute(&tris, &trees, &ray);
                            for tree in &box_trees {
                                let pre = PreparedRay::new(&ray);
                                let mut best: Option<Hit> = None;
                                tree.closest(&pre, |item, tfar| {
                                    let seg = Ray { tfar, ..ray };
                                    if let Some(h) = brute::intersect(&[tris[item as usize]][..], &seg)
                                        && best.is_none_or(|b| h.t < b.t || (h.t == b.t && item < b.prim))
                                    {
                                        best = Some(Hit { prim: item, ..h });
                                    }
                                    best.map_or(tfar, |b| b.t)
                                });
                                assert_eq!(best, expected, "box tree: {ray:?}");
                                let any = tree.any(&pre, |item| brute::occluded(&[tris[item as usize]][..], &ray));
                                assert_eq!(any, expected.is_some());
                            }
                            // The segment that ends exactly at the hit still has it; the one that
                            // starts there does not.
                            if let Some(h) = expected {
                                let ending = Ray::segment(origin, dir, 0.0, h.t);
                                assert_eq!(check_against_brute(&tris, &trees, &ending).map(|e| e.t), Some(h.t), "{ending:?}");
                                let starting = Ray::segment(origin, dir, h.t, f32::INFINITY);
                                let after = check_against_brute(&tris, &trees, &starting);
                                assert!(after.is_none_or(|a| a.t > h.t), "{starting:?}");
                            }
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 40_000, "{checked} rays");
}
