//! The tiny bright emitter (`builtin:hard-cases?case=tiny-emitter`: a 1 cm quad of radiance
//! 1e5 over a floor, beside a sphere): the realtime mode's relMSE against the converged CPU
//! reference after 32 frames, with the firefly clamp (`FrameSettings::firefly_clamp`) off and
//! at 0.5 and 2 (luminance of one indirect path).
//!
//! Measured (32x32, 32 frames, defaults otherwise (bounce cap 3), seeds 1 to 4; CPU reference
//! 1024 spp, own noise 1.3e-3; image mean 0.4972), with the sun's exact light outside the
//! denoiser, the clamp on the indirect paths and the direct pass's BRDF sample, the a-trous
//! filter's luminance sigma at 2, the first path continuing along the direct pass's BRDF ray,
//! the indirect pass's numbers on the direct pass's stream at a seed of its own, and the
//! resolve's clamp fading out on the still view:
//!
//! | clamp | relMSE, seeds 1 to 4 | mean relMSE | image mean (seed 2) |
//! |---|---|---|---|
//! | off | 1.40e-2, 1.72e-2, 1.90e-2, 2.13e-2 | 1.79e-2 | 0.4777 |
//! | 0.5 | 1.48e-2, 1.52e-2, 1.78e-2, 1.60e-2 | 1.60e-2 | 0.4716 |
//! | 2 | 1.40e-2, 1.66e-2, 1.86e-2, 1.92e-2 | 1.71e-2 | 0.4753 |
//!
//! The clamp lowers the mean error (11% at 0.5, 4% at 2 over the four seeds), though not on
//! every seed (seed 1: 1.48e-2 at 0.5 against 1.40e-2 off), for about 1% of the image's
//! energy. With the resolve's clamp kept whole on the still view the means were 1.63e-2 off,
//! 1.53e-2 at 0.5 and 1.59e-2 at 2: that clamp cut some of the same rare bright paths. The
//! image is 4% darker than the reference without any clamp, so that is not the bounce cap's
//! bias; presumably the rare bright paths that a heavy-tailed estimate needs are mostly
//! missing from 32 frames (not measured). Asserted: the mean relMSE over the seeds at 0.5 and
//! at 2 below the mean without the clamp; and, for each seed, the clamp only removes energy
//! (each clamped mean at most the unclamped one).

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_reference::PathSettings;
use chiaro_scene::load_scene;
use glam::Vec3;
use hard_cases_common::{cpu_reference, mode, settings};

fn mean(x: &[Vec3]) -> f64 {
    x.iter().map(|p| f64::from(p.x + p.y + p.z)).sum::<f64>() / (3 * x.len()) as f64
}

#[test]
fn the_firefly_clamp_lowers_realtime_error_on_the_tiny_emitter() {
    let Some(gpu) = common::gpu() else { return };
    let (size, frames) = (32, 32);
    let mut world = World::new();
    load_scene(&mut world, "builtin:hard-cases?case=tiny-emitter").unwrap();
    let cpu = cpu_reference(&mut world, size, 1024, PathSettings::default());
    eprintln!(
        "CPU reference: own noise {:.2e}, mean {:.4}",
        cpu.halves_rel_mse() / 4.0,
        mean(&cpu.image)
    );
    let mut renderer = Renderer::new(gpu);
    // Per clamp: (relMSE, mean) per seed.
    let mut runs = Vec::new();
    for clamp in [0.0, 0.5, 2.0] {
        let realtime = FrameSettings {
            firefly_clamp: clamp,
            ..mode(RenderMode::Realtime)
        };
        let mut per_seed = Vec::new();
        for seed in [1, 2, 3, 4] {
            let out = renderer
                .render(&mut world, &settings(size, frames, seed, realtime))
                .unwrap();
            per_seed.push((common::rel_mse(&out.hdr, &cpu.image), mean(&out.hdr)));
        }
        eprintln!("firefly clamp {clamp}: (relMSE, mean) per seed {per_seed:.4?}");
        runs.push(per_seed);
    }
    let mean_error =
        |runs: &[(f64, f64)]| runs.iter().map(|r| r.0).sum::<f64>() / runs.len() as f64;
    let (off, half, two) = (
        mean_error(&runs[0]),
        mean_error(&runs[1]),
        mean_error(&runs[2]),
    );
    assert!(
        half < off,
        "clamp 0.5: mean relMSE {half} against {off} off"
    );
    assert!(two < off, "clamp 2: mean relMSE {two} against {off} off");
    for (seed, ((off, half), two)) in runs[0].iter().zip(&runs[1]).zip(&runs[2]).enumerate() {
        assert!(
            half.1 <= off.1 && two.1 <= off.1,
            "seed {}: a clamp added energy",
            seed + 1
        );
    }
}
