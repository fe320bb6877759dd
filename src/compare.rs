//! `chiaro compare`: the error of an image against a reference, one measure per line.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;

use chiaro::eval::{CompareSettings, HdrImage, compare, write_heatmap};
use chiaro::shading::tonemap::{Tonemapper, exposure_from_ev};

/// What `chiaro compare` takes.
#[derive(Args)]
pub struct CompareArgs {
    /// The image under test (.exr or .hdr: linear; .png or .jpg: 8-bit sRGB).
    test: PathBuf,
    /// The reference image, the same size.
    reference: PathBuf,
    /// Also write FLIP's per-pixel error map here, as a PNG heatmap (magma colour map).
    #[arg(long)]
    heatmap: Option<PathBuf>,
    /// relMSE's epsilon, added to the reference's square: mean((x - y)^2 / (y^2 + epsilon)).
    #[arg(long, default_value_t = chiaro::eval::metrics::DEFAULT_REL_MSE_EPSILON,
          value_parser = crate::args::positive, allow_negative_numbers = true)]
    epsilon: f32,
    /// Tonemapper that turns linear images into the 8-bit sRGB ones PSNR and FLIP read (aces,
    /// neutral, clamp); 8-bit inputs are used as stored.
    #[arg(long, default_value = "neutral")]
    tonemapper: Tonemapper,
    /// Exposure in stops of the tonemapped images PSNR and FLIP read: linear radiance times
    /// 2^STOPS before tonemapping (-30..=30). relMSE and SMAPE read the linear images as they
    /// are, at any exposure.
    #[arg(long, default_value_t = 0.0, value_parser = crate::args::exposure_stops,
          allow_negative_numbers = true)]
    exposure: f32,
}

/// Prints `name value` for each measure, then writes the heatmap when asked.
pub fn run(args: &CompareArgs) -> Result<()> {
    let test = HdrImage::read(&args.test)?;
    let reference = HdrImage::read(&args.reference)?;
    let settings = CompareSettings {
        rel_mse_epsilon: args.epsilon,
        tonemapper: args.tonemapper,
        exposure: exposure_from_ev(args.exposure),
        ..CompareSettings::default()
    };
    let comparison = compare(&test, &reference, &settings)?;
    for (name, value) in comparison.metrics.named() {
        if name == "psnr_db" {
            println!("{name} {value:.3}");
        } else {
            println!("{name} {value:.6e}");
        }
    }
    if let Some(path) = &args.heatmap {
        write_heatmap(Path::new(path), &comparison)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}
