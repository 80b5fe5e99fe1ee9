//! Picking by weight: piecewise-constant distributions, and the tables that pick an environment
//! image's texels by the light they bring. The renderer picks emitting triangles by power with
//! the first; an image keeps the second once it has lit a frame (see
//! [`crate::Image::environment_tables`]), so that the progressive passes and frames after the
//! first do not build them again.

use std::f32::consts::PI;

use glam::Vec3;
use rayon::prelude::*;

use crate::texture::Level;

/// The luminance of a linear-RGB colour (Rec. 709 weights).
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// A piecewise-constant distribution over [0, 1) with one piece per weight.
#[derive(Clone, Debug)]
pub struct Distribution {
    /// Cumulative weights, normalised: `cdf[i]` is the probability of the pieces before `i`.
    cdf: Vec<f32>,
    /// The sum of the weights.
    pub total: f32,
}

impl Distribution {
    /// The distribution proportional to `weights` (uniform if they are all zero).
    pub fn new(weights: Vec<f32>) -> Distribution {
        // Summed in double precision: a list of a million triangles keeps each one's share.
        let total: f64 = weights.iter().map(|&w| w as f64).sum();
        let n = weights.len() as f64;
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut running = 0.0f64;
        cdf.push(0.0);
        for (i, &w) in weights.iter().enumerate() {
            running += if total > 0.0 { w as f64 / total } else { 1.0 / n };
            cdf.push(if i + 1 == weights.len() { 1.0 } else { running as f32 });
        }
        Distribution { cdf, total: total as f32 }
    }

    /// The probability of piece `i`.
    #[inline]
    pub fn density(&self, i: usize) -> f32 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// The piece `u` falls in and where in the piece it falls, from 0 to 1.
    #[inline]
    pub fn pick(&self, u: f32) -> (usize, f32) {
        let pieces = self.cdf.len() - 1;
        let i = (self.cdf.partition_point(|&c| c <= u).max(1) - 1).min(pieces - 1);
        let width = self.density(i);
        let within = if width > 0.0 { ((u - self.cdf[i]) / width).clamp(0.0, 1.0) } else { 0.5 };
        (i, within)
    }

    /// The piece `u` falls in and the point in [0, 1) it maps to.
    #[inline]
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let (i, within) = self.pick(u);
        let pieces = (self.cdf.len() - 1) as f32;
        (i, ((i as f32 + within) / pieces).min(1.0 - f32::EPSILON))
    }

    /// The memory its table takes.
    pub fn memory_bytes(&self) -> u64 {
        (self.cdf.len() * size_of::<f32>()) as u64
    }
}

/// An equirectangular (latitude-longitude) image's texels by the light they bring: each texel's
/// luminance times the solid angle it covers (rows near the poles cover less).
#[derive(Clone, Debug)]
pub struct EnvironmentTables {
    /// Rows by their total.
    pub rows: Distribution,
    /// Within each row, columns by their weight.
    pub columns: Vec<Distribution>,
}

impl EnvironmentTables {
    /// The tables of `level`, its rows in parallel: an HDR image has millions of texels.
    pub(crate) fn of(level: &Level) -> EnvironmentTables {
        let (w, h) = (level.width() as usize, level.height() as usize);
        let columns: Vec<Distribution> = (0..h)
            .into_par_iter()
            .map(|y| {
                // Texels near the poles cover less solid angle.
                let sin = (PI * (y as f32 + 0.5) / h as f32).sin();
                Distribution::new((0..w).map(|x| luminance(level.texel(x as i64, y as i64)) * sin).collect())
            })
            .collect();
        let rows = Distribution::new(columns.iter().map(|c| c.total).collect());
        EnvironmentTables { rows, columns }
    }

    /// The memory its tables take.
    pub fn memory_bytes(&self) -> u64 {
        self.rows.memory_bytes() + self.columns.iter().map(|c| c.memory_bytes() + size_of::<Distribution>() as u64).sum::<u64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distributions_sample_in_proportion() {
        let d = Distribution::new(vec![1.0, 0.0, 3.0]);
        assert_eq!(d.sample(0.1).0, 0);
        assert_eq!(d.sample(0.3).0, 2);
        assert!((d.density(2) - 0.75).abs() < 1e-6 && d.density(1) == 0.0);
        let (_, x) = d.sample(0.25 + 0.375);
        assert!((x - (2.5 / 3.0)).abs() < 1e-5, "{x}");
    }
}
