//! Per-pixel error as a picture: FLIP's error map through the magma colour map (black for no
//! visible difference, through purple and orange, to pale yellow for the largest).

use std::path::Path;

use crate::error::EvalError;
use crate::metrics::Comparison;

/// Writes `comparison`'s FLIP error map to `path` as an 8-bit PNG in the magma colour map.
pub fn write_heatmap(path: &Path, comparison: &Comparison) -> Result<(), EvalError> {
    let lut = nv_flip::magma_lut();
    let map = nv_flip::FlipImageFloat::with_data(
        comparison.width,
        comparison.height,
        &comparison.flip_error,
    );
    let rgb = map.apply_color_lut(&lut).to_vec();
    chiaro_reference::write_png_pixels(
        path,
        comparison.width,
        comparison.height,
        &rgb,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|e| EvalError::Write {
        path: path.display().to_string(),
        message: match e {
            chiaro_reference::ReferenceError::Write { message, .. } => message,
            other => other.to_string(),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hdr_image::HdrImage;
    use crate::metrics::{CompareSettings, compare};
    use glam::Vec3;

    #[test]
    fn heatmap_is_dark_where_equal_and_bright_where_different() {
        let (w, h) = (32, 16);
        let reference = HdrImage::new("reference", w, h, vec![Vec3::splat(0.3); 512]).unwrap();
        let mut test = reference.clone();
        // The right half differs strongly.
        for (i, p) in test.pixels.iter_mut().enumerate() {
            if i as u32 % w >= w / 2 {
                *p = Vec3::new(2.0, 0.0, 0.0);
            }
        }
        let comparison = compare(&test, &reference, &CompareSettings::default()).unwrap();
        let path = std::env::temp_dir().join(format!("chiaro_heatmap_{}.png", std::process::id()));
        write_heatmap(&path, &comparison).unwrap();
        let png = image::open(&path).unwrap().into_rgb8();
        assert_eq!(png.dimensions(), (w, h));
        let brightness = |x: u32| {
            png.get_pixel(x, h / 2)
                .0
                .iter()
                .map(|&c| u32::from(c))
                .sum::<u32>()
        };
        assert!(
            brightness(2) < 30,
            "equal pixels map to black: {}",
            brightness(2)
        );
        assert!(
            brightness(w - 3) > 300,
            "different pixels map bright: {}",
            brightness(w - 3)
        );
    }
}
