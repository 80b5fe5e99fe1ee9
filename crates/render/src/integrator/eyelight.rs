//! The eye-light preview: every surface lit by a light at the eye, no secondary rays. Shapes read
//! clearly with no lights or materials set up, and a frame costs little more than its primary
//! rays.

use glam::{Vec3, Vec4};
use raystage_kernel::Ray;
use raystage_scene::SceneHit;

use super::Tracer;
use super::quads::{pack, quad, quads};

/// Light reaching a surface seen edge-on, so that silhouettes stay visible.
const AMBIENT: f32 = 0.15;

/// The colours of up to a packet of camera rays under the eye light, `found(k, colour)` for
/// `rays[k]` whose first hit is `hits[k]`, light from area lights met on the way excluded (see
/// `Tracer::emission`). Only the normal and the material of a hit are looked up (no hit point),
/// which keeps the preview close to the cost of its camera rays; the cosines between normals and
/// rays are computed four at a time.
pub(crate) fn shade(t: &Tracer<'_, '_>, rays: &[Ray], hits: &[Option<SceneHit>], mut found: impl FnMut(usize, Vec3)) {
    const N: usize = raystage_kernel::PACKET_SIZE;
    assert!(rays.len() == hits.len() && hits.len() <= N, "a ray per hit, at most a packet");
    // Per hit: the surface's colour and its normal's coordinates (zero for misses); the hits the
    // eye light shades (not emitters or constant colours), and the misses, a bit per ray.
    let mut colour = [Vec3::ZERO; N];
    let (mut nx, mut ny, mut nz) = ([0.0f32; N], [0.0f32; N], [0.0f32; N]);
    let (mut lit, mut missed) = ([false; N], 0u32);
    for (k, (ray, hit)) in rays.iter().zip(hits).enumerate() {
        let Some(hit) = hit else {
            missed |= 1 << k;
            continue;
        };
        let point = t.frame.preview(hit);
        let Some(preview) = t.materials.preview_colour(&point, || t.frame.preview_attributes(ray, hit), |set| t.frame.texture_density(hit, 0.0, set)) else {
            // The normal map's normal needs the hit point's texture coordinates and tangent:
            // the hit is resolved in full (its albedo, occluded, is the preview's colour).
            let full = t.resolve(ray, *hit, 0.0);
            let footprint = t.materials.footprint(&full.surface, |set| t.frame.texture_density(hit, 0.0, set));
            let occlusion = t.materials.preview_occlusion(point.shader_id, full.surface.local_position, [full.surface.uv, full.surface.uv1], footprint);
            (colour[k], lit[k]) = (full.material.albedo * occlusion, true);
            (nx[k], ny[k], nz[k]) = (full.surface.shading_normal.x, full.surface.shading_normal.y, full.surface.shading_normal.z);
            continue;
        };
        (colour[k], lit[k]) = preview;
        (nx[k], ny[k], nz[k]) = (point.normal.x, point.normal.y, point.normal.z);
    }
    let (mut dx, mut dy, mut dz) = ([0.0f32; N], [0.0f32; N], [0.0f32; N]);
    for (k, ray) in rays.iter().enumerate() {
        (dx[k], dy[k], dz[k]) = (ray.dir.x, ray.dir.y, ray.dir.z);
    }
    // The light's factor on each colour: `normalize_or_zero` of the normal, `dot` with the ray
    // and `abs` give the cosine (the same correctly rounded operations as one by one; camera
    // rays have unit directions, see `CameraRays::ray`, and the preview shades nothing else),
    // and hits the light does not shade keep their colour.
    let mut factor = [1.0f32; N];
    for lane in quads() {
        let at = |values: &[f32; N]| quad(values, lane);
        let (x, y, z) = (at(&nx), at(&ny), at(&nz));
        let rcp = ((x * x + y * y) + z * z).sqrt().recip();
        let normalisable = rcp.is_finite_mask() & rcp.cmpgt(Vec4::ZERO);
        let unit = |v: Vec4| Vec4::select(normalisable, v * rcp, Vec4::ZERO);
        let cos = ((unit(x) * at(&dx) + unit(y) * at(&dy)) + unit(z) * at(&dz)).abs();
        Vec4::select(pack(&lit, lane), Vec4::splat(AMBIENT) + Vec4::splat(1.0 - AMBIENT) * cos, Vec4::ONE).write_to_slice(&mut factor[lane..]);
    }
    let backdrops = if missed != 0 { t.backdrops(rays, missed) } else { [Vec3::ZERO; N] };
    for (k, _) in rays.iter().enumerate() {
        let seen = if missed & (1 << k) == 0 { colour[k] * factor[k] } else { backdrops[k] };
        found(k, seen);
    }
}
