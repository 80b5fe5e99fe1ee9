//! The eye-light preview: every surface lit by a light at the eye, no secondary rays. Shapes read
//! clearly with no lights or materials set up, and a frame costs little more than its primary
//! rays.

use glam::Vec3;
use raystage_kernel::Ray;
use raystage_scene::SceneHit;

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
    // Per ray: the surface's colour, whether the eye light shades it, and its normal and the
    // ray's direction by component (zeros where nothing is lit).
    let mut colour = [Vec3::ZERO; N];
    let mut lit = [false; N];
    let mut normal = [[0.0f32; N]; 3];
    let mut dir = [[0.0f32; N]; 3];
    for (k, (ray, hit)) in rays.iter().zip(hits).enumerate() {
        let Some(hit) = hit else {
            colour[k] = t.background(ray.dir, Seen::Directly);
            continue;
        };
        let point = t.frame.preview(ray, hit);
        (colour[k], lit[k]) = t.materials.preview_colour(&point);
        for axis in 0..3 {
            normal[axis][k] = point.normal[axis];
            dir[axis][k] = ray.dir[axis];
        }
    }
    // `normalize_or_zero`, `dot` and `abs` of each lane, side by side. Camera rays have unit
    // directions (`CameraRays::ray`), and the preview shades nothing else.
    let mut shade = [0.0f32; N];
    for (k, shade) in shade.iter_mut().enumerate() {
        let (x, y, z) = (normal[0][k], normal[1][k], normal[2][k]);
        let rcp = 1.0 / ((x * x) + (y * y) + (z * z)).sqrt();
        let (x, y, z) = if rcp.is_finite() && rcp > 0.0 { (x * rcp, y * rcp, z * rcp) } else { (0.0, 0.0, 0.0) };
        let cos = ((x * dir[0][k]) + (y * dir[1][k]) + (z * dir[2][k])).abs();
        *shade = AMBIENT + (1.0 - AMBIENT) * cos;
    }
    for (k, c) in out.iter_mut().enumerate() {
        *c = if lit[k] { colour[k] * shade[k] } else { colour[k] };
    }
}
