//! Scattering functions: how much light a surface reflects or transmits from one direction to
//! another, and how to sample that. Directions are in the shading frame (`z` the normal) and
//! point away from the surface; `wo` is towards the viewer.
//!
//! The models follow the seed's ray tracing chapter (Shirley: Lambert, Phong, mirror reflection,
//! Snell refraction, Schlick's Fresnel approximation for metals and the exact dielectric Fresnel
//! equations, DIGEST §1.6) and, for rough metal, the GGX microfacet distribution with visible-normal
//! sampling (Heitz 2018), so that the path tracer's estimates stay unbiased. Rough transmission
//! through the same microfacets is Walter et al.'s (2007) BTDF, as pbrt-v4's dielectric writes it
//! (without the η² compression of radiance, which cancels on every path that enters a volume and
//! leaves it again, as the smooth `Glass` leaves it out).

use glam::Vec3;

use crate::sheen;
use crate::warp::{concentric_disc, cosine_hemisphere, uniform_hemisphere};

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
    /// glTF 2.0's metallic-roughness BSDF and its extensions (see [`Pbr`]).
    PhysicallyBased(Pbr),
}

/// glTF 2.0's metallic-roughness BSDF (its Appendix B): a Lambertian base under a GGX
/// specular layer of a dielectric (Fresnel from `f0`, 0.04 for index 1.5, tinted by glTF's
/// `KHR_materials_specular` colour), blended by `metallic` with a GGX conductor of colour
/// `base`. The dielectric's Fresnel runs from `f0` head-on to `f90` at grazing (1, or glTF's `KHR_materials_specular` factor, 0 leaving
/// a pure Lambertian base). Specular masking is Smith's, height-correlated; `alpha` is the
/// roughness squared. Single scattering: rough surfaces lose the light that bounces between
/// microfacets (a white rough metal keeps about 80 % seen head-on).
///
/// With `transmission` (glTF's KHR_materials_transmission), that fraction of the dielectric
/// gives up its diffuse base: it reflects by the exact Fresnel equations of relative index
/// `eta` (the side of `wo` over the other side, which knows total internal reflection) and
/// transmits the rest through the same GGX microfacets, tinted by `base`. A `thin` wall
/// transmits the reflection lobe mirrored through the surface (no bending, no medium
/// entered); otherwise the light refracts by Walter et al.'s BTDF.
///
/// With `coat` (glTF's KHR_materials_clearcoat), a smooth-to-rough dielectric coat of index
/// 1.5 and GGX roughness `coat_alpha` lies over all of it: it reflects `coat` × its Schlick
/// Fresnel and lets the rest through to what is under it, on the way in and on the way out
/// (so that the coupling stays reciprocal and within its light).
///
/// With `sheen` (glTF's KHR_materials_sheen), a layer of fibres, as velvet and other cloth
/// have, lies over the base and under the coat: Estevez and Kulla's "Charlie" distribution of
/// microfibre α `sheen_alpha` with Ashikhmin's visibility, as the extension specifies, scaling
/// what lies under it by the light it leaves (`1 − max(sheen) E(cos)`, where E is the lobe's
/// directional albedo, the lesser for the two directions, so that it stays reciprocal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Pbr {
    pub base: Vec3,
    pub metallic: f32,
    pub alpha: f32,
    pub f0: Vec3,
    pub f90: f32,
    pub transmission: f32,
    pub eta: f32,
    pub thin: bool,
    pub coat: f32,
    pub coat_alpha: f32,
    pub sheen: Vec3,
    pub sheen_alpha: f32,
}

impl Bsdf {
    /// Whether the function is a delta (cannot be evaluated for a given pair of directions).
    pub fn is_specular(&self) -> bool {
        matches!(self, Bsdf::Mirror { .. } | Bsdf::Glass { .. })
    }

    /// BSDF × |cos θi| for the pair of directions (zero for delta lobes).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z == 0.0 {
            return Vec3::ZERO;
        }
        if let Some((under, coat, coat_alpha)) = self.coated() {
            let through = (1.0 - coat * coat_fresnel(wo.z)) * (1.0 - coat * coat_fresnel(wi.z.abs()));
            let mut value = under.eval(wo, wi) * through;
            if wi.z > 0.0 {
                let h = (wo + wi).normalize();
                value += Vec3::splat(coat * coat_fresnel(wo.dot(h)) * ggx_d(h, coat_alpha) * smith_height_correlated(wo, wi, coat_alpha) * wi.z);
            }
            return value;
        }
        if let Some((under, sheen, sheen_alpha)) = self.sheened() {
            let through = sheen::left(sheen, sheen_alpha, wo.z).min(sheen::left(sheen, sheen_alpha, wi.z.abs()));
            return under.eval(wo, wi) * through + sheen * sheen::lobe(wo, wi, sheen_alpha);
        }
        if wi.z < 0.0 {
            return self.transmitted(wo, wi);
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
            Bsdf::PhysicallyBased(Pbr { base, metallic, alpha, f0, f90, transmission, .. }) => {
                let h = (wo + wi).normalize();
                let specular = self.layer_reflectance(wo.dot(h)) * (ggx_d(h, alpha) * smith_height_correlated(wo, wi, alpha));
                // Light the dielectric's layer lets through, on the way in and on the way out,
                // reaches the diffuse base and leaves it; what the layer turns back inside is
                // given back to the base on average (divided by 1 − the layer's hemispherical
                // reflectance, f0 + (f90 − f0)/21 for Schlick's), so the base reflects 1 − F(wo)
                // of the light in all. (glTF's reference weighs the base by 1 − F at the half
                // vector, which reflects up to 1 % more than it receives; this coupling is
                // reciprocal and keeps within its light.)
                // Per colour channel, since KHR_materials_specular's colour tints f0; a channel
                // that reflects everything head-on and at grazing passes nothing (0 / ε).
                let average = f0 + (Vec3::splat(f90) - f0) / 21.0;
                let dielectric = |cos: f32| fresnel_schlick(f0, Vec3::splat(f90), cos);
                let through = (Vec3::ONE - dielectric(wo.z)) * (Vec3::ONE - dielectric(wi.z)) / (Vec3::ONE - average).max(Vec3::splat(1e-6));
                let diffuse = base * through * ((1.0 - metallic) * (1.0 - transmission) * std::f32::consts::FRAC_1_PI);
                (specular + diffuse) * wi.z
            }
            Bsdf::Mirror { .. } | Bsdf::Glass { .. } => Vec3::ZERO,
        }
    }

    /// Density with which [`Bsdf::sample`] picks `wi` given `wo` (0 for delta lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        if let Some((under, coat, coat_alpha)) = self.coated() {
            let p = coat_probability(coat, wo.z);
            let lobe = if wi.z > 0.0 {
                let h = (wo + wi).normalize();
                ggx_d(h, coat_alpha) * smith_g1(wo, coat_alpha) / (4.0 * wo.z)
            } else {
                0.0
            };
            return p * lobe + (1.0 - p) * under.pdf(wo, wi);
        }
        if let Some((under, sheen, sheen_alpha)) = self.sheened() {
            let p = sheen_probability(sheen, sheen_alpha, wo.z);
            let lobe = if wi.z > 0.0 { sheen::UNIFORM_PDF } else { 0.0 };
            return p * lobe + (1.0 - p) * under.pdf(wo, wi);
        }
        if wi.z < 0.0 {
            return self.transmission_pdf(wo, wi);
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
            Bsdf::PhysicallyBased(Pbr { alpha, eta, thin, .. }) => {
                let [specular, diffuse, transmitted] = self.lobe_probabilities(wo);
                let h = (wo + wi).normalize();
                // Refraction samples that meet total internal reflection at their microfacet
                // reflect off it instead.
                let reflected = if transmitted > 0.0 && !thin && refract_about(wo, h, eta).is_none() { specular + transmitted } else { specular };
                reflected * ggx_d(h, alpha) * smith_g1(wo, alpha) / (4.0 * wo.z) + diffuse * wi.z * std::f32::consts::FRAC_1_PI
            }
            Bsdf::Mirror { .. } | Bsdf::Glass { .. } => 0.0,
        }
    }

    /// Samples a direction for `wo` from two uniform numbers (and a third for choosing a lobe).
    pub fn sample(&self, wo: Vec3, u: [f32; 2], choose: f32) -> Option<BsdfSample> {
        if let Some((under, coat, coat_alpha)) = self.coated() {
            if wo.z <= 0.0 {
                return None;
            }
            // The coat's lobe by its share of the light, else what lies under it (the lobe
            // number stretched back over [0, 1)); the weight over the whole density.
            let p = coat_probability(coat, wo.z);
            let wi = if choose < p {
                Some(reflect(wo, sample_visible_normal(wo, coat_alpha, u))).filter(|wi| wi.z > 0.0)?
            } else {
                under.sample(wo, u, ((choose - p) / (1.0 - p)).min(1.0 - f32::EPSILON))?.wi
            };
            return self.weighed(wo, wi);
        }
        if let Some((under, sheen, sheen_alpha)) = self.sheened() {
            if wo.z <= 0.0 {
                return None;
            }
            // As for the coat: the fibres' lobe by its share of the light, else the layer under.
            let p = sheen_probability(sheen, sheen_alpha, wo.z);
            let wi = if choose < p { uniform_hemisphere(u) } else { under.sample(wo, u, ((choose - p) / (1.0 - p)).min(1.0 - f32::EPSILON))?.wi };
            return self.weighed(wo, wi);
        }
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
            Bsdf::PhysicallyBased(Pbr { alpha, eta, thin, .. }) => {
                if wo.z <= 0.0 {
                    return None;
                }
                // One lobe by its share of the light, the weight over every lobe's density (the
                // one-sample model: unbiased whichever lobe drew it). A lobe's direction on the
                // wrong side of the surface is refused, so that each side's density is that of
                // the lobes that give directions there.
                let [specular, _, transmitted] = self.lobe_probabilities(wo);
                let wi = if choose < specular {
                    Some(reflect(wo, sample_visible_normal(wo, alpha, u))).filter(|wi| wi.z > 0.0)
                } else if choose < specular + transmitted {
                    let h = sample_visible_normal(wo, alpha, u);
                    let reflected = reflect(wo, h);
                    if thin {
                        Some(Vec3::new(reflected.x, reflected.y, -reflected.z)).filter(|wi| wi.z < 0.0)
                    } else {
                        match refract_about(wo, h, eta) {
                            Some(wi) => Some(wi).filter(|wi| wi.z < 0.0),
                            None => Some(reflected).filter(|wi| wi.z > 0.0),
                        }
                    }
                } else {
                    Some(cosine_hemisphere(u))
                }?;
                self.weighed(wo, wi)
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
    /// For [`Bsdf::PhysicallyBased`], the probabilities that a sample picks the specular, the
    /// diffuse and the transmission lobe: each lobe's share of the light at `wo`'s angle (the
    /// specular lobe at least 10 % of them, so that a dark base's highlights are still found; 1
    /// for a pure metal, 0 without a specular layer). Transmission keeps at least a tenth of its
    /// share where Fresnel reflects all at the macro normal, since rough microfacets there still
    /// let some light through.
    fn lobe_probabilities(&self, wo: Vec3) -> [f32; 3] {
        let Bsdf::PhysicallyBased(Pbr { base, metallic, f0, f90, transmission, eta, .. }) = *self else { return [0.0; 3] };
        let specular = crate::lights::luminance(self.layer_reflectance(wo.z)).max(0.0);
        let dielectric = crate::lights::luminance(fresnel_schlick(f0, Vec3::splat(f90), wo.z));
        let diffuse = crate::lights::luminance(base) * (1.0 - metallic) * (1.0 - transmission) * (1.0 - dielectric);
        let share = (1.0 - metallic) * transmission;
        let transmitted = if share > 0.0 { crate::lights::luminance(base) * share * (1.0 - f90 * fresnel_dielectric(wo.z, eta)).max(0.1) } else { 0.0 };
        let total = specular + diffuse + transmitted;
        if specular == 0.0 || total == 0.0 {
            return [0.0, diffuse, transmitted].map(|p| if total > 0.0 { p / total } else { 0.0 });
        }
        let p = (specular / total).max(0.1);
        let rest = diffuse + transmitted;
        if rest == 0.0 { [1.0, 0.0, 0.0] } else { [p, (1.0 - p) * diffuse / rest, (1.0 - p) * transmitted / rest] }
    }

    /// For [`Bsdf::PhysicallyBased`], the specular layer's Fresnel reflectance for a direction
    /// at `cos` to the microfacet normal: the dielectric's grey Schlick term blended to the
    /// metal's colour; the transmitting share of the dielectric reflects by the exact equations
    /// instead (Schlick's knows no total internal reflection), so that with what it transmits it
    /// makes one.
    fn layer_reflectance(&self, cos: f32) -> Vec3 {
        let Bsdf::PhysicallyBased(Pbr { base, metallic, f0, f90, transmission, eta, .. }) = *self else { return Vec3::ZERO };
        let (layer_f0, layer_f90) = layer(base, metallic, f0, f90);
        let schlick = fresnel_schlick(layer_f0, layer_f90, cos);
        if transmission == 0.0 {
            return schlick;
        }
        let dielectric = fresnel_schlick(f0, Vec3::splat(f90), cos);
        schlick + (Vec3::splat(f90 * fresnel_dielectric(cos, eta)) - dielectric) * ((1.0 - metallic) * transmission)
    }

    /// For a transmitting [`Bsdf::PhysicallyBased`], BTDF × |cos θi| for `wi` below the surface
    /// (`wo` above it); zero for every other function.
    fn transmitted(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let Bsdf::PhysicallyBased(Pbr { base, metallic, alpha, f90, transmission, eta, thin, .. }) = *self else { return Vec3::ZERO };
        let tint = base * ((1.0 - metallic) * transmission);
        if tint == Vec3::ZERO {
            return Vec3::ZERO;
        }
        if thin {
            // The reflection lobe, mirrored through the wall: reciprocal, and it keeps what
            // the reflection would.
            let mirrored = Vec3::new(wi.x, wi.y, -wi.z);
            let h = (wo + mirrored).normalize();
            let f = f90 * fresnel_dielectric(wo.dot(h), eta);
            return tint * ((1.0 - f) * ggx_d(h, alpha) * smith_height_correlated(wo, mirrored, alpha) * mirrored.z);
        }
        let Some((h, o, i)) = refraction_half_vector(wo, wi, eta) else { return Vec3::ZERO };
        let f = f90 * fresnel_dielectric(o, eta);
        let denominator = (i + eta * o) * (i + eta * o);
        tint * ((1.0 - f) * ggx_d(h, alpha) * smith_g2(wo, wi, alpha) * (i * o).abs() / (denominator * wo.z))
    }

    /// The density with which [`Bsdf::sample`] picks `wi` below the surface.
    fn transmission_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Bsdf::PhysicallyBased(Pbr { alpha, eta, thin, .. }) = *self else { return 0.0 };
        let transmitted = self.lobe_probabilities(wo)[2];
        if transmitted == 0.0 {
            return 0.0;
        }
        if thin {
            let h = (wo + Vec3::new(wi.x, wi.y, -wi.z)).normalize();
            return transmitted * ggx_d(h, alpha) * smith_g1(wo, alpha) / (4.0 * wo.z);
        }
        let Some((h, o, i)) = refraction_half_vector(wo, wi, eta) else { return 0.0 };
        // The visible normals' density, times that of the refracted direction per normal.
        let visible = smith_g1(wo, alpha) * o * ggx_d(h, alpha) / wo.z;
        transmitted * visible * i.abs() / ((i + eta * o) * (i + eta * o))
    }

    /// Whether the function lets light through to the other side of the surface (glass, or a
    /// physically based surface with transmission).
    pub fn transmits(&self) -> bool {
        match *self {
            Bsdf::Glass { .. } => true,
            Bsdf::PhysicallyBased(Pbr { metallic, transmission, .. }) => transmission > 0.0 && metallic < 1.0,
            _ => false,
        }
    }

    /// Whether light goes through without entering a medium (a thin transmitting wall).
    pub fn is_thin(&self) -> bool {
        matches!(*self, Bsdf::PhysicallyBased(Pbr { thin: true, transmission, .. }) if transmission > 0.0)
    }

    /// The function at a boundary of relative index `eta` (the side the ray comes from over
    /// the other side): a transmitting physically based surface's Fresnel and refraction use
    /// it; other functions are unchanged. Index-matched boundaries are kept a little away from
    /// 1, where the refraction lobe would collapse to a delta the BTDF cannot evaluate.
    pub fn across(self, eta: f32) -> Bsdf {
        match self {
            Bsdf::PhysicallyBased(p) if p.transmission > 0.0 => {
                let eta = if (eta - 1.0).abs() >= MIN_INDEX_CONTRAST { eta } else if eta >= 1.0 { 1.0 + MIN_INDEX_CONTRAST } else { 1.0 - MIN_INDEX_CONTRAST };
                Bsdf::PhysicallyBased(Pbr { eta, ..p })
            }
            other => other,
        }
    }

    /// What Whitted's recursion traces through a transmitting physically based surface for
    /// `wo`: the direction of its smooth refraction (straight through a thin wall) and its
    /// weight, the light the exact Fresnel equations let through, tinted by the base colour
    /// (roughness does not fade it, as it fades the mirror: a rough window still shows what is
    /// behind it, blurred). `None` for other functions, and under total internal reflection.
    pub fn smooth_transmission(&self, wo: Vec3) -> Option<(Vec3, Vec3)> {
        let Bsdf::PhysicallyBased(Pbr { base, metallic, f90, transmission, eta, thin, .. }) = *self else { return None };
        if !self.transmits() {
            return None;
        }
        let wi = if thin { -wo } else { refract(wo, eta)? };
        Some((wi, base * ((1.0 - metallic) * transmission * (1.0 - f90 * fresnel_dielectric(wo.z, eta)))))
    }

    /// What Whitted's and Cook's recursions trace for a physically based surface seen at
    /// `cos_o` from its normal: its specular layer as a GGX metal of the layer's colour at
    /// normal incidence (the diffuse base is lit by the lights alone), for Cook's samples of
    /// the lobe; and for Whitted's one mirror ray, the layer's Fresnel reflectance faded out
    /// with roughness (a rough surface mirrors nothing). `None` for other functions, and for a
    /// surface without a specular layer.
    pub fn specular_layer(&self, cos_o: f32) -> Option<(Bsdf, Vec3)> {
        let Bsdf::PhysicallyBased(Pbr { base, metallic, alpha, f0, f90, .. }) = *self else { return None };
        let (layer_f0, layer_f90) = layer(base, metallic, f0, f90);
        (layer_f90.max_element() > 0.0).then(|| (Bsdf::Glossy { reflectance: layer_f0, alpha }, self.layer_reflectance(cos_o) * (1.0 - alpha.sqrt())))
    }
}

impl Bsdf {
    /// What Whitted's and Cook's recursions trace for a coated physically based function seen
    /// at `cos_o` from its normal, as [`Bsdf::specular_layer`] gives for the layer under it:
    /// the coat as a GGX dielectric of its roughness (Schlick's Fresnel from 4 %), the coat's
    /// weight, Whitted's one mirror ray's weight before it (the coat's Fresnel reflectance faded
    /// out with roughness), and the share of light the coat lets through to what is under it.
    /// `None` without a coat.
    pub fn coat_layer(&self, cos_o: f32) -> Option<(Bsdf, f32, f32, f32)> {
        let (_, coat, coat_alpha) = self.coated()?;
        let reflectance = coat_fresnel(cos_o);
        Some((Bsdf::Glossy { reflectance: Vec3::splat(0.04), alpha: coat_alpha }, coat, reflectance * (1.0 - coat_alpha.sqrt()), 1.0 - coat * reflectance))
    }

    /// A sample in direction `wi` with its weight over the whole function's density (the
    /// one-sample model of layered functions: unbiased whichever layer drew it).
    fn weighed(&self, wo: Vec3, wi: Vec3) -> Option<BsdfSample> {
        let pdf = self.pdf(wo, wi);
        (pdf > 0.0).then(|| BsdfSample { wi, weight: self.eval(wo, wi) / pdf, pdf, transmitted: wi.z < 0.0 })
    }

    /// A physically based function with sheen (and no coat over it: [`Bsdf::coated`] takes the
    /// coat off first) as what lies under the fibres, their colour and α; `None` otherwise.
    fn sheened(&self) -> Option<(Bsdf, Vec3, f32)> {
        match *self {
            Bsdf::PhysicallyBased(p) if p.sheen.max_element() > 0.0 => Some((Bsdf::PhysicallyBased(Pbr { sheen: Vec3::ZERO, ..p }), p.sheen, p.sheen_alpha)),
            _ => None,
        }
    }

    /// A coated physically based function as what lies under its coat, the coat's weight and
    /// its α; `None` for any other function.
    fn coated(&self) -> Option<(Bsdf, f32, f32)> {
        match *self {
            Bsdf::PhysicallyBased(p) if p.coat > 0.0 => Some((Bsdf::PhysicallyBased(Pbr { coat: 0.0, ..p }), p.coat, p.coat_alpha)),
            _ => None,
        }
    }
}

/// The clearcoat's Fresnel reflectance at `cos` (Schlick's, index 1.5: 4 % head-on).
fn coat_fresnel(cos: f32) -> f32 {
    fresnel_schlick(Vec3::splat(0.04), Vec3::ONE, cos).x
}

/// Probability that a sample of a function with sheen picks the fibres' lobe: their share of
/// the light at `wo`, at least a tenth of their strength so that the rim is found head-on.
fn sheen_probability(sheen: Vec3, alpha: f32, cos_o: f32) -> f32 {
    let strength = sheen.max_element().min(1.0);
    (strength * sheen::albedo(cos_o, alpha)).max(0.1 * strength).min(0.9)
}

/// Probability that a sample of a coated function picks the coat: its reflectance at `wo`, at
/// least a tenth of its weight so that its highlight is found even head-on.
fn coat_probability(coat: f32, cos_o: f32) -> f32 {
    (coat * coat_fresnel(cos_o)).max(0.1 * coat).min(0.9)
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

/// How close to 1 the relative index of a transmitting rough boundary may come (see
/// [`Bsdf::across`]).
const MIN_INDEX_CONTRAST: f32 = 1e-3;

/// `wo` (above the microfacet of normal `h`) refracted through it, a boundary of relative index
/// `eta` (the side of `wo` over the other); `None` under total internal reflection.
fn refract_about(wo: Vec3, h: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = wo.dot(h);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-eta * wo + (eta * cos_i - cos_t) * h)
}

/// The microfacet normal that refracts `wo` (above the surface) into `wi` (below it) through a
/// boundary of relative index `eta`, facing up, with `wo · h` and `wi · h`; `None` where no
/// microfacet facing both does (Walter et al. 2007, eq. 16).
fn refraction_half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32, f32)> {
    let h = (eta * wo + wi).try_normalize()?;
    let h = if h.z < 0.0 { -h } else { h };
    let (o, i) = (wo.dot(h), wi.dot(h));
    (o > 0.0 && i < 0.0).then_some((h, o, i))
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

/// The specular layer of a physically based surface: the dielectric's Fresnel (`f0` to `f90`)
/// blended by `metallic` to the metal's (`base` to white).
fn layer(base: Vec3, metallic: f32, f0: Vec3, f90: f32) -> (Vec3, Vec3) {
    (f0.lerp(base, metallic), Vec3::splat(f90).lerp(Vec3::ONE, metallic))
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

/// Smith's height-correlated masking-shadowing G2 for GGX, for directions on either side of the
/// surface: 1 / (1 + Λ(wo) + Λ(wi)).
fn smith_g2(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let lambda = |w: Vec3| {
        let cos2 = w.z * w.z;
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        0.5 * ((1.0 + alpha * alpha * tan2).sqrt() - 1.0)
    };
    1.0 / (1.0 + lambda(wo) + lambda(wi))
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

    /// ∫ BSDF |cos| over the sphere by the mean weight of `n²` stratified samples: the
    /// directional albedo as the path tracer sees it, reflected and transmitted.
    fn albedo(bsdf: &Bsdf, wo: Vec3, n: usize) -> Vec3 {
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
        assert!((albedo(&Bsdf::Lambert { albedo: Vec3::ONE }, wo, 128) - Vec3::ONE).abs().max_element() < 1e-3);
        let phong = albedo(&Bsdf::Phong { diffuse: Vec3::splat(0.5), specular: Vec3::splat(0.5), exponent: 50.0 }, wo, 128);
        assert!(phong.max_element() <= 1.0 + 1e-2, "{phong}");
    }

    /// An opaque physically based surface.
    fn opaque(base: Vec3, metallic: f32, alpha: f32, f0: f32, f90: f32) -> Bsdf {
        Bsdf::PhysicallyBased(Pbr { base, metallic, alpha, f0: Vec3::splat(f0), f90, transmission: 0.0, eta: 1.0 / 1.5, thin: false, coat: 0.0, coat_alpha: 0.01, sheen: Vec3::ZERO, sheen_alpha: 0.25 })
    }

    /// The metallic × roughness corners and middle of the physically based BRDF.
    fn physically_based_grid() -> Vec<Bsdf> {
        let mut grid = Vec::new();
        for metallic in [0.0, 0.5, 1.0] {
            for roughness in [0.05f32, 0.5, 1.0] {
                grid.push(opaque(Vec3::new(0.9, 0.7, 0.4), metallic, roughness * roughness, 0.04, 1.0));
            }
        }
        // Clearcoated: a smooth and a rough coat over a rough dielectric and a metal.
        grid.push(coated(opaque(Vec3::new(0.9, 0.7, 0.4), 0.0, 0.25, 0.04, 1.0), 0.01));
        grid.push(coated(opaque(Vec3::new(0.9, 0.7, 0.4), 1.0, 0.25, 0.04, 1.0), 0.25));
        // Sheen over a rough and a smooth dielectric, and under a coat; a tinted specular.
        grid.push(sheened(opaque(Vec3::new(0.2, 0.1, 0.4), 0.0, 0.64, 0.04, 1.0), Vec3::new(1.0, 0.8, 0.6), 0.3));
        grid.push(sheened(opaque(Vec3::new(0.9, 0.7, 0.4), 0.0, 0.09, 0.04, 1.0), Vec3::new(0.5, 0.5, 0.9), 0.8));
        grid.push(coated(sheened(opaque(Vec3::new(0.9, 0.7, 0.4), 0.0, 0.25, 0.04, 1.0), Vec3::ONE, 0.5), 0.09));
        grid.push(tinted(opaque(Vec3::new(0.9, 0.7, 0.4), 0.0, 0.25, 0.04, 1.0), Vec3::new(0.9, 0.1, 0.4)));
        grid
    }

    /// `bsdf` under fibres of colour `sheen` and perceptual roughness `roughness`.
    fn sheened(mut bsdf: Bsdf, sheen: Vec3, roughness: f32) -> Bsdf {
        if let Bsdf::PhysicallyBased(p) = &mut bsdf {
            (p.sheen, p.sheen_alpha) = (sheen, roughness * roughness);
        }
        bsdf
    }

    /// `bsdf` with its dielectric's head-on reflectance tinted by `colour` (KHR_materials_specular).
    fn tinted(mut bsdf: Bsdf, colour: Vec3) -> Bsdf {
        if let Bsdf::PhysicallyBased(p) = &mut bsdf {
            p.f0 = (p.f0 * colour * 10.0).min(Vec3::ONE);
        }
        bsdf
    }

    /// `bsdf` under a full clearcoat of microfacet α `coat_alpha`.
    fn coated(mut bsdf: Bsdf, coat_alpha: f32) -> Bsdf {
        if let Bsdf::PhysicallyBased(Pbr { coat, coat_alpha: a, .. }) = &mut bsdf {
            (*coat, *a) = (1.0, coat_alpha);
        }
        bsdf
    }

    /// A transmitting physically based surface of index 1.5 (`eta` the side of `wo` over the
    /// other).
    fn transmitting(base: Vec3, metallic: f32, roughness: f32, transmission: f32, eta: f32, thin: bool) -> Bsdf {
        Bsdf::PhysicallyBased(Pbr { base, metallic, alpha: (roughness * roughness).max(1e-3), f0: Vec3::splat(0.04), f90: 1.0, transmission, eta, thin, coat: 0.0, coat_alpha: 0.01, sheen: Vec3::ZERO, sheen_alpha: 0.25 })
    }

    /// Transmitting surfaces: thin walls and volume boundaries seen from outside and inside,
    /// part and wholly transmitting, part metallic, smooth to rough.
    fn transmitting_grid() -> Vec<Bsdf> {
        let mut grid = Vec::new();
        for (eta, thin) in [(1.0 / 1.5, true), (1.0 / 1.5, false), (1.5, false)] {
            for (metallic, transmission) in [(0.0, 1.0), (0.0, 0.5), (0.5, 1.0)] {
                for roughness in [0.1, 0.4, 0.8] {
                    grid.push(transmitting(Vec3::new(0.9, 0.7, 0.4), metallic, roughness, transmission, eta, thin));
                }
            }
        }
        grid
    }

    #[test]
    fn sampled_weights_match_eval_over_pdf() {
        let wo = Vec3::new(-0.2, 0.4, 0.7).normalize();
        let mut transmitted = 0;
        for bsdf in [
            Bsdf::Phong { diffuse: Vec3::splat(0.3), specular: Vec3::splat(0.6), exponent: 20.0 },
            Bsdf::Glossy { reflectance: Vec3::new(0.9, 0.6, 0.3), alpha: 0.3 },
        ]
        .into_iter()
        .chain(physically_based_grid())
        .chain(transmitting_grid())
        {
            for i in 0..200 {
                let u = [(i as f32 * 0.618) % 1.0, (i as f32 * 0.414) % 1.0];
                if let Some(s) = bsdf.sample(wo, u, (i as f32 * 0.73) % 1.0) {
                    assert_eq!(s.transmitted, s.wi.z < 0.0, "{bsdf:?}");
                    transmitted += s.transmitted as u32;
                    let expected = bsdf.eval(wo, s.wi) / bsdf.pdf(wo, s.wi);
                    assert!((s.weight - expected).abs().max_element() < 2e-3 * (1.0 + expected.max_element()), "{bsdf:?}: {} vs {expected}", s.weight);
                }
            }
        }
        assert!(transmitted > 1000, "only {transmitted} samples went through");
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
        let white = |metallic: f32, roughness: f32| opaque(Vec3::ONE, metallic, roughness * roughness, 0.04, 1.0);
        for wo in [Vec3::new(0.1, 0.2, 0.95), Vec3::new(0.6, -0.3, 0.5), Vec3::new(-0.9, 0.1, 0.2)].map(Vec3::normalize) {
            // White under a coat: the coat reflects what it does not let through, never more.
            let coated_white = [coated(white(0.0, 0.3), 0.09), coated(white(1.0, 0.2), 0.25)];
            // White fibres over white: the sheen takes its light from the layer under it.
            let sheened_white = [sheened(white(0.0, 0.5), Vec3::ONE, 0.3), sheened(white(0.0, 1.0), Vec3::ONE, 1.0), tinted(white(0.0, 0.5), Vec3::ONE)];
            for bsdf in physically_based_grid().into_iter().chain([white(0.0, 0.3), white(1.0, 0.3), white(0.0, 1.0), white(1.0, 1.0)]).chain(coated_white).chain(sheened_white) {
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
                if let Bsdf::PhysicallyBased(Pbr { alpha, coat, coat_alpha, .. }) = bsdf
                    && alpha >= 0.09
                    && (coat == 0.0 || coat_alpha >= 0.09)
                {
                    assert!((total - given).abs() < 0.02, "{bsdf:?} at {wo}: density integrates to {total}, {given} of the samples given");
                }
            }
            // Energy lost to single scattering: little when smooth, more when rough.
            let smooth = albedo_by_quadrature(&white(0.0, 0.3), Vec3::new(0.1, 0.2, 0.95).normalize());
            assert!(smooth.min_element() > 0.95, "a smooth white dielectric keeps {smooth}");
            // Without a specular layer, exactly Lambert.
            let lambert = opaque(Vec3::splat(0.5), 0.0, 1.0, 0.0, 0.0);
            let wi = Vec3::new(0.7, 0.1, 0.2).normalize();
            assert!((lambert.eval(wo, wi) - Bsdf::Lambert { albedo: Vec3::splat(0.5) }.eval(wo, wi)).abs().max_element() < 1e-6);
            assert!((lambert.pdf(wo, wi) - wi.z / std::f32::consts::PI).abs() < 1e-6);
        }
    }

    /// ∫ `f` over the whole sphere of directions by a midpoint rule in (cos θ, φ).
    fn over_sphere(f: impl Fn(Vec3) -> Vec3) -> Vec3 {
        let below = over_hemisphere(|w| f(Vec3::new(w.x, w.y, -w.z)));
        over_hemisphere(f) + below
    }

    /// Transmission never makes light (whatever side of a boundary the light comes from, total
    /// internal reflection included), and a smooth white dielectric that transmits loses
    /// nothing: what Fresnel does not reflect goes through.
    #[test]
    fn transmission_keeps_within_its_light_and_loses_none_when_smooth() {
        let directions = [Vec3::new(0.1, 0.2, 0.95), Vec3::new(0.6, -0.3, 0.5), Vec3::new(-0.9, 0.1, 0.2)].map(Vec3::normalize);
        for wo in directions {
            for bsdf in transmitting_grid().into_iter().chain([transmitting(Vec3::ONE, 0.0, 0.5, 1.0, 1.5, false), transmitting(Vec3::ONE, 0.0, 1.0, 1.0, 1.0 / 1.5, true)]) {
                let sampled = albedo(&bsdf, wo, 256);
                assert!(sampled.max_element() <= 1.0 + 1e-2, "{bsdf:?} at {wo}: sampled albedo {sampled}");
                let Bsdf::PhysicallyBased(Pbr { alpha, .. }) = bsdf else { unreachable!() };
                if alpha >= 0.1 {
                    let q = over_sphere(|wi| bsdf.eval(wo, wi));
                    assert!(q.max_element() <= 1.0 + 1e-2, "{bsdf:?} at {wo}: albedo by quadrature {q}");
                    assert!((q - sampled).abs().max_element() < 0.02, "{bsdf:?} at {wo}: quadrature {q}, sampled {sampled}");
                }
            }
            for (eta, thin) in [(1.0 / 1.5, true), (1.0 / 1.5, false), (1.5, false)] {
                let smooth = transmitting(Vec3::ONE, 0.0, 0.0, 1.0, eta, thin);
                let a = albedo(&smooth, wo, 128);
                assert!((a - Vec3::ONE).abs().max_element() < 5e-3, "eta {eta}, thin {thin} at {wo}: {a}");
            }
        }
    }

    /// Light goes through a thin wall alike both ways; through a boundary between media, the
    /// BTDF (without the η² compression of radiance) is reciprocal up to the ratio of the
    /// indices squared (Veach 1997, §5.2): f(wo → wi) η_o² = f(wi → wo) η_i². Seen from the other
    /// side, a direction's z flips.
    #[test]
    fn transmission_is_reciprocal() {
        let flip = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
        let pairs = [(Vec3::new(0.1, 0.2, 0.95), Vec3::new(-0.2, 0.1, -0.9)), (Vec3::new(0.6, -0.3, 0.5), Vec3::new(-0.4, 0.2, -0.7)), (Vec3::new(-0.3, 0.1, 0.4), Vec3::new(0.1, 0.1, -0.6))];
        let mut compared = 0;
        for (wo, wi) in pairs.map(|(a, b)| (a.normalize(), b.normalize())) {
            for bsdf in transmitting_grid() {
                let Bsdf::PhysicallyBased(Pbr { eta, thin, .. }) = bsdf else { unreachable!() };
                let back = if thin { bsdf } else { bsdf.across(1.0 / eta) };
                let there = bsdf.eval(wo, wi) / wi.z.abs();
                let again = back.eval(flip(wi), flip(wo)) / wo.z.abs();
                let scale = if thin { 1.0 } else { eta * eta };
                assert!((there * scale - again).abs().max_element() <= 1e-3 * (1.0 + again.max_element()), "{bsdf:?}: {there} × {scale} vs {again}");
                compared += (there.max_element() > 0.0) as u32;
            }
        }
        assert!(compared > 40, "only {compared} pairs transmit");
    }

    /// A chi-square-style comparison of where samples land with the density [`Bsdf::pdf`]
    /// claims, over the whole sphere (reflection and transmission): for each of a grid of cells
    /// in (cos θ, φ), the count of samples in it against the density integrated over it, and
    /// the density over the sphere against the share of samples given.
    #[test]
    fn transmitted_samples_follow_the_claimed_density() {
        let (rows, columns, per_cell) = (20usize, 20usize, 16usize);
        let wo = Vec3::new(0.5, -0.2, 0.6).normalize();
        for bsdf in transmitting_grid().into_iter().filter(|b| matches!(b, Bsdf::PhysicallyBased(Pbr { alpha, .. }) if *alpha >= 0.1)) {
            let m = 512;
            let mut counts = vec![0u32; rows * columns];
            let cell = |w: Vec3| {
                let row = (((w.z + 1.0) / 2.0 * rows as f32) as usize).min(rows - 1);
                let phi = w.y.atan2(w.x).rem_euclid(std::f32::consts::TAU);
                row * columns + ((phi / std::f32::consts::TAU * columns as f32) as usize).min(columns - 1)
            };
            let mut given = 0;
            // Independent uniform numbers (a 64-bit LCG's high bits), not a lattice: a lattice
            // mapped through the lobes and the lobe choice lands in moiré bands.
            let mut state = 0x2545_f491_4f6c_dd1du64;
            let mut uniform = || {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                (state >> 40) as f32 / (1u64 << 24) as f32
            };
            for _ in 0..m * m {
                if let Some(s) = bsdf.sample(wo, [uniform(), uniform()], uniform()) {
                    counts[cell(s.wi)] += 1;
                    given += 1;
                }
            }
            let mut chi2 = 0.0;
            let mut dof = 0;
            let mut total = 0.0;
            for (k, &count) in counts.iter().enumerate() {
                let (row, column) = (k / columns, k % columns);
                // The density over the cell by a midpoint rule (area element: d(cos θ) dφ).
                let mut mass = 0.0;
                for a in 0..per_cell {
                    for b in 0..per_cell {
                        let z = -1.0 + 2.0 * (row as f32 + (a as f32 + 0.5) / per_cell as f32) / rows as f32;
                        let phi = std::f32::consts::TAU * (column as f32 + (b as f32 + 0.5) / per_cell as f32) / columns as f32;
                        let r = (1.0 - z * z).max(0.0).sqrt();
                        mass += bsdf.pdf(wo, Vec3::new(r * phi.cos(), r * phi.sin(), z));
                    }
                }
                let mass = mass * (2.0 / rows as f32) * (std::f32::consts::TAU / columns as f32) / (per_cell * per_cell) as f32;
                total += mass;
                let expected = mass * (m * m) as f32;
                if expected > 20.0 {
                    chi2 += (count as f32 - expected).powi(2) / expected;
                    dof += 1;
                }
            }
            let share = given as f32 / (m * m) as f32;
            assert!((total - share).abs() < 0.01, "{bsdf:?}: the density integrates to {total}, {share} of the samples given");
            // About 1 per cell for the right density (up to 1.3 seen: the quadrature's error);
            // a wrong one (a lobe's factor, a Jacobian) is far above.
            assert!(chi2 < 1.5 * dof as f32, "{bsdf:?}: chi² {chi2} over {dof} cells");
        }
    }

    #[test]
    fn glossy_metal_reflects_at_most_its_light() {
        let wo = Vec3::new(0.5, 0.0, 0.8).normalize();
        for alpha in [0.05, 0.3, 1.0] {
            let bsdf = Bsdf::Glossy { reflectance: Vec3::ONE, alpha };
            let a = albedo(&bsdf, wo, 128);
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
