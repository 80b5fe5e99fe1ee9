//! Camera rays' first hits on matte surfaces under point, spot and directional lights, shaded
//! a packet at a time.
//!
//! In a Whitted or distribution frame lit only by such delta lights, a matte (Lambert)
//! first hit's colour is its ambient term plus, for each light it sees, the light's irradiance
//! times the BSDF's cosine-weighted value, and the packets of [`first_shadows`] already know
//! which lights it sees. That is what [`Tracer::direct`] computes for one hit at a time; here a
//! packet's hits go through it together, light by light, with the same arithmetic in the same
//! order, so the image is bit for bit the one the recursion would make (a test holds it to
//! that), while the hits' chains of square roots and divisions overlap instead of waiting on
//! each other, and no hit pays for the recursion's generality.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec3, Vec4};
use raystage_kernel::{PACKET_SIZE, Ray};

use super::Tracer;
use super::first_hits::FirstHits;
use super::first_shadows::{self, KnownShadows, MAX_LIGHTS};
use super::quads::{pack, quad, quads, unpack};
use crate::lights::Delta;

/// Whether this frame's matte first hits are shaded here: their shadows go in packets, and
/// every light is a point, spot or directional light among the first [`MAX_LIGHTS`] (so every
/// shadow is known, and no light is extended or met by rays).
pub(crate) fn applies(t: &Tracer<'_, '_>) -> bool {
    let n = t.lights.len();
    first_shadows::applies(t) && n <= MAX_LIGHTS && (0..n).all(|i| t.lights.delta(i).is_some())
}

/// The colours of the matte hits among up to [`PACKET_SIZE`] first hits `first` of camera rays
/// `rays`, whose shadows are `known`, and of the rays that hit nothing: `out[k]` for lane `k`,
/// `None` where the hit is not matte (or a rounding corner case needs a shadow that was not
/// traced), for the recursion to shade.
pub(crate) fn shade(t: &Tracer<'_, '_>, rays: &[Ray], first: &FirstHits<'_>, known: &[KnownShadows], out: &mut [Option<Vec3>]) {
    let n = rays.len();
    assert!(n <= PACKET_SIZE && known.len() == n && out.len() == n, "one ray, shadow set and answer per hit");
    let mut lanes = Lanes::default();
    let mut missed = 0u32;
    for (k, ray) in rays.iter().enumerate() {
        let Some(surface) = first.surfaces[k] else {
            missed |= 1 << k;
            continue;
        };
        let Some(albedo) = first.matte[k] else { continue };
        let shading_normal = surface.shading_normal;
        // As the recursion has it: `wo` from the ray, its cosine in the shading frame, and the
        // ambient term first.
        let wo = -ray.dir.normalize();
        lanes.matte[k] = true;
        lanes.position.set(k, surface.position);
        lanes.geometric_normal.set(k, surface.geometric_normal);
        lanes.shading_normal.set(k, shading_normal);
        lanes.albedo.set(k, albedo);
        lanes.wo_cos[k] = wo.dot(shading_normal);
        lanes.sum.set(k, t.lights.ambient() * albedo);
    }
    for index in 0..t.lights.len() {
        let light = t.lights.delta(index).expect("`applies` checked every light is a delta light");
        let mut visible = [0.0; PACKET_SIZE];
        let mut tested = [false; PACKET_SIZE];
        for (k, known) in known.iter().enumerate() {
            if let Some(seen) = known.get(index) {
                tested[k] = true;
                visible[k] = seen as u32 as f32;
            }
        }
        lanes.add(&light, &visible, &tested);
    }
    // Rays that hit nothing see the backdrop, as in the recursion, unless they meet an area
    // light on the way.
    let backdrop_only = missed != 0 && !t.lights.has_area();
    let backdrops = if backdrop_only { t.backdrops(rays, missed) } else { [Vec3::ZERO; PACKET_SIZE] };
    for (k, answer) in out.iter_mut().enumerate() {
        *answer = if backdrop_only && missed & (1 << k) != 0 { Some(backdrops[k]) } else { lanes.matte[k].then(|| lanes.sum.get(k)) };
    }
}

/// One value per hit of the packet.
type PerHit = [f32; PACKET_SIZE];

/// A vector per hit of the packet, by component.
#[derive(Clone, Copy, Debug, Default)]
struct PerHit3([PerHit; 3]);

impl PerHit3 {
    fn set(&mut self, k: usize, v: Vec3) {
        (self.0[0][k], self.0[1][k], self.0[2][k]) = (v.x, v.y, v.z);
    }

    fn get(&self, k: usize) -> Vec3 {
        Vec3::new(self.0[0][k], self.0[1][k], self.0[2][k])
    }
}

/// The packet's hits as the light loop needs them (zeros for the hits that are not matte).
#[derive(Clone, Copy, Debug, Default)]
struct Lanes {
    /// Whether the hit is matte (and every light so far had what it needed).
    matte: [bool; PACKET_SIZE],
    position: PerHit3,
    geometric_normal: PerHit3,
    shading_normal: PerHit3,
    /// The Lambert BSDF's albedo.
    albedo: PerHit3,
    /// Cosine between the direction to the camera and the shading normal.
    wo_cos: PerHit,
    /// Light reflected so far.
    sum: PerHit3,
}

impl Lanes {
    /// Adds what `light` reflects at every hit, given whether it is `visible` there (1 or 0),
    /// where that was `tested`: `Tracer::direct`'s arithmetic for one light sample, hit by hit,
    /// four hits at a time (the same correctly rounded operations in the same order).
    fn add(&mut self, light: &Delta, visible: &PerHit, tested: &[bool; PACKET_SIZE]) {
        // Per hit: the unit direction to the light, the light arriving (irradiance facing it),
        // and whether the sample exists at all (a point light not at the hit itself).
        let mut wi = PerHit3::default();
        let mut weighted = PerHit3::default();
        let mut exists = [true; PACKET_SIZE];
        match *light {
            Delta::Positional(light) => {
                let mut distance = [0.0; PACKET_SIZE];
                for lane in quads() {
                    let [dx, dy, dz] = [0, 1, 2].map(|c| Vec4::splat(light.position[c]) - quad(&self.position.0[c], lane));
                    let d = ((dx * dx) + (dy * dy) + (dz * dz)).sqrt();
                    for (c, v) in [dx, dy, dz].into_iter().enumerate() {
                        (v / d).write_to_slice(&mut wi.0[c][lane..]);
                    }
                    d.write_to_slice(&mut distance[lane..]);
                    unpack(d.cmpgt(Vec4::ZERO) & d.is_finite_mask(), &mut exists, lane);
                }
                // A point light's fade is 1, which leaves its intensity as it is.
                let fade: PerHit = match light.cone {
                    None => [1.0; PACKET_SIZE],
                    Some(cone) => std::array::from_fn(|k| cone.fade(wi.get(k))),
                };
                for lane in quads() {
                    let d = quad(&distance, lane);
                    let d2 = d * d;
                    for c in 0..3 {
                        ((Vec4::splat(light.intensity[c]) * quad(&fade, lane)) / d2).write_to_slice(&mut weighted.0[c][lane..]);
                    }
                }
            }
            Delta::Directional { towards, intensity } => {
                for k in 0..PACKET_SIZE {
                    wi.set(k, towards);
                    weighted.set(k, intensity);
                }
            }
        }
        self.reflect(&wi, &weighted, &exists, visible, tested);
    }

    /// Adds at every hit the light `weighted` arriving from unit direction `wi`, if the sample
    /// `exists` and reaches the surface's front, as the Lambert BSDF reflects it towards the
    /// camera.
    fn reflect(&mut self, wi: &PerHit3, weighted: &PerHit3, exists: &[bool; PACKET_SIZE], visible: &PerHit, tested: &[bool; PACKET_SIZE]) {
        let q3 = |v: &PerHit3, lane: usize| [0, 1, 2].map(|c| quad(&v.0[c], lane));
        for lane in quads() {
            let ([gx, gy, gz], [nx, ny, nz], [wx, wy, wz]) = (q3(&self.geometric_normal, lane), q3(&self.shading_normal, lane), q3(wi, lane));
            let w = q3(weighted, lane);
            let wi_cos = (wx * nx) + (wy * ny) + (wz * nz);
            // `max` as `if a > b { a } else { b }`, which `Vec4::max` is.
            let lit = pack(exists, lane)
                & w[0].max(w[1]).max(w[2]).cmpgt(Vec4::ZERO)
                & ((gx * wx) + (gy * wy) + (gz * wz)).cmpgt(Vec4::ZERO)
                & quad(&self.wo_cos, lane).cmpgt(Vec4::ZERO)
                & wi_cos.cmpgt(Vec4::ZERO);
            // Lit, by rounding, from a side the shadow packet took for turned away: the
            // recursion traces this shadow ray itself.
            unpack(pack(&self.matte, lane) & (pack(tested, lane) | !lit), &mut self.matte, lane);
            let f = wi_cos * Vec4::splat(FRAC_1_PI);
            for (c, weighted) in w.into_iter().enumerate() {
                let reflected = quad(&self.albedo.0[c], lane) * f * weighted * quad(visible, lane);
                (quad(&self.sum.0[c], lane) + Vec4::select(lit, reflected, Vec4::ZERO)).write_to_slice(&mut self.sum.0[c][lane..]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{Affine3A, Quat};
    use raystage_demo::shading::{box_mesh, sphere_mesh};
    use raystage_scene::{Background, Camera, Light, Mesh, ObjectKind, ParamValue, Scene, ShaderId, Texture};

    use super::*;
    use crate::bsdf::Bsdf;
    use crate::integrator::{Hit, recursive};
    use crate::lights::Seen;
    use crate::sampler::PixelSampler;
    use crate::stats::RayCounts;
    use crate::{Integrator, RenderSettings};

    fn place(scene: &mut Scene, mesh: Mesh, shader: ShaderId, to_world: Affine3A) {
        let object = scene.add_object(ObjectKind::Static, mesh.with_shader(shader)).unwrap();
        scene.add_instance(object, to_world).unwrap();
    }

    /// Matte spheres and a textured matte floor on a rotated, scaled instance, a Phong and a mirror
    /// sphere among them, lit by a point light, a spot light whose cone edge crosses the floor,
    /// a directional light and an ambient light.
    fn scene() -> Scene {
        let mut scene = Scene::new();
        let mut shader = |class: &str, colour: Vec3| {
            let id = scene.add_shader(class).unwrap();
            let name = if class == "Mirror" { "reflectance" } else { "diffuse" };
            scene.set_param(id, name, ParamValue::Color(colour)).unwrap();
            id
        };
        let (red, grey, phong, mirror) =
            (shader("Diffuse", Vec3::new(0.8, 0.2, 0.1)), shader("Diffuse", Vec3::splat(0.6)), shader("Phong", Vec3::splat(0.5)), shader("Mirror", Vec3::splat(0.9)));
        // The floor is textured: matte, but not plain matte, so its hits are resolved in full.
        let checker = scene.add_texture(Texture::Checker { a: Vec3::splat(0.9), b: Vec3::splat(0.3), scale: 2.0 }).unwrap();
        scene.set_param(grey, "diffuse_texture", ParamValue::Texture(Some(checker))).unwrap();
        place(&mut scene, sphere_mesh(Vec3::new(-1.2, 0.0, 0.0), 0.8, 24, 12), red, Affine3A::IDENTITY);
        place(&mut scene, sphere_mesh(Vec3::new(1.2, 0.0, 0.0), 0.8, 24, 12), phong, Affine3A::IDENTITY);
        place(&mut scene, sphere_mesh(Vec3::new(0.0, 0.3, -1.5), 0.7, 24, 12), mirror, Affine3A::IDENTITY);
        let tilted = Affine3A::from_scale_rotation_translation(Vec3::new(3.0, 0.5, 2.0), Quat::from_rotation_y(0.4), Vec3::new(0.0, -1.3, 0.0));
        place(&mut scene, box_mesh(Vec3::new(-2.0, -1.0, -2.0), Vec3::new(2.0, 0.0, 2.0)), grey, tilted);
        scene.add_light(Light::Point { position: Vec3::new(2.0, 4.0, 3.0), intensity: Vec3::splat(30.0) }).unwrap();
        let spot = Light::Spot { position: Vec3::new(-2.0, 3.0, 1.0), direction: Vec3::new(0.5, -1.0, -0.2), intensity: Vec3::new(20.0, 15.0, 10.0), cone_degrees: 30.0, falloff_degrees: 20.0 };
        scene.add_light(spot).unwrap();
        scene.add_light(Light::Directional { direction: Vec3::new(-0.4, -1.0, -0.3), intensity: Vec3::new(0.6, 0.55, 0.5) }).unwrap();
        scene.add_light(Light::Ambient { intensity: Vec3::splat(0.05) }).unwrap();
        scene.set_camera(Camera::look_at(Vec3::new(0.0, 1.5, 6.0), Vec3::new(0.0, -0.3, 0.0), Vec3::Y, 50.0).unwrap()).unwrap();
        scene
    }

    /// Every matte first hit the packet shades, and every miss, gets bit for bit the colour the
    /// recursion gives it, and the hits it leaves to the recursion are the ones that are not
    /// matte.
    #[test]
    fn matte_first_hits_shade_exactly_as_the_recursion_shades_them() {
        let scene = scene();
        let frame = scene.frame();
        let settings = RenderSettings { integrator: Integrator::Whitted, background: Some(Background::Sky), ..RenderSettings::default() };
        let t = Tracer::new(&frame, &settings, 1);
        assert!(applies(&t), "point, spot, directional and ambient lights only");
        let (width, height) = (96, 64);
        let camera = frame.camera().rays(width, height);
        let (mut matte, mut textured, mut left, mut suns, mut skies) = (0, 0, 0, 0, 0);
        for y in (0..height).step_by(2) {
            for x in (0..width).step_by(4) {
                let pixels: Vec<(u32, u32)> = (0..8).map(|i| (x + i % 4, y + i / 4)).collect();
                let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); PACKET_SIZE];
                camera.centre_rays(&pixels, &mut rays);
                let mut hits = [None; PACKET_SIZE];
                frame.intersect_many(&rays, &mut hits, 0.0);
                // Each hit resolved in full, as the recursion resolves it.
                let resolved: Vec<Option<Hit<'_>>> = hits.iter().zip(&rays).map(|(hit, ray)| hit.map(|hit| t.resolve(ray, hit, 0.0))).collect();
                let mut first = FirstHits::new();
                first.resolve(&t, &rays, &hits, 0.0);
                let mut counts = RayCounts::default();
                let mut known = [KnownShadows::NONE; PACKET_SIZE];
                first_shadows::trace(&t, &first, 0.0, &mut counts, &mut known);
                // The shadows towards the directional light are the recursion's own rays.
                let sun = 2;
                for (hit, known) in resolved.iter().zip(&known) {
                    let (Some(hit), Some(visible)) = (hit, known.get(sun)) else { continue };
                    let ls = t.lights.sample(sun, hit.surface.position, hit.surface.shading_normal, [0.5, 0.5], true).expect("a sun sample");
                    let through = t.transmittance(&hit.surface, ls.wi, ls.distance, 0.0, &mut counts);
                    assert_eq!(through, Vec3::splat(visible as u32 as f32), "shadow towards the sun");
                    suns += 1;
                }
                let mut shaded = [None; PACKET_SIZE];
                shade(&t, &rays, &first, &known, &mut shaded);
                for k in 0..PACKET_SIZE {
                    let Some(hit) = &resolved[k] else {
                        let expected = t.background(rays[k].dir, Seen::Directly);
                        let colour = shaded[k].expect("a miss shows the sky");
                        assert_eq!(colour.to_array().map(f32::to_bits), expected.to_array().map(f32::to_bits), "pixel {:?}", pixels[k]);
                        skies += 1;
                        continue;
                    };
                    let is_matte = matches!(hit.material.bsdf, Some(Bsdf::Lambert { .. }));
                    let Some(colour) = shaded[k] else {
                        assert!(!is_matte, "pixel {:?}: a matte hit left to the recursion", pixels[k]);
                        left += 1;
                        continue;
                    };
                    let mut sampler = PixelSampler::new(pixels[k].0, pixels[k].1, settings.seed, 0, settings.laid_out_for());
                    let expected = recursive::shade::<true, true, false>(&t, &rays[k], hit, 0.0, known[k], &mut sampler, &mut counts);
                    assert_eq!(colour.to_array().map(f32::to_bits), expected.to_array().map(f32::to_bits), "pixel {:?}", pixels[k]);
                    matte += 1;
                    textured += first.resolved[k].is_some() as u32;
                }
            }
        }
        assert!(
            matte > 2000 && textured > 1000 && matte - textured > 150 && left > 200 && suns > 2000 && skies > 100,
            "{matte} matte hits shaded in packets ({textured} textured), {left} left to the recursion, {suns} sun shadows, {skies} skies"
        );
    }
}
