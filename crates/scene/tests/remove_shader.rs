//! Removing a shader: triangles that referred to it fall back to the default shader, new
//! geometry cannot bind it, and its id can be defined again.

use glam::{Affine3A, Vec3};
use raystage_kernel::Ray;
use raystage_scene::{Mesh, ObjectKind, ParamValue, Scene, SceneError};

#[test]
fn triangles_of_a_removed_shader_fall_back_to_the_default() {
    let mut scene = Scene::new();
    let shader = scene.reserve_shaders(1);
    scene.define_shader(shader, "Constant").unwrap();
    scene.set_param(shader, "color", ParamValue::Color(Vec3::new(0.0, 1.0, 0.0))).unwrap();
    let triangle = Mesh::new(vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)], vec![[0, 1, 2]]);
    let object = scene.add_object(ObjectKind::Static, triangle.clone().with_shader(shader)).unwrap();
    scene.add_instance(object, Affine3A::IDENTITY).unwrap();
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z);
    let class_seen = |scene: &Scene| {
        let frame = scene.frame();
        let hit = frame.intersect(&ray, 0.0).expect("the triangle");
        frame.surface(&ray, &hit, 0.0).shader.class().name
    };
    assert_eq!(class_seen(&scene), "Constant");

    scene.remove_shader(shader).unwrap();
    assert_eq!(class_seen(&scene), scene.default_shader().class().name);
    assert_eq!(scene.shader(shader), Err(SceneError::UnknownShader(shader)));
    assert_eq!(scene.remove_shader(shader), Err(SceneError::UnknownShader(shader)), "removed once only");
    let rebind = scene.add_object(ObjectKind::Static, triangle.with_shader(shader));
    assert_eq!(rebind, Err(SceneError::UnknownShader(shader)));

    // The id is still reserved: defining it again brings the triangles' shader back.
    scene.define_shader(shader, "Constant").unwrap();
    assert_eq!(class_seen(&scene), "Constant");
}
