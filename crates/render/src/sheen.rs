//! The sheen of cloth, as glTF's `KHR_materials_sheen` specifies it: back-scattering from a
//! layer of microfibres over a surface, with Estevez and Kulla's "Charlie" distribution (2017)
//! and Ashikhmin's visibility term. What the fibres reflect, the surface under them does not
//! receive: the extension scales it by `1 − max(colour) E(cos θ)`, E the lobe's directional
//! albedo, which has no closed form; it is tabulated here over roughness and angle once, when
//! a frame first meets sheen.

use std::f32::consts::{FRAC_1_PI, TAU};
use std::sync::OnceLock;

use glam::Vec3;

/// The smallest perceptual sheen roughness: below it the fibres' lobe is a rim at grazing
/// angles too sharp for the albedo table (and invisible in an image).
pub(crate) const MIN_ROUGHNESS: f32 = 0.07;

/// The Charlie distribution of microfibre normals at cosine `cos_h` to the surface normal,
/// for α = roughness²: (2 + 1/α) sin^(1/α) θ / 2π.
fn distribution(cos_h: f32, alpha: f32) -> f32 {
    let inverse = 1.0 / alpha;
    let sin2 = (1.0 - cos_h * cos_h).max(0.0);
    (2.0 + inverse) * sin2.powf(0.5 * inverse) / TAU
}

/// The white sheen lobe, BRDF × cos θi, for directions in the shading frame (`z` the normal),
/// kept within its light: where Charlie's distribution with Ashikhmin's visibility reflects
/// more than it receives (at grazing angles and low roughness it reflects up to 3.7 times its
/// light), it is divided by that albedo, the greater for the two directions, which keeps it
/// reciprocal. The rest of the sphere sees the extension's lobe as written.
pub(crate) fn lobe(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let excess = raw_albedo(wo.z, alpha).max(raw_albedo(wi.z, alpha)).max(1.0);
    raw_lobe(wo, wi, alpha) / excess
}

/// The lobe as the extension writes it; Ashikhmin's visibility,
/// 1 / 4(cos θi + cos θo − cos θi cos θo), keeps it reciprocal.
fn raw_lobe(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let Some(h) = (wo + wi).try_normalize() else { return 0.0 };
    let visibility = 1.0 / (4.0 * (wi.z + wo.z - wi.z * wo.z));
    distribution(h.z, alpha) * visibility * wi.z
}

/// The directional albedo of the white [`lobe`] seen at `cos` from the normal, for α `alpha`:
/// at most 1 (within a few per cent, bilinear in the table).
pub(crate) fn albedo(cos: f32, alpha: f32) -> f32 {
    raw_albedo(cos, alpha).min(1.0)
}

/// The directional albedo of the lobe as the extension writes it: bilinear in the table over
/// perceptual roughness and cosine.
fn raw_albedo(cos: f32, alpha: f32) -> f32 {
    let table = TABLE.get_or_init(tabulate);
    let last = (TABLE_SIZE - 1) as f32;
    let r = ((alpha.sqrt() - MIN_ROUGHNESS) / (1.0 - MIN_ROUGHNESS)).clamp(0.0, 1.0) * last;
    let c = cos.clamp(0.0, 1.0) * last;
    let (r0, c0) = ((r as usize).min(TABLE_SIZE - 2), (c as usize).min(TABLE_SIZE - 2));
    let (fr, fc) = (r - r0 as f32, c - c0 as f32);
    let at = |i: usize, j: usize| table[i * TABLE_SIZE + j];
    let low = at(r0, c0) * (1.0 - fc) + at(r0, c0 + 1) * fc;
    let high = at(r0 + 1, c0) * (1.0 - fc) + at(r0 + 1, c0 + 1) * fc;
    low * (1.0 - fr) + high * fr
}

/// What sheen of colour `sheen` leaves of the light for the layer under it, seen at `cos`.
pub(crate) fn left(sheen: Vec3, alpha: f32, cos: f32) -> f32 {
    1.0 - sheen.max_element() * albedo(cos, alpha)
}

/// Entries per axis of the albedo table.
const TABLE_SIZE: usize = 32;

/// E(cos, roughness), roughness from [`MIN_ROUGHNESS`] to 1 by rows, cosine from 0 to 1 by
/// columns.
static TABLE: OnceLock<Vec<f32>> = OnceLock::new();

/// The albedo table, by a midpoint rule over the hemisphere in (cos θi, φ); the lobe is
/// symmetric about the plane of `wo`, so half the circle is integrated and doubled. Grazing
/// columns use cos = 10⁻³, where the lobe is still finite.
fn tabulate() -> Vec<f32> {
    let (n_cos, n_phi) = (96, 48);
    let mut table = Vec::with_capacity(TABLE_SIZE * TABLE_SIZE);
    for i in 0..TABLE_SIZE {
        let roughness = MIN_ROUGHNESS + (1.0 - MIN_ROUGHNESS) * i as f32 / (TABLE_SIZE - 1) as f32;
        let alpha = roughness * roughness;
        for j in 0..TABLE_SIZE {
            let cos_o = (j as f32 / (TABLE_SIZE - 1) as f32).max(1e-3);
            let wo = Vec3::new((1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o);
            let mut sum = 0.0;
            for a in 0..n_cos {
                let cos_i = (a as f32 + 0.5) / n_cos as f32;
                let sin_i = (1.0 - cos_i * cos_i).sqrt();
                for b in 0..n_phi {
                    let phi = std::f32::consts::PI * (b as f32 + 0.5) / n_phi as f32;
                    sum += raw_lobe(wo, Vec3::new(sin_i * phi.cos(), sin_i * phi.sin(), cos_i), alpha);
                }
            }
            // dω = d(cos θ) dφ over [0, 1] × [0, 2π]: the half circle counted twice.
            table.push(sum * TAU / (n_cos * n_phi) as f32);
        }
    }
    table
}

/// The density of the sheen lobe's samples: uniform over the hemisphere (the lobe is broad,
/// and brightest where cosine sampling would rarely look, at grazing angles).
pub(crate) const UNIFORM_PDF: f32 = 0.5 * FRAC_1_PI;

#[cfg(test)]
mod tests {
    use super::*;

    /// The table agrees with a fine quadrature of the lobe where the lobe keeps within its
    /// light, and the bounded lobe never reflects more than it receives.
    #[test]
    fn the_albedo_table_matches_the_lobe() {
        let n = 400;
        for roughness in [MIN_ROUGHNESS, 0.2, 0.5, 0.8, 1.0] {
            let alpha = roughness * roughness;
            for cos_o in [0.02f32, 0.1, 0.3, 0.6, 0.9, 1.0] {
                let wo = Vec3::new((1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o);
                let (mut sum, mut bounded) = (0.0f64, 0.0f64);
                for a in 0..n {
                    let cos_i = (a as f32 + 0.5) / n as f32;
                    let sin_i = (1.0 - cos_i * cos_i).sqrt();
                    for b in 0..n {
                        let phi = TAU * (b as f32 + 0.5) / n as f32;
                        let wi = Vec3::new(sin_i * phi.cos(), sin_i * phi.sin(), cos_i);
                        sum += raw_lobe(wo, wi, alpha) as f64;
                        bounded += lobe(wo, wi, alpha) as f64;
                    }
                }
                let exact = (sum * std::f64::consts::TAU / (n * n) as f64) as f32;
                let table = albedo(cos_o, alpha);
                assert!((table - exact.min(1.0)).abs() < 0.01 + 0.03 * exact, "roughness {roughness}, cos {cos_o}: table {table}, quadrature {exact}");
                let bounded = (bounded * std::f64::consts::TAU / (n * n) as f64) as f32;
                assert!(bounded <= 1.0 + 0.01, "roughness {roughness}, cos {cos_o}: the lobe reflects {bounded}");
            }
        }
    }

    /// The lobe is reciprocal, and brightest at grazing angles (the rim light of velvet).
    #[test]
    fn the_lobe_is_reciprocal_and_grazing() {
        let (a, b) = (Vec3::new(0.3, 0.2, 0.93).normalize(), Vec3::new(-0.8, 0.1, 0.2).normalize());
        for alpha in [0.01, 0.25, 1.0] {
            assert!((lobe(a, b, alpha) / b.z - lobe(b, a, alpha) / a.z).abs() < 1e-5);
        }
        assert!(albedo(0.05, 0.25) > 2.0 * albedo(1.0, 0.25));
        assert_eq!(lobe(a, -b, 0.25), 0.0);
    }
}
