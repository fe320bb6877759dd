//! The `chiaro` binary end to end: `info` and `reference` on built-in scenes, a clear error
//! with a non-zero exit on bad input, and no panic when its output's reader has gone.

mod common;

use common::chiaro;

#[test]
fn info_prints_the_scene_summary() {
    let out = chiaro(&["info", "builtin:cornell"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("meshes: 8 (32 triangles stored)"), "{text}");
    assert!(text.contains("emissive triangles: 2"), "{text}");
    assert!(text.contains("features: emissive triangles\n"), "{text}");
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

#[test]
fn compare_prints_each_measure_and_writes_a_heatmap() {
    let dir = std::env::temp_dir().join(format!("chiaro-cli-compare-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (reference, test, heatmap) = (
        dir.join("reference.exr"),
        dir.join("test.exr"),
        dir.join("heat.png"),
    );
    let reference_pixels: Vec<glam::Vec3> = (0..48)
        .map(|i| glam::Vec3::new(i as f32 / 47.0, 0.3, 2.0))
        .collect();
    let test_pixels: Vec<glam::Vec3> = reference_pixels
        .iter()
        .enumerate()
        .map(|(i, p)| *p * if i % 3 == 0 { 1.2 } else { 0.9 })
        .collect();
    chiaro::reference::write_exr(&reference, 8, 6, &reference_pixels).unwrap();
    chiaro::reference::write_exr(&test, 8, 6, &test_pixels).unwrap();
    let out = chiaro(&[
        "compare",
        test.to_str().unwrap(),
        reference.to_str().unwrap(),
        "--heatmap",
        heatmap.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let value = |name: &str| -> f64 {
        text.lines()
            .find_map(|l| l.strip_prefix(name)?.strip_prefix(' '))
            .unwrap_or_else(|| panic!("no {name} line in {text}"))
            .parse()
            .unwrap()
    };
    let expected = chiaro::eval::metrics::rel_mse(&test_pixels, &reference_pixels, 0.01);
    assert!((value("relmse") / expected - 1.0).abs() < 1e-5, "{text}");
    assert!(value("smape") > 0.0 && value("flip_mean") > 0.0, "{text}");
    assert!(value("psnr_db").is_finite(), "{text}");
    assert_eq!(
        image::open(&heatmap).unwrap().into_rgb8().dimensions(),
        (8, 6)
    );

    let missing = dir.join("missing.exr");
    let out = chiaro(&[
        "compare",
        missing.to_str().unwrap(),
        reference.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("missing.exr"), "{err}");
}

/// Output into a pipe whose reader has closed (`chiaro info ... | head -0`) ends the program
/// without a panic (by SIGPIPE on Unix, as other command-line tools end).
#[test]
fn a_closed_output_pipe_ends_the_program_without_a_panic() {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_chiaro"))
        .args(["info", "builtin:cornell"])
        .stdout(writer)
        .stderr(std::process::Stdio::piped())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        !out.status.success(),
        "nothing was written, yet it exited 0"
    );
}

/// `--exposure STOPS` scales what the tonemapper reads by 2^STOPS: the reference's PNG at +1
/// stop is the tonemapped image of twice the linear radiance, while its EXR (linear radiance)
/// is the one of exposure 0, bit for bit; `compare --exposure` moves PSNR, not relMSE.
#[test]
fn exposure_in_stops_brightens_the_png_not_the_exr() {
    use chiaro::shading::color::linear_to_srgb;
    use chiaro::shading::tonemap::Tonemapper;
    let dir = std::env::temp_dir().join(format!("chiaro-cli-exposure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let render = |stops: &str| {
        let exr = dir.join(format!("cornell{stops}.exr"));
        let out = chiaro(&[
            "reference",
            "builtin:cornell",
            "--size",
            "12x12",
            "--spp",
            "2",
            "--exposure",
            stops,
            "--out",
            exr.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (_, _, linear) = chiaro::reference::read_exr(&exr).unwrap();
        let png = image::open(exr.with_extension("png")).unwrap().into_rgb8();
        (exr, linear, png.into_raw())
    };
    let (plain_exr, plain, plain_png) = render("0");
    let (_, bright, bright_png) = render("1");
    assert!(plain == bright, "the exposure changed the EXR");
    let expected: Vec<u8> = plain
        .iter()
        .flat_map(|p| Tonemapper::PbrNeutral.apply(*p * 2.0, 1.0).to_array())
        .map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8)
        .collect();
    assert_eq!(bright_png, expected, "+1 stop is not twice the radiance");
    assert_ne!(bright_png, plain_png, "+1 stop changed nothing");

    let measure = |stops: &str| {
        let half = plain_exr.with_extension("half.exr");
        let args = [
            "compare",
            plain_exr.to_str().unwrap(),
            half.to_str().unwrap(),
            "--exposure",
            stops,
        ];
        let out = chiaro(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        let value = |name: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(name)?.strip_prefix(' ')?.parse::<f64>().ok())
                .unwrap_or_else(|| panic!("no {name} in {text}"))
        };
        (value("relmse"), value("psnr_db"))
    };
    let (rel_plain, psnr_plain) = measure("0");
    let (rel_dark, psnr_dark) = measure("-3");
    assert_eq!(rel_plain, rel_dark, "relMSE moved with the exposure");
    assert_ne!(psnr_plain, psnr_dark, "PSNR ignored the exposure");
}
