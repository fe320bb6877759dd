//! chiaro's image metrics: how far an image is from a reference, by relMSE and SMAPE on linear
//! HDR and by PSNR and FLIP on what a viewer sees, plus a per-pixel error heatmap. The measures
//! and their parameters are documented in [`metrics`]. [`bench`](mod@bench) weighs the GPU
//! frame's configurations by speed against error.
//!
//! ```
//! use chiaro_eval::{CompareSettings, HdrImage, compare};
//! use glam::Vec3;
//!
//! let reference = HdrImage::new("reference", 8, 8, vec![Vec3::splat(0.5); 64]).unwrap();
//! let test = HdrImage::new("test", 8, 8, vec![Vec3::splat(0.55); 64]).unwrap();
//! let metrics = compare(&test, &reference, &CompareSettings::default()).unwrap().metrics;
//! assert!((metrics.rel_mse - 0.05f64.powi(2) / (0.25 + 0.01)).abs() < 1e-6);
//! ```

#![warn(missing_docs)]

pub mod bench;
mod error;
mod hdr_image;
mod heatmap;
pub mod metrics;

pub use error::EvalError;
pub use hdr_image::HdrImage;
pub use heatmap::write_heatmap;
pub use metrics::{CompareSettings, Comparison, Metrics, compare};
