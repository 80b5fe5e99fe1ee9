//! Error of an image against a reference.

use raystage_render::Film;

/// Errors of an image against the reference, over every pixel and colour channel of the linear
/// (not tone-mapped) radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    /// Root mean squared error.
    pub rmse: f64,
    /// Relative mean squared error: the squared error over the squared reference value (plus
    /// 0.01, so that black pixels do not dominate), averaged; the usual measure of denoising and
    /// rendering papers, fair to dark and bright regions alike.
    pub rel_mse: f64,
    /// Mean absolute error.
    pub mae: f64,
}

impl Errors {
    /// Compares `image` with `reference` (of the same size).
    ///
    /// # Panics
    /// If the sizes differ.
    pub fn between(image: &Film, reference: &Film) -> Errors {
        assert_eq!((image.width(), image.height()), (reference.width(), reference.height()), "images of one size");
        let (mut se, mut rel, mut ae) = (0.0f64, 0.0f64, 0.0f64);
        for y in 0..image.height() {
            for x in 0..image.width() {
                let (a, r) = (image.pixel(x, y), reference.pixel(x, y));
                for c in 0..3 {
                    let (a, r) = (a[c] as f64, r[c] as f64);
                    let d = a - r;
                    se += d * d;
                    rel += d * d / (r * r + 0.01);
                    ae += d.abs();
                }
            }
        }
        let n = (image.width() as f64) * (image.height() as f64) * 3.0;
        Errors { rmse: (se / n).sqrt(), rel_mse: rel / n, mae: ae / n }
    }

    /// The mean squared error.
    pub fn mse(&self) -> f64 {
        self.rmse * self.rmse
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn errors_of_a_constant_offset() {
        let reference = Film::from_pixels(2, 1, vec![Vec3::splat(1.0), Vec3::ZERO]);
        let image = Film::from_pixels(2, 1, vec![Vec3::splat(1.5), Vec3::splat(0.5)]);
        let e = Errors::between(&image, &reference);
        assert!((e.rmse - 0.5).abs() < 1e-12 && (e.mae - 0.5).abs() < 1e-12);
        assert!((e.rel_mse - 0.5 * (0.25 / 1.01 + 0.25 / 0.01)).abs() < 1e-9);
        assert_eq!(Errors::between(&reference, &reference), Errors { rmse: 0.0, rel_mse: 0.0, mae: 0.0 });
    }
}
