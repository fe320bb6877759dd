//! Tonemapping: linear HDR radiance to linear display values in [0, 1], which
//! [`crate::color::linear_to_srgb`] then encodes.
//!
//! - [`Tonemapper::AcesFitted`]: Stephen Hill's fit of the ACES reference rendering transform and
//!   sRGB output transform (Hill, 2016, "ACES.hlsl" in the BakingLab project, after the Academy
//!   Color Encoding System RRT + ODT): an sRGB -> "ACEScg-ish" input matrix (with the RRT's
//!   saturation adjustment folded in), a rational fit of the RRT + ODT tone curve, and an output
//!   matrix back to sRGB primaries.
//! - [`Tonemapper::PbrNeutral`]: Khronos PBR Neutral (Khronos 3D Commerce working group, 2024,
//!   "Khronos PBR Neutral Tone Mapper" specification): identity below a knee so base colours
//!   reproduce faithfully, then a hyperbolic highlight compression (start 0.8 - 0.04) with
//!   desaturation 0.15 toward white.
//! - [`Tonemapper::Clamp`]: no curve, values above 1 clip.
//!
//! Inputs are sanitised the same way for every operator: `exposure` multiplies the input (1 leaves
//! it alone; see [`exposure_from_ev`] for stops) and must be finite and non-negative, otherwise it
//! counts as 0; each channel is then clamped to [0, [`MAX_TONEMAP_INPUT`]] (NaN reads as 0). The
//! result is always in [0, 1], and a grey input gives a grey output that rises with the input.

use std::str::FromStr;

use glam::{Mat3, Vec3};

/// The largest linear value fed to a curve (after exposure); larger values (and +infinity) are
/// clamped to it. Every curve has saturated long before this.
pub const MAX_TONEMAP_INPUT: f32 = 1e9;

/// How linear radiance is mapped to display values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Tonemapper {
    /// ACES (RRT + sRGB ODT) after Stephen Hill's fit.
    AcesFitted,
    /// Khronos PBR Neutral.
    PbrNeutral,
    /// Clamp to [0, 1].
    Clamp,
}

/// A linear exposure multiplier for `ev` stops: 2^ev.
pub fn exposure_from_ev(ev: f32) -> f32 {
    ev.exp2()
}

/// Hill's input matrix, sRGB -> ACES AP1 with the RRT saturation folded in, rows as printed in
/// ACES.hlsl (each row sums to 1, so grey stays grey).
pub const ACES_INPUT: [[f32; 3]; 3] = [
    [0.597_19, 0.354_58, 0.048_23],
    [0.076_00, 0.908_34, 0.015_66],
    [0.028_40, 0.133_83, 0.837_77],
];

/// Hill's output matrix, ODT AP1 -> sRGB, rows as printed.
pub const ACES_OUTPUT: [[f32; 3]; 3] = [
    [1.604_75, -0.531_08, -0.073_67],
    [-0.102_08, 1.108_13, -0.006_05],
    [-0.003_27, -0.072_76, 1.076_02],
];

/// Hill's rational fit of the RRT + ODT tone curve, (v (v + a) - b) / (v (c v + d) + e), as
/// [a, b, c, d, e].
pub const ACES_FIT: [f32; 5] = [0.024_578_6, 0.000_090_537, 0.983_729, 0.432_951, 0.238_081];

/// Khronos PBR Neutral: where highlight compression starts (0.8 - 0.04).
pub const PBR_NEUTRAL_START_COMPRESSION: f32 = 0.8 - 0.04;
/// Khronos PBR Neutral: desaturation toward white of compressed highlights.
pub const PBR_NEUTRAL_DESATURATION: f32 = 0.15;
/// Khronos PBR Neutral: below this smallest channel the toe offset x - 6.25 x^2 applies.
pub const PBR_NEUTRAL_TOE_END: f32 = 0.08;
/// Khronos PBR Neutral: the toe's quadratic coefficient.
pub const PBR_NEUTRAL_TOE_SCALE: f32 = 6.25;
/// Khronos PBR Neutral: the offset above the toe.
pub const PBR_NEUTRAL_OFFSET: f32 = 0.04;

/// Every number of the curves above by name, for mirrors of these curves (the WGSL tonemap
/// reads them from generated constants): ACES_INPUT_RC / ACES_OUTPUT_RC (row R, column C),
/// ACES_FIT_A..E, and the PBR Neutral constants.
pub const CURVE_CONSTANTS: [(&str, f32); 28] = [
    ("ACES_INPUT_00", ACES_INPUT[0][0]),
    ("ACES_INPUT_01", ACES_INPUT[0][1]),
    ("ACES_INPUT_02", ACES_INPUT[0][2]),
    ("ACES_INPUT_10", ACES_INPUT[1][0]),
    ("ACES_INPUT_11", ACES_INPUT[1][1]),
    ("ACES_INPUT_12", ACES_INPUT[1][2]),
    ("ACES_INPUT_20", ACES_INPUT[2][0]),
    ("ACES_INPUT_21", ACES_INPUT[2][1]),
    ("ACES_INPUT_22", ACES_INPUT[2][2]),
    ("ACES_OUTPUT_00", ACES_OUTPUT[0][0]),
    ("ACES_OUTPUT_01", ACES_OUTPUT[0][1]),
    ("ACES_OUTPUT_02", ACES_OUTPUT[0][2]),
    ("ACES_OUTPUT_10", ACES_OUTPUT[1][0]),
    ("ACES_OUTPUT_11", ACES_OUTPUT[1][1]),
    ("ACES_OUTPUT_12", ACES_OUTPUT[1][2]),
    ("ACES_OUTPUT_20", ACES_OUTPUT[2][0]),
    ("ACES_OUTPUT_21", ACES_OUTPUT[2][1]),
    ("ACES_OUTPUT_22", ACES_OUTPUT[2][2]),
    ("ACES_FIT_A", ACES_FIT[0]),
    ("ACES_FIT_B", ACES_FIT[1]),
    ("ACES_FIT_C", ACES_FIT[2]),
    ("ACES_FIT_D", ACES_FIT[3]),
    ("ACES_FIT_E", ACES_FIT[4]),
    (
        "PBR_NEUTRAL_START_COMPRESSION",
        PBR_NEUTRAL_START_COMPRESSION,
    ),
    ("PBR_NEUTRAL_DESATURATION", PBR_NEUTRAL_DESATURATION),
    ("PBR_NEUTRAL_TOE_END", PBR_NEUTRAL_TOE_END),
    ("PBR_NEUTRAL_TOE_SCALE", PBR_NEUTRAL_TOE_SCALE),
    ("PBR_NEUTRAL_OFFSET", PBR_NEUTRAL_OFFSET),
];

/// A matrix from its rows (glam matrices are column-major, hence the transpose).
fn from_rows(rows: &[[f32; 3]; 3]) -> Mat3 {
    Mat3::from_cols_array_2d(rows).transpose()
}

/// Hill's rational fit of the RRT + ODT tone curve, per channel.
fn rrt_and_odt_fit(v: Vec3) -> Vec3 {
    let [fa, fb, fc, fd, fe] = ACES_FIT;
    let a = v * (v + fa) - fb;
    let b = v * (fc * v + fd) + fe;
    a / b
}

fn aces_fitted(c: Vec3) -> Vec3 {
    let v = from_rows(&ACES_INPUT) * c;
    let v = rrt_and_odt_fit(v);
    from_rows(&ACES_OUTPUT) * v
}

/// Khronos PBR Neutral, as in the specification's reference code.
fn pbr_neutral(mut color: Vec3) -> Vec3 {
    const START_COMPRESSION: f32 = PBR_NEUTRAL_START_COMPRESSION;
    const DESATURATION: f32 = PBR_NEUTRAL_DESATURATION;
    let x = color.min_element();
    let offset = if x < PBR_NEUTRAL_TOE_END {
        x - PBR_NEUTRAL_TOE_SCALE * x * x
    } else {
        PBR_NEUTRAL_OFFSET
    };
    color -= Vec3::splat(offset);
    let peak = color.max_element();
    if peak < START_COMPRESSION {
        return color;
    }
    let d = 1.0 - START_COMPRESSION;
    let new_peak = 1.0 - d * d / (peak + d - START_COMPRESSION);
    color *= new_peak / peak;
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    color.lerp(Vec3::splat(new_peak), g)
}

impl Tonemapper {
    /// Every operator, for listings.
    pub const ALL: [Tonemapper; 3] = [Self::AcesFitted, Self::PbrNeutral, Self::Clamp];

    /// Maps linear RGB radiance times `exposure` to linear display RGB in [0, 1] (see the module
    /// docs for how inputs are sanitised).
    pub fn apply(&self, linear: Vec3, exposure: f32) -> Vec3 {
        let exposure = if exposure.is_finite() && exposure > 0.0 {
            exposure
        } else {
            0.0
        };
        // `max` with NaN returns the other operand, so NaN channels read as 0.
        let c = (linear * exposure)
            .max(Vec3::ZERO)
            .min(Vec3::splat(MAX_TONEMAP_INPUT));
        let c = Vec3::new(san(c.x), san(c.y), san(c.z));
        let mapped = match self {
            Self::AcesFitted => aces_fitted(c),
            Self::PbrNeutral => pbr_neutral(c),
            Self::Clamp => c,
        };
        mapped.clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// The operator's command-line name: "aces", "neutral" or "clamp".
    pub fn name(&self) -> &'static str {
        match self {
            Self::AcesFitted => "aces",
            Self::PbrNeutral => "neutral",
            Self::Clamp => "clamp",
        }
    }
}

/// NaN -> 0 for one channel (`Vec3::max` is not guaranteed to drop NaN on every target).
fn san(x: f32) -> f32 {
    if x.is_nan() { 0.0 } else { x }
}

impl FromStr for Tonemapper {
    type Err = String;

    /// Parses [`Tonemapper::name`] (case-insensitive; "aces-fitted" and "pbr-neutral" also work).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "aces" | "aces-fitted" | "acesfitted" => Ok(Self::AcesFitted),
            "neutral" | "pbr-neutral" | "pbrneutral" => Ok(Self::PbrNeutral),
            "clamp" => Ok(Self::Clamp),
            other => Err(format!(
                "unknown tonemapper '{other}' (expected aces, neutral or clamp)"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;

    #[test]
    fn zero_maps_to_zero_and_bounds_hold() {
        let mut rng = Pcg32::new(6, 1);
        for t in Tonemapper::ALL {
            assert_eq!(t.apply(Vec3::ZERO, 1.0), Vec3::ZERO, "{t:?}");
            for _ in 0..20_000 {
                let scale = 10f32.powf(rng.next_f32() * 12.0 - 4.0);
                let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * scale;
                let out = t.apply(c, 1.0);
                assert!(
                    out.min_element() >= 0.0 && out.max_element() <= 1.0,
                    "{t:?} {c} -> {out}"
                );
            }
            for bad in [
                Vec3::splat(f32::NAN),
                Vec3::splat(f32::INFINITY),
                Vec3::new(-1.0, f32::MAX, 0.5),
            ] {
                let out = t.apply(bad, 1.0);
                assert!(out.is_finite() && out.min_element() >= 0.0 && out.max_element() <= 1.0);
            }
            assert_eq!(t.apply(Vec3::ONE, f32::NAN), Vec3::ZERO);
            assert_eq!(t.apply(Vec3::ONE, -1.0), Vec3::ZERO);
        }
    }

    /// Grey in, grey out, rising strictly until it saturates, never falling; white-ish at the top.
    #[test]
    fn grey_ramp_is_monotone_and_stays_grey() {
        for t in Tonemapper::ALL {
            let mut last = -1.0f32;
            for i in 0..=4000 {
                // 1e-4 to 1e4, logarithmically.
                let g = 10f32.powf(-4.0 + 8.0 * i as f32 / 4000.0);
                let out = t.apply(Vec3::splat(g), 1.0);
                assert!(
                    (out.x - out.y).abs() < 2e-3 && (out.x - out.z).abs() < 2e-3,
                    "{t:?} {g}: {out}"
                );
                let y = crate::color::luminance(out);
                assert!(y >= last, "{t:?}: luminance falls at {g}: {y} < {last}");
                // Strictly rising between black and white (ACES's fit crushes inputs below about
                // 0.0036 to black, so only once something shows).
                if last > 0.0 && last < 0.99 && g < 10.0 {
                    assert!(y > last, "{t:?}: flat at {g}");
                }
                last = y;
            }
            assert!(last > 0.98, "{t:?} never reaches white: {last}");
        }
    }

    /// Mid grey (0.18) lands between 0.08 and 0.25 linear (about 0.31 to 0.54 in sRGB).
    #[test]
    fn mid_grey_lands_in_a_sensible_range() {
        for t in Tonemapper::ALL {
            let out = t.apply(Vec3::splat(0.18), 1.0).x;
            assert!((0.08..=0.25).contains(&out), "{t:?}: {out}");
        }
        // Reference values worked by hand from the published formulas.
        let aces = Tonemapper::AcesFitted.apply(Vec3::splat(0.18), 1.0).x;
        assert!((aces - 0.105_6).abs() < 1e-3, "{aces}");
        let neutral = Tonemapper::PbrNeutral.apply(Vec3::splat(0.18), 1.0).x;
        assert!((neutral - 0.14).abs() < 1e-6, "{neutral}");
        // PBR Neutral is the identity (minus its 0.04 offset) for base colours below the knee.
        let c = Vec3::new(0.5, 0.3, 0.2);
        assert!(
            (Tonemapper::PbrNeutral.apply(c, 1.0) - (c - 0.04))
                .abs()
                .max_element()
                < 1e-6
        );
        assert_eq!(
            Tonemapper::Clamp.apply(Vec3::new(0.5, 2.0, -1.0), 1.0),
            Vec3::new(0.5, 1.0, 0.0)
        );
    }

    #[test]
    fn exposure_scales_the_input() {
        let c = Vec3::new(0.2, 0.4, 0.1);
        for t in Tonemapper::ALL {
            assert_eq!(t.apply(c, 4.0), t.apply(c * 4.0, 1.0));
        }
        assert_eq!(exposure_from_ev(2.0), 4.0);
        assert_eq!(exposure_from_ev(0.0), 1.0);
    }

    #[test]
    fn names_round_trip() {
        for t in Tonemapper::ALL {
            assert_eq!(t.name().parse::<Tonemapper>(), Ok(t));
        }
        assert_eq!(
            "PBR-Neutral".parse::<Tonemapper>(),
            Ok(Tonemapper::PbrNeutral)
        );
        assert!("filmic".parse::<Tonemapper>().is_err());
    }
}
