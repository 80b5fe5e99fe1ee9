//! Scattering functions: how much light a surface reflects or transmits from one direction to
//! another, and how to sample that. Directions are in the shading frame (`z` the normal) and
//! point away from the surface; `wo` is towards the viewer.
//!
//! The models follow the seed's ray tracing chapter (Shirley: Lambert, Phong, mirror reflection,
//! Snell refraction, Schlick's Fresnel approximation for metals and the exact dielectric Fresnel
//! equations, docs/design/seeds.md §1.6) and, for rough metal, the GGX microfacet distribution with
//! visible-normal sampling (Heitz 2018), so that the path tracer's estimates stay unbiased. Rough
//! transmission through the same microfacets is Walter et al.'s (2007) BTDF, as pbrt-v4's
//! dielectric writes it (without the η² compression of radiance, which cancels on every path that
//! enters a volume and leaves it again, as the smooth `Glass` leaves it out).

use glam::Vec3;

use crate::microfacet::{Ggx, Seen, dielectric_albedo, ggx_d, sample_visible_normal, smith_g1, smith_g2, smith_height_correlated};
use crate::sheen;
use crate::warp::{cosine_hemisphere, uniform_hemisphere};

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
    /// The specular layer of a [`Pbr`] alone, its GGX reflection and the multiple scattering
    /// of it, without the base, transmission, coat or sheen: what Whitted's and Cook's
    /// recursions trace for the layer's reflection of the scene (see [`Bsdf::specular_layer`]),
    /// so that every integrator reflects by the same lobes.
    Layer(Pbr),
}

/// glTF 2.0's metallic-roughness BSDF (its Appendix B): a Lambertian base under a GGX
/// specular layer of a dielectric (Fresnel from `f0`, 0.04 for index 1.5, tinted by glTF's
/// `KHR_materials_specular` colour), blended by `metallic` with a GGX conductor of colour
/// `base`. The dielectric's Fresnel runs from `f0` head-on to `f90` at grazing (1, or glTF's
/// `KHR_materials_specular` factor, 0 leaving a pure Lambertian base). Specular masking is
/// Smith's, height-correlated; `alpha` is the roughness squared.
///
/// The layers keep their energy as OpenPBR's and Cycles' Principled BSDF do, where glTF's
/// Appendix B loses it (a white rough dielectric seen at 75° kept 0.78 of the light, a white
/// metal of roughness 1 seen head-on 0.31): the GGX layer gets Kulla and Conty's
/// multiple-scattering lobe (see [`crate::microfacet`]), and the base under the dielectric is
/// scaled by one minus the layer's directional albedo E, tabulated over angle and roughness,
/// for both directions (`(1 − E(μo))(1 − E(μi)) / (1 − E_avg)`, reciprocal): a white
/// dielectric or a white metal at any roughness, index and angle reflects all the light it
/// receives.
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
/// Fresnel, and what lies under it is scaled by one minus the coat's directional albedo seen
/// from `wo` (OpenPBR's and Cycles' albedo scaling). A reciprocal scaling by both directions
/// cannot keep the light of every layer under it: (1 − E(μo))(1 − E(μi)) / (1 − E_avg) is
/// exact over a diffuse base but makes 5 % over a mirror seen head-on, and the coupling by
/// the Fresnel of both directions loses 4 % over a diffuse one. The coat's own multiple
/// scattering is left out: its Fresnel average (9 %) squared leaves it under 0.3 % of the light.
///
/// With `sheen` (glTF's KHR_materials_sheen), a layer of fibres, as velvet and other cloth
/// have, lies over the base and under the coat: Estevez and Kulla's "Charlie" distribution of
/// microfibre α `sheen_alpha` with Ashikhmin's visibility, as the extension specifies, scaling
/// what lies under it by the light it leaves, `1 − max(sheen) E(μo)` with E the lobe's
/// directional albedo, seen from `wo` as for the coat (the extension takes the lesser of the
/// scalings for the two directions, reciprocal, which loses light at every angle).
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

impl Pbr {
    /// The specular layer's Fresnel reflectance for a direction at `cos` to the microfacet
    /// normal: the dielectric's grey Schlick term blended to the metal's colour; the
    /// transmitting share of the dielectric reflects by the exact equations instead (Schlick's
    /// knows no total internal reflection), so that with what it transmits it makes one, and
    /// by `transmission_scale` more (see [`Energy::transmission_scale`]).
    fn layer_reflectance(&self, cos: f32, transmission_scale: f32) -> Vec3 {
        let Pbr { base, metallic, f0, f90, transmission, eta, .. } = *self;
        let (layer_f0, layer_f90) = layer(base, metallic, f0, f90);
        let schlick = fresnel_schlick(layer_f0, layer_f90, cos);
        if transmission == 0.0 {
            return schlick;
        }
        let dielectric = fresnel_schlick(f0, Vec3::splat(f90), cos);
        let share = (1.0 - metallic) * transmission;
        schlick - dielectric * share + Vec3::splat(f90 * fresnel_dielectric(cos, eta) * share * transmission_scale)
    }

    /// What the layers take of the albedo tables ([`crate::microfacet`]) for a direction at
    /// `cos_o` to the normal: read once per evaluation, since a path's bounce evaluates the
    /// function and its density several times (a frame of the sphere grid was 1.6× slower
    /// reading the tables for each term).
    fn energy(&self, cos_o: f32) -> Energy {
        let ggx = Ggx::new(self.alpha);
        let dielectric = ggx.multiple_scattering_colour(self.f0, Vec3::splat(self.f90));
        let metal = if self.metallic > 0.0 { ggx.multiple_scattering_colour(self.base, Vec3::ONE) } else { Vec3::ZERO };
        // The metal's and the opaque dielectric's multiple scattering, blended as their single
        // scattering is. The transmitting share's reflection, by the exact Fresnel equations,
        // has none (its rough microfacets lose what bounces between them, as its
        // transmission does).
        let compensation = metal * self.metallic + dielectric * ((1.0 - self.metallic) * (1.0 - self.transmission));
        let o = ggx.at(cos_o);
        let (f0, f90) = (self.f0, Vec3::splat(self.f90));
        let layer = ggx.albedo(f0, f90, dielectric, o);
        let base = (Vec3::ONE - layer).max(Vec3::ZERO) / (Vec3::ONE - ggx.average_albedo(f0, f90, dielectric)).max(Vec3::splat(1e-6));
        // A thin wall's reflection and its mirror image through the wall make one GGX lobe of
        // F = 1 together, whose albedo the reflection table holds.
        let kept = match (self.transmission > 0.0 && self.metallic < 1.0, self.thin) {
            (false, _) => 1.0,
            (true, true) => o.e,
            (true, false) => dielectric_albedo(cos_o, self.alpha, self.eta),
        };
        let g1_o = smith_g1(Vec3::new(0.0, 0.0, cos_o), self.alpha);
        Energy { ggx, o, dielectric, compensation, layer, base, transmission_scale: 1.0 / kept.max(MIN_KEPT), g1_o }
    }

    /// The specular layer's reflection, BRDF × cos θi, for `wi` seen by the tables as `i` and
    /// the pair's `half` vector: its GGX lobe and the multiple scattering of it.
    fn reflection(&self, energy: &Energy, i: Seen, wo: Vec3, wi: Vec3, half: &Half) -> Vec3 {
        let single = self.layer_reflectance(wo.dot(half.h), energy.transmission_scale) * (half.d * smith_height_correlated(wo, wi, self.alpha) * wi.z);
        single + energy.compensation * energy.ggx.multiple_scattering(energy.o, i, wi.z)
    }

    /// What of the light reaches the diffuse base through the dielectric's specular layer and
    /// leaves it again, for `wo` and a direction seen by the tables as `i`: (1 − E(μo))
    /// (1 − E(μi)) / (1 − E_avg), E the layer's directional albedo with its multiple scattering
    /// (Kulla and Conty 2017). A Lambertian base under it reflects base × (1 − E(μo)), all that
    /// the layer leaves, and the coupling is reciprocal. Per colour channel, since
    /// KHR_materials_specular's colour tints f0; a channel whose layer reflects everything
    /// passes nothing (0 / ε).
    fn base_through(&self, energy: &Energy, i: Seen) -> Vec3 {
        energy.base * (Vec3::ONE - energy.ggx.albedo(self.f0, Vec3::splat(self.f90), energy.dielectric, i)).max(Vec3::ZERO)
    }
}

/// What a [`Pbr`]'s layers take of the albedo tables for one direction `wo` (see
/// [`Pbr::energy`]).
#[derive(Clone, Copy)]
struct Energy {
    ggx: Ggx,
    /// `wo` as the tables see it.
    o: Seen,
    /// The colour of the dielectric's multiple-scattering lobe.
    dielectric: Vec3,
    /// The colour of the whole layer's multiple-scattering lobe.
    compensation: Vec3,
    /// The dielectric layer's directional albedo E(μo).
    layer: Vec3,
    /// (1 − E(μo)) / (1 − E_avg): [`Pbr::base_through`] but for the other direction's factor.
    base: Vec3,
    /// 1 / E(μo) for the transmitting share's reflection and refraction together
    /// ([`crate::microfacet::dielectric_albedo`]): what scales them up to keep the light
    /// that single scattering loses between the facets (Turquin's compensation, as Cycles'
    /// glass has it; not reciprocal, as refraction across a boundary is not either). 1 for a
    /// surface that transmits nothing.
    transmission_scale: f32,
    /// Smith's masking of `wo` by the GGX microfacets, which every density of a reflection
    /// for `wo` has.
    g1_o: f32,
}

/// The half vector of a pair of directions on the same side and GGX's density of it: what a
/// physically based function's reflection and the density of sampling it share, worked out
/// once where both are wanted.
struct Half {
    h: Vec3,
    d: f32,
}

impl Half {
    fn of(wo: Vec3, wi: Vec3, alpha: f32) -> Half {
        let h = (wo + wi).normalize();
        Half { h, d: ggx_d(h, alpha) }
    }
}

/// The least share of the light a transmitting boundary's single scattering is taken to keep
/// (the table's least is 0.45): a bound on the compensation's scale.
const MIN_KEPT: f32 = 0.25;

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
            let mut value = under.eval(wo, wi) * (1.0 - coat * coat_albedo(wo.z, coat_alpha));
            if wi.z > 0.0 {
                let h = (wo + wi).normalize();
                value += Vec3::splat(coat * coat_fresnel(wo.dot(h)) * ggx_d(h, coat_alpha) * smith_height_correlated(wo, wi, coat_alpha) * wi.z);
            }
            return value;
        }
        if let Some((under, sheen, sheen_alpha)) = self.sheened() {
            return under.eval(wo, wi) * sheen::left(sheen, sheen_alpha, wo.z) + sheen * sheen::lobe(wo, wi, sheen_alpha);
        }
        match *self {
            Bsdf::PhysicallyBased(p) | Bsdf::Layer(p) => self.physically_based_eval(&p.energy(wo.z), wo, wi),
            _ if wi.z < 0.0 => Vec3::ZERO,
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

    /// [`Bsdf::eval`] and [`Bsdf::pdf`] at once (see [`Scattering::eval_pdf`]).
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        self.towards(wo).eval_pdf(wi)
    }

    /// The function seen from `wo`: what its evaluations and samples for that direction share,
    /// worked out once.
    pub fn towards(&self, wo: Vec3) -> Scattering {
        let shared = match *self {
            Bsdf::PhysicallyBased(p) | Bsdf::Layer(p) if p.coat == 0.0 && p.sheen == Vec3::ZERO && wo.z > 0.0 => {
                let energy = p.energy(wo.z);
                let probabilities = self.lobe_probabilities(wo, &energy);
                Some((energy, probabilities))
            }
            _ => None,
        };
        Scattering { bsdf: *self, wo, shared }
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
        match *self {
            Bsdf::PhysicallyBased(p) | Bsdf::Layer(p) => {
                let energy = p.energy(wo.z);
                self.physically_based_pdf(&energy, wo, wi, self.lobe_probabilities(wo, &energy))
            }
            _ if wi.z < 0.0 => 0.0,
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
            // Without coat or sheen (taken off above), seen from above: see Scattering::sample.
            Bsdf::PhysicallyBased(_) | Bsdf::Layer(_) => (wo.z > 0.0).then(|| self.towards(wo).sample(u, choose))?,
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
    /// For [`Bsdf::PhysicallyBased`] and [`Bsdf::Layer`], the probabilities that a sample picks
    /// the specular, the cosine-distributed (the diffuse base and the specular layer's multiple
    /// scattering) and the transmission lobe: each lobe's share of the light at `wo`'s angle
    /// (the specular lobe at least 10 % of them, so that a dark base's highlights are still
    /// found; 0 without a specular layer). Transmission keeps at least a tenth of its share
    /// where Fresnel reflects all at the macro normal, since rough microfacets there still let
    /// some light through.
    fn lobe_probabilities(&self, wo: Vec3, energy: &Energy) -> [f32; 3] {
        let (p @ Pbr { base, metallic, f90, eta, .. }, whole) = match *self {
            Bsdf::PhysicallyBased(p) => (p, true),
            Bsdf::Layer(p) => (p, false),
            _ => return [0.0; 3],
        };
        // The layer alone has neither base nor transmission.
        let (base_share, share) = if whole { ((1.0 - metallic) * (1.0 - p.transmission), (1.0 - metallic) * p.transmission) } else { (0.0, 0.0) };
        let specular = crate::lights::luminance(p.layer_reflectance(wo.z, energy.transmission_scale)).max(0.0);
        let dielectric = crate::lights::luminance(energy.layer);
        let multiple = crate::lights::luminance(energy.compensation) * (1.0 - energy.o.e);
        let diffuse = crate::lights::luminance(base) * base_share * (1.0 - dielectric).max(0.0) + multiple;
        let transmitted = if share > 0.0 { crate::lights::luminance(base) * share * (1.0 - f90 * fresnel_dielectric(wo.z, eta)).max(0.1) } else { 0.0 };
        let total = specular + diffuse + transmitted;
        if specular == 0.0 || total == 0.0 {
            return [0.0, diffuse, transmitted].map(|p| if total > 0.0 { p / total } else { 0.0 });
        }
        let p = (specular / total).max(0.1);
        let rest = diffuse + transmitted;
        if rest == 0.0 { [1.0, 0.0, 0.0] } else { [p, (1.0 - p) * diffuse / rest, (1.0 - p) * transmitted / rest] }
    }

    /// For a transmitting [`Bsdf::PhysicallyBased`], BTDF × |cos θi| for `wi` below the surface
    /// (`wo` above it), times `scale` (its [`Energy::transmission_scale`]); zero for every other
    /// function.
    fn transmitted(&self, wo: Vec3, wi: Vec3, scale: f32) -> Vec3 {
        let Bsdf::PhysicallyBased(Pbr { base, metallic, alpha, f90, transmission, eta, thin, .. }) = *self else { return Vec3::ZERO };
        let tint = base * ((1.0 - metallic) * transmission * scale);
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

    /// For [`Bsdf::PhysicallyBased`] and [`Bsdf::Layer`] (without coat or sheen), BSDF ×
    /// |cos θi| with the tables read for `wo` as `energy`.
    fn physically_based_eval(&self, energy: &Energy, wo: Vec3, wi: Vec3) -> Vec3 {
        if wi.z < 0.0 {
            return self.transmitted(wo, wi, energy.transmission_scale);
        }
        self.reflected_eval(energy, wo, wi, &Half::of(wo, wi, self.alpha()))
    }

    /// For [`Bsdf::PhysicallyBased`] and [`Bsdf::Layer`] (without coat or sheen), the density
    /// of `wi` for its [`Bsdf::lobe_probabilities`], with the tables read for `wo` as `energy`.
    fn physically_based_pdf(&self, energy: &Energy, wo: Vec3, wi: Vec3, probabilities: [f32; 3]) -> f32 {
        if wi.z < 0.0 {
            return self.transmission_pdf(wo, wi, probabilities[2]);
        }
        self.reflected_pdf(energy, wo, wi, probabilities, &Half::of(wo, wi, self.alpha()))
    }

    /// [`Bsdf::physically_based_eval`] and [`Bsdf::physically_based_pdf`] at once, the half
    /// vector and its density worked out once for both.
    fn physically_based_eval_pdf(&self, energy: &Energy, wo: Vec3, wi: Vec3, probabilities: [f32; 3]) -> (Vec3, f32) {
        if wi.z < 0.0 {
            return (self.transmitted(wo, wi, energy.transmission_scale), self.transmission_pdf(wo, wi, probabilities[2]));
        }
        let half = Half::of(wo, wi, self.alpha());
        (self.reflected_eval(energy, wo, wi, &half), self.reflected_pdf(energy, wo, wi, probabilities, &half))
    }

    /// The microfacet α of [`Bsdf::PhysicallyBased`] and [`Bsdf::Layer`] (1 for the others,
    /// which have none).
    fn alpha(&self) -> f32 {
        match self {
            Bsdf::PhysicallyBased(p) | Bsdf::Layer(p) => p.alpha,
            _ => 1.0,
        }
    }

    /// [`Bsdf::physically_based_eval`] for `wi` above the surface, its half vector with `wo`
    /// given.
    fn reflected_eval(&self, energy: &Energy, wo: Vec3, wi: Vec3, half: &Half) -> Vec3 {
        match *self {
            Bsdf::PhysicallyBased(p) => {
                let i = energy.ggx.at(wi.z);
                let weight = (1.0 - p.metallic) * (1.0 - p.transmission);
                let diffuse = if weight > 0.0 { p.base * p.base_through(energy, i) * (weight * std::f32::consts::FRAC_1_PI) } else { Vec3::ZERO };
                p.reflection(energy, i, wo, wi, half) + diffuse * wi.z
            }
            Bsdf::Layer(p) => p.reflection(energy, energy.ggx.at(wi.z), wo, wi, half),
            _ => Vec3::ZERO,
        }
    }

    /// [`Bsdf::physically_based_pdf`] for `wi` above the surface, its half vector with `wo`
    /// given.
    fn reflected_pdf(&self, energy: &Energy, wo: Vec3, wi: Vec3, [specular, diffuse, transmitted]: [f32; 3], half: &Half) -> f32 {
        let (Bsdf::PhysicallyBased(Pbr { eta, thin, .. }) | Bsdf::Layer(Pbr { eta, thin, .. })) = *self else { return 0.0 };
        // Refraction samples that meet total internal reflection at their microfacet reflect
        // off it instead.
        let reflected = if transmitted > 0.0 && !thin && refract_about(wo, half.h, eta).is_none() { specular + transmitted } else { specular };
        reflected * half.d * energy.g1_o / (4.0 * wo.z) + diffuse * wi.z * std::f32::consts::FRAC_1_PI
    }

    /// The density with which [`Bsdf::sample`] picks `wi` below the surface, for a transmission
    /// lobe picked with probability `transmitted`.
    fn transmission_pdf(&self, wo: Vec3, wi: Vec3, transmitted: f32) -> f32 {
        let Bsdf::PhysicallyBased(Pbr { alpha, eta, thin, .. }) = *self else { return 0.0 };
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

    /// The simplest function that scatters as this one does: a physically based function
    /// whose every layer is off (no specular layer, f0 and f90 both 0 as glTF's
    /// KHR_materials_specular factor 0 makes them; no metal, transmission, coat or sheen) is
    /// its Lambertian base, which a path then shades without reading the albedo tables.
    /// Textures only scale the factors that turn layers on, so a shader reduced so is
    /// Lambertian at every point.
    pub fn simplest(self) -> Bsdf {
        match self {
            Bsdf::PhysicallyBased(Pbr { base, metallic: 0.0, f0: Vec3::ZERO, f90: 0.0, transmission: 0.0, coat: 0.0, sheen: Vec3::ZERO, .. }) => Bsdf::Lambert { albedo: base },
            other => other,
        }
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
    /// `cos_o` from its normal: its specular layer alone ([`Bsdf::Layer`]; the diffuse base is
    /// lit by the lights alone), for Cook's samples of the lobe; and for Whitted's one mirror
    /// ray, the layer's Fresnel reflectance faded out with roughness (a rough surface mirrors
    /// nothing). The coat and sheen over the layer take their share with
    /// [`Bsdf::through_layers`]. `None` for other functions, and for a surface without a
    /// specular layer.
    pub fn specular_layer(&self, cos_o: f32) -> Option<(Bsdf, Vec3)> {
        let Bsdf::PhysicallyBased(p @ Pbr { base, metallic, alpha, f0, f90, .. }) = *self else { return None };
        let (_, layer_f90) = layer(base, metallic, f0, f90);
        let alone = Pbr { coat: 0.0, sheen: Vec3::ZERO, ..p };
        (layer_f90.max_element() > 0.0).then(|| (Bsdf::Layer(alone), p.layer_reflectance(cos_o, 1.0) * (1.0 - alpha.sqrt())))
    }
}

impl Bsdf {
    /// What Whitted's and Cook's recursions trace for a coated physically based function seen
    /// at `cos_o` from its normal, as [`Bsdf::specular_layer`] gives for the layer under it:
    /// the coat's lobe (a GGX dielectric of its roughness, Schlick's Fresnel from 4 %, as a
    /// [`Bsdf::Layer`] over a black base), the coat's weight, and Whitted's one mirror ray's
    /// weight before it (the coat's Fresnel reflectance faded out with roughness). `None`
    /// without a coat.
    pub fn coat_layer(&self, cos_o: f32) -> Option<(Bsdf, f32, f32)> {
        let (under, coat, coat_alpha) = self.coated()?;
        let Bsdf::PhysicallyBased(p) = under else { return None };
        let lobe = Pbr { base: Vec3::ZERO, metallic: 0.0, alpha: coat_alpha, f0: Vec3::splat(0.04), f90: 1.0, transmission: 0.0, sheen: Vec3::ZERO, ..p };
        Some((Bsdf::Layer(lobe), coat, coat_fresnel(cos_o) * (1.0 - coat_alpha.sqrt())))
    }

    /// The share of the light seen at `cos_o` that a physically based function's coat and
    /// sheen leave to the layers under them, as [`Bsdf::eval`] scales those layers: one minus
    /// each one's directional albedo. 1 without either, and for other functions.
    pub fn through_layers(&self, cos_o: f32) -> f32 {
        if let Some((under, coat, coat_alpha)) = self.coated() {
            return (1.0 - coat * coat_albedo(cos_o, coat_alpha)) * under.through_layers(cos_o);
        }
        self.sheened().map_or(1.0, |(_, sheen, sheen_alpha)| sheen::left(sheen, sheen_alpha, cos_o))
    }

    /// A sample in direction `wi` with its weight over the whole function's density (the
    /// one-sample model of layered functions: unbiased whichever layer drew it).
    fn weighed(&self, wo: Vec3, wi: Vec3) -> Option<BsdfSample> {
        let (value, pdf) = self.eval_pdf(wo, wi);
        (pdf > 0.0).then(|| BsdfSample { wi, weight: value / pdf, pdf, transmitted: wi.z < 0.0 })
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

/// A function seen from one direction `wo` ([`Bsdf::towards`]): a physically based function's
/// albedo-table reads and lobe probabilities for `wo`, which every evaluation and sample for
/// that direction shares. A path's vertex evaluates its function for each light sample and
/// samples it once, all from the same `wo`: working these out once per vertex instead of at
/// every call saved a sixth of the shading's instructions on the sphere grid
/// (docs/performance.md).
#[derive(Clone, Copy)]
pub(crate) struct Scattering {
    bsdf: Bsdf,
    wo: Vec3,
    /// For a physically based function without coat or sheen, seen from above: what it takes
    /// of the tables for `wo`, and its lobes' probabilities.
    shared: Option<(Energy, [f32; 3])>,
}

impl Scattering {
    /// The function.
    pub fn bsdf(&self) -> &Bsdf {
        &self.bsdf
    }

    /// BSDF × |cos θi| and the density with which [`Scattering::sample`] picks `wi`.
    pub fn eval_pdf(&self, wi: Vec3) -> (Vec3, f32) {
        match &self.shared {
            Some((energy, probabilities)) if wi.z != 0.0 => {
                self.bsdf.physically_based_eval_pdf(energy, self.wo, wi, *probabilities)
            }
            _ => (self.bsdf.eval(self.wo, wi), self.bsdf.pdf(self.wo, wi)),
        }
    }

    /// Samples a direction from two uniform numbers and a third for choosing a lobe, as
    /// [`Bsdf::sample`] does.
    pub fn sample(&self, u: [f32; 2], choose: f32) -> Option<BsdfSample> {
        let (Some((energy, probabilities)), Bsdf::PhysicallyBased(Pbr { alpha, eta, thin, .. }) | Bsdf::Layer(Pbr { alpha, eta, thin, .. })) = (&self.shared, self.bsdf) else {
            return self.bsdf.sample(self.wo, u, choose);
        };
        let wo = self.wo;
        // One lobe by its share of the light, the weight over every lobe's density (the
        // one-sample model: unbiased whichever lobe drew it). A lobe's direction on the wrong
        // side of the surface is refused, so that each side's density is that of the lobes
        // that give directions there.
        let [specular, _, transmitted] = *probabilities;
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
        let (f, pdf) = self.bsdf.physically_based_eval_pdf(energy, wo, wi, *probabilities);
        (pdf > 0.0).then(|| BsdfSample { wi, weight: f / pdf, pdf, transmitted: wi.z < 0.0 })
    }
}

/// The clearcoat's Fresnel reflectance at `cos` (Schlick's, index 1.5: 4 % head-on).
fn coat_fresnel(cos: f32) -> f32 {
    fresnel_schlick(Vec3::splat(0.04), Vec3::ONE, cos).x
}

/// The full clearcoat's directional albedo seen at `cos`, for α `alpha`: what it reflects,
/// which the layers under it do not receive.
fn coat_albedo(cos: f32, alpha: f32) -> f32 {
    let ggx = Ggx::new(alpha);
    ggx.single_scattering(Vec3::splat(0.04), Vec3::ONE, ggx.at(cos)).x
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
pub(crate) fn refract_about(wo: Vec3, h: Vec3, eta: f32) -> Option<Vec3> {
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

    /// Independent uniform numbers (a 64-bit LCG's high bits), not a lattice: a lattice mapped
    /// through the lobes and the lobe choice lands in moiré bands.
    fn uniform_numbers() -> impl FnMut() -> f32 {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        }
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

    /// A physically based function with every layer off is its Lambertian base: the reduced
    /// function evaluates, weighs and samples as the general one does, to rounding, for
    /// directions on both sides and at grazing angles; and any layer turned on, however
    /// little, keeps the general function.
    #[test]
    fn a_function_with_every_layer_off_reduces_to_its_lambertian_base() {
        let base = Vec3::new(0.63, 0.065, 0.05);
        let off = Pbr { base, metallic: 0.0, alpha: 1.0, f0: Vec3::ZERO, f90: 0.0, transmission: 0.0, eta: 1.0 / 1.5, thin: false, coat: 0.0, coat_alpha: 0.01, sheen: Vec3::ZERO, sheen_alpha: 0.25 };
        let general = Bsdf::PhysicallyBased(off);
        let reduced = general.simplest();
        assert!(matches!(reduced, Bsdf::Lambert { albedo } if albedo == base), "{reduced:?}");
        let mut next = uniform_numbers();
        let direction = |next: &mut dyn FnMut() -> f32| {
            let (z, phi) = (2.0 * next() - 1.0, std::f32::consts::TAU * next());
            let r = (1.0 - z * z).max(0.0).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        };
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-6 * (1.0 + b.abs().max_element());
        for _ in 0..2000 {
            let (wo, wi) = (direction(&mut next), direction(&mut next));
            let (f, pdf) = general.towards(wo).eval_pdf(wi);
            let (f_reduced, pdf_reduced) = reduced.towards(wo).eval_pdf(wi);
            assert!(close(f_reduced, f) && (pdf_reduced - pdf).abs() <= 1e-6 * (1.0 + pdf), "wo {wo} wi {wi}: {f_reduced} {pdf_reduced} vs {f} {pdf}");
            let u = [next(), next()];
            let choose = next();
            match (general.towards(wo).sample(u, choose), reduced.towards(wo).sample(u, choose)) {
                (None, None) => {}
                (Some(g), Some(r)) => assert!(close(r.wi, g.wi) && close(r.weight, g.weight) && (r.pdf - g.pdf).abs() <= 1e-5 * g.pdf && r.transmitted == g.transmitted, "wo {wo}: {r:?} vs {g:?}"),
                (g, r) => panic!("wo {wo}: {r:?} vs {g:?}"),
            }
        }
        for on in [
            Pbr { metallic: 0.01, ..off },
            Pbr { f90: 0.01, ..off },
            Pbr { f0: Vec3::new(0.0, 0.0, 0.01), ..off },
            Pbr { transmission: 0.01, ..off },
            Pbr { coat: 0.01, ..off },
            Pbr { sheen: Vec3::new(0.01, 0.0, 0.0), ..off },
        ] {
            assert!(matches!(Bsdf::PhysicallyBased(on).simplest(), Bsdf::PhysicallyBased(p) if p == on), "{on:?}");
        }
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
        // The layers Whitted's and Cook's recursions sample alone.
        .chain(physically_based_grid().into_iter().chain(transmitting_grid()).flat_map(|b| [b.specular_layer(wo.z).map(|l| l.0), b.coat_layer(wo.z).map(|l| l.0)]).flatten())
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

    /// The physically based BRDF never reflects more than it receives, loses little when smooth
    /// (a white dielectric keeps its light, a white metal nearly all), and its sampling density
    /// integrates to one over the hemisphere. Without a coat or sheen it is reciprocal; the
    /// coat and the sheen scale what lies under them by the light they take from the view
    /// direction alone (see [`Pbr`]), which is not.
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
                let layered = matches!(bsdf, Bsdf::PhysicallyBased(p) if p.coat > 0.0 || p.sheen != Vec3::ZERO);
                assert!(layered || (a - b).abs().max_element() <= 1e-4 * (1.0 + a.max_element()), "{bsdf:?}: {a} vs {b}");
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

    /// The white furnace of the issue (36): under light from everywhere, a white dielectric of
    /// any roughness and index 1 to 2 reflects all of it, seen from any angle to 85°, and so
    /// does a white metal (F0 = 1, its Fresnel average 1), as Cycles' Principled BSDF does.
    /// Measured (by the mean weight of 256² independent samples per direction, whose own error
    /// is about 0.3 %; a lattice of samples, as [`albedo`] takes, is up to 1.6 % off at grazing
    /// angles for a smooth metal): within 0.4 % everywhere. The same surfaces without the
    /// multiple-scattering lobe fall well outside (a white metal of roughness 1 keeps 0.31
    /// head-on), and with glTF's Fresnel-weighted base (before) the dielectric of roughness 1
    /// kept 0.78 at 75°, 0.41 at 85°.
    #[test]
    fn white_surfaces_reflect_all_the_light() {
        let mut worst_without = 0.0f32;
        for metallic in [0.0f32, 1.0] {
            for ior in [1.0f32, 1.2, 1.5, 2.0] {
                for roughness in [0.0f32, 0.25, 0.5, 0.75, 1.0] {
                    let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
                    let Bsdf::PhysicallyBased(p) = opaque(Vec3::ONE, metallic, (roughness * roughness).max(1e-3), f0, 1.0) else { unreachable!() };
                    let p = Pbr { eta: 1.0 / ior, ..p };
                    let bsdf = Bsdf::PhysicallyBased(p);
                    for degrees in [0.0f32, 30.0, 60.0, 75.0, 85.0] {
                        let wo = Vec3::new(degrees.to_radians().sin(), 0.0, degrees.to_radians().cos());
                        let mut uniform = uniform_numbers();
                        let a = (0..256 * 256).filter_map(|_| bsdf.sample(wo, [uniform(), uniform()], uniform())).map(|s| s.weight).sum::<Vec3>() / (256 * 256) as f32;
                        assert!((a - Vec3::ONE).abs().max_element() < 0.01, "metallic {metallic}, ior {ior}, roughness {roughness}, {degrees}°: {a}");
                        // The compensation taken out: the multiple-scattering lobe's albedo.
                        let energy = p.energy(wo.z);
                        let without = a - energy.compensation * (1.0 - energy.o.e);
                        worst_without = worst_without.max((Vec3::ONE - without).max_element());
                    }
                }
            }
        }
        assert!(worst_without > 0.5, "without the compensation the worst loses only {worst_without}");
    }

    /// A coat or fibres over a white surface, and a coat over fibres over it, take their light
    /// from what lies under them and give back what they do not reflect: the stack reflects all
    /// of it, from any angle, smooth or rough.
    #[test]
    fn white_stacks_reflect_all_the_light() {
        let white = |metallic: f32, roughness: f32| opaque(Vec3::ONE, metallic, roughness * roughness, 0.04, 1.0);
        let mut worst = 0.0f32;
        for (metallic, roughness) in [(0.0, 0.3), (1.0, 0.2), (0.0, 1.0), (1.0, 0.8)] {
            let stacks = [
                coated(white(metallic, roughness), 0.01),
                coated(white(metallic, roughness), 0.5),
                sheened(white(metallic, roughness), Vec3::ONE, 0.3),
                sheened(white(metallic, roughness), Vec3::ONE, 1.0),
                coated(sheened(white(metallic, roughness), Vec3::ONE, 0.5), 0.09),
            ];
            for bsdf in stacks {
                for degrees in [0.0f32, 40.0, 70.0, 85.0] {
                    let wo = Vec3::new(degrees.to_radians().sin(), 0.0, degrees.to_radians().cos());
                    let mut uniform = uniform_numbers();
                    let a = (0..256 * 256).filter_map(|_| bsdf.sample(wo, [uniform(), uniform()], uniform())).map(|s| s.weight).sum::<Vec3>() / (256 * 256) as f32;
                    worst = worst.max((a - Vec3::ONE).abs().max_element());
                }
            }
        }
        // Measured: 0.75 % at worst (fibres of roughness 0.3 seen at 85°).
        assert!(worst < 0.01, "a white stack is off by {worst}");
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

    /// The white furnace for transmitting surfaces (issue 36): a white, clear dielectric of any
    /// roughness, thin or a boundary seen from either side, reflects and transmits all the
    /// light it receives, as Cycles' glass does, where single scattering alone loses up to
    /// half of it (seen from inside at roughness 1). By the mean weight of 1024² samples (fewer
    /// are too noisy here: from inside past the critical angle the refraction is drawn rarely
    /// and weighs much; a quadrature over the sphere cannot resolve the narrow refracted lobe
    /// seen head-on); measured within 1.4 % (0.986 at roughness 0.4 seen head-on from inside,
    /// the table's own error, see `microfacet::DIELECTRIC_RULE`).
    #[test]
    fn white_transmitting_surfaces_keep_all_the_light() {
        let (mut worst, mut worst_without) = (0.0f32, 0.0f32);
        for (eta, thin) in [(1.0 / 1.5, true), (1.0 / 1.5, false), (1.5, false), (1.0 / 1.33, false), (2.0, false)] {
            for roughness in [0.4f32, 1.0] {
                let bsdf = transmitting(Vec3::ONE, 0.0, roughness, 1.0, eta, thin);
                let Bsdf::PhysicallyBased(p) = bsdf else { unreachable!() };
                for degrees in [0.0f32, 45.0, 75.0] {
                    let wo = Vec3::new(degrees.to_radians().sin(), 0.0, degrees.to_radians().cos());
                    let mut uniform = uniform_numbers();
                    let n = 1024 * 1024;
                    let a = ((0..n).filter_map(|_| bsdf.sample(wo, [uniform(), uniform()], uniform())).map(|s| f64::from(s.weight.x)).sum::<f64>() / n as f64) as f32;
                    worst = worst.max((a - 1.0).abs());
                    worst_without = worst_without.max(1.0 - a / p.energy(wo.z).transmission_scale);
                }
            }
        }
        assert!(worst < 0.02, "a white transmitting surface is off by {worst}");
        assert!(worst_without > 0.3, "without the compensation the worst loses only {worst_without}");
    }

    /// Light goes through a thin wall alike both ways; through a boundary between media, the
    /// BTDF (without the η² compression of radiance) is reciprocal up to the ratio of the
    /// indices squared (Veach 1997, §5.2): f(wo → wi) η_o² = f(wi → wo) η_i². Seen from the other
    /// side, a direction's z flips. The multiple-scattering compensation (1 / E of the direction
    /// looked from, [`Energy::transmission_scale`]) is not reciprocal, as Turquin's is not: the
    /// single-scattering functions under it are compared.
    #[test]
    fn transmission_is_reciprocal() {
        let flip = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
        let pairs = [(Vec3::new(0.1, 0.2, 0.95), Vec3::new(-0.2, 0.1, -0.9)), (Vec3::new(0.6, -0.3, 0.5), Vec3::new(-0.4, 0.2, -0.7)), (Vec3::new(-0.3, 0.1, 0.4), Vec3::new(0.1, 0.1, -0.6))];
        let mut compared = 0;
        for (wo, wi) in pairs.map(|(a, b)| (a.normalize(), b.normalize())) {
            for bsdf in transmitting_grid() {
                let Bsdf::PhysicallyBased(Pbr { eta, thin, .. }) = bsdf else { unreachable!() };
                let back = if thin { bsdf } else { bsdf.across(1.0 / eta) };
                let compensation = |b: &Bsdf, w: Vec3| match b {
                    Bsdf::PhysicallyBased(p) => p.energy(w.z).transmission_scale,
                    _ => unreachable!(),
                };
                let there = bsdf.eval(wo, wi) / wi.z.abs() / compensation(&bsdf, wo);
                let again = back.eval(flip(wi), flip(wo)) / wo.z.abs() / compensation(&back, flip(wi));
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
            let mut uniform = uniform_numbers();
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
