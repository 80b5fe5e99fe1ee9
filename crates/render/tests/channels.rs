//! Channels beside the colour, checked against geometry whose answers are known: a plane at a
//! known distance (depth, camera-space z, normal), two instances of two objects (ids), a
//! coloured shader (albedo), and the sky where nothing is hit.

mod common;

use common::shader;
use glam::{Affine3A, Vec3};
use raystage_render::{Channel, NO_ID, render_channels};
use raystage_scene::{Camera, Mesh, ObjectKind, ParamValue, Scene};

/// A square of half-size `s` in the xy plane, facing +z.
fn square(s: f32) -> Mesh {
    Mesh {
        positions: vec![Vec3::new(-s, -s, 0.0), Vec3::new(s, -s, 0.0), Vec3::new(s, s, 0.0), Vec3::new(-s, s, 0.0)],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    }
}

/// The camera at (0, 0, 4) looking down −z; an orange square filling the left half of the
/// image at z = 0 (object 0, instance 0), and a tilted blue one on the right, nearer (object 1,
/// instance 1), its face turned 30° about y.
fn scene() -> Scene {
    let mut scene = Scene::new();
    let orange = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::new(0.8, 0.4, 0.1)))]);
    let blue = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::new(0.1, 0.2, 0.9)))]);
    let left = scene.add_object(ObjectKind::Static, square(1.0).with_shader(orange)).unwrap();
    let right = scene.add_object(ObjectKind::Static, square(0.5).with_shader(blue)).unwrap();
    scene.add_instance(left, Affine3A::from_translation(Vec3::new(-1.0, 0.0, 0.0))).unwrap();
    let tilt = Affine3A::from_translation(Vec3::new(1.0, 0.0, 1.0)) * Affine3A::from_rotation_y(30f32.to_radians());
    scene.add_instance(right, tilt).unwrap();
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 60.0).unwrap()).unwrap();
    scene
}

#[test]
fn channels_say_what_each_pixel_sees() {
    let scene = scene();
    let (w, h) = (64, 32);
    let images = render_channels(&scene.frame(), w, h, &Channel::ALL).unwrap();
    let get = |c: Channel| images.iter().find(|i| i.channel == c).unwrap();
    let at = |c: Channel, x: u32, y: u32| {
        let i = get(c);
        let n = c.components();
        i.values[(y * w + x) as usize * n..][..n].to_vec()
    };
    let id = |c: Channel, x: u32, y: u32| get(c).ids[(y * w + x) as usize];

    // A pixel on the orange square: the ray through its centre and the plane z = 0.
    let (x, y) = (20, 16);
    let ray = scene.camera().ray(x as f32 + 0.5, y as f32 + 0.5, w, h);
    let t = -ray.origin.z / ray.dir.z;
    assert!((at(Channel::Depth, x, y)[0] - t).abs() < 1e-4, "depth {:?} against {t}", at(Channel::Depth, x, y));
    assert!((at(Channel::Z, x, y)[0] - 4.0).abs() < 1e-4, "the plane is 4 in front of the eye: {:?}", at(Channel::Z, x, y));
    assert_eq!(at(Channel::Normal, x, y), vec![0.0, 0.0, 1.0]);
    assert_eq!(at(Channel::Albedo, x, y), vec![0.8, 0.4, 0.1]);
    assert_eq!([id(Channel::Instance, x, y), id(Channel::Object, x, y)], [0, 0]);
    assert!(id(Channel::Primitive, x, y) < 2);

    // The tilted square: its normal turned 30° about y, nearer than the plane behind.
    let (x, y) = (41, 16);
    let n = at(Channel::Normal, x, y);
    let expected = Vec3::new(30f32.to_radians().sin(), 0.0, 30f32.to_radians().cos());
    assert!((Vec3::from_slice(&n) - expected).length() < 1e-4, "{n:?}");
    assert_eq!([id(Channel::Instance, x, y), id(Channel::Object, x, y)], [1, 1]);
    assert_eq!(at(Channel::Albedo, x, y), vec![0.1, 0.2, 0.9]);
    assert!(at(Channel::Z, x, y)[0] < 4.0);

    // Nothing above the squares.
    let (x, y) = (32, 0);
    assert_eq!((at(Channel::Depth, x, y)[0], at(Channel::Normal, x, y)), (f32::INFINITY, vec![0.0; 3]));
    assert_eq!([id(Channel::Instance, x, y), id(Channel::Object, x, y), id(Channel::Primitive, x, y)], [NO_ID; 3]);
}

#[test]
fn channels_encode_as_pfm_and_png_and_refuse_what_cannot_be() {
    let scene = scene();
    let images = render_channels(&scene.frame(), 8, 4, &[Channel::Depth, Channel::Normal, Channel::Instance]).unwrap();
    let [depth, normal, instance] = &images[..] else { panic!() };
    assert!(depth.pfm().starts_with(b"Pf\n8 4\n-1.0\n") && depth.pfm().len() == 12 + 8 * 4 * 4);
    assert!(normal.pfm().starts_with(b"PF\n8 4\n-1.0\n") && normal.pfm().len() == 12 + 8 * 4 * 12);
    assert!(depth.png().unwrap_err().to_string().contains("PFM"));
    let ids = image::load_from_memory(&instance.png().unwrap()).unwrap().to_rgb8();
    assert_eq!(ids.get_pixel(4, 0).0, [255, 255, 255], "nothing hit");
    assert_eq!(ids.get_pixel(5, 2).0, [1, 0, 0], "instance 1");
    let normals = image::load_from_memory(&normal.png().unwrap()).unwrap().to_rgb8();
    assert_eq!(normals.get_pixel(2, 2).0, [128, 128, 255]);

    assert!("colour".parse::<Channel>().unwrap_err().to_string().contains("depth, z, normal"));
    assert!(render_channels(&scene.frame(), 0, 4, &[Channel::Depth]).is_err());
}
