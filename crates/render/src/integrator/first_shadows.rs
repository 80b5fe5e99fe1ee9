//! Shadow rays from camera rays' first hits towards point, spot and directional lights, traced
//! in packets.
//!
//! Whitted's and Cook's recursions send a shadow ray from every lit hit to every light. Towards
//! a point or spot light, the rays of neighbouring pixels all end at one point, the light:
//! traced backwards from it, they share their origin and go through the scene as one packet
//! ([`raystage_scene::Frame::occluded_many`]), sharing its node tests, as camera rays do.
//! Towards a directional light they are parallel, which makes a packet as well; they are the
//! very rays the recursion would trace. The recursion then looks up the answer at its first hit
//! instead of tracing the ray there (deeper hits, fewer and incoherent, trace their own).
//!
//! A backward ray covers the forward ray's segment: it starts a ten-thousandth of the distance
//! from the light, where the forward ray stops (see `shorten`), and stops the same fraction
//! short of the hit's spawned origin, as pbrt-v4's `SpawnRayTo` does between two surfaces.
//! What it can miss lies within that sliver at the surface, far above rounding error.

use glam::Vec3;
use raystage_kernel::{PACKET_SIZE, Ray};

use super::Tracer;
use super::first_hits::FirstHits;
use crate::Integrator;
use crate::lights::Delta;
use crate::stats::RayCounts;

/// The fraction of a shadow segment left off at each end.
const END_GAP: f32 = 1e-4;

/// Lights numbered below this can have their shadows known (one bit each).
pub(crate) const MAX_LIGHTS: usize = 32;

/// What is known about the shadows at one hit: for each light whose bit is set in `tested`,
/// whether it is visible.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct KnownShadows {
    tested: u32,
    visible: u32,
}

impl KnownShadows {
    /// Nothing known: every shadow ray is traced where it is needed.
    pub const NONE: KnownShadows = KnownShadows { tested: 0, visible: 0 };

    /// Whether light `index` is visible, if that is known.
    pub fn get(&self, index: usize) -> Option<bool> {
        (index < MAX_LIGHTS && self.tested & (1 << index) != 0).then(|| self.visible & (1 << index) != 0)
    }
}

/// Whether this frame's first hits get their shadows in packets: opaque shadows (transparent
/// ones are traced through glass ray by ray), one shutter time for all rays, a recursive
/// integrator, and a point, spot or directional light among the first [`MAX_LIGHTS`].
pub(crate) fn applies(t: &Tracer<'_, '_>) -> bool {
    let e = t.effects;
    e.shadows
        && !e.transparent_shadows
        && !e.motion_blur
        && matches!(t.settings.integrator, Integrator::Whitted | Integrator::Distribution)
        && (0..t.lights.len().min(MAX_LIGHTS)).any(|i| t.lights.delta(i).is_some())
}

/// The shadows of up to [`PACKET_SIZE`] first hits (at shutter time `time`) towards every point
/// and spot light, `out[k]` for lane `k` of `first`: each light's rays traced as one packet,
/// only from hits whose material takes direct light and that face the light.
pub(crate) fn trace(t: &Tracer<'_, '_>, first: &FirstHits<'_>, time: f32, rays: &mut RayCounts, out: &mut [KnownShadows]) {
    assert!(out.len() <= PACKET_SIZE, "at most a packet");
    out.fill(KnownShadows::NONE);
    for light in 0..t.lights.len().min(MAX_LIGHTS) {
        let Some(delta) = t.lights.delta(light) else { continue };
        let mut segments = [Ray::new(Vec3::ZERO, Vec3::X); PACKET_SIZE];
        let mut owners = [0usize; PACKET_SIZE];
        let mut n = 0;
        for k in 0..out.len() {
            if first.lit & (1 << k) == 0 {
                continue;
            }
            // A lit hit is a hit: its surface is there.
            let Some(surface) = &first.surfaces[k] else { continue };
            let normal = surface.geometric_normal;
            segments[n] = match delta {
                Delta::Positional(light) => {
                    // The direction need not be a unit vector: only its side of the surface
                    // matters, to `direct` and to the spawned origin. A ray traced for a light
                    // that `direct` then finds dark (a spot light's cone facing away) is wasted,
                    // never wrong: `direct` traces whatever it needs and finds no answer for.
                    let towards = light.position - surface.position;
                    if normal.dot(towards) <= 0.0 {
                        continue;
                    }
                    let origin = surface.spawn_origin(towards);
                    Ray::segment(light.position, origin - light.position, END_GAP, 1.0 - END_GAP)
                }
                // The ray `Tracer::transmittance` traces, for the hits `direct` traces it from.
                Delta::Directional { towards, .. } => {
                    if normal.dot(towards) <= 0.0 {
                        continue;
                    }
                    Ray::segment(surface.spawn_origin(towards), towards, 0.0, f32::INFINITY)
                }
            };
            owners[n] = k;
            n += 1;
        }
        if n == 0 {
            continue;
        }
        rays.shadow += n as u64;
        let blocked = t.frame.occluded_many(&segments[..n], time);
        for (j, &k) in owners[..n].iter().enumerate() {
            out[k].tested |= 1 << light;
            if blocked & (1 << j) == 0 {
                out[k].visible |= 1 << light;
            }
        }
    }
}
