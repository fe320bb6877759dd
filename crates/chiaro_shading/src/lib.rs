//! chiaro's shading model in plain Rust (glam only, no ECS, no GPU).
//!
//! This crate is the spec that the WGSL in `shaders/lib/` mirrors function for function: the CPU
//! reference path tracer and the GPU passes shade with exactly these formulas, so a parity test can
//! run both on the same random inputs and compare.
//!
//! - [`color`]: the sRGB transfer functions and luminance.
//! - [`rng`]: PCG32, the random stream both sides draw from.
//! - [`owen_sobol`]: Owen-scrambled Sobol points, the quasi-random draws of the references.
//! - [`frame`]: the local shading frame (z = normal).
//! - [`sampling`]: warps from uniform numbers to directions and points; the power heuristic.
//! - [`distribution`]: discrete 1D and 2D distributions (light selection, environment texels).
//! - [`ggx`]: the GGX microfacet distribution, Smith masking-shadowing, visible-normal sampling.
//! - [`brdf`]: the glTF metallic-roughness BRDF with its extensions' layers: `eval`, `pdf`,
//!   `sample`.
//! - [`sheen`]: KHR_materials_sheen's sheen lobe and albedo scaling, layered by the BRDF.
//! - [`shading_normal`]: shading normals turned back where the view's mirror reflection would
//!   leave below the surface.
//! - [`lights`]: point, spot, directional, triangle and environment lights: sampling and pdfs.
//! - [`light_tree`]: a light tree choosing among many lights by their importance to a point.
//! - [`reservoir`]: weighted reservoir sampling, resampled importance sampling and its reuse
//!   (ReSTIR).
//! - [`tonemap`]: ACES (fitted), Khronos PBR Neutral, clamp.
//!
//! Conventions: directions are unit vectors pointing away from the surface; BRDF functions work in
//! the local frame of [`frame::Frame`], light functions in world space. Every sampling function
//! takes its uniform random numbers as arguments. Hard cases (grazing angles, zero roughness,
//! degenerate lights) have defined, finite answers, documented where they are made.
//!
//! ```
//! use chiaro_shading::brdf::{self, SurfaceParams};
//! use chiaro_shading::color::{linear_to_srgb, luminance, srgb_to_linear};
//! use chiaro_shading::frame::Frame;
//! use chiaro_shading::rng::Pcg32;
//! use glam::Vec3;
//!
//! let grey = srgb_to_linear(0.5);
//! assert!((linear_to_srgb(grey) - 0.5).abs() < 1e-6);
//! assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
//!
//! // Shade a rough gold-ish metal seen at 60 degrees from the normal.
//! let params = SurfaceParams {
//!     base_color: Vec3::new(1.0, 0.8, 0.3),
//!     metallic: 1.0,
//!     roughness: 0.4,
//!     ..SurfaceParams::default()
//! };
//! let normal = Vec3::new(0.0, 1.0, 0.0);
//! let frame = Frame::from_normal(normal);
//! let to_viewer = Vec3::new(0.866, 0.5, 0.0);
//! let wo = frame.to_local(to_viewer);
//! let mut rng = Pcg32::new(1, 0);
//! if let Some(s) = brdf::sample(&params, wo, rng.next_f32(), rng.next_vec2()) {
//!     let wi_world = frame.to_world(s.wi);
//!     assert!(wi_world.dot(normal) > 0.0);
//!     assert!(s.weight.is_finite() && s.pdf > 0.0);
//! }
//! ```

#![warn(missing_docs)]

pub mod brdf;
pub mod color;
pub mod coverage;
pub mod distribution;
pub mod frame;
pub mod ggx;
pub mod light_tree;
pub mod lights;
pub mod owen_sobol;
pub mod reservoir;
pub mod rng;
pub mod sampling;
pub mod shading_normal;
pub mod sheen;
pub mod tonemap;

#[cfg(test)]
mod test_util;
