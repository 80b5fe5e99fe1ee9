//! The eye-light preview: every surface lit by a light at the eye, no secondary rays. Shapes read
//! clearly with no lights or materials set up, and a frame costs little more than its primary
//! rays.

use glam::Vec3;
use raystage_kernel::Ray;
use raystage_scene::SceneHit;

use super::Tracer;
use crate::lights::Seen;
use crate::sky;

/// Light reaching a surface seen edge-on, so that silhouettes stay visible.
const AMBIENT: f32 = 0.15;

/// The colours of up to a packet of camera rays under the eye light, `out[k]` for `rays[k]`
/// whose first hit is `hits[k]`, light from area lights met on the way excluded (see
/// `Tracer::emission`). Only the normal and the material of a hit are looked up (no hit point),
/// which keeps the preview close to the cost of its camera rays; the normals of the hits and
/// the directions of the misses (for the sky) are normalised side by side.
pub(crate) fn shade(t: &Tracer<'_, '_>, rays: &[Ray], hits: &[Option<SceneHit>], out: &mut [Vec3]) {
    const N: usize = raystage_kernel::PACKET_SIZE;
    assert!(rays.len() == hits.len() && hits.len() == out.len() && hits.len() <= N, "a colour per ray, at most a packet");
    // Per hit: the surface's colour, whether the eye light shades it, and its normal.
    let mut colour = [Vec3::ZERO; N];
    let mut lit = [false; N];
    let mut normal = [Vec3::ZERO; N];
    let mut missed = 0;
    for (k, (ray, hit)) in rays.iter().zip(hits).enumerate() {
        match hit {
            Some(hit) => {
                let point = t.frame.preview(hit);
                (colour[k], lit[k]) = t.materials.preview_colour(&point, || t.frame.preview_attributes(ray, hit));
                normal[k] = point.normal;
            }
            None => missed |= 1 << k,
        }
    }
    // `Vec3::length` of each normal, then its reciprocal, side by side.
    let rcp = raystage_kernel::reciprocal_sqrt8(normal.map(Vec3::length_squared));
    let environment = t.lights.has_environment();
    // What `Tracer::background` shows camera rays without an environment.
    let skies = if missed != 0 && !environment { sky::skies(rays, missed) } else { [Vec3::ZERO; N] };
    for (k, (ray, hit)) in rays.iter().zip(hits).enumerate() {
        let v = normal[k];
        out[k] = match hit {
            None if environment => t.background(ray.dir, Seen::Directly),
            None => skies[k],
            // `normalize_or_zero`, `dot` and `abs`. Camera rays have unit directions
            // (`CameraRays::ray`), and the preview shades nothing else.
            Some(_) if lit[k] => {
                let (x, y, z) = if rcp[k].is_finite() && rcp[k] > 0.0 { (v.x * rcp[k], v.y * rcp[k], v.z * rcp[k]) } else { (0.0, 0.0, 0.0) };
                let cos = ((x * ray.dir.x) + (y * ray.dir.y) + (z * ray.dir.z)).abs();
                colour[k] * (AMBIENT + (1.0 - AMBIENT) * cos)
            }
            Some(_) => colour[k],
        };
    }
}
