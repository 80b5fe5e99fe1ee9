//! Scattering functions: how much light a surface reflects or transmits from one direction to
//! another, and how to sample that. Directions are in the shading frame (`z` the normal) and
//! point away from the surface; `wo` is towards the viewer.
//!
//! The models follow the seed's ray tracing chapter (Shirley: Lambert, Phong, mirror reflection,
//! Snell refraction, Schlick's Fresnel approximation for metals and the exact dielectric Fresnel
//! equations, DIGEST §1.6) and, for rough metal, the GGX microfacet distribution with visible-normal
//! sampling (Heitz 2018), so that the path tracer's estimates stay unbiased.

use glam::Vec3;

use crate::warp::{cosine_hemisphere, concentric_disc};

/// A sampled scattering direction.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BsdfSample {
    /// The new direction (away from the surface).
    pub wi: Vec3,
    /// BSDF × |cos θi| / pdf: the weight the sample carries.
    pub weight: Vec3,
    /// Density of `wi`, or 0 for a delta (specular) lobe.
    pub pdf: f32,
    /// Whether the ray went through the surface.
    pub transmitted: bool,
}

/// A surface's scattering function.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Bsdf {
    /// Ideal diffuse reflection.
    Lambert { albedo: Vec3 },
    /// Lambert plus a normalised Blinn-Phong lobe: (n + 2) / 8π · cos^n of the half vector.
    Phong { diffuse: Vec3, specular: Vec3, exponent: f32 },
    /// A perfect mirror.
    Mirror { reflectance: Vec3 },
    /// GGX microfacet metal with Schlick's Fresnel term.
    Glossy { reflectance: Vec3, alpha: f32 },
    /// A smooth dielectric boundary; `eta` is the index of refraction on the side `wo` is on
    /// over the index on the other side.
    Glass { eta: f32 },
}

impl Bsdf {
    /// Whether the function is a delta (cannot be evaluated for a given pair of directions).
    pub fn is_specular(&self) -> bool {
        matches!(self, Bsdf::Mirror { .. } | Bsdf::Glass { .. })
    }

    /// BSDF × cos θi for the pair of directions (zero for delta lobes).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        match *self {
            Bsdf::Lambert { albedo } => albedo * (wi.z * std::f32::consts::FRAC_1_PI),
            Bsdf::Phong { diffuse, specular, exponent } => {
                let h = (wo + wi).normalize();
                let lobe = (exponent + 2.0) / (8.0 * std::f32::consts::PI) * h.z.max(0.0).powf(exponent);
                (diffuse * std::f32::consts::FRAC_1_PI + specular * lobe) * wi.z
            }
            Bsdf::Glossy { reflectance, alpha } => {
                let h = (wo + wi).normalize();
                let f = schlick(reflectance, wo.dot(h));
                f * (ggx_d(h, alpha) * smith_g1(wo, alpha) * smith_g1(wi, alpha) / (4.0 * wo.z))
            }
            Bsdf::Mirror { .. } | Bsdf::Glass { .. } => Vec3::ZERO,
        }
    }

    /// Density with which [`Bsdf::sample`] picks `wi` given `wo` (0 for delta lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        match *self {
            Bsdf::Lambert { .. } => wi.z * std::f32::consts::FRAC_1_PI,
            Bsdf::Phong { diffuse, specular, exponent } => {
                let p = phong_specular_probability(diffuse, specular);
                let h = (wo + wi).normalize();
                let lobe = (exponent + 1.0) / (2.0 * std::f32::consts::PI) * h.z.powf(exponent) / (4.0 * wo.dot(h));
                (1.0 - p) * wi.z * std::f32::consts::FRAC_1_PI + p * lobe
            }
            Bsdf::Glossy { alpha, .. } => {
                let h = (wo + wi).normalize();
                ggx_d(h, alpha) * smith_g1(wo, alpha) / (4.0 * wo.z)
            }
            Bsdf::Mirror { .. } | Bsdf::Glass { .. } => 0.0,
        }
    }

    /// Samples a direction for `wo` from two uniform numbers (and a third for choosing a lobe).
    pub fn sample(&self, wo: Vec3, u: [f32; 2], choose: f32) -> Option<BsdfSample> {
        match *self {
            Bsdf::Lambert { albedo } => {
                if wo.z <= 0.0 {
                    return None;
                }
                let wi = cosine_hemisphere(u);
                Some(BsdfSample { wi, weight: albedo, pdf: wi.z * std::f32::consts::FRAC_1_PI, transmitted: false })
            }
            Bsdf::Phong { diffuse, specular, exponent } => {
                if wo.z <= 0.0 {
                    return None;
                }
                let wi = if choose < phong_specular_probability(diffuse, specular) {
                    // Half vector with density (n + 1)/2π cos^n, reflected about.
                    let cos = u[0].powf(1.0 / (exponent + 1.0));
                    let sin = (1.0 - cos * cos).max(0.0).sqrt();
                    let phi = std::f32::consts::TAU * u[1];
                    let h = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                    reflect(wo, h)
                } else {
                    cosine_hemisphere(u)
                };
                let pdf = self.pdf(wo, wi);
                (pdf > 0.0).then(|| BsdfSample { wi, weight: self.eval(wo, wi) / pdf, pdf, transmitted: false })
            }
            Bsdf::Mirror { reflectance } => {
                (wo.z > 0.0).then(|| BsdfSample { wi: Vec3::new(-wo.x, -wo.y, wo.z), weight: reflectance, pdf: 0.0, transmitted: false })
            }
            Bsdf::Glossy { reflectance, alpha } => {
                if wo.z <= 0.0 {
                    return None;
                }
                let h = sample_visible_normal(wo, alpha, u);
                let wi = reflect(wo, h);
                if wi.z <= 0.0 {
                    return None;
                }
                // With visible-normal sampling the weight is F · G1(wi).
                let weight = schlick(reflectance, wo.dot(h)) * smith_g1(wi, alpha);
                Some(BsdfSample { wi, weight, pdf: self.pdf(wo, wi), transmitted: false })
            }
            Bsdf::Glass { eta } => {
                if wo.z <= 0.0 {
                    return None;
                }
                // Reflect with Fresnel's probability, else refract (always reflect under total
                // internal reflection, where the reflectance is 1).
                if choose < fresnel_dielectric(wo.z, eta) {
                    return Some(BsdfSample { wi: Vec3::new(-wo.x, -wo.y, wo.z), weight: Vec3::ONE, pdf: 0.0, transmitted: false });
                }
                let wi = refract(wo, eta)?;
                Some(BsdfSample { wi, weight: Vec3::ONE, pdf: 0.0, transmitted: true })
            }
        }
    }
}

/// Probability that a Phong sample picks the specular lobe: its share of the reflectance.
fn phong_specular_probability(diffuse: Vec3, specular: Vec3) -> f32 {
    let (d, s) = (diffuse.max_element(), specular.max_element());
    if d + s > 0.0 { s / (d + s) } else { 0.0 }
}

/// `w` reflected about the normal `n` (both away from the surface).
pub(crate) fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    2.0 * w.dot(n) * n - w
}

/// `wo` (above the surface, z > 0) refracted through a boundary of relative index `eta`
/// (outside / inside) into the lower half-space; `None` under total internal reflection.
pub(crate) fn refract(wo: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = wo.z;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(Vec3::new(-eta * wo.x, -eta * wo.y, -cos_t))
}

/// Fresnel reflectance of a dielectric boundary for unpolarised light arriving at `cos_i`, with
/// `eta` = index of the side it comes from / index of the other side. 1 under total internal
/// reflection. The cosine's sign is ignored: with interpolated shading normals a direction
/// seen from the front of the triangle can lie behind its shading normal, and the formulas
/// below, fed a negative cosine, divide by about zero and return reflectances far above 1 (a
/// glass sphere nested in glass of the same index then shone brighter than its light).
pub(crate) fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.abs().min(1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_s = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_p = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_s * r_s + r_p * r_p)
}

/// Schlick's approximation of a metal's Fresnel reflectance from its reflectance at normal
/// incidence.
fn schlick(f0: Vec3, cos: f32) -> Vec3 {
    f0 + (Vec3::ONE - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

/// The GGX normal distribution.
fn ggx_d(h: Vec3, alpha: f32) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = h.z * h.z * (a2 - 1.0) + 1.0;
    a2 / (std::f32::consts::PI * t * t)
}

/// Smith's masking term for GGX.
fn smith_g1(w: Vec3, alpha: f32) -> f32 {
    if w.z <= 0.0 {
        return 0.0;
    }
    let tan2 = (1.0 - w.z * w.z).max(0.0) / (w.z * w.z);
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// A microfacet normal sampled from the normals GGX surface shows to `wo` (Heitz 2018).
fn sample_visible_normal(wo: Vec3, alpha: f32, u: [f32; 2]) -> Vec3 {
    let v = Vec3::new(alpha * wo.x, alpha * wo.y, wo.z).normalize();
    let t1 = if v.z < 0.9999 { Vec3::Z.cross(v).normalize() } else { Vec3::X };
    let t2 = v.cross(t1);
    let d = concentric_disc(u);
    let s = 0.5 * (1.0 + v.z);
    let p2 = (1.0 - s) * (1.0 - d.x * d.x).max(0.0).sqrt() + s * d.y;
    let p = t1 * d.x + t2 * p2 + v * (1.0 - d.x * d.x - p2 * p2).max(0.0).sqrt();
    Vec3::new(alpha * p.x, alpha * p.y, p.z.max(1e-6)).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ BSDF cos over the hemisphere by importance sampling: the directional albedo.
    fn albedo(bsdf: &Bsdf, wo: Vec3) -> Vec3 {
        let n = 128;
        let mut sum = Vec3::ZERO;
        for i in 0..n * n {
            let u = [((i % n) as f32 + 0.5) / n as f32, ((i / n) as f32 + 0.5) / n as f32];
            if let Some(s) = bsdf.sample(wo, u, ((i * 7919) % (n * n)) as f32 / (n * n) as f32) {
                sum += s.weight;
            }
        }
        sum / (n * n) as f32
    }

    #[test]
    fn lambert_and_phong_conserve_energy() {
        let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
        assert!((albedo(&Bsdf::Lambert { albedo: Vec3::ONE }, wo) - Vec3::ONE).abs().max_element() < 1e-3);
        let phong = albedo(&Bsdf::Phong { diffuse: Vec3::splat(0.5), specular: Vec3::splat(0.5), exponent: 50.0 }, wo);
        assert!(phong.max_element() <= 1.0 + 1e-2, "{phong}");
    }

    #[test]
    fn sampled_weights_match_eval_over_pdf() {
        let wo = Vec3::new(-0.2, 0.4, 0.7).normalize();
        for bsdf in [
            Bsdf::Phong { diffuse: Vec3::splat(0.3), specular: Vec3::splat(0.6), exponent: 20.0 },
            Bsdf::Glossy { reflectance: Vec3::new(0.9, 0.6, 0.3), alpha: 0.3 },
        ] {
            for i in 0..50 {
                let u = [(i as f32 * 0.618) % 1.0, (i as f32 * 0.414) % 1.0];
                if let Some(s) = bsdf.sample(wo, u, (i as f32 * 0.73) % 1.0) {
                    let expected = bsdf.eval(wo, s.wi) / bsdf.pdf(wo, s.wi);
                    assert!((s.weight - expected).abs().max_element() < 2e-3 * (1.0 + expected.max_element()), "{bsdf:?}: {} vs {expected}", s.weight);
                }
            }
        }
    }

    /// ∫ BSDF cos over the hemisphere by a midpoint rule in (cos θ, φ), independent of the
    /// BSDF's own sampling.
    fn albedo_by_quadrature(bsdf: &Bsdf, wo: Vec3) -> Vec3 {
        let n = 512;
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            for j in 0..n {
                let cos = (i as f32 + 0.5) / n as f32;
                let phi = std::f32::consts::TAU * (j as f32 + 0.5) / n as f32;
                let sin = (1.0 - cos * cos).sqrt();
                sum += bsdf.eval(wo, Vec3::new(sin * phi.cos(), sin * phi.sin(), cos));
            }
        }
        sum * std::f32::consts::TAU / (n * n) as f32
    }

    #[test]
    fn glossy_metal_reflects_at_most_its_light() {
        let wo = Vec3::new(0.5, 0.0, 0.8).normalize();
        for alpha in [0.05, 0.3, 1.0] {
            let bsdf = Bsdf::Glossy { reflectance: Vec3::ONE, alpha };
            let a = albedo(&bsdf, wo);
            assert!(a.max_element() <= 1.0 + 1e-3, "alpha {alpha}: {a}");
            // Single-scattering microfacet models lose the light that bounces between facets:
            // little when smooth, much when rough (Kulla and Conty 2017).
            assert!(alpha > 0.2 || a.min_element() > 0.9, "alpha {alpha}: {a}");
            if alpha >= 0.3 {
                let q = albedo_by_quadrature(&bsdf, wo);
                assert!((a - q).abs().max_element() < 0.01, "alpha {alpha}: sampled {a}, quadrature {q}");
            }
        }
    }

    /// The GGX distribution projects to the unit disc, and the visible normals it shows a
    /// direction, masked by Smith's term, cover that direction's projected area exactly (the
    /// "weak white furnace" test): so energy the metal loses is light that would bounce between
    /// facets, not an error in either term.
    #[test]
    fn ggx_terms_are_normalised() {
        let wo = Vec3::new(0.6, 0.0, 0.8);
        for alpha in [0.1, 0.3, 1.0] {
            let (n, m) = (4096, 64);
            let (mut projected, mut visible) = (0.0f64, 0.0f64);
            for i in 0..n {
                let cos = (i as f32 + 0.5) / n as f32;
                let sin = (1.0 - cos * cos).sqrt();
                for j in 0..m {
                    let phi = std::f32::consts::TAU * (j as f32 + 0.5) / m as f32;
                    let h = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                    let d = ggx_d(h, alpha) as f64;
                    projected += d * cos as f64;
                    visible += smith_g1(wo, alpha) as f64 * wo.dot(h).max(0.0) as f64 * d / wo.z as f64;
                }
            }
            let cell = std::f64::consts::TAU / (n * m) as f64;
            assert!((projected * cell - 1.0).abs() < 2e-3, "alpha {alpha}: ∫D cos = {}", projected * cell);
            assert!((visible * cell - 1.0).abs() < 2e-3, "alpha {alpha}: weak furnace {}", visible * cell);
        }
    }

    #[test]
    fn dielectric_fresnel_and_total_internal_reflection() {
        // Normal incidence on glass: ((1 − 1.5) / (1 + 1.5))² = 0.04.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        // From inside glass beyond the critical angle (41.8°): everything reflects.
        let grazing = 60f32.to_radians().cos();
        assert_eq!(fresnel_dielectric(grazing, 1.5), 1.0);
        assert!(refract(Vec3::new(grazing.acos().sin(), 0.0, grazing), 1.5).is_none());
        // Snell: sin θt = sin θi / 1.5 entering glass.
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let t = refract(wo, 1.0 / 1.5).unwrap();
        assert!((t.x.abs() - 0.6 / 1.5).abs() < 1e-6 && (t.length() - 1.0).abs() < 1e-6 && t.z < 0.0);
    }
}
