//! The sphere scene of the benchmark probe at a low resolution: raystage's hit count and sum of
//! hit distances against brute force (always) and against Embree 3 (with the `embree` feature,
//! which the test script turns on whenever Embree is installed, as it is in CI).

use raystage_bench::kernel::{Api, Calls, Schedule, Tracer, build_raystage, primary_hits, trace_all};
use raystage_bench::rays;
use raystage_demo::StandardScene;
use raystage_kernel::brute;

#[test]
fn sphere_scene_checksums() {
    let scene = StandardScene::Spheres;
    let mesh = scene.mesh();
    assert_eq!(mesh.indices.len(), 1_000_002);
    let (bvh, _) = build_raystage(&mesh, 2);
    let primary = rays::primary(scene, 64, 36);
    let ours = trace_all(&bvh, &primary, 1, Calls::Closest(Api::Single), Schedule::Halves);
    let packets = trace_all(&bvh, &rays::in_blocks(&primary, 64, 36, (4, 2)), 1, Calls::Closest(Api::Packets), Schedule::Shared);
    assert_eq!((packets.hits, packets.tsum), (ours.hits, ours.tsum), "packets trace exactly what single rays do");
    let groups = rays::in_blocks(&primary, 64, 36, (4, 4));
    let shadows = rays::shadows(rays::light(scene), &groups, &primary_hits(&bvh, &mesh, &groups));
    same_in_groups(&bvh, &groups, &shadows);
    // The camera looks down at the grid: most rays hit a sphere or the ground.
    assert!(ours.hits > primary.len() as u64 * 3 / 4, "{} of {} rays hit", ours.hits, primary.len());

    // Brute force on every 16th ray: the same hits, bit for bit.
    let indexed = mesh.as_indexed();
    for ray in primary.iter().step_by(16) {
        assert_eq!(bvh.intersect(ray), brute::intersect(&indexed, ray), "ray {ray:?}");
    }

    #[cfg(feature = "embree")]
    {
        use raystage_bench::embree::{Device, Quality, Scene};
        let device = Device::new(2).expect("Embree device");
        let (embree, _) = Scene::build(&device, &mesh, Quality::High);
        let theirs = trace_all(&embree as &dyn Tracer, &primary, 1, Calls::Closest(Api::Single), Schedule::Halves);
        same_in_groups(&embree, &groups, &shadows);
        // Embree's Möller-Trumbore test and raystage's watertight test may disagree on rays that
        // graze an edge; the benchmark allows 0.01 % of hits, here that is less than one ray.
        assert_eq!(ours.hits, theirs.hits, "hit count against Embree");
        let rel = (ours.tsum - theirs.tsum).abs() / theirs.tsum;
        assert!(rel < 1e-6, "sum of distances {} vs Embree {} (relative {rel:e})", ours.tsum, theirs.tsum);
    }
}

/// `tracer`'s 4×4 groups of `rays` find what its single rays find, and its groups of `shadows`
/// are blocked where its single shadow rays are; some shadows are blocked and some not.
fn same_in_groups(tracer: &dyn Tracer, rays: &[raystage_kernel::Ray], shadows: &[raystage_kernel::Ray]) {
    let single = trace_all(tracer, rays, 1, Calls::Closest(Api::Single), Schedule::Halves);
    let grouped = trace_all(tracer, rays, 1, Calls::ClosestGroups, Schedule::Halves);
    assert_eq!((grouped.hits, grouped.tsum), (single.hits, single.tsum), "groups trace what single rays do");
    let blocked = trace_all(tracer, shadows, 1, Calls::Occluded, Schedule::Halves);
    let blocked_in_groups = trace_all(tracer, shadows, 1, Calls::OccludedGroups, Schedule::Halves);
    assert_eq!(blocked_in_groups.hits, blocked.hits, "grouped shadow rays are blocked where single ones are");
    assert!(0 < blocked.hits && blocked.hits < shadows.len() as u64, "{} of {} shadow rays blocked", blocked.hits, shadows.len());
}
