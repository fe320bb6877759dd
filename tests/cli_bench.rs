//! `chiaro bench` end to end on a tiny image: every output is written, the figures are
//! finite and complete, the reference is cached and read back on a second run, and bad
//! settings are refused with a clear error. Skipped with a message when this machine has no
//! GPU adapter, unless CI is set.

use std::path::Path;
mod common;

use common::{chiaro, gpu_missing};

use serde_json::Value;

/// `chiaro bench` on the Cornell box at `size` into `dir`, without warm-up, with `extra`.
fn tiny_bench(dir: &Path, size: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "bench",
        "--scenes",
        "builtin:cornell",
        "--size",
        size,
        "--warmup",
        "0",
        "--out",
        dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    chiaro(&args)
}

fn bench(dir: &Path) -> std::process::Output {
    tiny_bench(
        dir,
        "16x12",
        &["--reference-spp", "8", "--checkpoints", "1,2,4"],
    )
}

fn results(dir: &Path) -> Value {
    let text = std::fs::read_to_string(dir.join("results.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn bench_writes_results_table_and_plot_and_caches_the_reference() {
    let dir = std::env::temp_dir().join(format!("chiaro_cli_bench_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let out = bench(&dir);
    if gpu_missing(&out) {
        return;
    }
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let first = results(&dir);
    assert_eq!(
        (first["width"].as_u64(), first["height"].as_u64()),
        (Some(16), Some(12))
    );
    assert!(!first["adapter"].as_str().unwrap().is_empty());
    let scenes = first["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 1);
    let scene = &scenes[0];
    assert_eq!(scene["scene"], "builtin:cornell");
    assert!(scene["reference_seconds"].as_f64().unwrap() > 0.0);
    let runs = scene["runs"].as_array().unwrap();
    let names: Vec<&str> = runs.iter().map(|r| r["config"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "direct",
            "realtime",
            "realtime-no-denoise",
            "realtime-spp2",
            "realtime-spp4",
            "realtime-bounces1",
            "realtime-bounces2",
            "naive",
            "reference",
            "realtime-path",
        ]
    );
    // One converged reference: the camera path comes back to the camera's pose at each
    // checkpoint and is measured against it.
    let cached = std::fs::read_dir(dir.join("cache"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "exr")
        })
        .count();
    assert_eq!(cached, 1);
    for run in runs {
        assert!(run["median_frame_ms"].as_f64().unwrap() > 0.0, "{run}");
        assert!(!run["pass_ms"].as_array().unwrap().is_empty(), "{run}");
        let frames: Vec<u64> = run["checkpoints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["frames"].as_u64().unwrap())
            .collect();
        assert_eq!(frames, [1, 2, 4], "{run}");
        let mut previous_seconds = 0.0;
        for c in run["checkpoints"].as_array().unwrap() {
            let rel_mse = c["rel_mse"].as_f64().unwrap();
            let flip = c["flip_mean"].as_f64().unwrap();
            let seconds = c["seconds"].as_f64().unwrap();
            assert!(rel_mse.is_finite() && rel_mse > 0.0, "{c}");
            assert!((0.0..=1.0).contains(&flip), "{c}");
            assert!(seconds > previous_seconds, "{c}");
            previous_seconds = seconds;
        }
        let table = std::fs::read_to_string(dir.join("results.md")).unwrap();
        let row = format!("| {} |", run["config"].as_str().unwrap());
        assert!(table.contains(&row), "{table}");
    }
    let plot = dir.join("error_vs_time_0.png");
    if Path::new("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf").exists() {
        let image = image::open(&plot).unwrap();
        assert_eq!((image.width(), image.height()), (900, 600));
    }

    // The second run reads the reference from the cache.
    let out = bench(&dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let second = results(&dir);
    assert_eq!(second["scenes"][0]["reference_seconds"].as_f64(), Some(0.0));
    assert_eq!(
        second["scenes"][0]["reference_noise"],
        first["scenes"][0]["reference_noise"]
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bench_refuses_checkpoints_out_of_order() {
    let dir = std::env::temp_dir().join(format!("chiaro_cli_bench_bad_{}", std::process::id()));
    let out = chiaro(&[
        "bench",
        "--scenes",
        "builtin:cornell",
        "--checkpoints",
        "4,1",
        "--out",
        dir.to_str().unwrap(),
    ]);
    if gpu_missing(&out) {
        return;
    }
    assert!(!out.status.success());
    let text = String::from_utf8(out.stderr).unwrap();
    assert!(
        text.contains("checkpoints [4, 1] must be a non-empty increasing list"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The one converged reference a bench run in `dir` cached.
fn cached_reference(dir: &Path) -> Vec<glam::Vec3> {
    let exr = std::fs::read_dir(dir.join("cache"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "exr"))
        .unwrap();
    chiaro::reference::read_exr(&exr).unwrap().2
}

#[test]
fn a_gpu_drawn_reference_agrees_with_the_cpu_reference_to_their_noise() {
    let run = |drawn_by: &str| {
        let dir = std::env::temp_dir().join(format!(
            "chiaro_cli_bench_{drawn_by}_ref_{}",
            std::process::id()
        ));
        std::fs::remove_dir_all(&dir).ok();
        // Pixels small enough that edges are few: at 16x12 and 64 spp the two references
        // differed by 3.6 times the sum of their noise (the renderers' sub-pixel positions, most
        // likely, in pixels that are mostly edge), at 48x36 and 256 spp by 0.94 times.
        let out = tiny_bench(
            &dir,
            "48x36",
            &[
                "--reference-spp",
                "256",
                "--reference",
                drawn_by,
                "--configs",
                "reference",
                "--no-camera-path",
                "--checkpoints",
                "1,4",
            ],
        );
        (dir, out)
    };
    let (cpu_dir, out) = run("cpu");
    if gpu_missing(&out) {
        return;
    }
    let (gpu_dir, gpu_out) = run("gpu");
    for out in [&out, &gpu_out] {
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let (cpu, gpu) = (results(&cpu_dir), results(&gpu_dir));
    assert_eq!(cpu["reference_renderer"], "CPU reference");
    assert_eq!(gpu["reference_renderer"], "GPU reference mode");
    let noise = |r: &Value| r["scenes"][0]["reference_noise"].as_f64().unwrap();
    let (cpu_noise, gpu_noise) = (noise(&cpu), noise(&gpu));
    assert!(gpu_noise > 0.0 && gpu_noise.is_finite(), "{gpu}");
    // Two estimates of the same image at the same sample count: noise of the same size.
    assert!(
        (0.25..4.0).contains(&(gpu_noise / cpu_noise)),
        "GPU reference noise {gpu_noise:.3e} against the CPU's {cpu_noise:.3e}"
    );
    // Independent estimates of the same image differ by about the sum of their noise; a bias
    // of either would add to it.
    let between = chiaro::eval::metrics::rel_mse(
        &cached_reference(&gpu_dir),
        &cached_reference(&cpu_dir),
        0.01,
    );
    assert!(
        between < 3.0 * (cpu_noise + gpu_noise),
        "relMSE {between:.3e} between the GPU and CPU references, noise {cpu_noise:.3e} and \
         {gpu_noise:.3e}"
    );
    // The GPU reference mode's own run draws other random numbers than the reference's.
    let first = gpu["scenes"][0]["runs"][0]["checkpoints"][0]["rel_mse"]
        .as_f64()
        .unwrap();
    assert!(first > gpu_noise, "{gpu}");
    for dir in [cpu_dir, gpu_dir] {
        std::fs::remove_dir_all(&dir).ok();
    }
}
