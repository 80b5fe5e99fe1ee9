//! How far a rendered image is from a reference image of the same scene (both linear RGB, row
//! by row from the top, of one size): the measures the reference tests judge renders by
//! (`tests/materials_reference.rs` against Mitsuba, `tests/cycles_reference.rs` against
//! Cycles). PSNR and SSIM are taken after the tone curve x / (1 + x), so that highlights weigh
//! no more than the rest; means are taken on the linear values.

use glam::Vec3;

/// The tone curve the structural measures see: x / (1 + x) per channel.
fn tone(c: Vec3) -> Vec3 {
    c / (Vec3::ONE + c)
}

/// Peak signal-to-noise ratio of the tone-mapped images, dB.
pub fn psnr(image: &[Vec3], reference: &[Vec3]) -> f32 {
    assert_eq!(image.len(), reference.len(), "images of one size");
    let squares: f64 = image.iter().zip(reference).map(|(a, b)| (tone(*a) - tone(*b)).length_squared() as f64).sum();
    (10.0 * (3.0 * image.len() as f64 / squares).log10()) as f32
}

/// Mean structural similarity (Wang et al. 2004) of the tone-mapped luminances over every 7×7
/// window, `width` pixels wide.
pub fn ssim(image: &[Vec3], reference: &[Vec3], width: usize) -> f32 {
    assert_eq!(image.len(), reference.len(), "images of one size");
    const W: usize = 7;
    let lum = |img: &[Vec3]| img.iter().map(|c| tone(*c).dot(Vec3::new(0.2126, 0.7152, 0.0722))).collect::<Vec<f32>>();
    let (a, b) = (lum(image), lum(reference));
    let height = a.len() / width;
    let (c1, c2) = (0.01f64 * 0.01, 0.03f64 * 0.03);
    let mut total = 0.0f64;
    for y in 0..=height - W {
        for x in 0..=width - W {
            let window = || (0..W * W).map(|i| (y + i / W) * width + x + i % W);
            let n = (W * W) as f64;
            let (ma, mb) = (window().map(|i| a[i] as f64).sum::<f64>() / n, window().map(|i| b[i] as f64).sum::<f64>() / n);
            let (mut va, mut vb, mut cov) = (0.0, 0.0, 0.0);
            for i in window() {
                let (da, db) = (a[i] as f64 - ma, b[i] as f64 - mb);
                va += da * da;
                vb += db * db;
                cov += da * db;
            }
            let (va, vb, cov) = (va / (n - 1.0), vb / (n - 1.0), cov / (n - 1.0));
            total += (2.0 * ma * mb + c1) * (2.0 * cov + c2) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
        }
    }
    (total / ((height - W + 1) * (width - W + 1)) as f64) as f32
}

/// Per channel, the image's mean over the reference's.
pub fn channel_ratio(image: &[Vec3], reference: &[Vec3]) -> Vec3 {
    image.iter().sum::<Vec3>() / reference.iter().sum::<Vec3>()
}

/// The mean of each square cell of side `side` pixels, row by row from the top left, of an
/// image `width` pixels wide (cells that do not fit whole are left out).
pub fn cell_means(image: &[Vec3], width: usize, side: usize) -> Vec<Vec3> {
    let (columns, rows) = (width / side, image.len() / width / side);
    (0..rows * columns)
        .map(|cell| {
            let (cx, cy) = (cell % columns, cell / columns);
            let pixels = (0..side * side).map(|i| image[(cy * side + i / side) * width + cx * side + i % side]);
            pixels.sum::<Vec3>() / (side * side) as f32
        })
        .collect()
}

/// Per cell (as [`cell_means`] has them), the largest relative difference of a channel's mean
/// from the reference's.
pub fn cell_differences(image: &[Vec3], reference: &[Vec3], width: usize, side: usize) -> Vec<f32> {
    let (a, b) = (cell_means(image, width, side), cell_means(reference, width, side));
    a.iter().zip(&b).map(|(a, b)| (*a / *b - Vec3::ONE).abs().max_element()).collect()
}

/// The pixels of `image` (rows of `width`) in columns `columns` of rows `rows`, row by row: the
/// part of two images a comparison judges, where the rest differs by convention.
pub fn crop(image: &[Vec3], width: usize, columns: std::ops::Range<usize>, rows: std::ops::Range<usize>) -> Vec<Vec3> {
    rows.flat_map(|y| image[y * width + columns.start..y * width + columns.end].iter().copied()).collect()
}
