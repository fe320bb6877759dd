//! The error of an image against a reference, by the measures chiaro reports.
//!
//! - relMSE = mean((x - y)^2 / (y^2 + epsilon)) over pixels and channels, on linear HDR, with
//!   y the reference (epsilon 0.01 by default: it keeps black pixels from dominating).
//! - SMAPE = mean(|x - y| / (|x| + |y| + 0.01)) over pixels and channels, on linear HDR: the
//!   symmetric relative error of Vogels et al. 2018 ("Denoising with Kernel Prediction and
//!   Asymmetric Loss Functions"), in [0, 1).
//! - PSNR = 10 log10(255^2 / MSE) on the 8-bit sRGB images a viewer sees (infinite when equal).
//! - FLIP: mean LDR-FLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for Alternating
//!   Images") of the same 8-bit sRGB images, through the `nv-flip` crate, at 67 pixels per degree
//!   (a 0.7 m viewing distance from a 0.7 m wide 4K monitor: FLIP's default).
//!
//! The 8-bit images are the linear ones tonemapped (Khronos PBR Neutral at exposure 1 unless
//! set otherwise) and sRGB-encoded; an image read from an 8-bit file is used as stored.

use chiaro_shading::tonemap::Tonemapper;
use glam::Vec3;

use crate::error::EvalError;
use crate::hdr_image::HdrImage;

/// relMSE's epsilon unless set otherwise.
pub const DEFAULT_REL_MSE_EPSILON: f32 = 0.01;

/// SMAPE's epsilon (Vogels et al. 2018).
pub const SMAPE_EPSILON: f32 = 0.01;

/// How images are compared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompareSettings {
    /// relMSE's epsilon, added to the reference's square.
    pub rel_mse_epsilon: f32,
    /// Tonemapper for the 8-bit images PSNR and FLIP read.
    pub tonemapper: Tonemapper,
    /// Exposure before tonemapping.
    pub exposure: f32,
    /// FLIP's observer: pixels per degree of visual angle.
    pub pixels_per_degree: f32,
}

impl Default for CompareSettings {
    fn default() -> Self {
        Self {
            rel_mse_epsilon: DEFAULT_REL_MSE_EPSILON,
            tonemapper: Tonemapper::PbrNeutral,
            exposure: 1.0,
            pixels_per_degree: nv_flip::DEFAULT_PIXELS_PER_DEGREE,
        }
    }
}

/// The measures of one comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// relMSE on linear HDR.
    pub rel_mse: f64,
    /// SMAPE on linear HDR.
    pub smape: f64,
    /// PSNR of the 8-bit sRGB images, decibels (infinite when they are equal).
    pub psnr_db: f64,
    /// Mean LDR-FLIP of the 8-bit sRGB images, in [0, 1].
    pub flip_mean: f64,
}

impl Metrics {
    /// Name and value of each measure, in the order `chiaro compare` prints them.
    pub fn named(&self) -> [(&'static str, f64); 4] {
        [
            ("relmse", self.rel_mse),
            ("smape", self.smape),
            ("psnr_db", self.psnr_db),
            ("flip_mean", self.flip_mean),
        ]
    }
}

/// A comparison's measures and FLIP's per-pixel error map.
pub struct Comparison {
    /// The measures.
    pub metrics: Metrics,
    /// Width of the error map.
    pub width: u32,
    /// Height of the error map.
    pub height: u32,
    /// FLIP's error per pixel, in [0, 1], row-major.
    pub flip_error: Vec<f32>,
}

/// relMSE of `test` against `reference` with `epsilon`; both the same length.
pub fn rel_mse(test: &[Vec3], reference: &[Vec3], epsilon: f32) -> f64 {
    mean_over_channels(test, reference, |x, y| {
        let d = x - y;
        d * d / (y * y + f64::from(epsilon))
    })
}

/// SMAPE of `test` against `reference` (symmetric: the order does not matter).
pub fn smape(test: &[Vec3], reference: &[Vec3]) -> f64 {
    mean_over_channels(test, reference, |x, y| {
        (x - y).abs() / (x.abs() + y.abs() + f64::from(SMAPE_EPSILON))
    })
}

/// PSNR in decibels between two 8-bit images of the same length.
pub fn psnr_db(test: &[u8], reference: &[u8]) -> f64 {
    let sum: f64 = test
        .iter()
        .zip(reference)
        .map(|(&a, &b)| (f64::from(a) - f64::from(b)).powi(2))
        .sum();
    let mse = sum / test.len().max(1) as f64;
    10.0 * (255.0 * 255.0 / mse).log10()
}

fn mean_over_channels(test: &[Vec3], reference: &[Vec3], f: impl Fn(f64, f64) -> f64) -> f64 {
    let sum: f64 = test
        .iter()
        .zip(reference)
        .flat_map(|(x, y)| (0..3).map(move |c| (f64::from(x[c]), f64::from(y[c]))))
        .map(|(x, y)| f(x, y))
        .sum();
    sum / (3 * test.len().max(1)) as f64
}

/// Compares `test` against `reference`: both must have the same size and finite pixels.
pub fn compare(
    test: &HdrImage,
    reference: &HdrImage,
    settings: &CompareSettings,
) -> Result<Comparison, EvalError> {
    if (test.width, test.height) != (reference.width, reference.height) {
        return Err(EvalError::SizeMismatch {
            test: test.name.clone(),
            test_size: (test.width, test.height),
            reference: reference.name.clone(),
            reference_size: (reference.width, reference.height),
        });
    }
    if test.pixels.is_empty() {
        return Err(EvalError::Settings(format!(
            "{} and {} are empty: nothing to compare",
            test.name, reference.name
        )));
    }
    if !(settings.rel_mse_epsilon > 0.0 && settings.rel_mse_epsilon.is_finite()) {
        return Err(EvalError::Settings(format!(
            "relMSE epsilon {} must be positive and finite",
            settings.rel_mse_epsilon
        )));
    }
    if !(settings.pixels_per_degree > 0.0 && settings.pixels_per_degree.is_finite()) {
        return Err(EvalError::Settings(format!(
            "FLIP's pixels per degree {} must be positive and finite",
            settings.pixels_per_degree
        )));
    }
    test.check_finite()?;
    reference.check_finite()?;
    let test_ldr = test.to_srgb8(settings.tonemapper, settings.exposure);
    let reference_ldr = reference.to_srgb8(settings.tonemapper, settings.exposure);
    let (width, height) = (test.width, test.height);
    let flip_map = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(width, height, &reference_ldr),
        nv_flip::FlipImageRgb8::with_data(width, height, &test_ldr),
        settings.pixels_per_degree,
    );
    let flip_error = flip_map.to_vec();
    let flip_mean =
        flip_error.iter().map(|&e| f64::from(e)).sum::<f64>() / flip_error.len().max(1) as f64;
    Ok(Comparison {
        metrics: Metrics {
            rel_mse: rel_mse(&test.pixels, &reference.pixels, settings.rel_mse_epsilon),
            smape: smape(&test.pixels, &reference.pixels),
            psnr_db: psnr_db(&test_ldr, &reference_ldr),
            flip_mean,
        },
        width,
        height,
        flip_error,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_shading::rng::Pcg32;

    fn scene_like(w: u32, h: u32) -> HdrImage {
        let pixels = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32 / w as f32, (i / w) as f32 / h as f32);
                Vec3::new(2.0 * x, 0.5 + 0.5 * (6.0 * y).sin(), 0.2)
                    * if x > 0.5 { 1.0 } else { 0.3 }
            })
            .collect();
        HdrImage::new("reference", w, h, pixels).unwrap()
    }

    /// `image` with zero-mean multiplicative noise of relative size `amount`.
    fn noisy(image: &HdrImage, amount: f32, seed: u64) -> HdrImage {
        let mut rng = Pcg32::new(seed, 7);
        let pixels = image
            .pixels
            .iter()
            .map(|p| *p * (1.0 + amount * (2.0 * rng.next_f32() - 1.0)))
            .collect();
        HdrImage::new("test", image.width, image.height, pixels).unwrap()
    }

    #[test]
    fn an_image_against_itself_has_no_error() {
        let a = scene_like(32, 24);
        let m = compare(&a, &a, &CompareSettings::default())
            .unwrap()
            .metrics;
        assert_eq!((m.rel_mse, m.smape, m.flip_mean), (0.0, 0.0, 0.0));
        assert!(m.psnr_db.is_infinite() && m.psnr_db > 0.0);
    }

    #[test]
    fn rel_mse_follows_its_formula() {
        // Bright pixels: epsilon is negligible, so a relative error d gives relMSE ~ d^2.
        let y = vec![Vec3::splat(100.0); 4];
        let x: Vec<Vec3> = y.iter().map(|p| *p * 1.1).collect();
        assert!((rel_mse(&x, &y, 0.01) - 0.01).abs() < 1e-6);
        // Black reference: the error is divided by epsilon alone.
        let black = vec![Vec3::ZERO; 4];
        let grey = vec![Vec3::splat(0.1); 4];
        assert!((rel_mse(&grey, &black, 0.01) - 1.0).abs() < 1e-6);
        // Not symmetric: the reference is the denominator.
        assert!(rel_mse(&black, &grey, 0.01) < 0.6);
    }

    #[test]
    fn smape_is_symmetric_and_bounded() {
        let a = scene_like(16, 16);
        let b = noisy(&a, 0.5, 1);
        let ab = smape(&a.pixels, &b.pixels);
        assert!((ab - smape(&b.pixels, &a.pixels)).abs() < 1e-12);
        assert!(ab > 0.0 && ab < 1.0);
        let far = vec![Vec3::splat(1e6); 256];
        let zero = vec![Vec3::ZERO; 256];
        assert!(smape(&far, &zero) < 1.0 && smape(&far, &zero) > 0.999);
    }

    #[test]
    fn every_measure_grows_with_the_noise() {
        let reference = scene_like(48, 32);
        let settings = CompareSettings::default();
        let measures: Vec<Metrics> = [0.02, 0.1, 0.5]
            .iter()
            .map(|&a| {
                compare(&noisy(&reference, a, 3), &reference, &settings)
                    .unwrap()
                    .metrics
            })
            .collect();
        for pair in measures.windows(2) {
            let (less, more) = (pair[0], pair[1]);
            assert!(less.rel_mse < more.rel_mse, "{less:?} {more:?}");
            assert!(less.smape < more.smape, "{less:?} {more:?}");
            assert!(less.psnr_db > more.psnr_db, "{less:?} {more:?}");
            assert!(less.flip_mean < more.flip_mean, "{less:?} {more:?}");
        }
        assert!(measures[2].flip_mean > 0.01 && measures[2].flip_mean < 1.0);
    }

    #[test]
    fn mismatched_or_non_finite_inputs_are_refused_by_name() {
        let a = scene_like(8, 8);
        let b = scene_like(8, 9);
        let e = compare(&a, &b, &CompareSettings::default())
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("reference is (8, 9)"), "{e}");
        let mut c = noisy(&a, 0.1, 2);
        c.pixels[3] = Vec3::NAN;
        let e = compare(&c, &a, &CompareSettings::default())
            .err()
            .unwrap()
            .to_string();
        assert!(e.starts_with("test: 1 non-finite"), "{e}");
        let settings = CompareSettings {
            rel_mse_epsilon: 0.0,
            ..CompareSettings::default()
        };
        assert!(compare(&a, &a, &settings).is_err());
    }
}
