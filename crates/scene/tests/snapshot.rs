//! Snapshots: a clone of the scene renders the scene as it was when it was taken, whatever edits
//! follow, shares the trees its frames build, and edits never show half-applied in it.

use glam::{Affine3A, Vec3};
use raystage_kernel::Ray;
use raystage_scene::{Mesh, ObjectKind, ParamValue, Scene};

/// A square of side 2 centred at `centre`, facing +z.
fn square(centre: Vec3) -> Mesh {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    Mesh::new(corners.iter().map(|&(x, y)| centre + Vec3::new(x, y, 0.0)).collect(), vec![[0, 1, 2], [0, 2, 3]])
}

/// The distance along -z from z = 10 at `(x, y)` to the first surface, if any.
fn depth(scene: &Scene, x: f32, y: f32) -> Option<f32> {
    scene.frame().intersect(&Ray::new(Vec3::new(x, y, 10.0), Vec3::NEG_Z), 0.0).map(|h| h.t)
}

#[test]
fn a_snapshot_sees_the_scene_as_it_was_and_the_scene_sees_the_edits() {
    let mut scene = Scene::new();
    let shader = scene.add_shader("Diffuse").unwrap();
    let moving = scene.add_object(ObjectKind::Unstructured, square(Vec3::ZERO).with_shader(shader)).unwrap();
    let redefined = scene.add_object(ObjectKind::Static, square(Vec3::new(5.0, 0.0, 0.0))).unwrap();
    let instance = scene.add_instance(moving, Affine3A::IDENTITY).unwrap();
    scene.add_instance(redefined, Affine3A::IDENTITY).unwrap();
    assert_eq!(depth(&scene, 0.0, 0.0), Some(10.0));

    let snapshot = scene.clone();
    scene.set_transform(instance, Affine3A::from_translation(Vec3::new(0.0, 0.0, 1.0))).unwrap();
    scene.define_object(redefined, ObjectKind::Static, square(Vec3::new(5.0, 0.0, 3.0))).unwrap();
    scene.set_positions(moving, square(Vec3::new(0.0, 0.0, 2.0)).positions).unwrap();
    scene.set_param(shader, "diffuse", ParamValue::Color(Vec3::X)).unwrap();

    assert_eq!((depth(&snapshot, 0.0, 0.0), depth(&snapshot, 5.0, 0.0)), (Some(10.0), Some(10.0)));
    assert_eq!(snapshot.shader(shader).unwrap().get("diffuse"), Some(ParamValue::Color(Vec3::splat(0.8))));
    assert_eq!((depth(&scene, 0.0, 0.0), depth(&scene, 5.0, 0.0)), (Some(7.0), Some(7.0)));
    assert_eq!(scene.shader(shader).unwrap().get("diffuse"), Some(ParamValue::Color(Vec3::X)));
}

#[test]
fn trees_a_snapshot_builds_are_the_scene_s_and_a_refit_leaves_the_snapshot_s_tree_alone() {
    let mut scene = Scene::new();
    let object = scene.add_object(ObjectKind::Unstructured, square(Vec3::ZERO)).unwrap();
    scene.add_instance(object, Affine3A::IDENTITY).unwrap();
    let snapshot = scene.clone();
    assert_eq!(depth(&snapshot, 0.0, 0.0), Some(10.0));
    assert!(scene.is_built(object).unwrap(), "the snapshot's build is kept by the scene");

    // The snapshot still holds the tree: the refit works on a copy of it.
    scene.set_positions(object, square(Vec3::new(0.0, 0.0, 4.0)).positions).unwrap();
    let frame = scene.frame();
    let hit = frame.intersect(&Ray::new(Vec3::new(0.0, 0.0, 10.0), Vec3::NEG_Z), 0.0).unwrap();
    assert_eq!((hit.t, frame.work().refitted, frame.work().built), (6.0, 1, 0));
    assert_eq!(depth(&snapshot, 0.0, 0.0), Some(10.0));
}

#[test]
fn edits_while_a_snapshot_renders_never_show_half_applied() {
    // Every edit moves both squares together: a frame sees them at one depth or the scene is
    // torn.
    let mut scene = Scene::new();
    let left = scene.add_object(ObjectKind::Unstructured, square(Vec3::new(-2.0, 0.0, 0.0))).unwrap();
    let right = scene.add_object(ObjectKind::Static, square(Vec3::new(2.0, 0.0, 0.0))).unwrap();
    scene.add_instance(left, Affine3A::IDENTITY).unwrap();
    let right_instance = scene.add_instance(right, Affine3A::IDENTITY).unwrap();
    let scene = std::sync::Arc::new(std::sync::RwLock::new(scene));
    let stop = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|s| {
        s.spawn(|| {
            for step in 1..=200 {
                let z = step as f32 * 0.01;
                let mut scene = scene.write().unwrap();
                scene.set_positions(left, square(Vec3::new(-2.0, 0.0, z)).positions).unwrap();
                scene.set_transform(right_instance, Affine3A::from_translation(Vec3::new(0.0, 0.0, z))).unwrap();
            }
            stop.store(true, std::sync::atomic::Ordering::Release);
        });
        let mut frames = 0;
        while !stop.load(std::sync::atomic::Ordering::Acquire) || frames == 0 {
            let snapshot = scene.read().unwrap().clone();
            let (l, r) = (depth(&snapshot, -2.0, 0.0), depth(&snapshot, 2.0, 0.0));
            assert_eq!(l, r, "frame {frames} saw the edit half-applied");
            frames += 1;
        }
    });
    let last = scene.read().unwrap().clone();
    assert_eq!(depth(&last, -2.0, 0.0), Some(8.0));
}
