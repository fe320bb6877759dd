//! `chiaro render` end to end: a PNG and an EXR of the Cornell box on the GPU (skipped with a
//! message when this machine has no GPU adapter, unless CI is set), and a clear error for a
//! bad output name.

mod common;

use common::{chiaro, gpu_missing};

#[test]
fn render_writes_png_and_exr() {
    let dir = std::env::temp_dir().join(format!("chiaro_cli_render_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("cornell.png");
    let out = chiaro(&[
        "render",
        "builtin:cornell",
        "--size",
        "24x16",
        "--frames",
        "6",
        "--frames-in-flight",
        "2",
        "--out",
        png.to_str().unwrap(),
    ]);
    if gpu_missing(&out) {
        return;
    }
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("24x16, 6 frames"), "{text}");
    assert!(text.contains("direct"), "{text}");
    // Throughput from the last three frames' starts; latency and submission as medians.
    let line = text
        .lines()
        .find(|l| l.starts_with("throughput "))
        .unwrap_or("");
    let number = |after: &str| -> f64 {
        let rest = &line[line.find(after).unwrap_or_else(|| panic!("{text}")) + after.len()..];
        rest.split_whitespace().next().unwrap().parse().unwrap()
    };
    assert!(number("throughput ") > 0.0, "{text}");
    assert!(number("latency ") > 0.0, "{text}");
    assert!(line.contains("frames in flight"), "{text}");
    let image = image::open(&png).unwrap().into_rgba8();
    assert_eq!(image.dimensions(), (24, 16));
    // The lit box is neither black nor white.
    let mean = image.pixels().map(|p| f64::from(p[0])).sum::<f64>() / (24.0 * 16.0);
    assert!(mean > 5.0 && mean < 250.0, "mean red {mean}");

    let exr = dir.join("cornell.exr");
    let out = chiaro(&[
        "render",
        "--size",
        "8x8",
        "--frames",
        "1",
        "--env",
        "0.5,0.5,0.5",
        "--out",
        exr.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let hdr = image::open(&exr).unwrap().into_rgb32f();
    assert_eq!(hdr.dimensions(), (8, 8));
    assert!(
        hdr.pixels()
            .all(|p| p.0.iter().all(|c| c.is_finite() && *c >= 0.0))
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_refuses_an_unknown_output_format() {
    let out = chiaro(&["render", "--size", "8x8", "--out", "image.bmp"]);
    assert!(!out.status.success());
    let text = String::from_utf8(out.stderr).unwrap();
    assert!(
        text.contains("image.bmp: the output must end in .png or .exr"),
        "{text}"
    );
}

#[test]
fn render_refuses_settings_out_of_range() {
    for (flag, value, name) in [("--spp", "0", "spp"), ("--bounces", "65", "bounces")] {
        let out = chiaro(&["render", "--size", "8x8", flag, value, "--out", "x.png"]);
        assert!(!out.status.success());
        let text = String::from_utf8_lossy(&out.stderr);
        assert!(
            text.contains(&format!("frame setting {name} = {value} is out of range")),
            "{text}"
        );
    }
}
