//! The retained scene as a user drives it: lazy builds, redefinition, frame semantics,
//! instancing against baked geometry, refits against rebuilds, and bad input.

use glam::{Affine3A, Quat, Vec3};
use proptest::prelude::*;
use raystage_kernel::Ray;
use raystage_scene::{Camera, Frame, Mesh, ObjectId, ObjectKind, ParamValue, Scene, SceneError};

/// A square of side 2 centred at `centre` in the plane z = centre.z, facing +z.
fn square(centre: Vec3) -> Mesh {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    Mesh::new(corners.iter().map(|&(x, y)| centre + Vec3::new(x, y, 0.0)).collect(), vec![[0, 1, 2], [0, 2, 3]])
}

/// Traces a `n × n` grid of camera rays through the frame; returns the hits.
fn look(frame: &Frame<'_>, n: u32) -> Vec<Option<raystage_scene::SceneHit>> {
    (0..n * n).map(|i| frame.pick(i % n, i / n, n, n)).collect()
}

/// Traces the same grid as [`look`], eight neighbouring rays at a time as a renderer does.
fn look_in_packets(frame: &Frame<'_>, n: u32) -> Vec<Option<raystage_scene::SceneHit>> {
    let rays: Vec<Ray> = (0..n * n).map(|i| frame.camera().ray((i % n) as f32 + 0.5, (i / n) as f32 + 0.5, n, n)).collect();
    let mut hits = vec![None; rays.len()];
    frame.intersect_many(&rays, &mut hits, 0.0);
    hits
}

#[test]
fn an_object_hidden_behind_a_wall_is_never_built() {
    for look in [look, look_in_packets] {
        hidden_behind_a_wall(look);
    }
}

fn hidden_behind_a_wall(look: fn(&Frame<'_>, u32) -> Vec<Option<raystage_scene::SceneHit>>) {
    let mut scene = Scene::new();
    let wall = scene.add_object(ObjectKind::Static, square(Vec3::ZERO).scaled(20.0)).unwrap();
    let hidden = scene.add_object(ObjectKind::Static, square(Vec3::new(0.0, 0.0, -5.0))).unwrap();
    let visible = scene.add_object(ObjectKind::Static, square(Vec3::new(0.0, 0.0, 2.0))).unwrap();
    // The hidden object comes first, so that only a near-first walk skips it.
    for object in [hidden, wall, visible] {
        scene.add_instance(object, Affine3A::IDENTITY).unwrap();
    }
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y, 60.0).unwrap()).unwrap();

    let frame = scene.frame();
    let hits = look(&frame, 32);
    assert!(hits.iter().all(|h| h.is_some()), "the wall fills the view");
    assert!(hits.iter().any(|h| h.unwrap().object == visible));
    assert!(hits.iter().all(|h| h.unwrap().object != hidden));
    let work = frame.work();
    assert_eq!((work.built, work.skipped), (2, 1), "{work:?}");
    drop(frame);
    assert!(!scene.is_built(hidden).unwrap());
    assert!(scene.is_built(visible).unwrap() && scene.is_built(wall).unwrap());

    // Nothing changed: the next frame builds nothing.
    let frame = scene.frame();
    look(&frame, 32);
    assert_eq!(frame.work().built, 0);
}

trait Scaled {
    fn scaled(self, s: f32) -> Self;
}

impl Scaled for Mesh {
    fn scaled(mut self, s: f32) -> Mesh {
        self.positions.iter_mut().for_each(|p| *p *= s);
        self
    }
}

fn straight_down_z(x: f32, y: f32) -> Ray {
    Ray::new(Vec3::new(x, y, 10.0), Vec3::NEG_Z)
}

#[test]
fn redefining_an_object_moves_every_instance() {
    let mut scene = Scene::new();
    let object = scene.add_object(ObjectKind::Unstructured, square(Vec3::ZERO)).unwrap();
    let left = scene.add_instance(object, Affine3A::from_translation(Vec3::new(-5.0, 0.0, 0.0))).unwrap();
    let right = scene.add_instance(object, Affine3A::from_translation(Vec3::new(5.0, 0.0, 0.0))).unwrap();
    let hit_at = |scene: &Scene, x: f32| scene.frame().intersect(&straight_down_z(x, 0.0), 0.0).map(|h| (h.instance, h.t));
    assert_eq!(hit_at(&scene, -5.0), Some((left, 10.0)));
    assert_eq!(hit_at(&scene, 5.0), Some((right, 10.0)));

    // Redefine the object 3 units up and 1 unit towards the viewer: both instances follow.
    scene.define_object(object, ObjectKind::Unstructured, square(Vec3::new(0.0, 3.0, 1.0))).unwrap();
    assert_eq!(hit_at(&scene, -5.0), None);
    let frame = scene.frame();
    assert_eq!(frame.intersect(&straight_down_z(-5.0, 3.0), 0.0).map(|h| (h.instance, h.t)), Some((left, 9.0)));
    assert_eq!(frame.intersect(&straight_down_z(5.0, 3.0), 0.0).map(|h| (h.instance, h.t)), Some((right, 9.0)));
    drop(frame);

    // Delete every instance, then instantiate again.
    scene.clear_instances();
    assert_eq!(scene.frame().intersect(&straight_down_z(5.0, 3.0), 0.0), None);
    let again = scene.add_instance(object, Affine3A::from_translation(Vec3::new(5.0, 0.0, 0.0))).unwrap();
    assert_eq!(hit_at(&scene, 5.0), None, "the object is still redefined");
    assert_eq!(scene.frame().intersect(&straight_down_z(5.0, 3.0), 0.0).map(|h| h.instance), Some(again));
    scene.remove_instance(again).unwrap();
    assert_eq!(scene.frame().instance_count(), 0);
}

#[test]
fn a_parameter_written_after_the_geometry_still_changes_it() {
    // The seed's case: diffuse red, triangle A, diffuse green, triangle B, frame: both green.
    let mut scene = Scene::new();
    let shader = scene.add_shader("Diffuse").unwrap();
    let red = Vec3::new(1.0, 0.0, 0.0);
    let green = Vec3::new(0.0, 1.0, 0.0);
    scene.set_param(shader, "diffuse", ParamValue::Color(red)).unwrap();
    let a = scene.add_object(ObjectKind::Static, square(Vec3::new(-2.0, 0.0, 0.0)).with_shader(shader)).unwrap();
    scene.set_param(shader, "diffuse", ParamValue::Color(green)).unwrap();
    let b = scene.add_object(ObjectKind::Static, square(Vec3::new(2.0, 0.0, 0.0)).with_shader(shader)).unwrap();
    for object in [a, b] {
        scene.add_instance(object, Affine3A::IDENTITY).unwrap();
    }
    let frame = scene.frame();
    for x in [-2.0, 2.0] {
        let ray = straight_down_z(x, 0.0);
        let hit = frame.intersect(&ray, 0.0).expect("a square");
        assert_eq!(frame.surface(&ray, &hit, 0.0).shader.color("diffuse"), green, "square at x = {x}");
    }
    drop(frame);
    // A parameter the class does not export is ignored, silently and harmlessly.
    assert_eq!(scene.set_param(shader, "specularColor", ParamValue::Color(red)), Ok(false));
    assert_eq!(scene.shader(shader).unwrap().color("diffuse"), green);
}

#[test]
fn refit_then_trace_equals_rebuild_then_trace() {
    let mut seed = 17u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32 - 0.5
    };
    let cloud: Vec<Vec3> = (0..3 * 2000).map(|_| Vec3::new(next(), next(), next()) * 4.0).collect();
    let mesh = |positions: Vec<Vec3>| {
        let n = positions.len() as u32 / 3;
        Mesh::new(positions, (0..n).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect())
    };
    let mut refitted = Scene::new();
    let object = refitted.add_object(ObjectKind::Unstructured, mesh(cloud.clone())).unwrap();
    refitted.add_instance(object, Affine3A::IDENTITY).unwrap();
    let rays: Vec<Ray> = (0..400)
        .map(|_| Ray::new(Vec3::new(next(), next(), 10.0), Vec3::new(next() * 0.3, next() * 0.3, -1.0)))
        .chain((0..10).map(|i| straight_down_z(i as f32 * 0.1, 0.2)))
        .collect();
    look_all(&refitted.frame(), &rays);

    // Two small drifts, then a scramble: every triangle jumps to where another one was; then two
    // small drifts of the scrambled cloud. After a refit that had to be rebuilt, the next
    // redefinition is rebuilt without trying a refit first; the one after that refits again.
    let drift = |from: &[Vec3], scale: f32| -> Vec<Vec3> { from.iter().enumerate().map(|(i, p)| *p + Vec3::splat((i % 7) as f32 * scale)).collect() };
    let scrambled: Vec<Vec3> = (0..cloud.len()).map(|i| cloud[(i / 3 * 3 * 7919 + i % 3) % cloud.len()]).collect();
    let frames = [
        (1, drift(&cloud, 0.001), false),
        (2, drift(&cloud, 0.002), false),
        (3, scrambled.clone(), true),
        (4, drift(&scrambled, 0.001), true),
        (5, drift(&scrambled, 0.002), false),
    ];
    for (frame_no, moved, large) in frames {
        // The second drift moves the vertices only, as an animation loop does.
        if frame_no == 2 {
            refitted.set_positions(object, moved.clone()).unwrap();
        } else {
            refitted.define_object(object, ObjectKind::Unstructured, mesh(moved.clone())).unwrap();
        }
        let mut rebuilt = Scene::new();
        let fresh = rebuilt.add_object(ObjectKind::Static, mesh(moved)).unwrap();
        rebuilt.add_instance(fresh, Affine3A::IDENTITY).unwrap();

        let frame = refitted.frame();
        let ours = look_all(&frame, &rays);
        let theirs = look_all(&rebuilt.frame(), &rays);
        assert_eq!(ours, theirs, "frame {frame_no}");
        let work = frame.work();
        assert_eq!(work.refitted + work.rebuilt, 1, "frame {frame_no}: {work:?}");
        if large {
            assert_eq!(work.rebuilt, 1, "frame {frame_no}: a scramble, or the move after one, is rebuilt: {work:?}");
        } else {
            assert_eq!(work.refitted, 1, "frame {frame_no}: a small move is refitted: {work:?}");
        }
    }
}

/// Hit distance and triangle of every ray.
fn look_all(frame: &Frame<'_>, rays: &[Ray]) -> Vec<Option<(f32, u32)>> {
    rays.iter().map(|r| frame.intersect(r, 0.0).map(|h| (h.t, h.prim))).collect()
}

#[test]
fn bad_input_names_the_problem_and_changes_nothing() {
    let mut scene = Scene::new();
    let object = scene.add_object(ObjectKind::Static, square(Vec3::ZERO)).unwrap();
    let instance = scene.add_instance(object, Affine3A::IDENTITY).unwrap();
    let shader = scene.add_shader("Diffuse").unwrap();
    let before = format!("{scene:?}");

    let bad_mesh = Mesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 3]]);
    assert_eq!(
        scene.add_object(ObjectKind::Static, bad_mesh).unwrap_err().to_string(),
        "triangle 0 uses vertex 3, but the mesh has 3 vertices"
    );
    assert_eq!(scene.add_object(ObjectKind::Static, Mesh::default()), Err(SceneError::EmptyMesh));
    let nan = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0)], vec![[0, 1, 2]]);
    assert_eq!(scene.define_object(object, ObjectKind::Static, nan), Err(SceneError::NotFinite { field: "positions", index: 2 }));
    let mut short = square(Vec3::ZERO);
    short.normals = vec![Vec3::Z; 3];
    assert_eq!(
        scene.define_object(object, ObjectKind::Static, short).unwrap_err().to_string(),
        "normals has 3 entries, expected 4"
    );
    let unknown_shader = square(Vec3::ZERO).with_shader(raystage_scene::ShaderId(99));
    assert_eq!(scene.add_object(ObjectKind::Static, unknown_shader).unwrap_err().to_string(), "unknown shader 99");
    assert_eq!(scene.add_instance(ObjectId(42), Affine3A::IDENTITY).unwrap_err().to_string(), "unknown object 42");
    assert!(matches!(
        scene.set_transform(instance, Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0))),
        Err(SceneError::SingularTransform { field: "transform", .. })
    ));
    assert!(matches!(
        scene.set_motion(instance, Affine3A::IDENTITY, Some(Affine3A::from_translation(Vec3::new(f32::INFINITY, 0.0, 0.0)))),
        Err(SceneError::NotFinite { field: "end_transform", .. })
    ));
    assert_eq!(
        scene.set_param(shader, "diffuse", ParamValue::Float(0.5)).unwrap_err().to_string(),
        "parameter `diffuse` of shader class `Diffuse` takes a colour (three numbers)"
    );
    assert_eq!(scene.add_shader("Velvet").unwrap_err().to_string(), "unknown shader class `Velvet`");
    assert_eq!(scene.set_param(shader, "velvetness", ParamValue::Float(0.5)), Ok(false), "an unknown parameter name is ignored");
    assert!(scene.set_camera(Camera::look_at(Vec3::ONE, Vec3::ONE, Vec3::Y, 45.0).unwrap_or_default()).is_ok());
    assert_eq!(
        Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Z, 45.0).unwrap_err().to_string(),
        "camera.up is out of range: is parallel to the view direction"
    );
    assert!(Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 180.0).is_err());
    assert_eq!(scene.remove_instance(raystage_scene::InstanceId(7)).unwrap_err().to_string(), "unknown instance 7");
    assert_eq!(format!("{scene:?}"), before, "no failed edit changed the scene");
}

/// A random rigid-plus-scale transform, sometimes mirrored, sometimes tiny or huge, translated
/// by up to 50 of its own units (so that baking it into the vertices keeps their precision;
/// far-away tiny objects are the numerical hard cases' business).
fn transform() -> impl Strategy<Value = Affine3A> {
    let axis = (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_filter("axis", |(x, y, z)| x * x + y * y + z * z > 0.01);
    (axis, 0.0f32..std::f32::consts::TAU, prop::sample::select(vec![1e-2f32, 0.5, 1.0, 3.0, 100.0]), any::<bool>(), (-50.0f32..50.0, -50.0f32..50.0, -50.0f32..50.0))
        .prop_map(|((x, y, z), angle, scale, mirror, (tx, ty, tz))| {
            let scale = Vec3::new(if mirror { -scale } else { scale }, scale, scale);
            let translation = Vec3::new(tx, ty, tz) * scale.y;
            Affine3A::from_scale_rotation_translation(scale, Quat::from_axis_angle(Vec3::new(x, y, z).normalize(), angle), translation)
        })
}

/// [`transform`], or now and then the identity, which a lone instance's tree is walked in place
/// with (no transform at all: the packet goes straight into the object's tree).
fn transform_or_identity() -> impl Strategy<Value = Affine3A> {
    prop_oneof![1 => Just(Affine3A::IDENTITY), 3 => transform()]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Rays aimed at triangle centres hit the same triangle at the same distance whether the
    /// object is instanced with a transform or baked into world space, and the world normal
    /// points the same way.
    #[test]
    fn instanced_rays_hit_what_baked_geometry_hits(
        to_world in transform(),
        positions in prop::collection::vec((-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0), 30..90),
        eye in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
    ) {
        let positions: Vec<Vec3> = positions.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect();
        let n = positions.len() as u32 / 3;
        let local = Mesh::new(positions.clone(), (0..n).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect());
        let baked = Mesh::new(positions.iter().map(|&p| to_world.transform_point3(p)).collect(), local.indices.clone());

        let mut instanced = Scene::new();
        let o = instanced.add_object(ObjectKind::Animated, local.clone()).unwrap();
        instanced.add_instance(o, to_world).unwrap();
        let mut flat = Scene::new();
        let b = flat.add_object(ObjectKind::Static, baked.clone()).unwrap();
        flat.add_instance(b, Affine3A::IDENTITY).unwrap();
        let (fi, fb) = (instanced.frame(), flat.frame());

        let eye = to_world.transform_point3(Vec3::new(eye.0, eye.1, eye.2) * 4.0 + Vec3::splat(5.0));
        for prim in 0..n {
            let target = baked.triangle(prim).iter().sum::<Vec3>() / 3.0;
            let ray = Ray::new(eye, target - eye);
            // Rounding moves a triangle by a few ulps either way; along the ray that becomes a
            // distance error that grows as the ray grazes the triangle.
            let tri = baked.triangle(prim);
            let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
            let cos = normal.dot(ray.dir.normalize()).abs();
            if cos < 0.05 {
                continue;
            }
            let (a, c) = (fi.intersect(&ray, 0.0), fb.intersect(&ray, 0.0));
            prop_assert_eq!(a.is_some(), c.is_some());
            let (Some(a), Some(c)) = (a, c) else { continue };
            let tolerance = 2e-4 * (1.0 + a.t.abs()) / cos;
            if a.prim != c.prim {
                // Either two triangles at the same spot (the distances agree), or the ray passes
                // within rounding of an edge of the nearer one, which one version then clips.
                let near = if a.t < c.t { a } else { c };
                let edge = near.u.min(near.v).min(1.0 - near.u - near.v);
                prop_assert!(
                    (a.t - c.t).abs() <= 5.0 * tolerance || edge < 1e-3,
                    "prims {} vs {}, t {} vs {}, nearest edge at {edge}", a.prim, c.prim, a.t, c.t
                );
                continue;
            }
            prop_assert!((a.t - c.t).abs() <= tolerance, "t {} vs {} (cos {cos})", a.t, c.t);
            let (na, nc) = (fi.surface(&ray, &a, 0.0).geometric_normal, fb.surface(&ray, &c, 0.0).geometric_normal);
            prop_assert!(na.dot(nc) > 0.99, "normals {na} vs {nc}");
        }
    }
}

/// Packets through the top level return exactly the single-ray hits and occlusion: random
/// instances of two objects (some overlapping, some mirrored, some the identity, sometimes two
/// coincident so that ties between instances occur, sometimes one alone, walked in place), packets of rays sharing an origin as camera rays (and shadow
/// rays from a light) do, fanning out by different amounts around the first instance, and
/// parallel rays from their hits towards a distant light.
#[test]
fn packets_through_the_top_level_hit_and_are_blocked_as_single_rays() {
    let strategy = (
        prop::collection::vec(transform_or_identity(), 1..12),
        any::<bool>(),
        prop::collection::vec((-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0), 30..60),
        (-60.0f32..60.0, -60.0f32..60.0, -60.0f32..60.0),
        prop::collection::vec((-60.0f32..60.0, -60.0f32..60.0, -60.0f32..60.0), 8..=8),
        prop::sample::select(vec![1e-3f32, 0.05, 1.0]),
    );
    let hits = std::cell::Cell::new(0);
    let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig { cases: 48, ..ProptestConfig::default() });
    let result = runner.run(&strategy, |(transforms, duplicate, positions, eye, targets, spread)| {
        let positions: Vec<Vec3> = positions.iter().map(|&(x, y, z)| Vec3::new(x, y, z) * 10.0).collect();
        let n = positions.len() as u32 / 3;
        let mesh = Mesh::new(positions, (0..n).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect());
        let mut scene = Scene::new();
        let a = scene.add_object(ObjectKind::Static, mesh.clone()).unwrap();
        let b = scene.add_object(ObjectKind::Animated, mesh.scaled(0.5)).unwrap();
        for (k, t) in transforms.iter().enumerate() {
            scene.add_instance(if k % 2 == 0 { a } else { b }, *t).unwrap();
            if duplicate && k == 0 {
                scene.add_instance(a, *t).unwrap();
            }
        }
        let frame = scene.frame();
        let eye = Vec3::new(eye.0, eye.1, eye.2);
        let first = Vec3::from(transforms[0].translation);
        let rays: Vec<Ray> = targets
            .iter()
            .map(|&(x, y, z)| Ray::new(eye, (first + Vec3::new(x, y, z) * spread - eye).normalize_or(Vec3::Z)))
            .collect();
        let mut many = vec![None; rays.len()];
        frame.intersect_many(&rays, &mut many, 0.0);
        for (ray, packet) in rays.iter().zip(&many) {
            prop_assert_eq!(*packet, frame.intersect(ray, 0.0));
        }
        // Parallel rays from different origins, as an orthographic camera makes them: found as
        // one by one.
        let along = (first - eye).normalize_or(Vec3::Z);
        let parallel: Vec<Ray> = targets.iter().map(|&(x, y, z)| Ray::new(eye + Vec3::new(x, y, z) * spread, along)).collect();
        let mut found = vec![None; parallel.len()];
        frame.intersect_many(&parallel, &mut found, 0.0);
        for (ray, packet) in parallel.iter().zip(&found) {
            prop_assert_eq!(*packet, frame.intersect(ray, 0.0));
        }
        // Shadow-ray segments from the same origin, ending short of, at and beyond the hits:
        // blocked as a packet exactly as one by one.
        let segments: Vec<Ray> = rays
            .iter()
            .zip(&many)
            .enumerate()
            .map(|(i, (ray, hit))| Ray::segment(ray.origin, ray.dir, 1e-3, hit.map_or(200.0, |h| h.t) * [0.5, 1.0, 2.0][i % 3]))
            .collect();
        let blocked = frame.occluded_many(&segments, 0.0);
        for (i, segment) in segments.iter().enumerate() {
            prop_assert_eq!(blocked & (1 << i) != 0, frame.occluded(segment, 0.0), "segment {}", i);
        }
        // Parallel rays towards a distant light from the hits (or points along the misses),
        // some stopping short: one packet of a common direction, blocked exactly as one by one.
        let sun = (eye - first).normalize_or(Vec3::Y);
        let towards_sun: Vec<Ray> = rays
            .iter()
            .zip(&many)
            .enumerate()
            .map(|(i, (ray, hit))| Ray::segment(ray.at(hit.map_or(50.0, |h| h.t) * 0.999), sun, 0.0, if i % 4 == 3 { 5.0 } else { f32::INFINITY }))
            .collect();
        let blocked = frame.occluded_many(&towards_sun, 0.0);
        for (i, ray) in towards_sun.iter().enumerate() {
            prop_assert_eq!(blocked & (1 << i) != 0, frame.occluded(ray, 0.0), "ray {} towards the sun", i);
        }
        hits.set(hits.get() + many.iter().filter(|h| h.is_some()).count());
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    assert!(hits.get() > 48, "only {} of the rays hit anything", hits.get());
}

/// An image environment is its texture and its light, added together: a refused light (a turn
/// that is not a number, a negative radiance) leaves no texture behind.
#[test]
fn an_environment_map_is_added_with_its_texture_or_not_at_all() {
    let mut scene = Scene::new();
    let sky = || raystage_scene::Image::new(2, 1, vec![Vec3::ONE, Vec3::X]).unwrap();
    assert!(scene.add_environment_map(sky(), Vec3::ONE, f32::NAN).is_err());
    assert!(scene.add_environment_map(sky(), -Vec3::ONE, 0.0).is_err());
    assert_eq!(scene.textures().count(), 0, "no texture left behind");
    let id = scene.add_environment_map(sky(), Vec3::splat(2.0), 90.0).unwrap();
    let (texture, _) = scene.textures().next().unwrap();
    assert_eq!(scene.lights().find(|(l, _)| *l == id).map(|(_, l)| *l), Some(raystage_scene::Light::Environment { radiance: Vec3::splat(2.0), map: Some(texture), rotate_degrees: 90.0 }));
}

#[test]
fn world_triangles_gathers_exactly_the_triangles_of_the_chosen_shaders() {
    // A strip of triangles whose shaders come in runs (as a glTF mesh's primitives do), and one
    // whose shaders alternate too often to be kept as runs: either way the chosen shader's
    // triangles come back, each once, in order, and nothing else.
    let mut scene = Scene::new();
    let [a, b] = [0, 1].map(|_| scene.add_shader("Constant").unwrap());
    let strip = |n: u32| {
        let positions = (0..n + 2).map(|k| Vec3::new(k as f32, (k % 2) as f32, 0.0)).collect();
        Mesh::new(positions, (0..n).map(|k| [k, k + 1, k + 2]).collect())
    };
    let runs = [a, a, b, b, b, a, b];
    let alternating: Vec<_> = (0..200).map(|k| if k % 3 == 0 { b } else { a }).collect();
    for shaders in [runs.to_vec(), alternating] {
        let n = shaders.len() as u32;
        let object = scene.add_object(ObjectKind::Static, Mesh { shaders: shaders.clone(), ..strip(n) }).unwrap();
        let instance = scene.add_instance(object, Affine3A::from_translation(Vec3::new(0.0, 0.0, 3.0))).unwrap();
        let frame = scene.frame();
        let gathered = frame.world_triangles(|id, _| id == Some(b), |t| Some((t.shader_id, t.corners[0].x as u32, t.corners[0].z)));
        let expected: Vec<_> = (0..n).filter(|&k| shaders[k as usize] == b).map(|k| (Some(b), k, 3.0)).collect();
        assert_eq!(gathered, expected, "{shaders:?}");
        drop(frame);
        scene.remove_instance(instance).unwrap();
    }
}
