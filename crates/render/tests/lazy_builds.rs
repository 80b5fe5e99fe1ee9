//! Lazy object builds under many threads: every object a ray reaches is built exactly once, none
//! other is, the image is the one a single thread renders, and builds racing tiles for the same
//! object never deadlock (rayon-rs/rayon#1251's pattern: a builder's `join` stealing a tile that
//! needs the object it is building).

mod common;

use std::sync::mpsc;
use std::time::Duration;

use common::{pixels, place, point_light, shader};
use glam::{Affine3A, Vec3};
use raystage_demo::shading::sphere_mesh;
use raystage_render::{Film, FrameStats, Integrator, RenderSettings, render};
use raystage_scene::{Camera, ObjectKind, ParamValue, Scene};

/// Objects in view, each its own mesh: big enough (8,192 triangles) that the builder splits its
/// work into rayon tasks.
const IN_VIEW: usize = 12;

/// Objects behind the camera: no ray reaches them.
const BEHIND: usize = 5;

/// A row of spheres in view, each a separate object, a floor, and spheres behind the camera.
fn scene() -> Scene {
    let mut scene = Scene::new();
    let matte = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::new(0.7, 0.6, 0.5)))]);
    for i in 0..IN_VIEW {
        let x = i as f32 - (IN_VIEW - 1) as f32 / 2.0;
        place(&mut scene, sphere_mesh(Vec3::new(x, 0.0, 0.0), 0.45, 128, 64), matte);
    }
    place(&mut scene, raystage_demo::shading::box_mesh(Vec3::new(-20.0, -1.0, -20.0), Vec3::new(20.0, -0.5, 20.0)), matte);
    for i in 0..BEHIND {
        let object = scene.add_object(ObjectKind::Static, sphere_mesh(Vec3::ZERO, 0.5, 32, 16).with_shader(matte)).unwrap();
        scene.add_instance(object, Affine3A::from_translation(Vec3::new(i as f32, 0.0, 30.0))).unwrap();
    }
    scene.add_light(point_light()).unwrap();
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 1.5, 8.0), Vec3::ZERO, Vec3::Y, 75.0).unwrap()).unwrap();
    scene
}

/// Renders a fresh copy of the scene (nothing built) on `threads` threads, failing the test if
/// it takes more than a minute (a deadlock).
fn first_frame(threads: usize, integrator: Integrator) -> (Film, FrameStats) {
    let (done, result) = mpsc::channel();
    std::thread::spawn(move || {
        let scene = scene();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let settings = RenderSettings { width: 96, height: 64, integrator, samples_per_pixel: 2, ..RenderSettings::default() };
        let rendered = pool.install(|| render(&scene.frame(), &settings).unwrap());
        let _ = done.send(rendered);
    });
    result.recv_timeout(Duration::from_secs(60)).unwrap_or_else(|_| panic!("the first frame on {threads} threads did not finish: deadlock"))
}

#[test]
fn every_reached_object_is_built_once_and_the_image_does_not_depend_on_threads() {
    let (one, stats_one) = first_frame(1, Integrator::Whitted);
    for threads in [2, 8] {
        let (many, stats) = first_frame(threads, Integrator::Whitted);
        assert_eq!(stats.work.built as usize, IN_VIEW + 1, "{threads} threads: built {:?}", stats.work);
        assert_eq!(stats.work.skipped as usize, BEHIND, "{threads} threads");
        assert!(pixels(&many) == pixels(&one), "{threads} threads changed the image");
    }
    assert_eq!(stats_one.work.built as usize, IN_VIEW + 1);
    // Build time is wall time, part of the frame's.
    assert!(stats_one.phases.object_builds > 0.0 && stats_one.phases.object_builds <= stats_one.seconds);
}

#[test]
fn builds_racing_tiles_never_deadlock() {
    // Many threads and small tiles: every tile's first rays reach unbuilt spheres at once, and
    // the path tracer's bounces reach the others from everywhere.
    for round in 0..6 {
        let (film, stats) = first_frame(16, Integrator::Path);
        // Bounces may reach the spheres behind the camera too; each object is built at most once.
        assert_eq!((stats.work.built + stats.work.skipped) as usize, IN_VIEW + 1 + BEHIND, "round {round}: {:?}", stats.work);
        assert!(pixels(&film).iter().all(|p| p.is_finite()));
    }
}

#[test]
fn a_frame_s_tasks_are_small_shares_of_its_work() {
    let (_, stats) = first_frame(2, Integrator::Whitted);
    // 96 × 64 in 8-pixel tiles.
    assert_eq!(stats.tasks.count, 12 * 8);
    assert!(stats.tasks.largest_share() > 0.0 && stats.tasks.largest_share() < 1.0);
    assert!(stats.tasks.total_seconds <= 2.0 * stats.seconds, "tasks {} s on 2 threads in {} s", stats.tasks.total_seconds, stats.seconds);
}
