//! Helpers shared by the GPU tests.

use chiaro_gpu::{ContextError, GpuContext};
use glam::Vec3;

/// A GPU context for a test, or `None` (after a message) when this machine has no adapter.
/// With the environment variable `CI` set, a missing or unusable adapter fails the test.
#[allow(dead_code)]
pub fn gpu() -> Option<GpuContext> {
    match GpuContext::new_headless() {
        Ok(context) => {
            eprintln!("GPU tests run on {}", context.describe());
            Some(context)
        }
        Err(e @ ContextError::NoAdapter { .. }) if std::env::var_os("CI").is_none() => {
            eprintln!("skipped: {e}");
            None
        }
        Err(e) => panic!("no usable GPU adapter: {e}"),
    }
}

/// relMSE as DESIGN.md defines it: mean((x - y)^2 / (y^2 + 0.01)) over pixels and channels.
#[allow(dead_code)]
pub fn rel_mse(x: &[Vec3], y: &[Vec3]) -> f64 {
    let sum: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| {
            let d = (*a - *b) * (*a - *b) / (*b * *b + Vec3::splat(0.01));
            f64::from(d.x + d.y + d.z)
        })
        .sum();
    sum / (3 * x.len()) as f64
}
