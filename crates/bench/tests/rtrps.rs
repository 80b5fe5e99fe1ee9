//! The RTRPS experiment (`raystage-bench rtrps`): its bounding spheres hold what they bound, and
//! over a few frames of the robots (rigid motion, many instances, robots in view) and of a small
//! museum (a deforming object refitted and rebuilt) its hits equal raystage's ray for ray, so a
//! sphere culled while its instance is visible fails the run.

use glam::{Affine3A, Quat, Vec3};
use raystage_bench::rtrps::{Sphere, compare};
use raystage_demo::animated::{Animation, Museum, Robots, Staged};
use raystage_scene::Mesh;

#[test]
fn a_placed_sphere_holds_the_placed_vertices() {
    let positions: Vec<Vec3> = (0..60).map(|i| Vec3::new((i as f32 * 0.37).sin() * 3.0, (i as f32 * 0.11).cos() - 2.0, i as f32 * 0.05)).collect();
    let mesh = Mesh::new(positions.clone(), (0..20).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect());
    let sphere = Sphere::around(&mesh);
    let transforms = [
        Affine3A::IDENTITY,
        Affine3A::from_scale_rotation_translation(Vec3::new(0.5, 3.0, 1.2), Quat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.7), Vec3::new(100.0, -4.0, 7.5)),
        // A shear, whose columns are not orthogonal.
        Affine3A::from_cols(Vec3::new(1.0, 0.8, 0.0).into(), Vec3::new(0.0, 1.0, 0.9).into(), Vec3::new(0.4, 0.0, 1.0).into(), Vec3::new(-3.0, 2.0, 1.0).into()),
    ];
    for t in transforms {
        let placed = sphere.placed(&t);
        for p in &positions {
            let d = t.transform_point3(*p).distance(placed.centre);
            assert!(d <= placed.radius, "{p} placed by {t:?} lies {d} from the centre, radius {}", placed.radius);
        }
    }
}

#[test]
fn rtrps_hits_equal_raystage_on_the_robots() {
    // The robots are in view: some camera rays of the last frame hit instances other than the
    // city, so culling their spheres would change hits.
    let mut staged = Staged::new(&Robots).unwrap();
    staged.advance(&Robots.instances(2), Robots.deform(2)).unwrap();
    let frame = staged.scene.frame();
    let city = staged.scene.instances().next().unwrap().0;
    let rays = raystage_bench::dynamic::primary_rays(staged.scene.camera());
    let robots = rays.iter().step_by(7).filter(|r| frame.intersect(r, 0.0).is_some_and(|h| h.instance != city)).count();
    assert!(robots > 100, "only {robots} sampled rays hit a robot");

    let (runs, tally) = compare(&Robots, 2, 2);
    assert_eq!(tally.mismatches.get(), 0, "rays whose RTRPS hit differs from raystage's");
    let instances = Robots.instances(0).len() as f64;
    assert!(tally.kept_per_tile() < instances / 4.0, "tiles keep {} of {instances} spheres", tally.kept_per_tile());
    let names: Vec<&str> = runs.iter().map(|r| r.system.as_str()).collect();
    assert_eq!(names, ["raystage", "rtrps", "raystage-packets", "rtrps-packets"]);
    // Same rays, same hits: every system counts as many.
    let hits: Vec<u64> = runs.iter().map(|r| r.frames[1].hits).collect();
    assert!(hits[0] > 0 && hits.iter().all(|&h| h == hits[0]), "{hits:?}");
}

#[test]
fn rtrps_hits_equal_raystage_on_a_deforming_museum() {
    let museum = Museum::new(512);
    let (_, tally) = compare(&museum, 1, 3);
    assert_eq!(tally.mismatches.get(), 0, "rays whose RTRPS hit differs from raystage's");
}
