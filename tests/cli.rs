//! The `chiaro` binary end to end: `info` and `reference` on built-in scenes, and a clear error
//! with a non-zero exit on bad input.

use std::process::Command;

fn chiaro(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_chiaro"))
        .args(args)
        .output()
        .expect("the chiaro binary runs")
}

#[test]
fn info_prints_the_scene_summary() {
    let out = chiaro(&["info", "builtin:cornell"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("meshes: 8 (32 triangles stored)"), "{text}");
    assert!(text.contains("emissive triangles: 2"), "{text}");
}

#[test]
fn info_takes_a_constant_environment() {
    let out = chiaro(&[
        "info",
        "builtin:cornell",
        "--env",
        "0.1,0.2,0.3",
        "--env-strength",
        "2",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("environment: constant (0.100, 0.200, 0.300), strength 2"),
        "{text}"
    );
}

#[test]
fn reference_writes_exr_png_and_half() {
    let dir = std::env::temp_dir().join(format!("chiaro-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let exr = dir.join("furnace.exr");
    let out = chiaro(&[
        "reference",
        "builtin:furnace",
        "--size",
        "8x6",
        "--spp",
        "4",
        "--out",
        exr.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (w, h, pixels) = chiaro::reference::read_exr(&exr).unwrap();
    assert_eq!((w, h), (8, 6));
    let mean = pixels.iter().map(|p| p.x).sum::<f32>() / pixels.len() as f32;
    assert!((mean - 1.0).abs() < 0.2, "{mean}");
    assert!(dir.join("furnace.png").is_file() && dir.join("furnace.half.exr").is_file());
}

#[test]
fn bad_scene_fails_with_a_message_naming_it() {
    let out = chiaro(&["info", "/no/such/model.glb"]);
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("/no/such/model.glb: cannot read it"), "{err}");
    let out = chiaro(&["reference", "builtin:cornell", "--size", "0x4"]);
    assert!(!out.status.success());
}
