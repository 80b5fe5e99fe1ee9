//! Numerically hard cases for the two-level scene (docs/design/hard-cases.md): secondary
//! rays spawned from hit points at scales from 1e-4 to 1e4 and up to 1e6 from the origin, thin
//! walls, instances with tiny, huge, squashed and mirroring transforms, a tiny object in a huge
//! scene, and NaN or infinite input at every entry point of the scene API.

#[path = "../../kernel/tests/shapes/mod.rs"]
mod shapes;

use glam::{Affine3A, Quat, Vec2, Vec3};
use raystage_kernel::Ray;
use raystage_scene::{Camera, Image, Light, Mesh, ObjectKind, ParamValue, Scene, SceneError, SceneHit, Texture};
use shapes::{Rng, Shape, cube, icosphere, torus};

fn mesh(shape: &Shape) -> Mesh {
    Mesh::new(shape.vertices.clone(), shape.indices.clone())
}

/// How a shape is put into the world.
#[derive(Clone, Copy, Debug)]
enum Placement {
    /// Vertices transformed into world space, instanced by the identity.
    Baked,
    /// Instanced by the transform.
    Instanced,
}

/// A scene holding only `shape` placed by `to_world`; returns it with the world centre.
fn scene_of(shape: &Shape, to_world: Affine3A, placement: Placement) -> (Scene, Vec3) {
    let mut scene = Scene::new();
    let (mesh, transform) = match placement {
        Placement::Baked => {
            let mut baked = mesh(&shape.mapped(|v| to_world.transform_point3(v)));
            // Baking a mirror into the vertices turns their winding inside out: turn it back, as
            // an exporter does.
            if to_world.matrix3.determinant() < 0.0 {
                baked.indices.iter_mut().for_each(|t| t.swap(1, 2));
            }
            (baked, Affine3A::IDENTITY)
        }
        Placement::Instanced => (mesh(shape), to_world),
    };
    let object = scene.add_object(ObjectKind::Static, mesh).unwrap();
    scene.add_instance(object, transform).unwrap();
    (scene, to_world.transform_point3(shape.centre))
}

/// A unit vector at angle `acos(cos)` from the unit vector `n`, in a random direction around it.
fn around(rng: &mut Rng, n: Vec3, cos: f32) -> Vec3 {
    let (t, b) = n.any_orthonormal_pair();
    let phi = std::f32::consts::TAU * rng.f32();
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    (n * cos + (t * phi.cos() + b * phi.sin()) * sin).normalize()
}

/// Cosines from head-on to grazing (a thousandth of a radian above the surface).
const COSINES: [f32; 6] = [1.0, 0.7, 0.3, 0.05, 0.01, 1e-3];

/// The transforms the self-intersection test places its shapes with, at `scale`, `offset`
/// from the origin: uniform, squashed along one axis, and mirrored (negative determinant).
fn transforms(scale: f32, offset: Vec3) -> [(&'static str, Affine3A); 3] {
    let rotation = Quat::from_axis_angle(Vec3::new(0.3, 1.0, -0.2).normalize(), 0.7);
    [
        ("uniform", Affine3A::from_scale_rotation_translation(Vec3::splat(scale), rotation, offset)),
        ("squashed", Affine3A::from_scale_rotation_translation(Vec3::new(scale, 0.25 * scale, 2.0 * scale), rotation, offset)),
        ("mirrored", Affine3A::from_scale_rotation_translation(Vec3::new(-scale, scale, scale), rotation, offset)),
    ]
}

/// Wächter and Binder, *A Fast and Robust Method for Avoiding Self-Intersection* (Ray Tracing
/// Gems, ch. 6, 2019), and pbrt-v4's conservative error bounds (§6.8): a ray spawned from a hit
/// point with [`raystage_scene::SurfacePoint::spawn_ray`] never hits the triangle it leaves.
/// Convex closed shapes alone in the scene, at scales 1e-4 … 1e4 and up to 1e6 from the origin,
/// baked or instanced (uniform, squashed, mirrored): every ray that leaves outwards, from head-on
/// to a thousandth of a radian above the surface, escapes; every ray that goes inwards crosses
/// the inside and hits another face, from whose inside the rays out escape in turn. Hits from
/// outside are front faces, normals face the ray and point outwards.
#[test]
fn spawned_rays_never_hit_their_own_surface() {
    let mut rng = Rng(0x5EED_0101);
    let mut checked = 0u64;
    for (name, shape) in [("icosphere", icosphere(2)), ("cube", cube(2))] {
        for scale in [1e-4f32, 1e-2, 1.0, 1e2, 1e4] {
            // As far out as leaves the shape (and its squashed axis) hundreds of ulps thick.
            let far = (scale * 4096.0).min(1e6);
            for offset in [Vec3::ZERO, Vec3::new(0.36, -0.48, 0.8) * far, Vec3::new(-1.0, 0.0, 0.0) * far] {
                for (how, to_world) in transforms(scale, offset) {
                    for placement in [Placement::Baked, Placement::Instanced] {
                        let (scene, centre) = scene_of(&shape, to_world, placement);
                        let frame = scene.frame();
                        let case = format!("{name} {how} {placement:?} at scale {scale:e}, offset {offset}");
                        for _ in 0..250 {
                            let eye = centre + rng.unit() * scale * rng.range(3.0, 12.0);
                            let aim = centre + rng.unit() * scale * 0.2;
                            let ray = Ray::new(eye, aim - eye);
                            let Some(hit) = frame.intersect(&ray, 0.0) else { panic!("{case}: missed the shape with {ray:?}") };
                            let sp = frame.surface(&ray, &hit, 0.0);
                            let n = sp.geometric_normal;
                            assert!(sp.front_face, "{case}: hit from outside on a back face");
                            assert!(n.dot(ray.dir) < 0.0 && n.dot(sp.position - centre) > 0.0, "{case}: normal {n} neither faces the ray nor points out");
                            let ulp = f32::EPSILON * offset.abs().max_element();
                            assert!((sp.position - ray.at(hit.t)).length() <= 1e-3 * scale + 32.0 * ulp, "{case}: hit point {} vs {}", sp.position, ray.at(hit.t));
                            for cos in COSINES {
                                let out = around(&mut rng, n, cos);
                                let escape = sp.spawn_ray(out);
                                assert_eq!(frame.intersect(&escape, 0.0), None, "{case}: a ray leaving at cos {cos} hit its own surface: {escape:?}");
                                assert!(!frame.occluded(&escape, 0.0), "{case}: a shadow ray at cos {cos} is occluded by its own surface");
                                checked += 2;
                                // Within rounding of a triangle's edge the point may lie outside
                                // the neighbouring face, which a ray going in then rightly misses.
                                if hit.u.min(hit.v).min(1.0 - hit.u - hit.v) < 1e-3 {
                                    continue;
                                }
                                let into = sp.spawn_ray(around(&mut rng, -n, cos));
                                let Some(far_hit) = frame.intersect(&into, 0.0) else { panic!("{case}: a ray going in at cos {cos} leaked out: {into:?}") };
                                checked += 1;
                                if shape.face[far_hit.prim as usize] == shape.face[hit.prim as usize] {
                                    panic!("{case}: a ray going in at cos {cos} hit its own face again at t = {}", far_hit.t);
                                }
                                let inside = frame.surface(&into, &far_hit, 0.0);
                                assert!(!inside.front_face && inside.geometric_normal.dot(into.dir) < 0.0, "{case}: the far side is not a back face");
                                // From the inside: straight out escapes; reflected back in hits
                                // some other face (again not within rounding of an edge).
                                let leave = inside.spawn_ray(into.dir);
                                assert_eq!(frame.intersect(&leave, 0.0), None, "{case}: a ray leaving from inside hit the shape again: {leave:?}");
                                if far_hit.u.min(far_hit.v).min(1.0 - far_hit.u - far_hit.v) < 1e-3 {
                                    continue;
                                }
                                let m = inside.geometric_normal;
                                let back = inside.spawn_ray(around(&mut rng, m, cos.max(0.05)));
                                match frame.intersect(&back, 0.0) {
                                    Some(h) => assert_ne!(shape.face[h.prim as usize], shape.face[far_hit.prim as usize], "{case}: re-hit from inside"),
                                    None => panic!("{case}: a ray reflected inside leaked out: {back:?}"),
                                }
                                checked += 2;
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 1_000_000, "{checked} rays");
}

/// The other half of the offset's job: it must be small. A slab a thousandth of its width thick
/// (and at least 64 ulps of its coordinates), up to 1e6 from the origin: a ray entering its top
/// face hits its bottom face from inside, and light never skips through (the old fixed offset of
/// 1e-4 × |p| jumped 100 units there).
#[test]
fn thin_walls_are_never_skipped() {
    let mut rng = Rng(0x5EED_0102);
    for scale in [1e-3f32, 1.0, 1e3] {
        for distance in [0.0f32, 1e3, 1e6] {
            let offset = Vec3::new(0.6, 0.0, -0.8) * distance;
            let ulp = (offset.abs().max_element() + scale).next_up() - (offset.abs().max_element() + scale);
            let thickness = (1e-3 * scale).max(64.0 * ulp);
            if thickness > 0.05 * scale {
                continue; // not a thin wall at this precision
            }
            for placement in [Placement::Baked, Placement::Instanced] {
                let to_world = Affine3A::from_translation(offset) * Affine3A::from_scale(Vec3::new(scale, thickness / 2.0, scale));
                let (scene, centre) = scene_of(&cube(1), to_world, placement);
                let frame = scene.frame();
                let case = format!("{placement:?} slab {thickness:e} thick at scale {scale:e}, {distance:e} from the origin");
                for _ in 0..2000 {
                    let eye = centre + Vec3::new(rng.range(-0.5, 0.5) * scale, rng.range(0.05, 2.0) * scale, rng.range(-0.5, 0.5) * scale);
                    let aim = centre + Vec3::new(rng.range(-0.8, 0.8) * scale, 0.0, rng.range(-0.8, 0.8) * scale);
                    let ray = Ray::new(eye, aim - eye);
                    let hit = frame.intersect(&ray, 0.0).expect("the slab is below");
                    let top = frame.surface(&ray, &hit, 0.0);
                    for cos in COSINES {
                        let dir = around(&mut rng, -top.geometric_normal, cos);
                        let into = top.spawn_ray(dir);
                        let Some(h) = frame.intersect(&into, 0.0) else { panic!("{case}: a ray at cos {cos} skipped through the slab: {into:?}") };
                        let bottom = frame.surface(&into, &h, 0.0);
                        assert!(!bottom.front_face, "{case}: the ray into the slab met a front face: top {:?} {:?} into {into:?} hit {h:?} at {:?}", hit, top.position, bottom.position);
                        assert!(frame.occluded(&Ray::segment(into.origin, dir, 0.0, 4.0 * scale / cos.max(1e-3)), 0.0), "{case}: the shadow ray skipped the slab");
                    }
                }
            }
        }
    }
}

/// Transforms with scales of 1e-4 and 1e4, squashed by 1e2 along one axis, or mirrored: hits
/// agree with the same geometry baked into world space (to rounding), and the surface normal
/// points out of the closed shape and towards the ray, with `front_face` telling outside from
/// inside whatever the sign of the determinant.
#[test]
fn extreme_and_mirroring_instances_hit_and_face_correctly() {
    let mut rng = Rng(0x5EED_0103);
    let shape = icosphere(3);
    let rotation = Quat::from_axis_angle(Vec3::new(1.0, -0.4, 0.2).normalize(), 2.1);
    for scale in [Vec3::splat(1e-4), Vec3::splat(1e4), Vec3::new(1e2, 1.0, 1.0), Vec3::new(1.0, 1e-2, 1.0), Vec3::new(-1.0, 1.0, 1.0), Vec3::new(-1e-4, -1e-4, 1e-4), Vec3::splat(-1e4)] {
        let size = scale.abs().max_element();
        let to_world = Affine3A::from_scale_rotation_translation(scale, rotation, Vec3::new(3.0, -2.0, 1.0) * size);
        let (instanced, centre) = scene_of(&shape, to_world, Placement::Instanced);
        let (baked, _) = scene_of(&shape, to_world, Placement::Baked);
        let (fi, fb) = (instanced.frame(), baked.frame());
        for _ in 0..2000 {
            let eye = centre + rng.unit() * size * rng.range(2.0, 8.0);
            let aim = centre + to_world.transform_vector3(rng.unit() * 0.5);
            for (ray, outside) in [(Ray::new(eye, aim - eye), true), (Ray::new(aim, rng.unit()), false)] {
                let (Some(a), Some(b)) = (fi.intersect(&ray, 0.0), fb.intersect(&ray, 0.0)) else {
                    panic!("scale {scale}: {ray:?} missed a closed shape it starts in or points into")
                };
                let (sa, sb) = (fi.surface(&ray, &a, 0.0), fb.surface(&ray, &b, 0.0));
                assert!((sa.position - sb.position).length() <= 1e-4 * size, "scale {scale}: instanced {} vs baked {}", sa.position, sb.position);
                for (what, s) in [("instanced", &sa), ("baked", &sb)] {
                    assert_eq!(s.front_face, outside, "scale {scale}, {what}: front_face from {}", if outside { "outside" } else { "inside" });
                    assert!(s.geometric_normal.dot(ray.dir) < 0.0, "scale {scale}, {what}: the normal does not face the ray");
                    let outward = if outside { s.geometric_normal } else { -s.geometric_normal };
                    assert!(outward.dot(s.position - centre) > 0.0, "scale {scale}, {what}: the normal does not point out of the shape");
                    assert!((s.geometric_normal.length() - 1.0).abs() < 1e-5 && s.position_error.is_finite());
                }
            }
        }
    }
}

/// Haines's "teapot in a stadium" in the two-level scene: a 1e-3 object (instanced by a scale of
/// 1e-3, 60 units out) among 400 instanced boxes in a 1e5 stadium is hit exactly as when it is
/// alone: same triangle, bit-identical distance, barycentrics and hit point.
#[test]
fn a_teapot_in_a_stadium_is_hit_as_in_isolation() {
    let centre = Vec3::new(37.1, 2.3, -51.7);
    let teapot = {
        let a = icosphere(3);
        let b = torus(1.2, 0.3, 32, 12);
        let offset = a.vertices.len() as u32;
        let mut m = mesh(&a);
        m.positions.extend(b.vertices);
        m.indices.extend(b.indices.iter().map(|t| t.map(|i| i + offset)));
        m
    };
    let place = Affine3A::from_scale_rotation_translation(Vec3::splat(1e-3), Quat::from_rotation_y(0.3), centre);
    let mut alone = Scene::new();
    let t = alone.add_object(ObjectKind::Static, teapot.clone()).unwrap();
    alone.add_instance(t, place).unwrap();
    let mut stadium = Scene::new();
    let t = stadium.add_object(ObjectKind::Static, teapot).unwrap();
    stadium.add_instance(t, place).unwrap();
    let inward = cube(8);
    let walls = stadium.add_object(ObjectKind::Static, Mesh::new(inward.vertices.clone(), inward.indices.iter().map(|t| [t[0], t[2], t[1]]).collect())).unwrap();
    stadium.add_instance(walls, Affine3A::from_scale(Vec3::splat(5e4))).unwrap();
    let block = stadium.add_object(ObjectKind::Static, mesh(&cube(1))).unwrap();
    let mut rng = Rng(0x5EED_0104);
    for _ in 0..400 {
        let c = Vec3::new(rng.range(-4e4, 4e4), rng.range(0.0, 100.0), rng.range(-4e4, 4e4));
        stadium.add_instance(block, Affine3A::from_scale_rotation_translation(Vec3::splat(rng.range(1.0, 500.0)), Quat::from_rotation_y(rng.f32()), c)).unwrap();
    }
    let (fa, fs) = (alone.frame(), stadium.frame());
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..20_000 {
        let eye = centre + rng.unit() * rng.range(2e-3, 1e-2);
        let aim = centre + rng.unit() * 1.5e-3;
        let ray = Ray::new(eye, aim - eye);
        let key = |h: SceneHit| (h.t, h.prim, h.u, h.v);
        match (fa.intersect(&ray, 0.0), fs.intersect(&ray, 0.0)) {
            (Some(a), Some(s)) => {
                assert_eq!(key(a), key(s), "{ray:?}");
                assert_eq!(fa.surface(&ray, &a, 0.0).position, fs.surface(&ray, &s, 0.0).position);
                hits += 1;
            }
            (None, found) => {
                assert!(found.is_none_or(|s| s.t * ray.dir.length() > 0.5), "{ray:?} hit something near the teapot only in the stadium");
                misses += 1;
            }
            (Some(a), None) => panic!("{ray:?} hit the teapot alone ({a:?}) but nothing in the stadium"),
        }
    }
    assert!(hits > 1000 && misses > 1000, "{hits} hits, {misses} misses");
}

/// Every entry point of the scene API refuses NaN and infinite numbers, names the field, and
/// leaves the scene as it was: vertices and their attributes, transforms (and transforms whose
/// inverse is not finite), cameras, lights, shader parameters and textures.
#[test]
fn nan_and_infinity_are_refused_everywhere() {
    let mut scene = Scene::new();
    let good = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
    let object = scene.add_object(ObjectKind::Unstructured, good.clone()).unwrap();
    let instance = scene.add_instance(object, Affine3A::IDENTITY).unwrap();
    let shader = scene.add_shader("Phong").unwrap();
    let light = scene.add_light(Light::Point { position: Vec3::ONE, intensity: Vec3::ONE }).unwrap();
    let before = format!("{scene:?}");
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
    let not_finite = |r: Result<(), SceneError>, what: &str| match r {
        Err(SceneError::NotFinite { .. } | SceneError::SingularTransform { .. } | SceneError::OutOfRange { .. }) => {}
        other => panic!("{what}: {other:?}"),
    };
    for x in bad {
        let v = Vec3::new(0.5, x, 0.0);
        for field in ["positions", "normals", "colors", "uvs"] {
            let mut m = good.clone();
            match field {
                "positions" => m.positions[1] = v,
                "normals" => m.normals = vec![Vec3::Z, v, Vec3::Z],
                "colors" => m.colors = vec![Vec3::ONE, Vec3::ONE, v],
                _ => m.uvs = vec![Vec2::ZERO, Vec2::new(x, 0.0), Vec2::ONE],
            }
            not_finite(scene.add_object(ObjectKind::Static, m.clone()).map(|_| ()), field);
            not_finite(scene.define_object(object, ObjectKind::Unstructured, m), field);
        }
        not_finite(scene.set_positions(object, vec![Vec3::ZERO, v, Vec3::Y]), "set_positions");
        let transforms = [
            Affine3A::from_translation(v),
            Affine3A::from_scale(v),
            Affine3A::from_cols_array(&[1.0, 0.0, 0.0, 0.0, x, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
        ];
        for t in transforms {
            not_finite(scene.add_instance(object, t).map(|_| ()), "add_instance");
            not_finite(scene.set_transform(instance, t), "set_transform");
            not_finite(scene.set_motion(instance, Affine3A::IDENTITY, Some(t)), "set_motion end");
        }
        let cameras = [
            Camera { eye: v, ..Camera::default() },
            Camera { target: v, ..Camera::default() },
            Camera { up: v, ..Camera::default() },
            Camera { fov_y_degrees: x, ..Camera::default() },
            Camera { aperture_radius: x, ..Camera::default() },
            Camera { focus_distance: x, ..Camera::default() },
            Camera { shutter: [0.0, x], ..Camera::default() },
            Camera { shutter: [x, 1.0], ..Camera::default() },
        ];
        for c in cameras {
            not_finite(scene.set_camera(c), &format!("camera {c:?}"));
        }
        let lights = [
            Light::Point { position: v, intensity: Vec3::ONE },
            Light::Point { position: Vec3::ONE, intensity: v },
            Light::Spot { position: Vec3::ONE, direction: v, intensity: Vec3::ONE, cone_degrees: 30.0, falloff_degrees: 20.0 },
            Light::Spot { position: Vec3::ONE, direction: Vec3::NEG_Y, intensity: Vec3::ONE, cone_degrees: x, falloff_degrees: 20.0 },
            Light::Directional { direction: v, intensity: Vec3::ONE },
            Light::Ambient { intensity: v },
            Light::Area { corner: v, edge_u: Vec3::X, edge_v: Vec3::Z, radiance: Vec3::ONE },
            Light::Area { corner: Vec3::ZERO, edge_u: v, edge_v: Vec3::Z, radiance: Vec3::ONE },
            Light::Environment { radiance: v, map: None, rotate_degrees: 0.0 },
        ];
        for l in lights {
            not_finite(scene.add_light(l).map(|_| ()), &format!("{l:?}"));
            not_finite(scene.set_light(light, l), &format!("{l:?}"));
        }
        for (name, value) in [("diffuse", ParamValue::Color(v)), ("shininess", ParamValue::Float(x)), ("specular", ParamValue::Color(v))] {
            assert!(scene.set_param(shader, name, value).is_err(), "parameter {name} = {value:?}");
        }
        let textures = [
            Texture::Checker { a: v, b: Vec3::ONE, scale: 1.0 },
            Texture::Checker { a: Vec3::ONE, b: Vec3::ONE, scale: x },
            Texture::Noise { a: Vec3::ONE, b: v, scale: 1.0 },
        ];
        for t in textures {
            assert!(scene.add_texture(t).is_err(), "texture with {x}");
        }
        assert!(Image::new(1, 2, vec![Vec3::ONE, v]).is_err(), "image with {x}");
    }
    // Finite but absurd: a scale whose inverse overflows, and one that is exactly singular.
    for t in [Affine3A::from_scale(Vec3::splat(1e-30)), Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)), Affine3A::from_scale(Vec3::splat(1e30))] {
        not_finite(scene.add_instance(object, t).map(|_| ()), &format!("{t:?}"));
    }
    assert_eq!(format!("{scene:?}"), before, "a refused edit changed the scene");
}
