//! The sRGB transfer function (IEC 61966-2-1): the film holds linear light, PNGs hold sRGB.

/// Encodes a linear value as an 8-bit sRGB value, clamping to `[0, 1]` first (NaN becomes 0).
pub(crate) fn encode(linear: f32) -> u8 {
    let c = if linear.is_nan() { 0.0 } else { linear.clamp(0.0, 1.0) };
    let encoded = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (encoded * 255.0).round() as u8
}

/// Decodes an sRGB value in `[0, 1]` to linear light.
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
    fn clamps_out_of_range_and_nan() {
        assert_eq!(encode(-1.0), 0);
        assert_eq!(encode(7.0), 255);
        assert_eq!(encode(f32::NAN), 0);
    }
}
