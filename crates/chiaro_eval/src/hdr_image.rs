//! Images as the metrics see them: linear RGB, plus the 8-bit sRGB a viewer would show.

use std::path::Path;

use chiaro_shading::color::{linear_to_srgb, srgb_to_linear};
use chiaro_shading::tonemap::Tonemapper;
use glam::Vec3;

use crate::error::EvalError;

/// A linear RGB image, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Linear RGB, `width * height` of them.
    pub pixels: Vec<Vec3>,
    /// Where the image came from, for error messages.
    pub name: String,
    /// The file's own 8-bit sRGB values when it was read from an 8-bit file, so a PNG is shown
    /// (and FLIP-compared) exactly as stored rather than tonemapped a second time.
    srgb8: Option<Vec<u8>>,
}

impl HdrImage {
    /// An image of `width` x `height` linear `pixels`, called `name` in errors.
    pub fn new(name: &str, width: u32, height: u32, pixels: Vec<Vec3>) -> Result<Self, EvalError> {
        if pixels.len() != width as usize * height as usize {
            return Err(EvalError::Settings(format!(
                "{name}: {} pixels for a {width}x{height} image",
                pixels.len()
            )));
        }
        Ok(Self {
            width,
            height,
            pixels,
            name: name.to_owned(),
            srgb8: None,
        })
    }

    /// Reads `path`: EXR and Radiance HDR as linear floats; PNG and JPEG as 8-bit sRGB, decoded
    /// to linear (and kept as stored for display).
    pub fn read(path: &Path) -> Result<Self, EvalError> {
        let name = path.display().to_string();
        let read_error = |message: String| EvalError::Read {
            path: name.clone(),
            message,
        };
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        let decoded = image::open(path).map_err(|e| read_error(e.to_string()))?;
        match extension.as_str() {
            "exr" | "hdr" => {
                let rgb = decoded.into_rgb32f();
                let (width, height) = rgb.dimensions();
                let pixels = rgb.pixels().map(|p| Vec3::from_array(p.0)).collect();
                Self::new(&name, width, height, pixels)
            }
            "png" | "jpg" | "jpeg" => {
                let rgb = decoded.into_rgb8();
                let (width, height) = rgb.dimensions();
                let pixels = rgb
                    .pixels()
                    .map(|p| Vec3::from_array(p.0.map(|c| srgb_to_linear(f32::from(c) / 255.0))))
                    .collect();
                let mut image = Self::new(&name, width, height, pixels)?;
                image.srgb8 = Some(rgb.into_raw());
                Ok(image)
            }
            other => Err(read_error(format!(
                "unknown image type '{other}' (expected .exr, .hdr, .png, .jpg)"
            ))),
        }
    }

    /// The first non-finite pixel, if any, as an error naming the image.
    pub fn check_finite(&self) -> Result<(), EvalError> {
        let mut bad = self
            .pixels
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.is_finite());
        let Some((first, _)) = bad.next() else {
            return Ok(());
        };
        Err(EvalError::NonFinite {
            path: self.name.clone(),
            count: 1 + bad.count(),
            x: (first % self.width as usize) as u32,
            y: (first / self.width as usize) as u32,
        })
    }

    /// 8-bit sRGB as a viewer shows it: the stored values for an image read from an 8-bit
    /// file, else the linear pixels tonemapped with `tonemapper` at `exposure` and encoded
    /// with the sRGB transfer function.
    pub fn to_srgb8(&self, tonemapper: Tonemapper, exposure: f32) -> Vec<u8> {
        if let Some(stored) = &self.srgb8 {
            return stored.clone();
        }
        self.pixels
            .iter()
            .flat_map(|p| tonemapper.apply(*p, exposure).to_array())
            .map(|c| (linear_to_srgb(c.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("chiaro_eval_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    fn ramp() -> HdrImage {
        let pixels = (0..12)
            .map(|i| Vec3::new(i as f32 / 11.0, 0.5, 1.0 - i as f32 / 11.0))
            .collect();
        HdrImage::new("ramp", 4, 3, pixels).unwrap()
    }

    #[test]
    fn exr_round_trips_exactly() {
        let image = ramp();
        let path = temp("ramp.exr");
        chiaro_reference::write_exr(&path, 4, 3, &image.pixels).unwrap();
        let back = HdrImage::read(&path).unwrap();
        assert_eq!(back.pixels, image.pixels);
        assert_eq!((back.width, back.height), (4, 3));
    }

    #[test]
    fn png_decodes_to_linear_and_keeps_its_bytes() {
        let image = ramp();
        let path = temp("ramp.png");
        chiaro_reference::write_png(&path, 4, 3, &image.pixels, Tonemapper::Clamp, 1.0).unwrap();
        let back = HdrImage::read(&path).unwrap();
        for (a, b) in back.pixels.iter().zip(&image.pixels) {
            // 8-bit sRGB steps are at most about 0.014 in linear near white.
            assert!((*a - *b).abs().max_element() < 0.015, "{a} vs {b}");
        }
        assert_eq!(
            back.to_srgb8(Tonemapper::AcesFitted, 4.0),
            image.to_srgb8(Tonemapper::Clamp, 1.0),
            "an 8-bit file is shown as stored, not tonemapped again"
        );
    }

    #[test]
    fn bad_files_and_pixels_are_named() {
        let path = temp("not_an_image.png");
        std::fs::write(&path, b"hello").unwrap();
        let e = HdrImage::read(&path).unwrap_err().to_string();
        assert!(e.contains("not_an_image.png"), "{e}");
        let e = HdrImage::read(&temp("missing.exr"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.exr"), "{e}");

        let mut image = ramp();
        image.pixels[5].y = f32::NAN;
        image.pixels[7].x = f32::INFINITY;
        let e = image.check_finite().unwrap_err().to_string();
        assert!(
            e.contains("ramp: 2 non-finite pixels") && e.contains("x 1, y 1"),
            "{e}"
        );
        assert!(HdrImage::new("short", 4, 4, vec![Vec3::ZERO; 3]).is_err());
    }
}
