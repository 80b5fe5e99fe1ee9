//! The eye-light preview: every surface lit by a light at the eye, no secondary rays. Shapes read
//! clearly with no lights or materials set up, and a frame costs little more than its primary
//! rays.

use glam::Vec3;
use raystage_kernel::Ray;
use raystage_scene::ShadingModel;

use super::Hit;

/// Light reaching a surface seen edge-on, so that silhouettes stay visible.
const AMBIENT: f32 = 0.15;

/// The colour of `hit` of `ray` under the eye light.
pub(crate) fn shade(ray: &Ray, hit: &Hit<'_>) -> Vec3 {
    let m = &hit.material;
    match m.model {
        ShadingModel::Constant | ShadingModel::Emissive => m.emission,
        _ => {
            let cos = hit.surface.shading_normal.dot(ray.dir.normalize()).abs();
            m.albedo * (AMBIENT + (1.0 - AMBIENT) * cos)
        }
    }
}
