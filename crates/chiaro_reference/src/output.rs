//! Writing renders: EXR for linear HDR, PNG tonemapped to sRGB.

use std::path::Path;

use chiaro_shading::color::linear_to_srgb;
use chiaro_shading::tonemap::Tonemapper;
use glam::Vec3;

use crate::error::ReferenceError;

fn write_error(path: &Path, e: impl std::fmt::Display) -> ReferenceError {
    ReferenceError::Write {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Writes linear RGB as a 32-bit float EXR.
pub fn write_exr(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
) -> Result<(), ReferenceError> {
    let data: Vec<f32> = pixels.iter().flat_map(|p| p.to_array()).collect();
    let image = image::Rgb32FImage::from_raw(width, height, data)
        .ok_or_else(|| write_error(path, "pixel count does not match the size"))?;
    image
        .save_with_format(path, image::ImageFormat::OpenExr)
        .map_err(|e| write_error(path, e))
}

/// Writes linear RGB tonemapped with `tonemapper` at `exposure`, sRGB-encoded, as an 8-bit PNG.
pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    tonemapper: Tonemapper,
    exposure: f32,
) -> Result<(), ReferenceError> {
    let data: Vec<u8> = pixels
        .iter()
        .flat_map(|p| tonemapper.apply(*p, exposure).to_array())
        .map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8)
        .collect();
    write_png_pixels(path, width, height, &data, image::ExtendedColorType::Rgb8)
}

/// Writes 8-bit pixels (`color`: RGB8 or RGBA8, rows top to bottom) as a PNG. The file is
/// encoded in memory and written with one checked write, so a full disk or a failed write is
/// an error: the image crate's own `save` buffers the file and drops the error of its last
/// flush.
pub fn write_png_pixels(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[u8],
    color: image::ExtendedColorType,
) -> Result<(), ReferenceError> {
    let mut encoded = std::io::Cursor::new(Vec::new());
    image::write_buffer_with_format(
        &mut encoded,
        pixels,
        width,
        height,
        color,
        image::ImageFormat::Png,
    )
    .map_err(|e| write_error(path, e))?;
    std::fs::write(path, encoded.into_inner()).map_err(|e| write_error(path, e))
}

/// Reads an EXR back as linear RGB (for comparisons and tests).
pub fn read_exr(path: &Path) -> Result<(u32, u32, Vec<Vec3>), ReferenceError> {
    let image = image::open(path)
        .map_err(|e| write_error(path, e))?
        .into_rgb32f();
    let (w, h) = image.dimensions();
    Ok((
        w,
        h,
        image.pixels().map(|p| Vec3::from_array(p.0)).collect(),
    ))
}
