//! Colour: the sRGB transfer function (IEC 61966-2-1) and Rec. 709 luminance.

use glam::Vec3;

/// Rec. 709 / sRGB luminance weights for linear RGB.
pub const LUMINANCE_WEIGHTS: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Luminance of a linear Rec. 709 RGB colour.
pub fn luminance(rgb: Vec3) -> f32 {
    rgb.dot(LUMINANCE_WEIGHTS)
}

/// Decodes one sRGB-encoded channel in [0, 1] to linear.
pub fn srgb_to_linear(encoded: f32) -> f32 {
    if encoded <= 0.04045 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Encodes one linear channel to sRGB; input is clamped to [0, 1].
pub fn linear_to_srgb(linear: f32) -> f32 {
    let x = linear.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        x * 12.92
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transfer_functions_invert_each_other() {
        for i in 0..=255 {
            let e = i as f32 / 255.0;
            let back = linear_to_srgb(srgb_to_linear(e));
            assert!((back - e).abs() < 1e-5, "{e} -> {back}");
        }
    }

    #[test]
    fn transfer_function_is_continuous_at_the_knee() {
        let below = srgb_to_linear(0.04045);
        let above = srgb_to_linear(0.04045 + 1e-6);
        assert!((above - below).abs() < 1e-5);
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn luminance_of_primaries_sums_to_one() {
        let sum = luminance(Vec3::X) + luminance(Vec3::Y) + luminance(Vec3::Z);
        assert!((sum - 1.0).abs() < 1e-6);
        assert!(luminance(Vec3::Y) > luminance(Vec3::X));
    }
}
