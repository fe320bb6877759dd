//! `chiaro view` end to end: the window runs on an X server of its own (Xvfb, started here on a
//! free display), replays a script and exits; its screenshots are checked against headless
//! renders. Without Xvfb the tests print why they are skipped, unless `CI` is set (then that is
//! a failure). Without a GPU adapter (lavapipe counts) they are skipped likewise.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use chiaro::eval::metrics::rel_mse;
use chiaro::reference::read_exr;
use common::chiaro;

/// An Xvfb server, stopped when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

impl Drop for Xvfb {
    /// Stops the server with SIGTERM, so that it removes its socket and lock file (SIGKILL
    /// would leave them behind), and with SIGKILL if it has not stopped within 5 s.
    fn drop(&mut self) {
        let terminated = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status()
            .is_ok_and(|s| s.success());
        if terminated {
            let start = Instant::now();
            while start.elapsed() < Duration::from_secs(5) {
                if let Ok(Some(_)) = self.child.try_wait() {
                    return;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

static NEXT_DISPLAY: AtomicU32 = AtomicU32::new(0);

/// Starts Xvfb on a free display and waits for its socket; `None` (after a message) when Xvfb
/// is not installed and `CI` is not set.
fn xvfb() -> Option<Xvfb> {
    let base = 200 + (std::process::id() % 400) * 8;
    for _ in 0..16 {
        let n = base + NEXT_DISPLAY.fetch_add(1, Ordering::Relaxed);
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        if socket.exists() || Path::new(&format!("/tmp/.X{n}-lock")).exists() {
            continue;
        }
        let spawned = Command::new("Xvfb")
            .args([
                &format!(":{n}"),
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn();
        let mut child = match spawned {
            Ok(child) => child,
            Err(e) if std::env::var_os("CI").is_none() => {
                eprintln!("skipped: cannot start Xvfb ({e}); install the xvfb package");
                return None;
            }
            Err(e) => panic!("CI needs Xvfb for the viewer tests: {e}"),
        };
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(20) {
            if socket.exists() {
                return Some(Xvfb {
                    child,
                    display: format!(":{n}"),
                });
            }
            if let Ok(Some(_)) = child.try_wait() {
                break; // the display was taken meanwhile: try the next one
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = child.kill();
        let _ = child.wait();
    }
    panic!("Xvfb did not start on any of 16 displays from :{base}");
}

/// Runs `chiaro view` on `x` with `args`; `None` (after a message) when no adapter can present
/// to the window and `CI` is not set.
fn view(x: &Xvfb, args: &[&str]) -> Option<Output> {
    let out = Command::new(env!("CARGO_BIN_EXE_chiaro"))
        .arg("view")
        .args(args)
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the chiaro binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() && stderr.contains("no adapter on") {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI has no adapter: {stderr}"
        );
        eprintln!("skipped: {stderr}");
        return None;
    }
    assert!(out.status.success(), "chiaro view failed: {stderr}");
    Some(out)
}

/// `chiaro render ARGS --out OUT` (an .exr), which must succeed, and the image it wrote.
fn headless_render(args: &[&str], out: &Path) -> Vec<glam::Vec3> {
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend(["--out", out.to_str().unwrap()]);
    let render = chiaro(&all);
    assert!(
        render.status.success(),
        "{}",
        String::from_utf8_lossy(&render.stderr)
    );
    read_exr(out).unwrap().2
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("chiaro_viewer_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Mean and share of non-black pixels of an 8-bit image's RGB, and its size.
fn png_stats(path: &Path) -> (f64, f64, (u32, u32)) {
    let image = image::open(path).unwrap().into_rgb8();
    let count = f64::from(image.width() * image.height());
    let mean = image
        .pixels()
        .map(|p| p.0.iter().map(|&c| f64::from(c)).sum::<f64>() / 3.0)
        .sum::<f64>()
        / count;
    let lit = image
        .pixels()
        .filter(|p| p.0.iter().any(|&c| c > 8))
        .count() as f64
        / count;
    (mean, lit, image.dimensions())
}

/// Mean absolute difference of two same-size 8-bit images, over pixels and RGB.
fn mean_abs_diff(a: &Path, b: &Path) -> f64 {
    let (a, b) = (
        image::open(a).unwrap().into_rgb8(),
        image::open(b).unwrap().into_rgb8(),
    );
    assert_eq!(a.dimensions(), b.dimensions());
    let sum: f64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(&x, &y)| f64::from(x.abs_diff(y)))
        .sum();
    sum / a.as_raw().len() as f64
}

/// The window's frame after 8 frames of builtin:cornell (panel hidden, 96x96) is the headless
/// render from the same camera with the same settings, seed and frame count: relMSE (linear
/// HDR, epsilon 0.01) must stay under 1e-3; measured 0.0 on lavapipe (the same passes on the same
/// device give the same bits). Holding W for 4 frames then moves the camera through its
/// `Transform`: the image must change (relMSE against the still view above 1e-2; measured
/// 2.2e1: the walk goes well into the box). A scripted resize remakes the frame at the new size.
#[test]
fn scripted_window_matches_the_headless_render() {
    let Some(x) = xvfb() else { return };
    let dir = temp_dir("match");
    let (still, moved, png) = (
        dir.join("still.exr"),
        dir.join("moved.exr"),
        dir.join("end.png"),
    );
    let script = dir.join("script.txt");
    std::fs::write(
        &script,
        format!(
            "panel off\nframes 8\nscreenshot {}\nkey W 4\nscreenshot {}\nresize 72 72\nframes 1\n",
            still.display(),
            moved.display()
        ),
    )
    .unwrap();
    let Some(out) = view(
        &x,
        &[
            "builtin:cornell",
            "--size",
            "96x96",
            "--script",
            script.to_str().unwrap(),
            "--screenshot",
            png.to_str().unwrap(),
        ],
    ) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("still.exr (96x96)"), "{stdout}");

    let reference = headless_render(
        &["builtin:cornell", "--size", "96x96", "--frames", "8"],
        &dir.join("headless.exr"),
    );
    let (w, h, window) = read_exr(&still).unwrap();
    assert_eq!((w, h), (96, 96));
    let error = rel_mse(&window, &reference, 0.01);
    eprintln!("window against headless: relMSE {error:.3e}");
    assert!(error < 1e-3, "relMSE {error}");

    let (_, _, walked) = read_exr(&moved).unwrap();
    let change = rel_mse(&walked, &window, 0.01);
    eprintln!("after W: relMSE against the still view {change:.3e}");
    assert!(change > 1e-2, "holding W did not move the camera: {change}");

    // The 8-bit screenshot at the end, after a resize, is the lit box at the new size, not a
    // blank image.
    let (mean, lit, size) = png_stats(&png);
    assert_eq!(size, (72, 72));
    assert!(mean > 10.0 && lit > 0.9, "mean {mean}, lit share {lit}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Dropping a broken .glb keeps the scene: the viewer exits 0, prints the error naming the
/// file, and the frame after the drop is the scene before it (panel shown, so the frame is the
/// window's width less the panel's): mean absolute 8-bit difference under 4; measured 0.39
/// (two more frames of temporal accumulation).
#[test]
fn a_broken_dropped_file_keeps_the_scene() {
    let Some(x) = xvfb() else { return };
    let dir = temp_dir("drop");
    let broken = dir.join("broken.glb");
    std::fs::write(&broken, b"glTF\x02\x00\x00\x00garbage").unwrap();
    let (before, after) = (dir.join("before.png"), dir.join("after.png"));
    let script = dir.join("script.txt");
    std::fs::write(
        &script,
        format!(
            "frames 6\nscreenshot {}\ndrop {}\nframes 2\nscreenshot {}\n",
            before.display(),
            broken.display(),
            after.display()
        ),
    )
    .unwrap();
    let Some(out) = view(
        &x,
        &[
            "builtin:cornell",
            "--size",
            "360x100",
            "--script",
            script.to_str().unwrap(),
        ],
    ) else {
        return;
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("cannot load") && stderr.contains("broken.glb"),
        "{stderr}"
    );
    let (mean, lit, size) = png_stats(&after);
    assert!(size.0 > 16 && size.0 < 360 && size.1 == 100, "{size:?}");
    assert!(mean > 10.0 && lit > 0.9, "mean {mean}, lit share {lit}");
    let diff = mean_abs_diff(&before, &after);
    eprintln!("after the broken drop: mean absolute difference {diff:.2}");
    assert!(diff < 4.0, "the scene changed: {diff}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A bad script line is refused before any window opens, naming the line.
#[test]
fn a_bad_script_is_refused_naming_the_line() {
    let dir = temp_dir("bad_script");
    let script = dir.join("script.txt");
    std::fs::write(&script, "frames 2\nwalk 3\n").unwrap();
    let out = chiaro(&["view", "--script", script.to_str().unwrap()]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("script line 2") && stderr.contains("walk"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Dropping a .glb and then an .hdr replaces the scene and its environment: the window's frame
/// (nothing rendered before the drops) is the headless render of that file under that
/// environment at the same size and frame count: relMSE (linear HDR, epsilon 0.01) under 1e-3;
/// measured 0.0 on lavapipe.
#[test]
fn dropped_scene_and_environment_render_like_the_cli() {
    let Some(x) = xvfb() else { return };
    let scenes = common::shared_dir("scenes");
    let (glb, hdr) = (
        scenes.join("SimpleInstancing.glb"),
        scenes.join("qwantani_afternoon_puresky_1k.hdr"),
    );
    let dir = temp_dir("dropped");
    let shot = dir.join("dropped.exr");
    let script = dir.join("script.txt");
    std::fs::write(
        &script,
        format!(
            "panel off\ndrop {}\ndrop {}\nframes 4\nscreenshot {}\n",
            glb.display(),
            hdr.display(),
            shot.display()
        ),
    )
    .unwrap();
    let size = ["--size", "64x48"];
    let Some(_) = view(
        &x,
        &[
            "builtin:cornell",
            size[0],
            size[1],
            "--script",
            script.to_str().unwrap(),
        ],
    ) else {
        return;
    };
    let reference = headless_render(
        &[
            glb.to_str().unwrap(),
            "--env",
            hdr.to_str().unwrap(),
            size[0],
            size[1],
            "--frames",
            "4",
        ],
        &dir.join("headless.exr"),
    );
    let (w, h, window) = read_exr(&shot).unwrap();
    assert_eq!((w, h), (64, 48));
    let error = rel_mse(&window, &reference, 0.01);
    eprintln!("dropped scene against headless: relMSE {error:.3e}");
    assert!(error < 1e-3, "relMSE {error}");
    let mean = window.iter().map(|p| p.element_sum()).sum::<f32>() / window.len() as f32;
    assert!(mean > 0.05, "the dropped scene is dark: mean {mean}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The debug views show the G-buffer: in the albedo view (8-bit sRGB) the Cornell box's left
/// wall is red and its right wall green, the dominant channel ahead of the others by over 50
/// (measured: left (208, 72, 63), right (105, 179, 85)); in the normal view their normals are
/// opposite (red channels sum to 255 within 4: measured 255); the instance view colours the two
/// walls differently; after 4 frames of a still camera the history view reads a history of 4
/// frames (within 0.5: measured 4.02, i.e. 8-bit grey 32); the filtered lighting of the back
/// wall is lit; the frame view is the tonemapped frame again.
#[test]
fn debug_views_show_the_gbuffer() {
    let Some(x) = xvfb() else { return };
    let dir = temp_dir("debug_views");
    let shot = |view: &str| dir.join(format!("{view}.png"));
    let mut script = format!(
        "panel off\nframes 1\nview history\nframes 3\nscreenshot {}\n",
        shot("history").display()
    );
    for view in ["albedo", "normal", "instances", "filtered", "frame"] {
        script += &format!(
            "view {view}\nframes 1\nscreenshot {}\n",
            shot(view).display()
        );
    }
    let path = dir.join("script.txt");
    std::fs::write(&path, script).unwrap();
    let args = ["--size", "48x48", "--script", path.to_str().unwrap()];
    let Some(_) = view(&x, &args) else { return };
    let pixel = |view: &str, x: u32, y: u32| {
        let image = image::open(shot(view)).unwrap().into_rgb8();
        assert_eq!(image.dimensions(), (48, 48));
        image.get_pixel(x, y).0.map(i32::from)
    };
    let (left, right) = ((2, 20), (45, 20));
    let [r, g, b] = pixel("albedo", left.0, left.1);
    eprintln!("left wall albedo {:?}", [r, g, b]);
    assert!(r > g + 50 && r > b + 50, "left wall albedo {:?}", [r, g, b]);
    let [r, g, b] = pixel("albedo", right.0, right.1);
    eprintln!("right wall albedo {:?}", [r, g, b]);
    assert!(
        g > r + 50 && g > b + 50,
        "right wall albedo {:?}",
        [r, g, b]
    );
    let (nl, nr) = (
        pixel("normal", left.0, left.1),
        pixel("normal", right.0, right.1),
    );
    eprintln!("wall normals {nl:?} {nr:?}");
    assert!((nl[0] + nr[0] - 255).abs() <= 4, "normals {nl:?} {nr:?}");
    assert_ne!(
        pixel("instances", left.0, left.1),
        pixel("instances", right.0, right.1)
    );
    // Four frames of a still camera: a history of 4 frames on the back wall (grey = length / 32).
    let history = f64::from(pixel("history", 24, 10)[0]) * 32.0 / 255.0;
    eprintln!("history length {history}");
    assert!((history - 4.0).abs() < 0.5, "history length {history}");
    // The filtered lighting of the lit back wall is not black.
    let filtered = pixel("filtered", 24, 10);
    assert!(
        filtered.iter().all(|&c| c > 20),
        "filtered lighting {filtered:?}"
    );
    let frame = pixel("frame", left.0, left.1);
    assert!(
        frame[0] > frame[1],
        "the frame's left wall is red: {frame:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The traversal view is a heatmap of BVH steps (TLAS nodes + BLAS nodes entered + triangles
/// tested) along each pixel's camera ray, read back here through the viewer's own colour map
/// (nearest of its colours at 0..=MAX_STEPS steps). On builtin:cornell at 48x48: the ray through
/// the left column leaves the scene (0 steps, measured 0); the plain back wall takes a few
/// (measured 9, asserted 1 to 12); rays onto the boxes, where box and wall bounds overlap, take
/// more: pixel (21, 33) more than the wall (measured 16), pixel (15, 24) over 4 more (measured
/// 17). Not blank: over 80% of the pixels take a step or more (measured 91.8%).
#[test]
fn the_traversal_view_is_a_heatmap_of_bvh_steps() {
    use chiaro_viewer::traversal_view::{MAX_STEPS, heat_colour};

    let Some(x) = xvfb() else { return };
    let dir = temp_dir("traversal");
    let shot = dir.join("traversal.png");
    let script = format!(
        "panel off\nframes 1\nview traversal\nframes 1\nscreenshot {}\n",
        shot.display()
    );
    let path = dir.join("script.txt");
    std::fs::write(&path, script).unwrap();
    let args = ["--size", "48x48", "--script", path.to_str().unwrap()];
    let Some(_) = view(&x, &args) else { return };
    let image = image::open(&shot).unwrap().into_rgb8();
    assert_eq!(image.dimensions(), (48, 48));
    let colours: Vec<[f32; 3]> = (0..=MAX_STEPS)
        .map(|s| heat_colour(s as f32 / MAX_STEPS as f32).map(|c| c * 255.0))
        .collect();
    let steps = |x: u32, y: u32| {
        let p = image.get_pixel(x, y).0.map(f32::from);
        let distance = |c: &[f32; 3]| (0..3).map(|i| (c[i] - p[i]).powi(2)).sum::<f32>();
        let (best, c) = (0..=MAX_STEPS)
            .zip(&colours)
            .min_by(|a, b| distance(a.1).total_cmp(&distance(b.1)))
            .unwrap();
        assert!(
            distance(c) < 12.0,
            "({x}, {y}): {p:?} is off the colour map"
        );
        best
    };
    let (miss, wall, boxes) = (steps(0, 24), steps(33, 12), [steps(21, 33), steps(15, 24)]);
    eprintln!("steps: miss {miss}, back wall {wall}, boxes {boxes:?}");
    assert_eq!(miss, 0);
    assert!((1..=12).contains(&wall), "back wall {wall}");
    assert!(boxes[0] > wall, "boxes {boxes:?}, back wall {wall}");
    assert!(boxes[1] > wall + 4, "boxes {boxes:?}, back wall {wall}");
    let stepped = (0..48 * 48).filter(|i| steps(i % 48, i / 48) > 0).count();
    let share = stepped as f64 / (48.0 * 48.0);
    eprintln!("share of pixels with steps {share:.3}");
    assert!(share > 0.8, "share of pixels with steps {share}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An edit in the window is an edit of the World: a click selects the instance under it (a CPU
/// ray through the scene BVH) and `move` shifts its `Transform`; the window's frame 4 frames
/// later equals a headless renderer's that picks the same pixel and moves the same entity in
/// its own World between the same frames: relMSE (linear HDR, epsilon 0.01) under 1e-3,
/// measured 0.0 on lavapipe; and the edit shows (relMSE against the unedited view above 1e-3,
/// measured 2.6e-2).
#[test]
fn an_edit_in_the_window_is_an_edit_of_the_world() {
    use bevy_ecs::world::World;
    use chiaro::gpu::{FrameSettings, RenderSettings, Renderer};
    use chiaro::scene::{Name, Transform, load_scene};
    use glam::Vec3;

    let Some(x) = xvfb() else { return };
    let dir = temp_dir("edit");
    let (still, moved) = (dir.join("still.exr"), dir.join("moved.exr"));
    let (at, lift) = ((36.0, 55.0), Vec3::new(0.0, 0.1, 0.0));
    let script = dir.join("script.txt");
    std::fs::write(
        &script,
        format!(
            "panel off\nframes 4\nscreenshot {}\nclick {} {}\nmove {} {} {}\nframes 4\nscreenshot {}\n",
            still.display(),
            at.0,
            at.1,
            lift.x,
            lift.y,
            lift.z,
            moved.display()
        ),
    )
    .unwrap();
    let args = ["--size", "96x96", "--script", script.to_str().unwrap()];
    let Some(_) = view(&x, &args) else { return };

    let Some(context) = common::gpu() else { return };
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    let mut renderer = Renderer::new(context);
    let settings = RenderSettings {
        width: 96,
        height: 96,
        frames: 1,
        seed: 0,
        frame: FrameSettings::default(),
    };
    renderer.accumulate(&mut world, &settings, 4).unwrap();
    let entity = chiaro_viewer::selection::pick(&world, at.0, at.1, 96, 96).expect("a hit");
    assert_eq!(world.get::<Name>(entity).unwrap().as_str(), "tall block");
    world.get_mut::<Transform>(entity).unwrap().translation += lift;
    renderer.accumulate(&mut world, &settings, 4).unwrap();
    let expected = renderer.read(&settings).unwrap().hdr;

    let (_, _, window) = read_exr(&moved).unwrap();
    let error = rel_mse(&window, &expected, 0.01);
    eprintln!("edited window against the edited World: relMSE {error:.3e}");
    assert!(error < 1e-3, "relMSE {error}");
    let (_, _, before) = read_exr(&still).unwrap();
    let change = rel_mse(&window, &before, 0.01);
    eprintln!("edited against unedited: relMSE {change:.3e}");
    assert!(change > 1e-3, "the edit does not show: {change}");
    std::fs::remove_dir_all(&dir).unwrap();
}
