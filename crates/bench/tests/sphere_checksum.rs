//! The sphere scene of the benchmark probe at a low resolution: raystage's hit count and sum of
//! hit distances against brute force (always) and against Embree 3 (with the `embree` feature,
//! which the test script turns on whenever Embree is installed, as it is in CI).

use raystage_bench::kernel::{Api, Schedule, build_raystage, trace_all};
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
    let ours = trace_all(&bvh, &primary, 1, Api::Single, Schedule::Halves);
    let packets = trace_all(&bvh, &rays::in_packets(&primary, 64, 36), 1, Api::Packets, Schedule::Shared);
    assert_eq!((packets.hits, packets.tsum), (ours.hits, ours.tsum), "packets trace exactly what single rays do");
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
        use raystage_bench::kernel::Tracer;
        let device = Device::new(2).expect("Embree device");
        let (embree, _) = Scene::build(&device, &mesh, Quality::High);
        let theirs = trace_all(&embree as &dyn Tracer, &primary, 1, Api::Single, Schedule::Halves);
        // Embree's Möller-Trumbore test and raystage's watertight test may disagree on rays that
        // graze an edge; the benchmark allows 0.01 % of hits, here that is less than one ray.
        assert_eq!(ours.hits, theirs.hits, "hit count against Embree");
        let rel = (ours.tsum - theirs.tsum).abs() / theirs.tsum;
        assert!(rel < 1e-6, "sum of distances {} vs Embree {} (relative {rel:e})", ours.tsum, theirs.tsum);
    }
}
