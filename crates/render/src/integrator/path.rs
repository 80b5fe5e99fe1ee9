//! Unbiased path tracing: at every bounce, light sources are sampled directly (next-event
//! estimation) and the BSDF is sampled to continue the path; where both strategies can find the
//! same light, their contributions are combined by multiple importance sampling (Veach's power
//! heuristic). Paths end by Russian roulette, which keeps the estimate unbiased, or at the
//! maximum depth.

use glam::Vec3;
use raystage_kernel::Ray;
use raystage_scene::ShadingModel;

use super::first_shadows::KnownShadows;
use super::{Hit, Media, Tracer, offset};
use crate::lights::Seen;
use crate::sampler::PixelSampler;
use crate::stats::RayCounts;
use crate::warp::Frame3;

/// Bounces before Russian roulette may end a path: Mitsuba's `rr_depth`. Roulette trades time
/// for noise, and the trade is poor early on: from the third bounce, the closed Cornell room
/// took 0.82× the time per sample for 1.49× the squared error (256 spp, 2026-12-06), so paths
/// bounce five times first, for 1.12-1.22× less time to the same error in the room and the
/// room of spheres. Scenes that paths leave early (a glTF asset under the studio) are the
/// same either way.
const ROULETTE_AFTER: u32 = 5;

/// The radiance arriving along the camera ray `ray` at shutter time `time`, whose first hit
/// `first` is known.
pub(crate) fn shade(t: &Tracer<'_, '_>, ray: &Ray, first: Hit<'_>, time: f32, sampler: &mut PixelSampler, rays: &mut RayCounts) -> Vec3 {
    // The hit of the path's current ray: the camera ray's is known; each later one is traced
    // into this slot, so that the hit (a few hundred bytes) is not moved about at every bounce.
    let mut found = Some(first);
    let mut ray = *ray;
    // Which counter the next ray goes to: set by the bounce that produced it.
    let mut next = Bounce::Diffuse;
    let mut throughput = Vec3::ONE;
    let mut radiance = Vec3::ZERO;
    let mut media = Media::air();
    // How the current ray was chosen, which weighs the lights it meets.
    let mut seen = Seen::Directly;
    for depth in 0..t.settings.max_depth {
        if depth > 0 {
            let counter = match next {
                Bounce::Diffuse => &mut rays.diffuse,
                Bounce::Reflection => &mut rays.reflection,
                Bounce::Refraction => &mut rays.refraction,
            };
            found = t.trace(&ray, time, counter);
        }
        radiance += throughput * t.emission(&ray, found.as_ref().map(|h| h.hit.t), seen);
        let Some(hit) = &found else {
            radiance += throughput * t.background(ray.dir, seen) * media.attenuation(f32::INFINITY);
            break;
        };
        throughput *= media.attenuation(hit.hit.t * ray.dir.length());
        let wo = -ray.dir.normalize();
        let m = &hit.material;
        match m.model {
            // A flat colour: what the path sees, whichever way it came.
            ShadingModel::Constant => {
                radiance += throughput * m.emission;
                break;
            }
            // Emitting surfaces are lights, sampled at every bounce: what a scattered ray finds
            // of them is weighed against that.
            ShadingModel::Emissive => {
                radiance += throughput * t.surface_emission(&ray, hit, seen);
                break;
            }
            // Physically based surfaces may emit, and scatter as well.
            ShadingModel::PhysicallyBased => radiance += throughput * t.surface_emission(&ray, hit, seen),
            ShadingModel::AmbientOcclusion => {
                let open = t.occlusion(hit, time, 1, sampler, rays);
                radiance += throughput * m.albedo * open;
                break;
            }
            _ => {}
        }
        // The path has `depth + 1` segments: a light sampled from here, or a ray scattered on,
        // would be one more (Mitsuba's `max_depth` counts them so: 1 sees emitters only).
        if depth + 2 > t.settings.max_depth {
            break;
        }
        let bsdf = media.bsdf(hit).expect("scattering material");
        let frame3 = Frame3::around(hit.surface.shading_normal);
        // Seen from `wo` once, for the light samples and the bounce alike.
        let scattering = bsdf.towards(frame3.to_local(wo));
        if !bsdf.is_specular() {
            radiance += throughput * t.direct(hit, &scattering, time, KnownShadows::NONE, sampler, rays);
        }
        let (u, choose) = (sampler.next_2d(), sampler.next_1d());
        let Some(s) = scattering.sample(u, choose) else { break };
        throughput *= s.weight;
        // A black surface (an emitter's, say) ends the path: nothing more can reach the camera.
        if throughput == Vec3::ZERO {
            break;
        }
        let specular = s.pdf == 0.0;
        seen = if specular { Seen::Directly } else { Seen::Scattered { normal: hit.surface.shading_normal, pdf: s.pdf } };
        if t.settings.russian_roulette && depth + 1 >= ROULETTE_AFTER {
            let survive = throughput.max_element().min(0.95);
            if sampler.next_1d() >= survive {
                break;
            }
            throughput /= survive;
        }
        let wi = frame3.to_world(s.wi);
        next = if s.transmitted {
            media = media.crossed(hit);
            Bounce::Refraction
        } else if specular {
            Bounce::Reflection
        } else {
            Bounce::Diffuse
        };
        ray = continue_from(hit, wi);
    }
    radiance
}

/// How a path's ray came about, for counting rays by kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Bounce {
    Diffuse,
    Reflection,
    Refraction,
}

/// The next ray of the path, leaving `hit` in direction `wi`.
fn continue_from(hit: &Hit<'_>, wi: Vec3) -> Ray {
    let sp = &hit.surface;
    Ray::new(offset(sp, wi), wi)
}
