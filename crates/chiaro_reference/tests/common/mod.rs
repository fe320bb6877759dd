//! What the reference's test files measure on a render: the image mean and its standard error.

// Each test file uses its own part of this module.
#![allow(dead_code)]

use chiaro_reference::RenderOutput;
use glam::Vec3;

/// The mean of every channel of every pixel.
pub fn mean(image: &[Vec3]) -> f64 {
    image.iter().map(|p| (p.x + p.y + p.z) as f64).sum::<f64>() / (3 * image.len()) as f64
}

/// Standard error of the image mean where pixels are independent (camera paths only), from the
/// spread between the two independent halves: Var(pixel) = E[(half0 - half1)^2] / 4 for the
/// full image (equal-size halves).
pub fn standard_error(out: &RenderOutput) -> f64 {
    let [a, b] = &out.halves;
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (*x - *y) / 3.0;
            ((d.x + d.y + d.z) as f64).powi(2) / 4.0
        })
        .sum();
    sum.sqrt() / a.len() as f64
}

/// Standard error of the image mean from the spread of the two halves' means (each half an
/// independent estimate): for light tracing, whose splats reach any pixel, so that pixels are
/// not independent.
pub fn standard_error_of_halves(out: &RenderOutput) -> f64 {
    let [a, b] = &out.halves;
    (mean(a) - mean(b)).abs() / 2.0
}
