//! Scattering functions: how much light a surface reflects or transmits from one direction to
//! another, and how to sample that. Directions are in the shading frame (`z` the normal) and
//! point away from the surface; `wo` is towards the viewer.
//!
//! The models follow the seed's ray tracing chapter (Shirley: Lambert, Phong, mirror reflection,
//! Snell refraction, Schlick's Fresnel approximation for metals and the exact dielectric Fresnel
//! equations, DIGEST §1.6) and, for rough metal, the GGX microfacet distribution with visible-normal
//! sampling (Heitz 2018), so that the path tracer's estimates stay unbiased.

use glam::Vec3;

use crate::warp::{concentric_disc, cosine_hemisphere};

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
    /// glTF 2.0's metallic-roughness BRDF (its Appendix B): a Lambertian base under a GGX
    /// specular layer of a dielectric (Fresnel from `f0`, 0.04 for index 1.5), blended by
    /// `metallic` with a GGX conductor of colour `base`. The dielectric's Fresnel runs from
    /// `f0` head-on to `f90` at grazing (1, or glTF's `KHR_materials_specular` factor, 0 leaving
    /// a pure Lambertian base). Specular masking is Smith's, height-correlated; `alpha` is the
    /// roughness squared. Single scattering: rough surfaces lose the light that bounces between
    /// microfacets (a white rough metal keeps about 80 % seen head-on).
    PhysicallyBased { base: Vec3, metallic: f32, alpha: f32, f0: f32, f90: f32 },
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
            Bsdf::PhysicallyBased { base, metallic, alpha, f0, f90 } => {
                let h = (wo + wi).normalize();
                let v_dot_h = wo.dot(h);
                // The specular layer's colour: the dielectric's grey Fresnel blended to the metal's.
                let (layer_f0, layer_f90) = layer(base, metallic, f0, f90);
                let specular = fresnel_schlick(layer_f0, layer_f90, v_dot_h) * (ggx_d(h, alpha) * smith_height_correlated(wo, wi, alpha));
                // Light the dielectric's layer lets through, on the way in and on the way out,
                // reaches the diffuse base and leaves it; what the layer turns back inside is
                // given back to the base on average (divided by 1 − the layer's hemispherical
                // reflectance, f0 + (f90 − f0)/21 for Schlick's), so the base reflects 1 − F(wo)
                // of the light in all. (glTF's reference weighs the base by 1 − F at the half
                // vector, which reflects up to 1 % more than it receives; this coupling is
                // reciprocal and keeps within its light.)
                let average = f0 + (f90 - f0) / 21.0;
                let dielectric = |cos: f32| fresnel_schlick(Vec3::splat(f0), Vec3::splat(f90), cos).x;
                let through = (1.0 - dielectric(wo.z)) * (1.0 - dielectric(wi.z)) / (1.0 - average);
                let diffuse = base * ((1.0 - metallic) * through * std::f32::consts::FRAC_1_PI);
                (specular + diffuse) * wi.z
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
            Bsdf::PhysicallyBased { alpha, .. } => {
                let p = self.specular_probability(wo);
                let h = (wo + wi).normalize();
                p * ggx_d(h, alpha) * smith_g1(wo, alpha) / (4.0 * wo.z) + (1.0 - p) * wi.z * std::f32::consts::FRAC_1_PI
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
            Bsdf::PhysicallyBased { alpha, .. } => {
                if wo.z <= 0.0 {
                    return None;
                }
                // One lobe by its share of the reflected light, the weight over both lobes'
                // density (the one-sample model: unbiased whichever lobe drew it).
                let wi = if choose < self.specular_probability(wo) { reflect(wo, sample_visible_normal(wo, alpha, u)) } else { cosine_hemisphere(u) };
                let pdf = self.pdf(wo, wi);
                (wi.z > 0.0 && pdf > 0.0).then(|| BsdfSample { wi, weight: self.eval(wo, wi) / pdf, pdf, transmitted: false })
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

impl Bsdf {
    /// For [`Bsdf::PhysicallyBased`], the probability that a sample picks the specular lobe:
    /// its Fresnel reflectance at `wo`'s angle against what the diffuse base keeps (at least
    /// 10 %, so that a dark base's highlights are still found; 1 for a pure metal, 0 without a
    /// specular layer).
    fn specular_probability(&self, wo: Vec3) -> f32 {
        let Bsdf::PhysicallyBased { base, metallic, f0, f90, .. } = *self else { return 0.0 };
        let (layer_f0, layer_f90) = layer(base, metallic, f0, f90);
        let specular = crate::lights::luminance(fresnel_schlick(layer_f0, layer_f90, wo.z));
        let dielectric = fresnel_schlick(Vec3::splat(f0), Vec3::splat(f90), wo.z).x;
        let diffuse = crate::lights::luminance(base) * (1.0 - metallic) * (1.0 - dielectric);
        match (specular, diffuse) {
            (0.0, _) => 0.0,
            (_, 0.0) => 1.0,
            _ => (specular / (specular + diffuse)).max(0.1),
        }
    }

    /// What Whitted's and Cook's recursions trace for a physically based surface seen at
    /// `cos_o` from its normal: its specular layer as a GGX metal of the layer's colour at
    /// normal incidence (the diffuse base is lit by the lights alone), for Cook's samples of
    /// the lobe; and for Whitted's one mirror ray, the layer's Fresnel reflectance faded out
    /// with roughness (a rough surface mirrors nothing). `None` for other functions, and for a
    /// surface without a specular layer.
    pub fn specular_layer(&self, cos_o: f32) -> Option<(Bsdf, Vec3)> {
        let Bsdf::PhysicallyBased { base, metallic, alpha, f0, f90 } = *self else { return None };
        let (layer_f0, layer_f90) = layer(base, metallic, f0, f90);
        (layer_f90.max_element() > 0.0)
            .then(|| (Bsdf::Glossy { reflectance: layer_f0, alpha }, fresnel_schlick(layer_f0, layer_f90, cos_o) * (1.0 - alpha.sqrt())))
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

/// Schlick's approximation from the reflectance `f0` head-on to `f90` at grazing.
fn fresnel_schlick(f0: Vec3, f90: Vec3, cos: f32) -> Vec3 {
    f0 + (f90 - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

/// The specular layer of a physically based surface: the dielectric's Fresnel (`f0` to `f90`,
/// grey) blended by `metallic` to the metal's (`base` to white).
fn layer(base: Vec3, metallic: f32, f0: f32, f90: f32) -> (Vec3, Vec3) {
    (Vec3::splat(f0).lerp(base, metallic), Vec3::splat(f90).lerp(Vec3::ONE, metallic))
}

/// The height-correlated Smith visibility term `G2 / (4 cos θo cos θi)` for GGX (Heitz 2014,
/// as glTF's Appendix B writes it).
fn smith_height_correlated(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let lambda_o = wi.z * (wo.z * wo.z * (1.0 - a2) + a2).sqrt();
    let lambda_i = wo.z * (wi.z * wi.z * (1.0 - a2) + a2).sqrt();
    0.5 / (lambda_o + lambda_i)
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

    /// The metallic × roughness corners and middle of the physically based BRDF.
    fn physically_based_grid() -> Vec<Bsdf> {
        let mut grid = Vec::new();
        for metallic in [0.0, 0.5, 1.0] {
            for roughness in [0.05f32, 0.5, 1.0] {
                grid.push(Bsdf::PhysicallyBased { base: Vec3::new(0.9, 0.7, 0.4), metallic, alpha: roughness * roughness, f0: 0.04, f90: 1.0 });
            }
        }
        grid
    }

    #[test]
    fn sampled_weights_match_eval_over_pdf() {
        let wo = Vec3::new(-0.2, 0.4, 0.7).normalize();
        for bsdf in [
            Bsdf::Phong { diffuse: Vec3::splat(0.3), specular: Vec3::splat(0.6), exponent: 20.0 },
            Bsdf::Glossy { reflectance: Vec3::new(0.9, 0.6, 0.3), alpha: 0.3 },
        ]
        .into_iter()
        .chain(physically_based_grid())
        {
            for i in 0..50 {
                let u = [(i as f32 * 0.618) % 1.0, (i as f32 * 0.414) % 1.0];
                if let Some(s) = bsdf.sample(wo, u, (i as f32 * 0.73) % 1.0) {
                    let expected = bsdf.eval(wo, s.wi) / bsdf.pdf(wo, s.wi);
                    assert!((s.weight - expected).abs().max_element() < 2e-3 * (1.0 + expected.max_element()), "{bsdf:?}: {} vs {expected}", s.weight);
                }
            }
        }
    }

    /// ∫ `f` over the hemisphere of directions by a midpoint rule in (cos θ, φ).
    fn over_hemisphere(f: impl Fn(Vec3) -> Vec3) -> Vec3 {
        let n = 512;
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            for j in 0..n {
                let cos = (i as f32 + 0.5) / n as f32;
                let phi = std::f32::consts::TAU * (j as f32 + 0.5) / n as f32;
                let sin = (1.0 - cos * cos).sqrt();
                sum += f(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos));
            }
        }
        sum * std::f32::consts::TAU / (n * n) as f32
    }

    /// ∫ BSDF cos over the hemisphere, independent of the BSDF's own sampling.
    fn albedo_by_quadrature(bsdf: &Bsdf, wo: Vec3) -> Vec3 {
        over_hemisphere(|wi| bsdf.eval(wo, wi))
    }

    /// The physically based BRDF is reciprocal, never reflects more than it receives, loses
    /// little when smooth (a white dielectric keeps its light, a white metal nearly all), and
    /// its sampling density integrates to one over the hemisphere.
    #[test]
    fn physically_based_is_reciprocal_bounded_and_normalised() {
        let white = |metallic: f32, roughness: f32| Bsdf::PhysicallyBased { base: Vec3::ONE, metallic, alpha: roughness * roughness, f0: 0.04, f90: 1.0 };
        for wo in [Vec3::new(0.1, 0.2, 0.95), Vec3::new(0.6, -0.3, 0.5), Vec3::new(-0.9, 0.1, 0.2)].map(Vec3::normalize) {
            for bsdf in physically_based_grid().into_iter().chain([white(0.0, 0.3), white(1.0, 0.3), white(0.0, 1.0), white(1.0, 1.0)]) {
                let wi = Vec3::new(0.3, 0.5, 0.6).normalize();
                let (a, b) = (bsdf.eval(wo, wi) / wi.z, bsdf.eval(wi, wo) / wo.z);
                assert!((a - b).abs().max_element() <= 1e-4 * (1.0 + a.max_element()), "{bsdf:?}: {a} vs {b}");
                let q = albedo_by_quadrature(&bsdf, wo);
                assert!(q.max_element() <= 1.0 + 5e-3, "{bsdf:?} at {wo}: albedo {q}");
                // The density over the hemisphere, by the same quadrature.
                let total = over_hemisphere(|wi| Vec3::splat(bsdf.pdf(wo, wi))).x;
                // Smooth lobes are too sharp for the quadrature; the sampled test covers them. A
                // rough specular lobe reflects some visible normals below the horizon: those
                // samples are refused (unbiased: the density is that of the directions given),
                // so the density above it integrates to the share of samples given.
                let m = 256;
                let given = (0..m * m).filter(|i| bsdf.sample(wo, [((i % m) as f32 + 0.5) / m as f32, ((i / m) as f32 + 0.5) / m as f32], ((i * 7919) % (m * m)) as f32 / (m * m) as f32).is_some()).count();
                let given = given as f32 / (m * m) as f32;
                if let Bsdf::PhysicallyBased { alpha, .. } = bsdf
                    && alpha >= 0.09
                {
                    assert!((total - given).abs() < 0.02, "{bsdf:?} at {wo}: density integrates to {total}, {given} of the samples given");
                }
            }
            // Energy lost to single scattering: little when smooth, more when rough.
            let smooth = albedo_by_quadrature(&white(0.0, 0.3), Vec3::new(0.1, 0.2, 0.95).normalize());
            assert!(smooth.min_element() > 0.95, "a smooth white dielectric keeps {smooth}");
            // Without a specular layer, exactly Lambert.
            let lambert = Bsdf::PhysicallyBased { base: Vec3::splat(0.5), metallic: 0.0, alpha: 1.0, f0: 0.0, f90: 0.0 };
            let wi = Vec3::new(0.7, 0.1, 0.2).normalize();
            assert!((lambert.eval(wo, wi) - Bsdf::Lambert { albedo: Vec3::splat(0.5) }.eval(wo, wi)).abs().max_element() < 1e-6);
            assert!((lambert.pdf(wo, wi) - wi.z / std::f32::consts::PI).abs() < 1e-6);
        }
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
