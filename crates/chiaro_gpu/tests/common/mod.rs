//! Helpers shared by the GPU tests.

use chiaro_gpu::{ContextError, GpuContext};

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
