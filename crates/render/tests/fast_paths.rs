//! Every fast path computes what the general path computes, bit for bit
//! (docs/design/fast-paths.md): every demo scene rendered with every integrator, once with the
//! fast paths and the kernel compiled for the frame's effect set, once with neither
//! (`fast_paths` and `specialize` off: camera rays one by one, no lone instance walked in place,
//! no first-hit shadow packets or packet-wise matte shading, no preview packets, the kernel with
//! reflection and refraction compiled in), must give identical pixels. So must the glTF material
//! scenes: cut-outs (whose masked hits rays go on through), transmission, textures, vertex
//! colours, a lone instance with the identity transform.

use raystage_demo::animated::Demo;
use raystage_demo::material_scenes::MaterialScene;
use raystage_render::{Integrator, RenderSettings, render};
use raystage_scene::{Light, Scene};

/// Every demo but the sized museums (`museum` is one of them).
const DEMOS: [&str; 8] = ["spheres", "sphere", "soup", "cornell", "materials", "robots", "museum", "terrain"];

/// The scenes compared: the demos, and the material scenes lit by a point light (which first-hit
/// shadow packets and packet-wise matte shading apply to) under their uniform environment.
fn scenes() -> Vec<(String, Scene)> {
    let demos = DEMOS.iter().map(|name| (name.to_string(), Demo::from_name(name).unwrap().scene(0).unwrap()));
    let materials = MaterialScene::ALL.iter().map(|m| {
        let mut scene = raystage_gltf_import::read(m.gltf().as_bytes(), None, &raystage_gltf_import::Limits::default()).unwrap().into_scene().unwrap();
        scene.add_light(Light::Environment { radiance: glam::Vec3::from(m.environment()), map: None, rotate_degrees: 0.0 }).unwrap();
        scene.add_light(Light::Point { position: glam::Vec3::new(1.0, 3.0, 4.0), intensity: glam::Vec3::splat(20.0) }).unwrap();
        (m.name().to_string(), scene)
    });
    demos.chain(materials).collect()
}

#[test]
fn the_fast_paths_give_the_general_paths_pixels() {
    let mut compared = 0;
    let scenes = scenes();
    for (name, scene) in &scenes {
        for integrator in Integrator::ALL {
            // One sample through each pixel's centre, and two over the pixel.
            for samples_per_pixel in [1, 2] {
                let fast = RenderSettings { width: 64, height: 48, integrator, samples_per_pixel, ..RenderSettings::default() };
                let general = RenderSettings { fast_paths: false, specialize: false, ..fast };
                let (a, a_stats) = render(&scene.frame(), &fast).unwrap();
                let (b, b_stats) = render(&scene.frame(), &general).unwrap();
                let differing = a.pixels().iter().zip(b.pixels()).filter(|(p, q)| p.to_array().map(f32::to_bits) != q.to_array().map(f32::to_bits)).count();
                assert_eq!(differing, 0, "{name}, {} at {samples_per_pixel} spp: {differing} pixels differ", integrator.name());
                assert_eq!(a_stats.rays.primary, b_stats.rays.primary);
                compared += 1;
            }
        }
    }
    assert_eq!(compared, scenes.len() * Integrator::ALL.len() * 2);
}
