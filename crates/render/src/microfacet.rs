//! The GGX microfacet distribution with Smith's masking and visible-normal sampling (Heitz 2014,
//! 2018), and the light that a single scattering from it leaves out: a rough surface's facets
//! send some light into each other, which a single-scattering lobe drops (a white metal of
//! roughness 1 keeps 31 % of the light seen head-on). Kulla and Conty (2017, "Revisiting
//! physically based shading at Imageworks") give that light back with a second, diffuse-like
//! lobe built from the single-scattering lobe's directional albedo E(cos θ):
//!
//! f_ms(ωo, ωi) = F_ms (1 − E(μo)) (1 − E(μi)) / (π (1 − E_avg)),
//!
//! whose albedo is exactly 1 − E(μo), so that a white lobe reflects all the light, and which is
//! reciprocal. The same albedo scales a diffuse base under a dielectric specular layer (the
//! layering of OpenPBR and Cycles' Principled BSDF; see [`crate::bsdf::Pbr`]).
//!
//! E has no closed form. With Schlick's Fresnel, F = f0 + (f90 − f0)(1 − cos θh)⁵, the albedo is
//! linear in f0 and f90, so two tables over (cos θ, √α) hold it for every colour and index of
//! refraction: E for F = 1 and its grazing part E₅ for F = (1 − cos θh)⁵ (the "split sum" of
//! real-time renderers); the albedo for (f0, f90) is f0 (E − E₅) + f90 E₅. They are integrated
//! once, when a frame first meets a physically based material.
//!
//! A transmitting boundary loses light between its facets too; a third table, over
//! (cos θ, √α, η), holds what its reflection and refraction together keep
//! ([`dielectric_albedo`]).

use std::f32::consts::FRAC_1_PI;
use std::sync::OnceLock;

use glam::Vec3;

use crate::warp::concentric_disc;

/// The height-correlated Smith visibility term `G2 / (4 cos θo cos θi)` for GGX (Heitz 2014,
/// as glTF's Appendix B writes it).
pub(crate) fn smith_height_correlated(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
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
pub(crate) fn smith_g2(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let lambda = |w: Vec3| {
        let cos2 = w.z * w.z;
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        0.5 * ((1.0 + alpha * alpha * tan2).sqrt() - 1.0)
    };
    1.0 / (1.0 + lambda(wo) + lambda(wi))
}

/// The GGX normal distribution.
pub(crate) fn ggx_d(h: Vec3, alpha: f32) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = h.z * h.z * (a2 - 1.0) + 1.0;
    a2 / (std::f32::consts::PI * t * t)
}

/// Smith's masking term for GGX.
pub(crate) fn smith_g1(w: Vec3, alpha: f32) -> f32 {
    if w.z <= 0.0 {
        return 0.0;
    }
    let tan2 = (1.0 - w.z * w.z).max(0.0) / (w.z * w.z);
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// A microfacet normal sampled from the normals GGX surface shows to `wo` (Heitz 2018).
pub(crate) fn sample_visible_normal(wo: Vec3, alpha: f32, u: [f32; 2]) -> Vec3 {
    let v = Vec3::new(alpha * wo.x, alpha * wo.y, wo.z).normalize();
    let t1 = if v.z < 0.9999 { Vec3::Z.cross(v).normalize() } else { Vec3::X };
    let t2 = v.cross(t1);
    let d = concentric_disc(u);
    let s = 0.5 * (1.0 + v.z);
    let p2 = (1.0 - s) * (1.0 - d.x * d.x).max(0.0).sqrt() + s * d.y;
    let p = t1 * d.x + t2 * p2 + v * (1.0 - d.x * d.x - p2 * p2).max(0.0).sqrt();
    Vec3::new(alpha * p.x, alpha * p.y, p.z.max(1e-6)).normalize()
}

/// A GGX reflection lobe of one microfacet α as the albedo tables see it: the row of the tables
/// found once, so that the several albedos one evaluation of a layered BSDF needs cost a lookup
/// of a cosine each.
#[derive(Clone, Copy)]
pub(crate) struct Ggx {
    tables: &'static Tables,
    row: usize,
    /// Where α lies between `row` and the next, in √α.
    between: f32,
    /// 2 ∫ E(μ) μ dμ and 2 ∫ E₅(μ) μ dμ.
    average: [f32; 2],
}

/// The single-scattering albedo of a [`Ggx`] lobe seen at one angle: E for F = 1 and E₅, its
/// part for F = (1 − cos θh)⁵.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Seen {
    pub e: f32,
    pub grazing: f32,
}

impl Ggx {
    /// The lobe of microfacet α `alpha`.
    pub fn new(alpha: f32) -> Ggx {
        let tables = tables();
        let r = alpha.max(0.0).sqrt().min(1.0) * (TABLE_SIZE - 1) as f32;
        let row = (r as usize).min(TABLE_SIZE - 2);
        let between = r - row as f32;
        let (a, b) = (tables.averages[row], tables.averages[row + 1]);
        // The rows' averages are linear in √α as the rows are: the mean of the interpolated row.
        let average = [a[0] + (b[0] - a[0]) * between, a[1] + (b[1] - a[1]) * between];
        Ggx { tables, row, between, average }
    }

    /// The lobe seen at `cos` from the normal: bilinear in cos θ and √α.
    pub fn at(&self, cos: f32) -> Seen {
        let c = cos.clamp(0.0, 1.0) * (TABLE_SIZE - 1) as f32;
        let column = (c as usize).min(TABLE_SIZE - 2);
        let t = c - column as f32;
        let entry = |row: usize| {
            let (a, b) = (self.tables.entries[row * TABLE_SIZE + column], self.tables.entries[row * TABLE_SIZE + column + 1]);
            [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]
        };
        let (low, high) = (entry(self.row), entry(self.row + 1));
        Seen { e: low[0] + (high[0] - low[0]) * self.between, grazing: low[1] + (high[1] - low[1]) * self.between }
    }

    /// The directional albedo of the single-scattering reflection seen as `seen`, with
    /// Schlick's Fresnel from `f0` head-on to `f90` at grazing.
    pub fn single_scattering(&self, f0: Vec3, f90: Vec3, seen: Seen) -> Vec3 {
        f0 * (seen.e - seen.grazing) + f90 * seen.grazing
    }

    /// The colour of Kulla and Conty's multiple-scattering lobe for Schlick's Fresnel from `f0`
    /// to `f90`: of the light that the facets send into each other, the share that leaves
    /// after any number of bounces, F_avg² E_avg / (1 − F_avg (1 − E_avg)) with F_avg the
    /// cosine-weighted mean Fresnel reflectance, f0 + (f90 − f0) / 21. 1 for a white lobe.
    pub fn multiple_scattering_colour(&self, f0: Vec3, f90: Vec3) -> Vec3 {
        let e_avg = self.average[0];
        let f_avg = f0 + (f90 - f0) / 21.0;
        f_avg * f_avg * e_avg / (Vec3::ONE - f_avg * (1.0 - e_avg)).max(Vec3::splat(1e-6))
    }

    /// Kulla and Conty's white multiple-scattering lobe, BRDF × cos θi, for the two directions
    /// seen as `o` and `i`, `cos_i` from the normal: (1 − E(μo)) (1 − E(μi)) μi / (π (1 − E_avg)).
    /// Its albedo is 1 − E(μo), what the single-scattering lobe of F = 1 misses.
    pub fn multiple_scattering(&self, o: Seen, i: Seen, cos_i: f32) -> f32 {
        let e_avg = self.average[0];
        if e_avg >= 1.0 {
            return 0.0;
        }
        (1.0 - o.e) * (1.0 - i.e) * cos_i * FRAC_1_PI / (1.0 - e_avg)
    }

    /// The directional albedo seen as `seen` of the compensated lobe: single scattering with
    /// Schlick's Fresnel from `f0` to `f90`, plus [`Ggx::multiple_scattering`] of `colour` (its
    /// [`Ggx::multiple_scattering_colour`]).
    pub fn albedo(&self, f0: Vec3, f90: Vec3, colour: Vec3, seen: Seen) -> Vec3 {
        self.single_scattering(f0, f90, seen) + colour * (1.0 - seen.e)
    }

    /// The cosine-weighted mean of [`Ggx::albedo`] over the hemisphere, 2 ∫ albedo(μ) μ dμ: the
    /// share of light from everywhere at once that the compensated lobe reflects.
    pub fn average_albedo(&self, f0: Vec3, f90: Vec3, colour: Vec3) -> Vec3 {
        let [e_avg, grazing_avg] = self.average;
        f0 * (e_avg - grazing_avg) + f90 * grazing_avg + colour * (1.0 - e_avg)
    }
}

/// Entries per axis of the albedo tables: 32 cosines by 32 roughnesses, within 0.3 % of a fine
/// quadrature between the entries (the tests' bound is 0.5 %).
const TABLE_SIZE: usize = 32;

/// The smallest α tabulated (the first row, roughness 0): a sharper lobe than any material's.
const MIN_ALPHA: f32 = 1e-4;

/// E and E₅ over cos θ (columns, 0 to 1) and √α (rows, 0 to 1), and each row's
/// cosine-weighted mean.
struct Tables {
    entries: Vec<[f32; 2]>,
    averages: Vec<[f32; 2]>,
}

fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(Tables::integrate)
}

impl Tables {
    /// Each entry by a midpoint rule over the microfacet normals, in f64: the polar angle by
    /// the inverse of the distribution's cumulative (tan² θh = α² u / (1 − u), so that the
    /// rule's points follow D cos θh and the sharpest lobe is resolved), the azimuth over the
    /// half circle the lobe is symmetric in. The light reflected below the horizon is cut off
    /// along a curve that the rule converges to slowly (a grid of visible-normal samples
    /// converges no better: 0.8 % off at 64² samples). At 256 × 16 points (72 ms for the
    /// tables on one core) an entry is within 0.1 % of a 4096 × 1024 rule from cos θ = 0.25 up,
    /// 0.9 % at 0.03 and 1.6 % at 10⁻³, less than 2° from the horizon.
    fn integrate() -> Tables {
        let (n_u, n_phi) = (256, 16);
        let last = (TABLE_SIZE - 1) as f64;
        let mut entries = Vec::with_capacity(TABLE_SIZE * TABLE_SIZE);
        for row in 0..TABLE_SIZE {
            let a2 = (row as f64 / last).powi(4).max((MIN_ALPHA as f64).powi(2));
            for column in 0..TABLE_SIZE {
                let cos_o = (column as f64 / last).max(1e-3);
                let sin_o = (1.0 - cos_o * cos_o).sqrt();
                // Λ-like term of ωo in the height-correlated visibility (see
                // [`smith_height_correlated`]).
                let lambda_o = (cos_o * cos_o * (1.0 - a2) + a2).sqrt();
                let (mut e, mut grazing) = (0.0f64, 0.0f64);
                for a in 0..n_u {
                    let u = (a as f64 + 0.5) / n_u as f64;
                    let tan2 = a2 * u / (1.0 - u);
                    let (cos_h, sin_h) = ((1.0 / (1.0 + tan2)).sqrt(), (tan2 / (1.0 + tan2)).sqrt());
                    for b in 0..n_phi {
                        let phi = std::f64::consts::PI * (b as f64 + 0.5) / n_phi as f64;
                        let o_h = sin_o * sin_h * phi.cos() + cos_o * cos_h;
                        let cos_i = 2.0 * o_h * cos_h - cos_o;
                        if o_h <= 0.0 || cos_i <= 0.0 {
                            continue;
                        }
                        let visibility = 0.5 / (cos_i * lambda_o + cos_o * (cos_i * cos_i * (1.0 - a2) + a2).sqrt());
                        // BRDF cos θi over the density D cos θh / (4 ωo·h) of ωi.
                        let weight = 4.0 * visibility * cos_i * o_h / cos_h;
                        e += weight;
                        grazing += weight * (1.0 - o_h).powi(5);
                    }
                }
                let points = (n_u * n_phi) as f64;
                entries.push([(e / points).min(1.0) as f32, (grazing / points) as f32]);
            }
        }
        let averages = (0..TABLE_SIZE).map(|row| Self::row_average(&entries[row * TABLE_SIZE..(row + 1) * TABLE_SIZE])).collect();
        Tables { entries, averages }
    }

    /// 2 ∫ E(μ) μ dμ of a row as [`Ggx::at`] interpolates it (piecewise linear, integrated
    /// exactly), so that a lobe normalised by the average keeps exactly the light it should.
    fn row_average(row: &[[f32; 2]]) -> [f32; 2] {
        let step = 1.0 / (TABLE_SIZE - 1) as f32;
        let mut sum = [0.0f32; 2];
        for (j, pair) in row.windows(2).enumerate() {
            let (x0, x1) = (j as f32 * step, (j + 1) as f32 * step);
            for (s, (a, b)) in sum.iter_mut().zip(pair[0].iter().zip(&pair[1])) {
                // ∫ over [x0, x1] of the line from a to b, times μ.
                *s += (x1 - x0) * (a * (2.0 * x0 + x1) + b * (x0 + 2.0 * x1)) / 6.0;
            }
        }
        sum.map(|s| 2.0 * s)
    }
}

/// Entries of the rough dielectric's albedo table over √cos θ (denser towards grazing, where
/// the albedo changes fastest).
const DIELECTRIC_COSINES: usize = 32;

/// Entries of the rough dielectric's albedo table over √α.
const DIELECTRIC_ROUGHNESSES: usize = 16;

/// Entries of the rough dielectric's albedo table over the relative index η, evenly in ln η
/// from 1/3 to 3 (steps of 7 %).
const DIELECTRIC_ETAS: usize = 33;

/// The directional albedo of a rough dielectric boundary of relative index `eta` (the side of
/// `wo` over the other side), its GGX reflection and refraction together (Walter et al.'s
/// BTDF, as [`crate::bsdf`] has it), seen at `cos` from the normal: the share of the light that
/// a single scattering off the microfacets keeps. A boundary absorbs nothing, so the rest
/// (up to a fifth at roughness 1) is light that would scatter between the facets, which a
/// transmitting surface gives back by scaling its lobes by 1 / E (Turquin 2019, "Practical
/// multiple scattering compensation for microfacet models", as Cycles does for glass).
/// Trilinear in √cos θ, √α and ln η.
pub(crate) fn dielectric_albedo(cos: f32, alpha: f32, eta: f32) -> f32 {
    let table = dielectric_table();
    let axis = |x: f32, size: usize| {
        let x = x.clamp(0.0, 1.0) * (size - 1) as f32;
        let i = (x as usize).min(size - 2);
        (i, x - i as f32)
    };
    let (c, tc) = axis(cos.max(0.0).sqrt(), DIELECTRIC_COSINES);
    let (r, tr) = axis(alpha.max(0.0).sqrt(), DIELECTRIC_ROUGHNESSES);
    let (e, te) = axis(0.5 + 0.5 * eta.ln() / 3f32.ln(), DIELECTRIC_ETAS);
    let at = |e: usize, r: usize, c: usize| table[(e * DIELECTRIC_ROUGHNESSES + r) * DIELECTRIC_COSINES + c];
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let plane = |e: usize| lerp(lerp(at(e, r, c), at(e, r, c + 1), tc), lerp(at(e, r + 1, c), at(e, r + 1, c + 1), tc), tr);
    lerp(plane(e), plane(e + 1), te)
}

/// The table: [`integrate_dielectric_entry`]'s values, made once and checked in
/// (`dielectric_albedo.bin`, little-endian `f32`, η slowest, then √α, then √cos θ), since the
/// rule that gets them within 0.5 % takes seconds (a test recomputes entries and compares;
/// `RAYSTAGE_BLESS=1` writes the file anew; the rule is compiled for the tests only).
fn dielectric_table() -> &'static [f32] {
    static TABLE: OnceLock<Vec<f32>> = OnceLock::new();
    TABLE.get_or_init(|| DIELECTRIC_TABLE.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect())
}

static DIELECTRIC_TABLE: &[u8; DIELECTRIC_ETAS * DIELECTRIC_ROUGHNESSES * DIELECTRIC_COSINES * 4] = include_bytes!("dielectric_albedo.bin");

/// Samples per axis of the rule that made the table: the integrand bends sharply where total
/// internal reflection sets in on the steeper facets, so that 16 × 16 samples are up to 8 %
/// off; at 64 × 64 a rough boundary's entry is within 0.5 % of 512 × 512. A smoother one seen
/// from inside loses its light on a sliver of steep facets that the rule resolves slowly: up to
/// 1.6 % too much kept there (roughness 0.33, η 1.5, head-on: 0.999 for 0.984).
#[cfg(test)]
const DIELECTRIC_RULE: usize = 64;

/// Entry `index` of the table as [`DIELECTRIC_RULE`] integrates it.
#[cfg(test)]
fn integrate_dielectric_entry(index: usize) -> f32 {
    let (e, rest) = (index / (DIELECTRIC_ROUGHNESSES * DIELECTRIC_COSINES), index % (DIELECTRIC_ROUGHNESSES * DIELECTRIC_COSINES));
    let (r, c) = (rest / DIELECTRIC_COSINES, rest % DIELECTRIC_COSINES);
    let eta = 3f32.powf(2.0 * e as f32 / (DIELECTRIC_ETAS - 1) as f32 - 1.0);
    let alpha = (r as f32 / (DIELECTRIC_ROUGHNESSES - 1) as f32).powi(2).max(MIN_ALPHA);
    let cos = (c as f32 / (DIELECTRIC_COSINES - 1) as f32).powi(2).max(1e-3);
    dielectric_albedo_integrated(cos, alpha, eta, DIELECTRIC_RULE) as f32
}

/// [`dielectric_albedo`] by `n` × `n` stratified visible-normal samples, each weighing F G2 / G1
/// for the reflected direction and (1 − F) G2 / G1 for the refracted one (the BSDF over its
/// density, per microfacet normal), where each leaves on its own side of the surface.
#[cfg(test)]
fn dielectric_albedo_integrated(cos: f32, alpha: f32, eta: f32, n: usize) -> f64 {
    let wo = Vec3::new((1.0 - cos * cos).max(0.0).sqrt(), 0.0, cos);
    let g1 = smith_g1(wo, alpha);
    let mut sum = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
            let h = sample_visible_normal(wo, alpha, u);
            let o = wo.dot(h);
            let f = crate::bsdf::fresnel_dielectric(o, eta);
            let reflected = 2.0 * o * h - wo;
            if reflected.z > 0.0 {
                // The height-correlated visibility times 4 cos θo cos θi is G2.
                sum += f64::from(f * 4.0 * smith_height_correlated(wo, reflected, alpha) * wo.z * reflected.z / g1);
            }
            if let Some(refracted) = crate::bsdf::refract_about(wo, h, eta).filter(|t| t.z < 0.0) {
                sum += f64::from((1.0 - f) * smith_g2(wo, refracted, alpha) / g1);
            }
        }
    }
    sum / (n * n) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// ∫ `f` over the hemisphere of directions by a midpoint rule in (cos θ, φ), in f64.
    fn over_hemisphere(n: usize, f: impl Fn(Vec3) -> f32) -> f32 {
        let mut sum = 0.0f64;
        for i in 0..n {
            let cos = (i as f32 + 0.5) / n as f32;
            let sin = (1.0 - cos * cos).sqrt();
            for j in 0..n {
                let phi = std::f32::consts::TAU * (j as f32 + 0.5) / n as f32;
                sum += f(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)) as f64;
            }
        }
        (sum * std::f64::consts::TAU / (n * n) as f64) as f32
    }

    /// Between the entries (roughness and angle off the grid), the tables agree with a
    /// quadrature of the lobe that knows nothing of how they were made, for F = 1 and for the
    /// grazing part; and the compensated white lobe reflects all the light.
    #[test]
    fn the_tables_match_the_lobe_integrated() {
        for roughness in [0.23f32, 0.41, 0.58, 0.77, 0.96] {
            let alpha = roughness * roughness;
            for degrees in [3.0f32, 27.0, 48.0, 66.0, 79.0, 86.0] {
                let cos = degrees.to_radians().cos();
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let lobe = |wi: Vec3, grazing: bool| {
                    let h = (wo + wi).normalize();
                    let f = if grazing { (1.0 - wo.dot(h)).powi(5) } else { 1.0 };
                    f * ggx_d(h, alpha) * smith_height_correlated(wo, wi, alpha) * wi.z
                };
                let e = over_hemisphere(1024, |wi| lobe(wi, false));
                let grazing = over_hemisphere(1024, |wi| lobe(wi, true));
                let ggx = Ggx::new(alpha);
                let Seen { e: te, grazing: tg } = ggx.at(cos);
                assert!((te - e).abs() < 5e-3 && (tg - grazing).abs() < 5e-3, "roughness {roughness}, {degrees}°: table {te} {tg}, quadrature {e} {grazing}");
                let white = e + over_hemisphere(256, |wi| ggx.multiple_scattering(ggx.at(cos), ggx.at(wi.z), wi.z));
                assert!((white - 1.0).abs() < 5e-3, "roughness {roughness}, {degrees}°: a white lobe reflects {white}");
            }
        }
    }

    /// The averages are those of the rows as interpolated, and the compensated lobe's albedo
    /// averages to them: what normalises the multiple-scattering lobe and a base under a layer.
    #[test]
    fn the_averages_are_the_rows_integrated() {
        let (f0, f90) = (Vec3::new(0.04, 0.5, 0.9), Vec3::new(1.0, 0.8, 1.0));
        for roughness in [0.0f32, 0.3, 0.55, 1.0] {
            let ggx = Ggx::new(roughness * roughness);
            let colour = ggx.multiple_scattering_colour(f0, f90);
            let n = 4096;
            let mean = (0..n).map(|i| (i as f32 + 0.5) / n as f32).map(|mu| ggx.albedo(f0, f90, colour, ggx.at(mu)) * mu).sum::<Vec3>() * 2.0 / n as f32;
            let average = ggx.average_albedo(f0, f90, colour);
            assert!((mean - average).abs().max_element() < 1e-4, "roughness {roughness}: {mean} vs {average}");
        }
    }

    /// The checked-in table is the rule's (entries spread over it recomputed; with
    /// `RAYSTAGE_BLESS=1`, every entry, written to the file), and between its entries it agrees
    /// with a finer rule within 2 % (1.6 % at worst, see [`DIELECTRIC_RULE`]); a rough boundary
    /// loses what the compensation gives back, a smooth one nothing.
    #[test]
    fn the_dielectric_table_is_the_integral() {
        let entries = DIELECTRIC_ETAS * DIELECTRIC_ROUGHNESSES * DIELECTRIC_COSINES;
        if std::env::var_os("RAYSTAGE_BLESS").is_some() {
            let bytes: Vec<u8> = (0..entries).flat_map(|i| integrate_dielectric_entry(i).to_le_bytes()).collect();
            std::fs::write(concat!(env!("CARGO_MANIFEST_DIR"), "/src/dielectric_albedo.bin"), bytes).unwrap();
            return;
        }
        for index in (0..entries).step_by(97) {
            let (checked_in, now) = (dielectric_table()[index], integrate_dielectric_entry(index));
            assert!((checked_in - now).abs() < 1e-5, "entry {index}: checked in {checked_in}, integrated {now}");
        }
        let mut worst = (0.0f32, String::new());
        for eta in [1.0f32 / 2.2, 1.0 / 1.5, 1.0 / 1.1, 1.33, 1.5, 2.4] {
            for roughness in [0.07f32, 0.33, 0.62, 0.91] {
                for cos in [0.04f32, 0.3, 0.55, 0.83, 0.98] {
                    let table = dielectric_albedo(cos, roughness * roughness, eta);
                    let fine = dielectric_albedo_integrated(cos, roughness * roughness, eta, 256) as f32;
                    if (table - fine).abs() > worst.0 {
                        worst = ((table - fine).abs(), format!("η {eta}, roughness {roughness}, cos {cos}: table {table}, fine {fine}"));
                    }
                }
            }
        }
        assert!(worst.0 < 0.02, "the table is off a finer rule: {}", worst.1);
        assert!(dielectric_albedo(0.99, 1e-4, 1.5) > 0.995);
        assert!(dielectric_albedo(0.5, 1.0, 1.5) < 0.9, "a rough boundary keeps {}", dielectric_albedo(0.5, 1.0, 1.5));
    }
}
