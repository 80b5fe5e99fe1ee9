//! The standard scenes as retained scenes, ready to render: the probe's geometry and camera,
//! one shader per sphere (or per group of soup triangles) in distinct colours, a grey ground, a
//! sun and a fill light.

use glam::{Affine3A, Vec3};
use raystage_scene::{Background, Camera, Light, Mesh as SceneMesh, ObjectKind, ParamValue, Scene, SceneError, ShaderId};

use crate::StandardScene;

/// Triangles per sphere of the sphere grid (100 × 50 segments, two triangles each).
const TRIANGLES_PER_SPHERE: usize = 10_000;
/// Triangles per colour group of the soup, which has no objects to colour by.
const SOUP_GROUP: usize = 1024;
/// Golden-ratio conjugate: stepping the hue by it keeps consecutive colours far apart.
pub(crate) const HUE_STEP: f32 = 0.618_034;

impl StandardScene {
    /// The scene ready to render: one static object holding the whole mesh, one instance.
    pub fn scene(self) -> Result<Scene, SceneError> {
        let mesh = self.mesh();
        let mut scene = Scene::new();
        let (group, plain_tail) = match self {
            StandardScene::Spheres => (TRIANGLES_PER_SPHERE, 2),
            StandardScene::Soup => (SOUP_GROUP, 0),
        };
        let coloured = mesh.indices.len() - plain_tail;
        let mut shaders: Vec<ShaderId> = Vec::with_capacity(mesh.indices.len());
        for start in (0..coloured).step_by(group) {
            let shader = diffuse(&mut scene, palette((start / group) as f32 * HUE_STEP))?;
            shaders.extend(std::iter::repeat_n(shader, group.min(coloured - start)));
        }
        if plain_tail > 0 {
            let ground = diffuse(&mut scene, Vec3::splat(0.6))?;
            shaders.extend(std::iter::repeat_n(ground, plain_tail));
        }
        let object = scene.add_object(
            ObjectKind::Static,
            SceneMesh { positions: mesh.vertices, indices: mesh.indices, shaders, ..SceneMesh::default() },
        )?;
        scene.add_instance(object, Affine3A::IDENTITY)?;
        let (eye, target) = match self {
            StandardScene::Spheres => (Vec3::new(0.0, 8.0, 8.0), Vec3::new(0.0, 0.0, -10.0)),
            StandardScene::Soup => (Vec3::new(0.5, 0.5, 2.5), Vec3::new(0.5, 0.5, 0.5)),
        };
        scene.set_camera(Camera::look_at(eye, target, Vec3::Y, 60.0)?)?;
        let pi = std::f32::consts::PI;
        // Outdoors: the sky behind, as a backdrop (the sun and fill light it).
        scene.set_background(Some(Background::Sky))?;
        scene.add_light(Light::Directional { direction: Vec3::new(-0.5, -1.0, -0.4), intensity: Vec3::splat(0.85 * pi) })?;
        scene.add_light(Light::Directional { direction: Vec3::new(0.6, -0.3, -1.0), intensity: Vec3::splat(0.3 * pi) })?;
        Ok(scene)
    }
}

/// A Diffuse shader of the given albedo.
pub(crate) fn diffuse(scene: &mut Scene, albedo: Vec3) -> Result<ShaderId, SceneError> {
    let shader = scene.add_shader("Diffuse")?;
    scene.set_param(shader, "diffuse", ParamValue::Color(albedo))?;
    Ok(shader)
}

/// A pleasant, fairly saturated colour (linear RGB) for hue `hue` (wrapped to `[0, 1)`).
pub(crate) fn palette(hue: f32) -> Vec3 {
    let hue = hue.fract();
    let (saturation, value) = (0.55, 0.95);
    let channel = |n: f32| {
        let k = (n + hue * 6.0) % 6.0;
        value - value * saturation * k.min(4.0 - k).clamp(0.0, 1.0)
    };
    Vec3::new(channel(5.0), channel(3.0), channel(1.0)).map(|c| c.powf(2.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbouring_groups_get_distinct_colours() {
        for g in 0..99 {
            let (a, b) = (palette(g as f32 * HUE_STEP), palette((g + 1) as f32 * HUE_STEP));
            assert!((a - b).abs().max_element() > 0.05, "groups {g} and {}", g + 1);
        }
    }
}
