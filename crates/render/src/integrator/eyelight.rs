//! The eye-light preview: every surface lit by a light at the eye, no secondary rays. Shapes read
//! clearly with no lights or materials set up, and a frame costs little more than its primary
//! rays.

use glam::Vec3;
use raystage_kernel::Ray;
use raystage_scene::{SceneHit, ShadingModel};

use super::Tracer;
use crate::lights::Seen;

/// Light reaching a surface seen edge-on, so that silhouettes stay visible.
const AMBIENT: f32 = 0.15;

/// The colours of up to a packet of camera rays under the eye light, `out[k]` for `rays[k]`
/// whose first hit is `hits[k]`, light from area lights met on the way excluded (see
/// `Tracer::emission`). Only the normal and the material of a hit are looked up (no hit point),
/// which keeps the preview close to the cost of its camera rays; the normals of the packet are
/// normalised side by side.
pub(crate) fn shade(t: &Tracer<'_, '_>, rays: &[Ray], hits: &[Option<SceneHit>], out: &mut [Vec3]) {
    const N: usize = raystage_kernel::PACKET_SIZE;
    assert!(rays.len() == hits.len() && hits.len() == out.len() && hits.len() <= N, "a colour per ray, at most a packet");
    // Per ray: the surface's colour, whether the eye light shades it, and its normal.
    let mut colour = [Vec3::ZERO; N];
    let mut lit = [false; N];
    let mut normal = [Vec3::ZERO; N];
    for (k, (ray, hit)) in rays.iter().zip(hits).enumerate() {
        let Some(hit) = hit else {
            colour[k] = t.background(ray.dir, Seen::Directly);
            continue;
        };
        let point = t.frame.preview(ray, hit);
        let m = t.materials.at_preview(&point);
        match m.model {
            ShadingModel::Constant | ShadingModel::Emissive => colour[k] = m.emission,
            _ => (colour[k], lit[k], normal[k]) = (m.albedo, true, point.normal),
        }
    }
    for (k, (ray, c)) in rays.iter().zip(out.iter_mut()).enumerate() {
        // Camera rays have unit directions (`CameraRays::ray`), and the preview shades nothing
        // else.
        let cos = normal[k].normalize_or_zero().dot(ray.dir).abs();
        *c = if lit[k] { colour[k] * (AMBIENT + (1.0 - AMBIENT) * cos) } else { colour[k] };
    }
}
