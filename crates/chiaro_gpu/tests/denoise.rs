//! The realtime mode's denoiser (temporal accumulation, variance, a-trous; SVGF) against
//! converged CPU references of builtin:cornell (`chiaro_reference::render_world`, full paths):
//! error after one frame against the raw lighting and against the naive mode's first frame,
//! error falling over frames on a still
//! camera, history reset where geometry is revealed, no non-finite value in history or
//! output after injected NaN and Inf, and a camera pan and a moving object without ghosts.
//!
//! Error is relMSE = mean((x - y)^2 / (y^2 + 0.01)) over pixels and channels of the linear HDR
//! image. The bounds are the measured values (lavapipe, seeds as in the tests) with margin;
//! each test's doc comment gives them (measured with the bounce cap of 2 where not said; the
//! default cap of 3 lowers the still camera's error, as those two tests say).

mod common;

use std::sync::OnceLock;

use bevy_ecs::prelude::{Entity, Name};
use bevy_ecs::world::World;
use chiaro_gpu::{FrameSettings, RenderMode, RenderSettings, Renderer};
use chiaro_reference::{PathSettings, render_world};
use chiaro_scene::{ActiveCamera, Transform, load_scene};
use glam::{Quat, Vec3};

/// relMSE over the pixels where `mask` holds (all with `None`).
fn rel_mse(x: &[Vec3], y: &[Vec3], mask: Option<&[bool]>) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for (i, (a, b)) in x.iter().zip(y).enumerate() {
        if mask.is_some_and(|m| !m[i]) {
            continue;
        }
        let d = (*a - *b) * (*a - *b) / (*b * *b + Vec3::splat(0.01));
        sum += f64::from(d.x + d.y + d.z);
        count += 3;
    }
    sum / count.max(1) as f64
}

/// The pixels whose 3 x 3 neighbourhood has no reference value above 1: away from the
/// emitter, whose edge pixels the composite adds unfiltered each frame (one jittered point per
/// pixel against the reference's pixel-area mean: the error of such a pixel in one frame can
/// be 1e4 x that of a lit wall's, which would swamp what the denoiser does).
fn away_from_emitters(reference: &[Vec3], size: u32) -> Vec<bool> {
    let n = size as i32;
    (0..n * n)
        .map(|i| {
            let (x, y) = (i % n, i / n);
            (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let (qx, qy) = ((x + dx).clamp(0, n - 1), (y + dy).clamp(0, n - 1));
                    reference[(qy * n + qx) as usize].max_element() <= 1.0
                })
            })
        })
        .collect()
}

fn cornell() -> World {
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    world
}

/// The converged CPU image of `world` (full paths, Russian roulette).
fn reference(world: &mut World, size: u32, spp: u32) -> Vec<Vec3> {
    let settings = chiaro_reference::RenderSettings {
        width: size,
        height: size,
        spp,
        seed: 11,
        sampler: chiaro_reference::Sampler::default(),
        threads: None,
        path: PathSettings::default(),
    };
    render_world(world, &settings, false).unwrap().image
}

/// The still Cornell box's reference at 64 x 64 (shared by the tests that need it).
fn cornell_reference() -> &'static [Vec3] {
    static IMAGE: OnceLock<Vec<Vec3>> = OnceLock::new();
    IMAGE.get_or_init(|| reference(&mut cornell(), 64, 256))
}

fn settings(size: u32, frames: u32, denoise: bool) -> RenderSettings {
    let mut frame = FrameSettings {
        mode: RenderMode::Realtime,
        ..FrameSettings::default()
    };
    frame.denoise.enabled = denoise;
    RenderSettings {
        width: size,
        height: size,
        frames,
        seed: 5,
        frame,
    }
}

/// The entity named `name`.
fn named(world: &mut World, name: &str) -> Entity {
    let mut query = world.query::<(Entity, &Name)>();
    query
        .iter(world)
        .find(|(_, n)| n.as_str() == name)
        .map(|(e, _)| e)
        .unwrap_or_else(|| panic!("no entity named {name}"))
}

fn translate(world: &mut World, entity: Entity, by: Vec3) {
    world.get_mut::<Transform>(entity).unwrap().translation += by;
}

/// Pixels within one pixel of a depth edge: a neighbour shows another instance, nothing, or
/// a point more than 5% nearer or farther from the camera.
fn depth_edges(renderer: &Renderer, world: &mut World, size: u32) -> Vec<bool> {
    let g = renderer.read_gbuffer().unwrap();
    let camera = world.resource::<ActiveCamera>().0;
    let eye = world
        .get::<chiaro_scene::GlobalTransform>(camera)
        .unwrap()
        .0
        .translation;
    let eye = Vec3::from(eye);
    let n = size as i32;
    let depth = |i: usize| (g.position[i] - eye).length();
    (0..(n * n) as usize)
        .map(|i| {
            let (x, y) = (i as i32 % n, i as i32 / n);
            (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    let (qx, qy) = (x + dx, y + dy);
                    if qx < 0 || qy < 0 || qx >= n || qy >= n {
                        return false;
                    }
                    let j = (qy * n + qx) as usize;
                    match (g.instance[i], g.instance[j]) {
                        (Some(a), Some(b)) => {
                            a != b || (depth(i) - depth(j)).abs() > 0.05 * depth(i)
                        }
                        (None, None) => false,
                        _ => true,
                    }
                })
            })
        })
        .collect()
}

/// After one frame, the filtered image's relMSE against the converged reference is a small
/// fraction of the raw 1-spp image's (the denoiser off, same random numbers), and on the
/// pixels beside depth edges it is not worse than the raw one.
///
/// Measured (64 x 64, seed 5, reference 256 spp, pixels beside the emitter left out): raw
/// 1.14e-1, filtered 1.77e-2 (factor 6.5); near depth edges (1386 pixels) raw 9.31e-2,
/// filtered 2.72e-2. Asserted: factor above 4, edges filtered <= raw.
#[test]
fn one_frame_atrous_beats_the_raw_lighting() {
    let Some(gpu) = common::gpu() else { return };
    let reference = cornell_reference();
    let mut renderer = Renderer::new(gpu);
    let mut world = cornell();
    let raw = renderer
        .render(&mut world, &settings(64, 1, false))
        .unwrap();
    let mut world = cornell();
    let filtered = renderer.render(&mut world, &settings(64, 1, true)).unwrap();
    let interior = away_from_emitters(reference, 64);
    let edges: Vec<bool> = depth_edges(&renderer, &mut world, 64)
        .iter()
        .zip(&interior)
        .map(|(e, i)| *e && *i)
        .collect();
    let (e_raw, e_filtered) = (
        rel_mse(&raw.hdr, reference, Some(&interior)),
        rel_mse(&filtered.hdr, reference, Some(&interior)),
    );
    let (edge_raw, edge_filtered) = (
        rel_mse(&raw.hdr, reference, Some(&edges)),
        rel_mse(&filtered.hdr, reference, Some(&edges)),
    );
    eprintln!(
        "one frame: raw {e_raw:.4e}, filtered {e_filtered:.4e} (factor {:.1}); near edges ({} px) raw \
         {edge_raw:.4e}, filtered {edge_filtered:.4e}",
        e_raw / e_filtered,
        edges.iter().filter(|&&e| e).count()
    );
    assert!(e_raw / e_filtered > 4.0, "factor {}", e_raw / e_filtered);
    assert!(edge_filtered <= edge_raw);
}

/// After one frame the realtime image (denoised) is closer to the converged reference than the
/// naive mode's one frame of pure path tracing by orders of magnitude (64 x 64, pixels beside
/// the emitter left out, as both add the emission they see alike).
///
/// Measured: realtime 1.60e-2, naive 37.2 (factor 2322; with the bounce cap of 2, 1.77e-2 and
/// factor 2052). Asserted: realtime below a hundredth of naive.
#[test]
fn one_realtime_frame_beats_one_naive_frame() {
    let Some(gpu) = common::gpu() else { return };
    let reference = cornell_reference();
    let mut renderer = Renderer::new(gpu);
    let interior = away_from_emitters(reference, 64);
    let mut world = cornell();
    let realtime = renderer.render(&mut world, &settings(64, 1, true)).unwrap();
    let mut naive_settings = settings(64, 1, false);
    naive_settings.frame.mode = RenderMode::Naive;
    let naive = renderer.render(&mut world, &naive_settings).unwrap();
    let (e_realtime, e_naive) = (
        rel_mse(&realtime.hdr, reference, Some(&interior)),
        rel_mse(&naive.hdr, reference, Some(&interior)),
    );
    eprintln!(
        "one frame: realtime {e_realtime:.3e}, naive {e_naive:.3e} (factor {:.0})",
        e_naive / e_realtime
    );
    assert!(
        e_naive > 100.0 * e_realtime,
        "realtime {e_realtime}, naive {e_naive}"
    );
}

/// On a still camera the error against the converged reference falls from frame 1 to 4 to
/// 16 to 64 (64 x 64, temporal floor 0.05; pixels beside the emitter left out, see
/// [`away_from_emitters`]).
///
/// Measured, with the composite's resolve, the bounce cap of 3 and the still view's running
/// mean (chiaro_gpu::still_view): relMSE 1.45e-2, 7.14e-3, 4.41e-3, 3.09e-3 after 1, 4, 16, 64
/// frames; away from depth edges too: 8.9e-3, 6.1e-3, 4.3e-3, 3.0e-3 (with the resolve's clamp
/// kept whole on the still view: 1.45e-2, 7.42e-3, 4.91e-3, 3.94e-3). With the moving average
/// alone the error stopped at its floor from 16 frames on (1.60e-2, 9.91e-3, 6.70e-3, 6.64e-3;
/// away from depth edges 9.8e-3, 7.5e-3, 5.3e-3, 5.3e-3); the cap alone leaves about 1e-3
/// against the uncapped reference (docs/experiments/bounce-cap.md). With the cap of 2 (4e-3 of
/// bias) and the moving average: 1.77e-2, 1.22e-2, 9.75e-3, 9.71e-3. (Before the resolve, which
/// averages the emission and the silhouettes over frames, cap 2: 1.77e-2, 1.61e-2, 1.42e-2,
/// 1.12e-2.)
/// Asserted: 4 below 1, 16 below 4, 64 below 16 and below 0.6 x one frame; away from depth
/// edges, 64 frames below 0.85 x one frame.
#[test]
fn still_camera_error_falls_with_frames() {
    let Some(gpu) = common::gpu() else { return };
    let reference = cornell_reference();
    let mut renderer = Renderer::new(gpu);
    let mut world = cornell();
    let s = settings(64, 1, true);
    let interior = away_from_emitters(reference, 64);
    let mut out = renderer.render(&mut world, &s).unwrap();
    let inside: Vec<bool> = depth_edges(&renderer, &mut world, 64)
        .iter()
        .zip(&interior)
        .map(|(e, i)| !*e && *i)
        .collect();
    let (mut errors, mut inside_errors) = (Vec::new(), Vec::new());
    for total in [1, 4, 16, 64] {
        renderer
            .accumulate(&mut world, &s, total - out.frames)
            .unwrap();
        out = renderer.read(&s).unwrap();
        errors.push((total, rel_mse(&out.hdr, reference, Some(&interior))));
        inside_errors.push((total, rel_mse(&out.hdr, reference, Some(&inside))));
    }
    eprintln!("still camera: relMSE by frames {errors:?}; away from depth edges {inside_errors:?}");
    let e: Vec<f64> = errors.iter().map(|(_, e)| *e).collect();
    assert!(e[1] < e[0] && e[2] < e[1], "{errors:?}");
    assert!(e[3] < e[2] && e[3] < 0.6 * e[0], "{errors:?}");
    assert!(
        inside_errors[3].1 < 0.85 * inside_errors[0].1,
        "{inside_errors:?}"
    );
}

/// Moving the tall block sideways after 8 still frames restarts the history (length 1) on
/// every pixel where it showed the block and now shows what was behind it, and keeps it
/// (length 9) on at least 95% of the pixels that showed another, still surface both times.
///
/// Revealed pixels are those whose whole 3 x 3 neighbourhood showed the block: at the rim, the
/// temporal pass's 3 x 3 fallback (as SVGF's) may legitimately find the same wall one pixel
/// away. Measured (32 x 32): 62 of 62 revealed pixels restarted, 733 of 742 still pixels kept
/// 9 frames (the others lie on sub-pixel edges that the jitter moves).
#[test]
fn revealed_geometry_restarts_history() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let mut world = cornell();
    let s = settings(32, 8, true);
    renderer.render(&mut world, &s).unwrap();
    let tall = named(&mut world, "tall block");
    let before = renderer.read_gbuffer().unwrap().instance;
    // The tall block covers pixel (12, 20) at 32 x 32.
    let tall_id = before[20 * 32 + 12];
    assert!(tall_id.is_some());
    translate(&mut world, tall, Vec3::new(150.0, 0.0, 0.0));
    renderer.accumulate(&mut world, &s, 1).unwrap();
    let after = renderer.read_gbuffer().unwrap().instance;
    let frame = renderer.frame().unwrap();
    let c = &renderer.context;
    let length = frame
        .denoiser()
        .read_history_length(&c.device, &c.queue)
        .unwrap();
    let (mut revealed, mut reset, mut still, mut kept) = (0, 0, 0, 0);
    let n = 32i32;
    let all_tall_around = |i: usize| {
        let (x, y) = (i as i32 % n, i as i32 / n);
        (-1..=1).all(|dy| {
            (-1..=1).all(|dx| {
                let (qx, qy) = ((x + dx).clamp(0, n - 1), (y + dy).clamp(0, n - 1));
                before[(qy * n + qx) as usize] == tall_id
            })
        })
    };
    for i in 0..before.len() {
        if all_tall_around(i) && after[i] != tall_id && after[i].is_some() {
            revealed += 1;
            reset += usize::from(length[i] == 1.0);
        } else if before[i] == after[i] && before[i].is_some() && before[i] != tall_id {
            still += 1;
            kept += usize::from(length[i] == 9.0);
        }
    }
    eprintln!(
        "disocclusion: {reset} of {revealed} revealed pixels restarted, {kept} of {still} still \
         pixels kept 9 frames"
    );
    assert!(revealed >= 10, "only {revealed} revealed pixels");
    assert_eq!(reset, revealed);
    assert!(kept as f64 >= 0.95 * still as f64);
}

/// The indirect pass's test hook writes NaN at pixel (0, 0) and +Inf at (1, 0) every frame;
/// after 30 frames no pixel of the colour history, the moments, the filtered output or the
/// HDR image is non-finite (the lighting input does show the injected values).
#[test]
fn injected_non_finite_values_never_enter_history() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    renderer.inject_non_finite(true);
    let mut world = cornell();
    let out = renderer
        .render(&mut world, &settings(32, 30, true))
        .unwrap();
    let frame = renderer.frame().unwrap();
    let c = &renderer.context;
    let d = frame.denoiser();
    let lighting = d.read_lighting(&c.device, &c.queue).unwrap();
    assert!(
        lighting[0].x.is_nan() && lighting[1].x.is_infinite(),
        "{:?}",
        &lighting[..2]
    );
    let finite = |v: &[Vec3]| v.iter().all(|p| p.is_finite());
    assert!(finite(&d.read_color_history(&c.device, &c.queue).unwrap()));
    assert!(finite(&d.read_output(&c.device, &c.queue).unwrap()));
    assert!(
        d.read_moments(&c.device, &c.queue)
            .unwrap()
            .iter()
            .all(|m| m.is_finite())
    );
    assert!(finite(&out.hdr));
}

/// A camera pan (yaw 0.2 degrees a frame for 60 frames, about 10 pixels at 32 x 32): the last
/// frame's relMSE against the converged reference of its own view stays under a bound; for
/// scale, the same view after 60 frames of a still camera.
///
/// Measured (reference 256 spp, pixels beside the emitter left out): relMSE 9.19e-3 after
/// the pan, 3.64e-3 for 60 frames of the still final view. With the resolve's earlier rules
/// under motion (bilinear history clamped to the full 3 x 3 range, every other surface's
/// history left out) the pan measured 1.94e-2; with the nearest pixel's history, 2.7e-2.
/// Asserted: below 3e-2.
#[test]
fn camera_pan_stays_close_to_the_reference() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let mut world = cornell();
    let s = settings(32, 1, true);
    common::pan(&mut renderer, &mut world, &s, 60, 0.2);
    let panned = renderer.read(&s).unwrap();
    let reference = reference(&mut world, 32, 256);
    let still = renderer
        .render(&mut world, &settings(32, 60, true))
        .unwrap();
    let interior = away_from_emitters(&reference, 32);
    let (e_pan, e_still) = (
        rel_mse(&panned.hdr, &reference, Some(&interior)),
        rel_mse(&still.hdr, &reference, Some(&interior)),
    );
    eprintln!("pan: relMSE {e_pan:.4e}, still camera {e_still:.4e}");
    assert!(e_pan < PAN_BOUND, "{e_pan}");
}

const PAN_BOUND: f64 = 3e-2;

/// The emitter does not smear across the ceiling as the view pans: the camera turns 8 degrees
/// about its own up axis over 64 frames at 64 x 64 (0.2 pixels a frame, a steady pan), and
/// the last frame against the converged reference of its own view has relMSE under
/// [`EMITTER_PAN_BOUND`], the whole image with the emitter's edge. Measured (reference 512 spp):
/// 1.65e-2, against about 1e-2 for 64 frames of the still final view. When the resolve blended
/// the history of every surface under motion, it was 9.5e-2: three or four ceiling pixels
/// beside the emitter took its history, a relMSE near 300 each; with every other surface's
/// history left out, 2.2e-2.
#[test]
fn the_emitter_does_not_smear_across_the_ceiling_in_a_pan() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let mut world = cornell();
    let camera = world.resource::<ActiveCamera>().0;
    let start = *world.get::<Transform>(camera).unwrap();
    let turn = |world: &mut World, degrees: f32| {
        world.get_mut::<Transform>(camera).unwrap().rotation =
            start.rotation * Quat::from_rotation_y(degrees.to_radians());
    };
    let s = settings(64, 1, true);
    for frame in 1..=64 {
        turn(&mut world, 8.0 * frame as f32 / 64.0);
        if frame == 1 {
            renderer.render(&mut world, &s).unwrap();
        } else {
            renderer.accumulate(&mut world, &s, 1).unwrap();
        }
    }
    let panned = renderer.read(&s).unwrap();
    let reference = reference(&mut world, 64, 512);
    let error = rel_mse(&panned.hdr, &reference, None);
    eprintln!("8-degree pan: relMSE {error:.4e} in all pixels");
    assert!(error < EMITTER_PAN_BOUND, "{error}");
}

const EMITTER_PAN_BOUND: f64 = 5e-2;

/// The short block slides 240 mm sideways over 30 frames (about 8 pixels at 32 x 32), then
/// stays for 10 frames: where it stood at the start, now revealed, the error against the
/// converged reference is no worse than 2 x that of 10 frames of the final scene from a
/// fresh history, and the region's mean luminance differs from the reference's by no more
/// than 10 points beyond what the fresh history's does (a ghost of the block would show as
/// either).
///
/// Measured (reference 256 spp): 83 revealed pixels, relMSE 3.9e-3 (fresh history 3.1e-3),
/// mean luminance -8.1% (fresh history -5.7%: the filter's blur of the block's shadow).
#[test]
fn moved_object_leaves_no_ghost() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let mut world = cornell();
    let s = settings(32, 1, true);
    renderer.render(&mut world, &s).unwrap();
    let short = named(&mut world, "short block");
    let start = renderer.read_gbuffer().unwrap().instance;
    // The short block covers pixel (20, 24) at 32 x 32.
    let short_id = start[24 * 32 + 20];
    assert!(short_id.is_some());
    for _ in 1..30 {
        translate(&mut world, short, Vec3::new(-8.0, 0.0, 0.0));
        renderer.accumulate(&mut world, &s, 1).unwrap();
    }
    renderer.accumulate(&mut world, &s, 10).unwrap();
    let moved = renderer.read(&s).unwrap();
    let now = renderer.read_gbuffer().unwrap().instance;
    let region: Vec<bool> = (0..start.len())
        .map(|i| start[i] == short_id && now[i] != short_id)
        .collect();
    let pixels = region.iter().filter(|&&r| r).count();
    let reference = reference(&mut world, 32, 256);
    let fresh = renderer
        .render(&mut world, &settings(32, 10, true))
        .unwrap();
    let (e_moved, e_fresh) = (
        rel_mse(&moved.hdr, &reference, Some(&region)),
        rel_mse(&fresh.hdr, &reference, Some(&region)),
    );
    let mean = |img: &[Vec3]| {
        img.iter()
            .zip(&region)
            .filter(|(_, r)| **r)
            .map(|(p, _)| f64::from(p.dot(Vec3::new(0.2126, 0.7152, 0.0722))))
            .sum::<f64>()
            / pixels as f64
    };
    let bias = mean(&moved.hdr) / mean(&reference) - 1.0;
    let fresh_bias = mean(&fresh.hdr) / mean(&reference) - 1.0;
    eprintln!(
        "moved object: {pixels} revealed pixels, relMSE {e_moved:.4e} (fresh history \
         {e_fresh:.4e}), mean luminance bias {bias:+.3} (fresh history {fresh_bias:+.3})"
    );
    assert!(pixels >= 10, "only {pixels} revealed pixels");
    assert!(e_moved <= 2.0 * e_fresh, "{e_moved} against {e_fresh}");
    assert!(
        (bias - fresh_bias).abs() < 0.1,
        "{bias} against {fresh_bias}"
    );
}
