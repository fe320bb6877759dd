//! Helpers shared by the integration tests.

#![allow(dead_code)]

pub mod hand_made;
pub mod parity;

use std::path::PathBuf;

/// The shared folder beside the checkout; fails with a clear message when it is absent.
pub fn shared_dir(sub: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("shared")
        .join(sub);
    assert!(
        dir.is_dir(),
        "{} is missing: this test needs the shared test data folder (../shared/{sub}) beside the checkout",
        dir.display()
    );
    dir
}

/// The JSON of a .gltf or .glb file, parsed independently of chiaro.
pub fn gltf_json(bytes: &[u8]) -> serde_json::Value {
    if bytes.starts_with(b"glTF") {
        let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        assert_eq!(&bytes[16..20], b"JSON");
        serde_json::from_slice(&bytes[20..20 + len]).unwrap()
    } else {
        serde_json::from_slice(bytes).unwrap()
    }
}

/// Runs the chiaro binary with `args`.
pub fn chiaro(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_chiaro"))
        .args(args)
        .output()
        .expect("the chiaro binary runs")
}

/// True (with a message) when the command failed for want of a GPU adapter; with `CI` set
/// that is a failure instead.
pub fn gpu_missing(out: &std::process::Output) -> bool {
    let text = String::from_utf8_lossy(&out.stderr);
    let missing = !out.status.success() && text.contains("no GPU adapter found");
    if missing {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI has no GPU adapter: {text}"
        );
        eprintln!("skipped: {text}");
    }
    missing
}

/// A GPU context for a test, or `None` (after a message) when this machine has no adapter.
/// With the environment variable `CI` set, a missing or unusable adapter fails the test.
pub fn gpu() -> Option<chiaro::gpu::GpuContext> {
    use chiaro::gpu::{ContextError, GpuContext};
    match GpuContext::new_headless() {
        Ok(context) => Some(context),
        Err(e @ ContextError::NoAdapter { .. }) if std::env::var_os("CI").is_none() => {
            eprintln!("skipped: {e}");
            None
        }
        Err(e) => panic!("no usable GPU adapter: {e}"),
    }
}
