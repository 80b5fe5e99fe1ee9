//! The first hits of a packet of camera rays, resolved only as far as their shadows and their
//! shading need.
//!
//! The geometry of every hit is [`Frame::surface`](raystage_scene::Frame::surface)'s, kept for
//! [`first_shadows`](super::first_shadows) and [`first_matte`](super::first_matte). A hit on a
//! plain matte surface (an untextured `Diffuse` shader, the common case) needs nothing more: its
//! albedo is the shader's. Every other hit is resolved in full, as the recursion that shades it
//! needs it.

use glam::Vec3;
use raystage_kernel::{PACKET_SIZE, Ray};
use raystage_scene::{SceneHit, ShadingModel, SurfacePoint};

use super::{Hit, Tracer};
use crate::bsdf::Bsdf;

/// Up to [`PACKET_SIZE`] first hits, lane `k` for the hit of camera ray `k`. Of a packet shorter
/// than [`PACKET_SIZE`] rays, only the lanes of its rays are read: the others may still hold an
/// earlier packet's hits.
pub(crate) struct FirstHits<'f> {
    /// The geometry of every hit (`None` for a ray that hit nothing).
    pub surfaces: [Option<SurfacePoint<'f>>; PACKET_SIZE],
    /// The hits resolved in full: those whose material is not plain matte.
    pub resolved: [Option<Hit<'f>>; PACKET_SIZE],
    /// The hits whose material is lit by `Tracer::direct` (bit `k` for lane `k`).
    pub lit: u32,
    /// The albedo of the hits on Lambertian surfaces (`Diffuse` and `VertexColor`, textured
    /// or not): the colour of both their ambient term and their BSDF.
    pub matte: [Option<Vec3>; PACKET_SIZE],
}

impl<'f> FirstHits<'f> {
    /// No hits yet: a buffer that [`FirstHits::resolve`] fills packet after packet.
    pub fn new() -> FirstHits<'f> {
        FirstHits { surfaces: [None; PACKET_SIZE], resolved: [None; PACKET_SIZE], lit: 0, matte: [None; PACKET_SIZE] }
    }

    /// The first hits `hits` of camera rays `rays` at shutter time `time`, in place of the
    /// last packet's.
    pub fn resolve(&mut self, t: &Tracer<'_, 'f>, rays: &[Ray], hits: &[Option<SceneHit>], time: f32) {
        self.lit = 0;
        for (k, hit) in hits.iter().enumerate() {
            self.surfaces[k] = None;
            self.resolved[k] = None;
            self.matte[k] = None;
            let Some(hit) = hit else { continue };
            let surface = t.frame.surface(&rays[k], hit, time);
            self.surfaces[k] = Some(surface);
            if let Some(albedo) = t.materials.plain_matte(surface.shader_id) {
                self.lit |= 1 << k;
                self.matte[k] = Some(albedo);
                continue;
            }
            let full = t.resolve_at(&rays[k], *hit, surface, time);
            if takes_direct_light(full.material.model) {
                self.lit |= 1 << k;
            }
            if let (ShadingModel::Diffuse | ShadingModel::VertexColor, Some(Bsdf::Lambert { albedo })) = (full.material.model, full.material.bsdf) {
                self.matte[k] = Some(albedo);
            }
            self.resolved[k] = Some(full);
        }
    }
}

/// The shading models whose hits the recursion lights with `Tracer::direct`.
fn takes_direct_light(model: ShadingModel) -> bool {
    matches!(model, ShadingModel::Diffuse | ShadingModel::VertexColor | ShadingModel::Phong | ShadingModel::Glossy | ShadingModel::PhysicallyBased)
}
