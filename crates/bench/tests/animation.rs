//! The animation benchmark's generated skinned tube and its run: the tube's top ring skinned
//! where its joint chain, bent by hand, puts it; a short run reports every step, refits the
//! skinned object every frame, and (with the `embree` feature) Embree hits the same primary rays
//! as raystage (`animation::run` fails where the two differ).

use glam::{Quat, Vec3};
use raystage_bench::animation::{Asset, run};
use raystage_gltf_import::Limits;
use raystage_scene::Play;

#[test]
fn the_tube_bends_as_its_joint_chain() {
    let (rings, sides) = (9, 16);
    let mut scene = raystage_gltf_import::read(&raystage_demo::animated_assets::skinned_tube(rings, sides), None, &Limits::default()).unwrap().into_scene().unwrap();
    let object = scene.rig().unwrap().deformers[0].object;
    assert_eq!(scene.mesh(object).unwrap().indices.len(), 2 * (rings - 1) * sides);
    // At 0.5 s each of the seven joints above the root is turned by its full sway, 15° about z;
    // the joints are 4 / 7 apart and the tube's top ring, 0.4 from the axis, follows the last.
    scene.pose(Play::Clip(0), 0.5).unwrap();
    let (spacing, radius, sway) = (4.0 / 7.0, 0.4, 15f32.to_radians());
    let top = (1..=7).fold(Vec3::ZERO, |p, k| p + Quat::from_rotation_z((k - 1) as f32 * sway) * Vec3::Y * spacing);
    let mesh = scene.mesh(object).unwrap();
    for side in 0..sides {
        let angle = std::f32::consts::TAU * side as f32 / sides as f32;
        let expected = top + Quat::from_rotation_z(7.0 * sway) * Vec3::new(angle.cos(), 0.0, angle.sin()) * radius;
        let got = mesh.positions[(rings - 1) * sides + side];
        assert!((got - expected).length() < 1e-4, "side {side}: {got} where the chain puts {expected}");
    }
    // Bound to the root alone, the bottom ring stays where it was.
    assert!((mesh.positions[0] - Vec3::new(radius, 0.0, 0.0)).length() < 1e-5);
}

#[test]
fn a_short_run_reports_every_step() {
    let reports = run(&Asset::RiggedSimple, 1, 2).unwrap();
    let ours = &reports[0];
    assert_eq!((ours.system.as_str(), ours.triangles, ours.frames), ("raystage", 188, 2));
    assert!(ours.evaluate_ms > 0.0 && ours.skin_ms > 0.0 && ours.update_ms > 0.0 && ours.trace_ms > 0.0, "{ours:?}");
    assert!(ours.render_ms.is_some_and(|ms| ms > 0.0) && ours.preview_fps.is_some(), "{ours:?}");
    // The skinned cylinder moves a little each frame: refitted, never rebuilt.
    assert_eq!((ours.refitted, ours.rebuilt), (2, 0));
    let systems: Vec<&str> = reports.iter().map(|r| r.system.as_str()).collect();
    let expected: &[&str] = if cfg!(feature = "embree") { &["raystage", "embree-refit", "embree-low"] } else { &["raystage"] };
    assert_eq!(systems, expected);
    assert!(reports[1..].iter().all(|r| r.raystage_update_ratio.is_some_and(f64::is_finite) && r.raystage_trace_ratio.is_some_and(f64::is_finite)), "{reports:?}");
    assert!(ours.raystage_update_ratio.is_none() && ours.raystage_trace_ratio.is_none());
}
