//! The command line refuses what means nothing, naming the argument; fails with exit 1 when it
//! cannot write its output; refuses a render over the memory limit before building anything;
//! and prints nothing about Wayland or its dependencies' sources on a machine without a display.

mod common;

use std::path::PathBuf;
use std::process::{Command, Output};

use common::{chiaro, gpu_missing};

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A scratch folder of the test's own.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("chiaro-cli-args-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Asserts that `args` fail, with a message naming `argument` and containing `words`.
fn refused(args: &[&str], argument: &str, words: &str) {
    let out = chiaro(args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(
        err.contains(argument) && err.contains(words),
        "{args:?}: {err}"
    );
}

#[test]
fn numbers_that_mean_nothing_are_refused_by_argument() {
    for bad in ["nan", "inf", "-1", "1e39"] {
        refused(
            &["info", "builtin:cornell", "--env-strength", bad],
            "--env-strength",
            bad,
        );
    }
    refused(
        &["render", "--frames", "0"],
        "--frames",
        "not in 1..=1000000",
    );
    for bad in ["0", "4"] {
        refused(
            &["render", "--frames-in-flight", bad],
            "--frames-in-flight",
            "not in 1..=3",
        );
    }
    refused(
        &["render", "--firefly-clamp", "nan"],
        "--firefly-clamp",
        "not a finite",
    );
    refused(
        &["reference", "builtin:cornell", "--threads", "100000"],
        "--threads",
        "1..=1024",
    );
    refused(
        &["render", "--memory-limit", "lots"],
        "--memory-limit",
        "not a size",
    );
    for bad in ["nan", "inf", "31", "-31"] {
        refused(
            &["compare", "a.exr", "b.exr", "--exposure", bad],
            "--exposure",
            bad,
        );
    }
    refused(
        &["render", "--exposure", "40"],
        "--exposure",
        "outside -30..=30",
    );
    refused(
        &["info", "builtin:cornell", "--light-units", "lumens"],
        "--light-units",
        "photometric, unitless",
    );
    refused(
        &["info", "builtin:cornell", "--env=1,nan,2"],
        "--env",
        "'nan' is not a finite",
    );
    refused(
        &["info", "builtin:cornell", "--env=-1,0,0"],
        "--env",
        "-1 is below 0",
    );
    refused(
        &["info", "builtin:cornell", "--env=1e39,0,0"],
        "--env",
        "not a finite number",
    );
}

/// An integrator is one the reference knows, and only the CPU reference takes one other than
/// pt (the GPU reference mode traces from the camera).
#[test]
fn integrators_are_named_and_belong_to_the_cpu_reference() {
    refused(
        &["reference", "builtin:cornell", "--integrator", "vcm"],
        "--integrator",
        "expected pt, ptlt, bdpt, mlt or mmlt",
    );
    let out = chiaro(&[
        "bench",
        "--scenes",
        "builtin:cornell",
        "--reference",
        "gpu",
        "--reference-integrator",
        "mlt",
    ]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("applies to the CPU reference"), "{err}");
}

#[test]
fn a_render_over_the_memory_limit_is_refused_with_both_figures() {
    let out = chiaro(&[
        "render",
        "builtin:instances?n=20000",
        "--memory-limit",
        "300M",
        "--out",
        "never.png",
    ]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("builtin:instances?n=20000: rendering it would take about")
            && err.contains("instances")
            && err.contains("more than the memory limit of 300.0 MiB"),
        "{err}"
    );
    assert!(!std::path::Path::new("never.png").exists());
}

#[test]
fn an_image_that_cannot_be_written_fails_the_command() {
    let dir = scratch("full");
    let full = dir.join("full.png");
    let _ = std::fs::remove_file(&full);
    // /dev/full takes the file open and refuses every write with ENOSPC, as a full disk does.
    std::os::unix::fs::symlink("/dev/full", &full).unwrap();
    let pixels = vec![glam::Vec3::splat(0.5); 16];
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    chiaro::reference::write_exr(&a, 4, 4, &pixels).unwrap();
    chiaro::reference::write_exr(&b, 4, 4, &pixels).unwrap();
    let heat = [
        "compare",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--heatmap",
    ];
    let out = chiaro(&[&heat[..], &[full.to_str().unwrap()]].concat());
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("full.png") && err.contains("No space left"),
        "{err}"
    );

    let out = chiaro(&[
        "render",
        "--size",
        "8x8",
        "--frames",
        "1",
        "--out",
        full.to_str().unwrap(),
    ]);
    if gpu_missing(&out) {
        return;
    }
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("full.png") && err.contains("No space left"),
        "{err}"
    );
    assert!(!String::from_utf8_lossy(&out.stdout).contains("wrote"));
}

#[test]
fn a_render_without_wayland_prints_no_wayland_error() {
    let out = Command::new(env!("CARGO_BIN_EXE_chiaro"))
        .args(["render", "--size", "8x8", "--frames", "1", "--out"])
        .arg(scratch("xdg").join("x.png"))
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("NODEVICE_SELECT")
        .output()
        .unwrap();
    if gpu_missing(&out) {
        return;
    }
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(!err.contains("XDG_RUNTIME_DIR"), "{err}");
}

#[test]
fn view_without_a_display_says_so_in_words() {
    let out = Command::new(env!("CARGO_BIN_EXE_chiaro"))
        .arg("view")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap();
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("no display to open a window on: set DISPLAY"),
        "{err}"
    );
    assert!(!err.contains(".rs:"), "{err}");
}
