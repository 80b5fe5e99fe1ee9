//! Mapping uniform samples of the unit square to directions and points with known densities.

use glam::{Vec2, Vec3};

/// An orthonormal frame around a unit normal (Duff et al. 2017, *Building an Orthonormal Basis,
/// Revisited*): converts directions between the frame (z = normal) and world space.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame3 {
    pub tangent: Vec3,
    pub bitangent: Vec3,
    pub normal: Vec3,
}

impl Frame3 {
    /// The frame around unit normal `n`.
    pub fn around(n: Vec3) -> Frame3 {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Frame3 {
            tangent: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            bitangent: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            normal: n,
        }
    }

    /// A frame-space direction in world space.
    pub fn to_world(self, v: Vec3) -> Vec3 {
        self.tangent * v.x + self.bitangent * v.y + self.normal * v.z
    }

    /// A world-space direction in the frame.
    pub fn to_local(self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.tangent), v.dot(self.bitangent), v.dot(self.normal))
    }
}

/// A point of the unit disc, uniformly, by Shirley's concentric mapping (area preserving, low
/// distortion, so stratification survives).
pub(crate) fn concentric_disc(u: [f32; 2]) -> Vec2 {
    let (a, b) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    if a == 0.0 && b == 0.0 {
        return Vec2::ZERO;
    }
    // Which of the two wedges a point falls in is a coin toss, which a branch would
    // mispredict half the time: both angles are worked out and one is kept.
    let wide = a.abs() > b.abs();
    let r = std::hint::select_unpredictable(wide, a, b);
    let phi = std::hint::select_unpredictable(wide, std::f32::consts::FRAC_PI_4 * (b / a), std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (a / b));
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// A direction of the hemisphere around +z with density cos θ / π (Malley's method).
pub(crate) fn cosine_hemisphere(u: [f32; 2]) -> Vec3 {
    let d = concentric_disc(u);
    Vec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt())
}

/// A direction of the hemisphere around +z with uniform density 1 / 2π.
pub(crate) fn uniform_hemisphere(u: [f32; 2]) -> Vec3 {
    let z = u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u[1];
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The power heuristic (β = 2) weight of a sample from a strategy with density `f` when another
/// with density `g` could also have produced it (Veach 1997).
pub(crate) fn power_heuristic(f: f32, g: f32) -> f32 {
    let (f2, g2) = (f * f, g * g);
    if f2 + g2 > 0.0 { f2 / (f2 + g2) } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.4, 0.866).normalize(), Vec3::new(0.0, 0.0, -0.9999).normalize()] {
            let f = Frame3::around(n);
            for (a, b) in [(f.tangent, f.bitangent), (f.tangent, f.normal), (f.bitangent, f.normal)] {
                assert!(a.dot(b).abs() < 1e-5);
            }
            assert!((f.tangent.length() - 1.0).abs() < 1e-5 && (f.bitangent.length() - 1.0).abs() < 1e-5);
            let v = Vec3::new(0.2, -0.5, 0.7);
            assert!((f.to_local(f.to_world(v)) - v).length() < 1e-5);
        }
    }

    #[test]
    fn cosine_samples_average_to_the_right_moment() {
        // E[cos θ] under density cos θ / π is 2/3.
        let n = 256;
        let mean: f32 = (0..n * n)
            .map(|i| cosine_hemisphere([((i % n) as f32 + 0.5) / n as f32, ((i / n) as f32 + 0.5) / n as f32]).z)
            .sum::<f32>()
            / (n * n) as f32;
        assert!((mean - 2.0 / 3.0).abs() < 1e-3, "{mean}");
    }
}
