//! The preview shading of the retained scene: Lambertian reflection of every light with hard
//! shadows, until the shading library arrives. A scene without lights is lit from the eye, so
//! that whatever is in it can be looked at.

use glam::Vec3;
use raystage_kernel::Ray;
use raystage_scene::{Frame, SceneHit, ShadingModel, SurfacePoint};

/// Light reaching a surface seen edge-on under the eye light, so that silhouettes stay visible.
const EYE_AMBIENT: f32 = 0.15;

/// Rays a shaded pixel cost, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Camera rays.
    pub primary: u64,
    /// Shadow rays towards lights.
    pub shadow: u64,
}

impl std::ops::AddAssign for RayCounts {
    fn add_assign(&mut self, o: RayCounts) {
        self.primary += o.primary;
        self.shadow += o.shadow;
    }
}

/// The colour (linear RGB) of `hit` of `ray`, adding the shadow rays it traced to `rays`.
pub fn shade(frame: &Frame<'_>, ray: &Ray, hit: &SceneHit, rays: &mut RayCounts) -> Vec3 {
    let surface = frame.surface(ray, hit, 0.0);
    let albedo = match surface.shader.class().model {
        ShadingModel::Constant => return surface.shader.color("color"),
        ShadingModel::Diffuse => surface.shader.color("diffuse"),
        ShadingModel::VertexColor => surface.shader.color("diffuse") * surface.color.unwrap_or(Vec3::ONE),
    };
    if frame.lights().is_empty() {
        let cos = surface.shading_normal.dot(ray.dir.normalize()).abs();
        return albedo * (EYE_AMBIENT + (1.0 - EYE_AMBIENT) * cos);
    }
    albedo * direct_light(frame, &surface, rays)
}

/// Irradiance over π from every light that sees the point: Σ E·cos θ / π, each light tested
/// with a shadow ray.
fn direct_light(frame: &Frame<'_>, surface: &SurfacePoint<'_>, rays: &mut RayCounts) -> Vec3 {
    let origin = offset_origin(surface.position, surface.geometric_normal);
    frame
        .lights()
        .iter()
        .map(|light| {
            let (to_light, distance, irradiance) = light.sample(surface.position);
            let cos = surface.shading_normal.dot(to_light);
            if cos <= 0.0 || surface.geometric_normal.dot(to_light) <= 0.0 {
                return Vec3::ZERO;
            }
            rays.shadow += 1;
            let shadow = Ray::segment(origin, to_light, 0.0, distance * (1.0 - 1e-4));
            if frame.occluded(&shadow, 0.0) { Vec3::ZERO } else { irradiance * cos * std::f32::consts::FRAC_1_PI }
        })
        .sum()
}

/// A shadow ray's origin: the hit point pushed off the surface along its normal, by an amount
/// that grows with the point's magnitude (the floating-point spacing there), so the ray does not
/// hit the surface it starts on.
fn offset_origin(p: Vec3, n: Vec3) -> Vec3 {
    p + n * (1e-4 * p.abs().max_element().max(1.0))
}
