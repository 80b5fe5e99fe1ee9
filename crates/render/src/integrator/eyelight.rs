//! The eye-light preview: every surface lit by a light at the eye, no secondary rays. Shapes read
//! clearly with no lights or materials set up, and a frame costs little more than its primary
//! rays.

use glam::Vec3;
use raystage_kernel::Ray;
use raystage_scene::{SceneHit, ShadingModel};

use super::Tracer;

/// Light reaching a surface seen edge-on, so that silhouettes stay visible.
const AMBIENT: f32 = 0.15;

/// The colour of `hit` of `ray` under the eye light. Only the normal and the material are
/// looked up (no hit point), which keeps the preview close to the cost of its camera rays.
pub(crate) fn shade(t: &Tracer<'_, '_>, ray: &Ray, hit: &SceneHit) -> Vec3 {
    let point = t.frame.preview(ray, hit);
    let m = t.materials.at_preview(&point);
    match m.model {
        ShadingModel::Constant | ShadingModel::Emissive => m.emission,
        _ => {
            // Camera rays have unit directions (`CameraRays::ray`), and the preview shades
            // nothing else.
            let cos = point.normal.dot(ray.dir).abs();
            m.albedo * (AMBIENT + (1.0 - AMBIENT) * cos)
        }
    }
}
