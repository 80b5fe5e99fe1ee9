//! The sRGB transfer function (IEC 61966-2-1): the film holds linear light, PNGs hold sRGB.

/// Steps of the encoding table over `[0, 1]`: fine enough that a step moves the encoded value by
/// at most 0.05 of an 8-bit level (the curve is steepest at 0, 12.92 × 255 levels per unit).
const TABLE_STEPS: usize = 65_535;

/// Encodes a linear value as an 8-bit sRGB value, clamping to `[0, 1]` first (NaN becomes 0).
/// A table lookup: encoding a 1080p frame takes six million of these.
pub(crate) fn encode(linear: f32) -> u8 {
    static TABLE: std::sync::LazyLock<Vec<u8>> = std::sync::LazyLock::new(|| (0..=TABLE_STEPS).map(|i| encode_exact(i as f32 / TABLE_STEPS as f32)).collect());
    let c = if linear.is_nan() { 0.0 } else { linear.clamp(0.0, 1.0) };
    TABLE[(c * TABLE_STEPS as f32 + 0.5) as usize]
}

/// The sRGB curve itself, for values in `[0, 1]`.
fn encode_exact(c: f32) -> u8 {
    let encoded = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (encoded * 255.0).round() as u8
}

/// Decodes an sRGB value in `[0, 1]` to linear light (the tests check colour constants with it).
#[cfg(test)]
pub(crate) fn decode(encoded: f32) -> f32 {
    if encoded <= 0.040_45 { encoded / 12.92 } else { ((encoded + 0.055) / 1.055).powf(2.4) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_every_8_bit_value() {
        for v in 0..=255u8 {
            assert_eq!(encode(decode(v as f32 / 255.0)), v);
        }
    }

    #[test]
    fn the_table_matches_the_curve() {
        let mismatches = (0..=1_000_000).filter(|&i| {
            let c = i as f32 / 1_000_000.0;
            encode(c).abs_diff(encode_exact(c)) > 0
        });
        // Only values within half a table step of one of the 255 rounding boundaries may land
        // on the other side (about 0.2 % of them).
        assert!(mismatches.count() < 10_000);
        for i in 0..=1_000_000 {
            let c = i as f32 / 1_000_000.0;
            assert!(encode(c).abs_diff(encode_exact(c)) <= 1, "{c}");
        }
    }

    #[test]
    fn clamps_out_of_range_and_nan() {
        assert_eq!(encode(-1.0), 0);
        assert_eq!(encode(7.0), 255);
        assert_eq!(encode(f32::NAN), 0);
    }
}
