//! The hard-case suite on the GPU: `builtin:hard-cases`, each case seen from its own camera
//! (one world, so the pipelines compile once; `scale` in its own), in every mode.
//!
//! - No mode writes a non-finite pixel in any case: not in the final image, and not in the
//!   direct or indirect light before the composite's guard.
//! - (`hard_cases_reference.rs`: the GPU and CPU references agree case by case.)
//! - The white furnace (exact radiance 1): the reference mode's mean is 1 within 2%; the
//!   realtime mode with a bounce cap of b gathers light at b + 1 surfaces of albedo 0.5 over an
//!   emission of 0.5, so its mean is 1 - 0.5^(b + 2) (0.96875 at the default cap of 3),
//!   within 2% (b = 1, 2, 3, 4).
//! - The copy of the lit group 1e5 units from the origin renders like the original: relMSE
//!   between the two GPU reference images below 3 x their combined noise (measured at 24x24,
//!   64 frames of 4 paths: 1.4e-2 against a noise of 5.8e-2).
//!
//! Frame counts are kept low, and paths per pixel raised instead: on lavapipe, a frame's cost
//! is mostly per pixel and path, so fewer, richer frames reach the same noise sooner.

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_scene::builtin::HARD_CASES;
use chiaro_scene::load_scene;
use glam::Vec3;
use hard_cases_common::{CaseWorlds, mode, settings, view_case};

fn all_finite(pixels: &[Vec3]) -> bool {
    pixels.iter().all(|p| p.is_finite())
}

#[test]
fn no_mode_writes_a_non_finite_pixel_in_any_case() {
    let Some(gpu) = common::gpu() else { return };
    let mut worlds = CaseWorlds::load();
    let mut renderer = Renderer::new(gpu);
    for case in HARD_CASES {
        let world = worlds.view(case);
        for m in RenderMode::ALL {
            let out = renderer
                .render(world, &settings(24, 3, 5, mode(m)))
                .unwrap();
            let what = format!("{case}, {}", m.name());
            assert!(all_finite(&out.hdr), "{what}: non-finite image pixel");
            assert!(
                all_finite(&renderer.direct_light().unwrap()),
                "{what}: non-finite direct light"
            );
            assert!(
                all_finite(&renderer.indirect_light().unwrap()),
                "{what}: non-finite indirect light"
            );
        }
    }
}

#[test]
fn furnace_radiance_is_one_less_what_the_bounce_cap_drops() {
    let Some(gpu) = common::gpu() else { return };
    let mut world = World::new();
    load_scene(&mut world, "builtin:furnace").unwrap();
    let mut renderer = Renderer::new(gpu);
    let mean = |pixels: &[Vec3]| {
        pixels
            .iter()
            .map(|p| f64::from(p.x + p.y + p.z))
            .sum::<f64>()
            / (3 * pixels.len()) as f64
    };
    let reference = renderer
        .render(
            &mut world,
            &settings(24, 32, 3, mode(RenderMode::Reference)),
        )
        .unwrap();
    let r = mean(&reference.hdr);
    eprintln!("reference mode: mean radiance {r:.4}");
    assert!((r - 1.0).abs() < 0.02, "reference mode: mean radiance {r}");
    for bounces in [1, 2, 3, 4] {
        let realtime = FrameSettings {
            bounces,
            ..mode(RenderMode::Realtime)
        };
        let out = renderer
            .render(&mut world, &settings(24, 32, 3, realtime))
            .unwrap();
        let m = mean(&out.hdr);
        let expected = 1.0 - 0.5f64.powi(bounces as i32 + 2);
        eprintln!("realtime, {bounces} bounces: mean radiance {m:.4}, expected {expected:.4}");
        assert!(
            (m - expected).abs() < 0.02 * expected,
            "realtime with {bounces} bounces: mean radiance {m}, expected {expected}"
        );
    }
}

#[test]
fn far_copy_renders_like_the_original() {
    let Some(gpu) = common::gpu() else { return };
    let (size, frames) = (24, 64);
    let mut world = World::new();
    load_scene(&mut world, "builtin:hard-cases").unwrap();
    let mut renderer = Renderer::new(gpu);
    let reference = FrameSettings {
        spp: 4,
        ..mode(RenderMode::Reference)
    };
    let mut images = Vec::new();
    for case in ["lit-group", "far-copy"] {
        view_case(&mut world, case);
        for seed in [1, 2] {
            let out = renderer
                .render(&mut world, &settings(size, frames, seed, reference))
                .unwrap();
            images.push(out.hdr);
        }
    }
    let noise =
        (common::rel_mse(&images[0], &images[1]) + common::rel_mse(&images[2], &images[3])) / 2.0;
    let error = common::rel_mse(&images[2], &images[0]);
    eprintln!("far copy against the original: relMSE {error:.3e}, noise {noise:.3e}");
    assert!(error < 3.0 * noise, "relMSE {error} against noise {noise}");
}
