//! Recursive ray tracing: Whitted's (1980) model and Cook's distribution ray tracing (1984),
//! which is the same recursion with its choices made at random per pixel sample
//! (docs/design/seeds.md §1.6, §1.7).
//!
//! At each hit: emission, light from every source (a shadow ray each, when the frame has
//! shadows), then a reflection ray for reflective surfaces and a refraction ray for transmissive
//! ones, weighted by Fresnel's equations, with Beer's law inside absorbing media, to a fixed
//! depth. Whitted splits deterministically and reflects glossy surfaces as mirrors; the
//! distributed variant samples glossy lobes and chooses between reflection and refraction by
//! their Fresnel weights, so that averaging the pixel's samples gives glossy reflection, soft
//! shadows (lights sampled over their area), depth of field and motion blur (the camera ray's
//! lens position and time).
//!
//! `REFLECT` and `REFRACT` compile the reflection and refraction code in or out: the renderer
//! instantiates the variant the frame's effect set calls for, so a purely diffuse scene runs a
//! kernel with no trace of either (docs/design/architecture.md, "The effect set": a specialised
//! kernel must not be slower than one written by hand).

use glam::Vec3;
use raystage_kernel::Ray;
use raystage_scene::ShadingModel;

use super::first_shadows::KnownShadows;
use super::{Hit, Media, Tracer, offset};
use crate::bsdf::{Bsdf, fresnel_dielectric, reflect, refract};
use crate::lights::Seen;
use crate::sampler::PixelSampler;
use crate::stats::RayCounts;
use crate::warp::Frame3;

/// Ambient-occlusion probes per hit for Whitted; the distributed variant takes one per sample.
const WHITTED_OCCLUSION_PROBES: u32 = 16;

/// Hall and Greenberg's adaptive tree depth control: a ray whose weight (the product of the
/// Fresnel and colour factors from the camera to it) is below this is not traced, since it could
/// change the pixel by at most this fraction of the light it meets. (Cut, not played by Russian
/// roulette: a ray that survived would count a hundred times over, and Whitted's image would
/// turn noisy where it is exact.)
const MIN_WEIGHT: f32 = 1e-3;

/// Bounces at which Whitted's glass traces both the reflected and the refracted ray; deeper,
/// one of them is chosen by Russian roulette with the probability of its Fresnel weight (and
/// counts for both: unbiased), so that the rays of a pixel are at most 2^this chains of at most
/// the depth limit each, and a frame's cost grows with the depth limit linearly, not as 2 to
/// its power.
const SPLIT_DEPTH: u32 = 6;

/// A secondary ray of the recursion and what it is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Mirror reflection: the lights it meets are seen.
    Reflection,
    /// Refraction: the lights it meets are seen.
    Refraction,
    /// Reflection off a glossy surface, whose light from emitters the light samples already
    /// account for.
    Glossy,
}

/// The colour of a camera ray `ray` at shutter time `time` whose first hit `hit` is known, with
/// the shadows there that are `known` already.
pub(crate) fn shade<const REFLECT: bool, const REFRACT: bool, const DISTRIBUTED: bool>(
    t: &Tracer<'_, '_>,
    ray: &Ray,
    hit: &Hit<'_>,
    time: f32,
    known: KnownShadows,
    sampler: &mut PixelSampler,
    rays: &mut RayCounts,
) -> Vec3 {
    Recursion::<REFLECT, REFRACT, DISTRIBUTED> { t, time, first_hit_shadows: known, sampler, rays }.shade(ray, hit, Seen::Directly, Media::air(), 0, 1.0)
}

/// One camera sample's recursion: what stays the same from bounce to bounce.
struct Recursion<'a, 't, 'f, const REFLECT: bool, const REFRACT: bool, const DISTRIBUTED: bool> {
    t: &'a Tracer<'t, 'f>,
    /// The camera ray's shutter time, shared by every ray of the sample.
    time: f32,
    /// Shadows known at the camera ray's hit (depth 0).
    first_hit_shadows: KnownShadows,
    sampler: &'a mut PixelSampler,
    rays: &'a mut RayCounts,
}

impl<const REFLECT: bool, const REFRACT: bool, const DISTRIBUTED: bool> Recursion<'_, '_, '_, REFLECT, REFRACT, DISTRIBUTED> {
    /// The radiance arriving along `ray`, traced for `kind`, in the media `media`, `depth`
    /// bounces from the camera, with weight `weight` in the pixel (see [`MIN_WEIGHT`]).
    fn radiance(&mut self, ray: &Ray, kind: Kind, media: Media, depth: u32, weight: f32) -> Vec3 {
        if weight < MIN_WEIGHT {
            return Vec3::ZERO;
        }
        let (counter, seen) = match kind {
            Kind::Reflection => (&mut self.rays.reflection, Seen::Directly),
            Kind::Refraction => (&mut self.rays.refraction, Seen::Directly),
            Kind::Glossy => (&mut self.rays.reflection, Seen::Not),
        };
        let found = self.t.trace(ray, self.time, counter);
        let emitted = self.t.emission(ray, found.as_ref().map(|h| h.hit.t), seen);
        match found {
            None => emitted + self.t.background(ray.dir, seen) * media.attenuation(f32::INFINITY),
            Some(hit) => emitted + self.shade(ray, &hit, seen, media, depth, weight),
        }
    }

    /// The colour `ray`, which was `seen` as it was, carries back from `hit`, `depth` bounces
    /// from the camera, with weight `weight` in the pixel.
    fn shade(&mut self, ray: &Ray, hit: &Hit<'_>, seen: Seen, media: Media, depth: u32, weight: f32) -> Vec3 {
        let t = self.t;
        let attenuation = media.attenuation(hit.hit.t * ray.dir.length());
        let wo = -ray.dir.normalize();
        let deeper = depth + 1 < t.settings.max_depth;
        let m = &hit.material;
        let colour = match m.model {
            ShadingModel::Constant => m.emission,
            ShadingModel::Emissive => t.surface_emission(ray, hit, seen),
            ShadingModel::AmbientOcclusion => {
                let probes = if DISTRIBUTED { 1 } else { WHITTED_OCCLUSION_PROBES };
                let open = if t.effects.ambient_occlusion { t.occlusion(hit, self.time, probes, self.sampler, self.rays) } else { 1.0 };
                m.albedo * open
            }
            ShadingModel::Glass if (REFLECT || REFRACT) && deeper => self.glass(hit, wo, media, depth, weight),
            ShadingModel::Glass => Vec3::ZERO,
            ShadingModel::Mirror if REFLECT && deeper => {
                m.albedo * self.trace_on(hit, reflect(wo, hit.surface.shading_normal), Kind::Reflection, media, depth, weight * m.albedo.max_element())
            }
            ShadingModel::Mirror => Vec3::ZERO,
            ShadingModel::Glossy => {
                let bsdf = m.bsdf.expect("glossy materials scatter");
                let direct = t.direct(hit, &Tracer::scattering(hit, &bsdf, wo), self.time, self.known(depth), self.sampler, self.rays);
                let reflected = if REFLECT && deeper { self.glossy_reflection(hit, &bsdf, m.albedo, wo, media, depth, weight) } else { Vec3::ZERO };
                direct + reflected
            }
            ShadingModel::PhysicallyBased => {
                // Lit by the lights through the whole BSDF; the specular layer reflects the
                // scene too, as a glossy metal of the layer's colour does, and a transmitting
                // surface shows what is behind it, as glass does.
                let bsdf = media.bsdf(hit).expect("physically based materials scatter");
                let emitted = t.surface_emission(ray, hit, seen);
                let direct = t.direct(hit, &Tracer::scattering(hit, &bsdf, wo), self.time, self.known(depth), self.sampler, self.rays);
                let cos_o = wo.dot(hit.surface.shading_normal);
                let reflected = match bsdf.specular_layer(cos_o) {
                    Some((layer, mirror)) if REFLECT && deeper => self.glossy_reflection(hit, &layer, mirror, wo, media, depth, weight),
                    _ => Vec3::ZERO,
                };
                let transmitted = if REFRACT && deeper && bsdf.transmits() { self.transmission(hit, &bsdf, wo, media, depth, weight) } else { Vec3::ZERO };
                // A clear coat reflects the scene too; it and the sheen pass on the rest to what
                // is under them, as the BSDF scales it.
                let coat_reflected = match bsdf.coat_layer(cos_o) {
                    Some((lobe, coat, mirror)) if REFLECT && deeper => coat * self.glossy_reflection(hit, &lobe, Vec3::splat(mirror), wo, media, depth, weight * coat),
                    _ => Vec3::ZERO,
                };
                emitted + direct + reflected * bsdf.through_layers(cos_o) + transmitted + coat_reflected
            }
            ShadingModel::Diffuse | ShadingModel::VertexColor | ShadingModel::Phong => {
                let bsdf = m.bsdf.expect("matte materials scatter");
                t.direct(hit, &Tracer::scattering(hit, &bsdf, wo), self.time, self.known(depth), self.sampler, self.rays)
            }
        };
        colour * attenuation
    }

    /// The shadows known at a hit `depth` bounces from the camera.
    fn known(&self, depth: u32) -> KnownShadows {
        if depth == 0 { self.first_hit_shadows } else { KnownShadows::NONE }
    }

    /// Continues the recursion with a new ray of weight `weight` leaving `hit` in direction
    /// `dir`.
    fn trace_on(&mut self, hit: &Hit<'_>, dir: Vec3, kind: Kind, media: Media, depth: u32, weight: f32) -> Vec3 {
        let sp = &hit.surface;
        let ray = Ray::new(offset(sp, dir), dir);
        self.radiance(&ray, kind, media, depth + 1, weight)
    }

    /// Glossy reflection: Whitted takes the mirror direction scaled by `mirror`; the
    /// distributed variant samples the lobe `bsdf`.
    #[allow(clippy::too_many_arguments)]
    fn glossy_reflection(&mut self, hit: &Hit<'_>, bsdf: &Bsdf, mirror: Vec3, wo: Vec3, media: Media, depth: u32, weight: f32) -> Vec3 {
        let n = hit.surface.shading_normal;
        if !DISTRIBUTED {
            return mirror * self.trace_on(hit, reflect(wo, n), Kind::Glossy, media, depth, weight * mirror.max_element());
        }
        let frame3 = Frame3::around(n);
        let (u, choose) = (self.sampler.next_2d(), self.sampler.next_1d());
        match bsdf.sample(frame3.to_local(wo), u, choose) {
            Some(s) => s.weight * self.trace_on(hit, frame3.to_world(s.wi), Kind::Glossy, media, depth, weight * s.weight.max_element()),
            None => Vec3::ZERO,
        }
    }

    /// Light through a transmitting physically based surface: Whitted refracts one smooth ray
    /// (straight through a thin wall), with what a coat or sheen over it leaves; the distributed
    /// variant samples the BSDF and follows the samples that went through, weighted as the path
    /// tracer weighs them (unbiased for the transmitted light: the other samples stand for
    /// reflection, which [`Recursion::glossy_reflection`] and the lights already count).
    fn transmission(&mut self, hit: &Hit<'_>, bsdf: &Bsdf, wo: Vec3, media: Media, depth: u32, weight: f32) -> Vec3 {
        let frame3 = Frame3::around(hit.surface.shading_normal);
        let wo_local = frame3.to_local(wo);
        let through = if DISTRIBUTED {
            let (u, choose) = (self.sampler.next_2d(), self.sampler.next_1d());
            bsdf.sample(wo_local, u, choose).filter(|s| s.transmitted).map(|s| (s.wi, s.weight))
        } else {
            bsdf.smooth_transmission(wo_local).map(|(wi, tint)| (wi, tint * bsdf.through_layers(wo_local.z)))
        };
        let Some((wi, tint)) = through else { return Vec3::ZERO };
        tint * self.trace_on(hit, frame3.to_world(wi), Kind::Refraction, media.crossed(hit), depth, weight * tint.max_element())
    }

    /// Glass: Fresnel-weighted reflection and refraction (Whitted traces both for the first
    /// [`SPLIT_DEPTH`] bounces, then one; the distributed variant always picks one by its
    /// weight), total internal reflection, and the media the refracted ray enters or leaves.
    fn glass(&mut self, hit: &Hit<'_>, wo: Vec3, media: Media, depth: u32, weight: f32) -> Vec3 {
        let n = hit.surface.shading_normal;
        let Some(Bsdf::Glass { eta }) = media.bsdf(hit) else { unreachable!("glass has a glass boundary") };
        let frame3 = Frame3::around(n);
        let wo_local = frame3.to_local(wo);
        let f = fresnel_dielectric(wo_local.z, eta);
        let refracted = refract(wo_local, eta).map(|d| frame3.to_world(d));
        // Each branch scaled by its share of the light, which is also its weight in the pixel.
        let reflected = |this: &mut Self, share: f32| {
            if REFLECT && share > 0.0 {
                share * this.trace_on(hit, reflect(wo, n), Kind::Reflection, media, depth, weight * share)
            } else {
                Vec3::ZERO
            }
        };
        let transmitted = |this: &mut Self, dir: Vec3, share: f32| {
            if REFRACT && share > 0.0 {
                share * this.trace_on(hit, dir, Kind::Refraction, media.crossed(hit), depth, weight * share)
            } else {
                Vec3::ZERO
            }
        };
        match refracted {
            None => reflected(self, 1.0),
            Some(dir) if DISTRIBUTED || depth >= SPLIT_DEPTH => {
                // One branch, chosen with the probability of its share, stands for both.
                if self.sampler.next_1d() < f { reflected(self, 1.0) } else { transmitted(self, dir, 1.0) }
            }
            Some(dir) => reflected(self, f) + transmitted(self, dir, 1.0 - f),
        }
    }
}
