//! Linear light to 8-bit sRGB, row by row, for the PNG encoder: the same curve (IEC 61966-2-1)
//! and the same table as `raystage_render::Film::to_rgba8` (a test holds the two equal), but
//! by rows, so that the encoder can compress the first rows while the rest are still being
//! converted.

use raystage_render::Film;

/// Steps of the table over `[0, 1]` (the renderer's): a linear value `c` encodes as the 8-bit
/// value of step `round(c × STEPS)`.
const STEPS: usize = 65_535;

/// The encoded value of every step.
fn table() -> &'static [u8] {
    static TABLE: std::sync::LazyLock<Vec<u8>> = std::sync::LazyLock::new(|| {
        (0..=STEPS)
            .map(|i| {
                let c = i as f32 / STEPS as f32;
                let encoded = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
                (encoded * 255.0).round() as u8
            })
            .collect()
    });
    &TABLE
}

/// The 8-bit sRGB value of a linear value, clamped to `[0, 1]` first (NaN becomes 0: `max`
/// returns the other operand for NaN).
#[inline]
fn encode(table: &[u8], linear: f32) -> u8 {
    table[(linear.max(0.0).min(1.0) * STEPS as f32 + 0.5) as usize]
}

/// Rows `rows` of the film as sRGB RGB8 bytes, row by row.
pub(crate) fn rgb_rows(film: &Film, rows: std::ops::Range<u32>) -> Vec<u8> {
    let table = table();
    let mut out = Vec::with_capacity(rows.len() * film.width() as usize * 3);
    for y in rows {
        for x in 0..film.width() {
            let p = film.pixel(x, y);
            out.extend_from_slice(&[encode(table, p.x), encode(table, p.y), encode(table, p.z)]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    #[test]
    fn matches_the_films_own_encoding() {
        // Every step of the table and the values around each 8-bit boundary, plus the edges.
        let mut values: Vec<f32> = (0..=200_000).map(|i| i as f32 / 200_000.0).collect();
        values.extend([-1.0, 0.0, 1.0, 7.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e-9]);
        values.resize(values.len().next_multiple_of(3), 0.5);
        let pixels: Vec<Vec3> = values.chunks(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
        let film = Film::from_pixels(pixels.len() as u32, 1, pixels);
        let ours = rgb_rows(&film, 0..1);
        let theirs: Vec<u8> = film.to_rgba8().chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        assert!(ours == theirs, "the server's sRGB encoding differs from Film::to_rgba8");
    }
}
