//! chiaro's shading model in plain Rust (glam only, no ECS, no GPU).
//!
//! This crate is the spec that the WGSL in `shaders/lib/` mirrors. It starts with colour: the
//! sRGB transfer functions and luminance used by every other crate.
//!
//! ```
//! use chiaro_shading::color::{linear_to_srgb, luminance, srgb_to_linear};
//! use glam::Vec3;
//!
//! let grey = srgb_to_linear(0.5);
//! assert!((linear_to_srgb(grey) - 0.5).abs() < 1e-6);
//! assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
//! ```

pub mod color;
