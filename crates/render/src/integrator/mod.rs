//! Integrators: how a camera ray's colour is computed. Each one is a function of the ray that
//! uses the [`Tracer`] for everything it asks of the scene, so that rays are counted by kind and
//! only the effects in the frame's effect set are simulated.
//!
//! - [`eyelight`]: the fast preview, a light at the eye, no secondary rays;
//! - [`recursive`]: Whitted 1980, recursive shadows, reflection and refraction to a fixed depth,
//!   and Cook, Porter and Carpenter 1984, the same rays distributed over pixel area, lens,
//!   shutter time, light areas and glossy lobes, sharing each pixel sample;
//! - [`path`]: unbiased path tracing with next-event estimation, multiple importance sampling
//!   and Russian roulette.
//!
//! Beside the recursion, Whitted's and Cook's camera rays have two fast paths, kept because
//! each saves more than 10 % of a whole frame (docs/design/fast-paths.md): [`first_shadows`]
//! traces the first hits' shadow rays towards point, spot and directional lights as packets
//! (about 20 % of a sphere-grid frame), and [`first_matte`] shades matte first hits under such
//! lights a packet at a time (about 30 %), both from [`first_hits`]. Everything else goes through
//! the general path: each hit's geometry is [`Frame::surface`]'s, and the preview shades every
//! frame's packets as the camera rays come out of the tile's trace.

pub(crate) mod eyelight;
pub(crate) mod first_hits;
pub(crate) mod first_matte;
pub(crate) mod first_shadows;
pub(crate) mod path;
mod quads;
pub(crate) mod recursive;

use glam::Vec3;
use raystage_kernel::{PACKET_SIZE, Ray};
use raystage_scene::{Background, Frame, SceneHit, ShadingModel, SurfacePoint};

use crate::bsdf::{Bsdf, Scattering, fresnel_dielectric};
use crate::effects::EffectSet;
use crate::footprint::PixelFootprint;
use first_shadows::KnownShadows;
use crate::lights::{SceneLights, Seen};
use crate::material::{Material, Materials};
use crate::sampler::PixelSampler;
use crate::stats::RayCounts;
use crate::warp::{Frame3, cosine_hemisphere, power_heuristic};
use crate::sky::sky;
use crate::RenderSettings;

/// The deepest nesting of transmissive media a path keeps track of.
const MAX_MEDIA: usize = 4;

/// A hit and what is there.
#[derive(Clone, Copy)]
pub(crate) struct Hit<'f> {
    pub hit: SceneHit,
    pub surface: SurfacePoint<'f>,
    pub material: Material,
}

/// The media a ray is inside, innermost last: air, then every transmissive object it entered.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Media {
    ior: [f32; MAX_MEDIA],
    absorption: [Vec3; MAX_MEDIA],
    depth: usize,
}

impl Media {
    /// Air only.
    pub fn air() -> Media {
        Media { ior: [1.0; MAX_MEDIA], absorption: [Vec3::ZERO; MAX_MEDIA], depth: 1 }
    }

    /// Index of refraction of the medium the ray is in.
    pub fn ior(&self) -> f32 {
        self.ior[self.depth - 1]
    }

    /// Index of refraction of the medium around the one the ray is in.
    pub fn outer_ior(&self) -> f32 {
        self.ior[self.depth.saturating_sub(2)]
    }

    /// Beer's law: the fraction of light that survives `distance` in the current medium.
    pub fn attenuation(&self, distance: f32) -> Vec3 {
        let sigma = self.absorption[self.depth - 1];
        if sigma == Vec3::ZERO { Vec3::ONE } else { (-sigma * distance).exp() }
    }

    /// The media after crossing a transmissive boundary at `hit`: entering through its front,
    /// leaving through its back (a thin wall bounds no medium).
    pub fn crossed(mut self, hit: &Hit<'_>) -> Media {
        if hit.material.bsdf.is_some_and(|b| b.is_thin()) {
            return self;
        }
        if hit.surface.front_face {
            if self.depth < MAX_MEDIA {
                self.ior[self.depth] = hit.material.ior;
                self.absorption[self.depth] = hit.material.absorption;
                self.depth += 1;
            }
        } else if self.depth > 1 {
            self.depth -= 1;
        }
        self
    }

    /// The BSDF at `hit` between these media: a boundary's relative index is that of the side
    /// the ray is on over the other side (a thin wall has the medium the ray is in on both
    /// sides). `None` for a material that does not scatter.
    pub fn bsdf(&self, hit: &Hit<'_>) -> Option<Bsdf> {
        let m = &hit.material;
        let thin = m.bsdf.is_some_and(|b| b.is_thin());
        let eta = if hit.surface.front_face || thin { self.ior() / m.ior } else { m.ior / self.outer_ior() };
        match m.model {
            ShadingModel::Glass => Some(Bsdf::Glass { eta }),
            _ => m.bsdf.map(|b| b.across(eta)),
        }
    }
}

/// What camera rays that hit nothing show, and rays that only mirrors and glass bent on their
/// way from the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Backdrop {
    /// The environment light, as it lights the scene.
    Environment,
    /// The sky gradient.
    Sky,
    /// One colour (black for a scene that brings its own light and no environment).
    Color(Vec3),
}

/// Access to the scene for the integrators.
pub(crate) struct Tracer<'a, 'f> {
    pub frame: &'a Frame<'f>,
    pub lights: SceneLights<'f>,
    pub materials: Materials<'f>,
    pub effects: EffectSet,
    pub settings: &'a RenderSettings,
    pub backdrop: Backdrop,
}

impl<'a, 'f> Tracer<'a, 'f> {
    /// Everything the integrators need of `frame`, resolved when the frame starts, for a pass
    /// that brings the pixels to `samples` samples: its materials, its lights (emitting
    /// triangles among them, and the default sky if nothing lights the scene and the settings
    /// allow it), the effects they call for, and the backdrop: the settings', else the scene's
    /// environment light, else the scene's backdrop, else the sky where the default lights it,
    /// and black.
    pub fn new(frame: &'a Frame<'f>, settings: &'a RenderSettings, samples: u32) -> Tracer<'a, 'f> {
        // Image textures are filtered over a pixel's footprint at the frame's samples per pixel.
        let footprint = PixelFootprint::new(frame.camera().rays(settings.width, settings.height), settings.samples_per_pixel);
        let materials = Materials::of(frame, footprint);
        let lights = SceneLights::of(frame, &materials, settings.light_samples, settings.default_lights);
        let effects = EffectSet::of(frame, &lights, settings.integrator, samples);
        // An environment of the scene's own shows, as in Cycles and Mitsuba, unless the
        // settings say otherwise; the scene's backdrop shows where there is none.
        let chosen = match settings.background {
            Some(b) => Some(b),
            None if lights.has_environment() && !lights.defaulted() => None,
            None => frame.background(),
        };
        let backdrop = match chosen {
            Some(Background::Sky) => Backdrop::Sky,
            Some(Background::Color(c)) => Backdrop::Color(c),
            None if lights.defaulted() => Backdrop::Sky,
            None if lights.has_environment() => Backdrop::Environment,
            None => Backdrop::Color(Vec3::ZERO),
        };
        Tracer { frame, lights, materials, effects, settings, backdrop }
    }
}

impl<'f> Tracer<'_, 'f> {
    /// The closest hit of `ray` at shutter time `time`, counted as a ray of `kind`.
    pub fn trace(&self, ray: &Ray, time: f32, kind: &mut u64) -> Option<Hit<'f>> {
        *kind += 1;
        let hit = self.frame.intersect(ray, time)?;
        Some(self.resolve(ray, hit, time))
    }

    /// What is at a hit of `ray` found elsewhere (camera rays are traced in packets).
    pub fn resolve(&self, ray: &Ray, hit: SceneHit, time: f32) -> Hit<'f> {
        self.resolve_at(ray, hit, self.frame.surface(ray, &hit, time), time)
    }

    /// [`Tracer::resolve`] of a hit whose `surface` is computed already.
    pub fn resolve_at(&self, ray: &Ray, hit: SceneHit, mut surface: SurfacePoint<'f>, time: f32) -> Hit<'f> {
        let footprint = self.materials.footprint(&surface, |set| self.frame.texture_density(&hit, time, set));
        let material = self.materials.at(&surface, footprint);
        // A normal the map turns away from the viewer would shade the point black (nothing it
        // reflects reaches the viewer): the unmapped normal shades there, as where the map turns
        // it to the surface's far side.
        if let Some(n) = self.materials.mapped_normal(&surface, footprint, |set| self.frame.tangent(&hit, time, set))
            && n.dot(ray.dir) < 0.0
        {
            surface.shading_normal = n;
        }
        Hit { hit, surface, material }
    }

    /// What a ray in direction `dir` that hits nothing brings back, as it was `seen`: seen
    /// directly (a camera ray, or one that only mirrors and glass bent on its way from the
    /// camera), the backdrop; otherwise the environment light, if there is one.
    pub fn background(&self, dir: Vec3, seen: Seen) -> Vec3 {
        match (seen, self.backdrop) {
            (Seen::Directly, Backdrop::Sky) => sky(dir),
            (Seen::Directly, Backdrop::Color(c)) => c,
            _ if self.lights.has_environment() => self.lights.environment(dir.normalize(), seen),
            _ => Vec3::ZERO,
        }
    }

    /// [`Tracer::background`] of the camera rays among up to a packet of `rays` that hit
    /// nothing (bit `k` of `missed` for `rays[k]`; the others get black).
    pub fn backdrops(&self, rays: &[Ray], missed: u32) -> [Vec3; PACKET_SIZE] {
        std::array::from_fn(|k| if missed & (1 << k) != 0 { self.background(rays[k].dir, Seen::Directly) } else { Vec3::ZERO })
    }

    /// Light the surface at `hit` emits back along `ray`, as the ray was `seen` (see
    /// [`SceneLights::surface_emission`]): from its front, and from its back where its shader
    /// emits there too ([`Materials::emits_behind`]).
    pub fn surface_emission(&self, ray: &Ray, hit: &Hit<'_>, seen: Seen) -> Vec3 {
        let m = &hit.material;
        if !crate::material::emits(m.model) || m.emission == Vec3::ZERO || !(hit.surface.front_face || self.materials.emits_behind(hit.surface.shader_id)) {
            return Vec3::ZERO;
        }
        let length = ray.dir.length();
        // The geometric normal faces the side the ray came from.
        let cos = hit.surface.geometric_normal.dot(-ray.dir / length);
        let picked_by = self.materials.emission(hit.surface.shader_id).unwrap_or(m.emission);
        self.lights.surface_emission(m.emission, picked_by, hit.hit.t * length, cos, seen)
    }

    /// Light from area lights that `ray` meets before its hit at `t` (infinitely far if it hits
    /// nothing), as it was `seen`.
    pub fn emission(&self, ray: &Ray, t: Option<f32>, seen: Seen) -> Vec3 {
        if !self.lights.has_area() {
            return Vec3::ZERO;
        }
        let length = ray.dir.length();
        let tmax = t.map_or(f32::INFINITY, |t| t * length);
        self.lights.emission_along(ray.origin, ray.dir / length, tmax, seen)
    }

    /// The fraction of light arriving at surface point `sp` from `distance` away in
    /// direction `wi`: 0 or 1 for opaque occluders; with transparent shadows, transmissive
    /// surfaces on the way let through what Fresnel and Beer's law leave.
    pub fn transmittance(&self, sp: &SurfacePoint<'_>, wi: Vec3, distance: f32, time: f32, rays: &mut RayCounts) -> Vec3 {
        let mut ray = Ray::segment(offset(sp, wi), wi, 0.0, shorten(distance));
        if !self.effects.transparent_shadows {
            rays.shadow += 1;
            return if self.frame.occluded(&ray, time) { Vec3::ZERO } else { Vec3::ONE };
        }
        let mut through = Vec3::ONE;
        let mut inside_since: Option<(f32, Vec3)> = None;
        let mut travelled = 0.0;
        for _ in 0..8 * MAX_MEDIA {
            rays.shadow += 1;
            let Some(hit) = self.frame.intersect(&ray, time) else { return through };
            let surface = self.frame.surface(&ray, &hit, time);
            // Only whether it is glass, and its index and absorption, matter: no footprint.
            let material = self.materials.at(&surface, [0.0; 2]);
            if material.model != ShadingModel::Glass {
                return Vec3::ZERO;
            }
            let at = travelled + hit.t;
            through *= 1.0 - fresnel_dielectric(surface.geometric_normal.dot(-wi).abs(), 1.0 / material.ior);
            match (surface.front_face, inside_since) {
                (true, _) => inside_since = Some((at, material.absorption)),
                (false, Some((entered, sigma))) => through *= (-sigma * (at - entered)).exp(),
                (false, None) => {}
            }
            travelled = at;
            let origin = offset(&surface, wi);
            ray = Ray::segment(origin, wi, 0.0, (shorten(distance) - travelled).max(0.0));
        }
        through
    }

    /// Light from every light source reflected towards `wo` at `hit` (no emission): the ambient
    /// term, then each light sampled (extended lights at `light_samples` random points when the
    /// frame has soft shadows, else once at their centre), each sample tested with a shadow ray
    /// if the frame has shadows. In the path tracer, samples of extended lights are weighted
    /// against the BSDF sampling that could also find them (multiple importance sampling).
    /// Shadows already `known` (traced in packets for a camera ray's first hit) are not traced
    /// again.
    /// `scattering` is the surface's function seen from the viewer, in the shading frame
    /// ([`Tracer::scattering`]).
    pub fn direct(&self, hit: &Hit<'f>, scattering: &Scattering, time: f32, known: KnownShadows, sampler: &mut PixelSampler, rays: &mut RayCounts) -> Vec3 {
        let sp = &hit.surface;
        let frame3 = Frame3::around(sp.shading_normal);
        let mut sum = self.lights.ambient() * hit.material.albedo;
        let random = self.effects.area_lights;
        for index in 0..self.lights.len() {
            let samples = if random && self.lights.is_extended(index) { self.settings.light_samples } else { 1 };
            // Emitting triangles have no one centre to aim Whitted's rays at: they take random
            // points even there.
            let stochastic = (random && self.lights.is_extended(index)) || self.lights.is_emitters(index);
            let mut light = Vec3::ZERO;
            for _ in 0..samples {
                let u = if stochastic { sampler.next_2d() } else { [0.5, 0.5] };
                let Some(ls) = self.lights.sample(index, sp.position, sp.shading_normal, u, !random) else { continue };
                // Light from behind the surface reaches only what lets it through.
                if sp.geometric_normal.dot(ls.wi) <= 0.0 && !scattering.bsdf().transmits() {
                    continue;
                }
                let (f, pdf) = scattering.eval_pdf(frame3.to_local(ls.wi));
                if f == Vec3::ZERO {
                    continue;
                }
                let weight = if ls.pdf > 0.0 && self.effects.global_illumination { power_heuristic(samples as f32 * ls.pdf, pdf) } else { 1.0 };
                let visible = match known.get(index) {
                    Some(visible) => Vec3::splat(visible as u32 as f32),
                    None if self.effects.shadows => self.transmittance(sp, ls.wi, ls.distance, time, rays),
                    None => Vec3::ONE,
                };
                light += f * ls.weighted * visible * weight;
            }
            sum += light / samples as f32;
        }
        sum
    }

    /// `bsdf` at `hit` seen from `wo` (a world direction), in the hit's shading frame.
    pub fn scattering(hit: &Hit<'f>, bsdf: &Bsdf, wo: Vec3) -> Scattering {
        bsdf.towards(Frame3::around(hit.surface.shading_normal).to_local(wo))
    }

    /// Ambient occlusion at `hit`: the fraction of `samples` cosine-distributed probes that
    /// leave without meeting anything within `distance`.
    pub fn occlusion(&self, hit: &Hit<'f>, time: f32, samples: u32, sampler: &mut PixelSampler, rays: &mut RayCounts) -> f32 {
        let sp = &hit.surface;
        let frame3 = Frame3::around(sp.geometric_normal);
        let open = (0..samples)
            .filter(|_| {
                let wi = frame3.to_world(cosine_hemisphere(sampler.next_2d()));
                rays.diffuse += 1;
                let probe = Ray::segment(offset(sp, wi), wi, 0.0, hit.material.occlusion_distance);
                !self.frame.occluded(&probe, time)
            })
            .count();
        open as f32 / samples.max(1) as f32
    }

}

/// A secondary ray's origin: the hit point pushed off the surface along its geometric normal,
/// towards the side `dir` leaves on, by the bound of the point's rounding error (pbrt-v4's
/// `OffsetRayOrigin`, see [`SurfacePoint::spawn_origin`]): a few ulps of the point's own
/// coordinates, so the ray neither re-hits the surface it starts on nor skips a wall next to it,
/// at a millimetre or a million units from the origin.
#[inline]
pub(crate) fn offset(sp: &SurfacePoint<'_>, dir: Vec3) -> Vec3 {
    sp.spawn_origin(dir)
}

/// A shadow ray's extent: a little short of the light (pbrt's `ShadowEpsilon`, 10⁻⁴ of the
/// distance), so it does not hit geometry that the light sits on or pass through the point it
/// was aimed at.
fn shorten(distance: f32) -> f32 {
    if distance.is_finite() { distance * (1.0 - 1e-4) } else { f32::INFINITY }
}
