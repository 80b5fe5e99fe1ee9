//! The sRGB transfer function (IEC 61966-2-1): the film holds linear light, PNGs hold sRGB.

/// Steps of the encoding table over `[0, 1]`: fine enough that a step moves the encoded value by
/// at most 0.05 of an 8-bit level (the curve is steepest at 0, 12.92 × 255 levels per unit).
pub(crate) const TABLE_STEPS: usize = 65_535;
const _: () = assert!((TABLE_STEPS + 1).is_power_of_two(), "encode_with masks the step with TABLE_STEPS");

/// Encodes a linear value as an 8-bit sRGB value, clamping to `[0, 1]` first (NaN becomes 0).
/// (The film encodes whole rows with [`encode_with`]; the tests check values one by one.)
#[cfg(test)]
fn encode(linear: f32) -> u8 {
    encode_with(table(), linear)
}

/// The encoding table: the encoded value of every step over `[0, 1]`. Loops over many pixels
/// fetch it once and call [`encode_with`].
pub(crate) fn table() -> &'static [u8; TABLE_STEPS + 1] {
    static TABLE: std::sync::LazyLock<Box<[u8; TABLE_STEPS + 1]>> = std::sync::LazyLock::new(|| {
        let mut table = Box::new([0; TABLE_STEPS + 1]);
        for (i, entry) in table.iter_mut().enumerate() {
            *entry = encode_exact(i as f32 / TABLE_STEPS as f32);
        }
        table
    });
    &TABLE
}

/// One value encoded with the table in hand. `max` and `min` return the other operand for NaN, so
/// NaN lands on 0. The step is rounded to the nearest by adding 2²³: the sum's low mantissa
/// bits are then the step itself (at most `TABLE_STEPS`, so the lookup needs no bounds check),
/// which costs half of Rust's saturating float-to-integer cast in this loop.
#[inline]
#[allow(clippy::manual_clamp, reason = "`clamp` keeps NaN, which must encode as 0")]
pub(crate) fn encode_with(table: &[u8; TABLE_STEPS + 1], linear: f32) -> u8 {
    const ROUND: f32 = (1 << (f32::MANTISSA_DIGITS - 1)) as f32;
    let step = linear.max(0.0).min(1.0) * TABLE_STEPS as f32 + ROUND;
    table[(step.to_bits() & TABLE_STEPS as u32) as usize]
}

/// The sRGB curve itself, for values in `[0, 1]`.
fn encode_exact(c: f32) -> u8 {
    let encoded = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (encoded * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use raystage_scene::srgb_to_linear;

    use super::*;

    #[test]
    fn round_trips_every_8_bit_value() {
        for v in 0..=255u8 {
            assert_eq!(encode(srgb_to_linear(v as f32 / 255.0)), v);
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
