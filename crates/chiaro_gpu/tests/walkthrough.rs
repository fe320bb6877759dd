//! `builtin:walkthrough` on the GPU against the CPU reference at three poses along its
//! animation (the camera walking and turning, the doors swinging, the balls rolling, the fan
//! turning), one bay at the lowest detail: textures and normal maps, alpha-masked foliage,
//! metals, a glass ball with a tinted medium, a sun, a sky, point and spot lights and
//! emissive signs together.
//!
//! Sixteen lights close to stone make a heavy-tailed estimator (a bounce that picks a nearby
//! lantern with a small probability carries a large weight), so at test budgets single pixels
//! of any run hold fireflies that dominate a per-pixel relMSE. The images are compared in
//! 4 x 4 blocks (means of 16 pixels), where the same estimators are well behaved: the GPU
//! reference mode agrees with the CPU within three times their combined noise (its own
//! runs' difference, the CPU's halves), and the realtime frame within relMSE 0.05.

mod common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, RenderSettings, Renderer};
use chiaro_reference::PathSettings;
use chiaro_scene::{load_scene, pose_at};
use common::rel_mse;
use glam::Vec3;

/// One bay, the coarsest tessellation.
const SCENE: &str = "builtin:walkthrough?size=1&detail=1";
/// Image side, pixels.
const SIZE: u32 = 48;
/// Side of the blocks compared, pixels.
const BLOCK: usize = 4;

/// The means of `image`'s `BLOCK` x `BLOCK` blocks.
fn blocks(image: &[Vec3]) -> Vec<Vec3> {
    let (side, n) = (SIZE as usize, SIZE as usize / BLOCK);
    (0..n * n)
        .map(|b| {
            let (bx, by) = (b % n * BLOCK, b / n * BLOCK);
            let sum: Vec3 = (0..BLOCK * BLOCK)
                .map(|k| image[(by + k / BLOCK) * side + bx + k % BLOCK])
                .sum();
            sum / (BLOCK * BLOCK) as f32
        })
        .collect()
}

fn gpu_image(
    renderer: &mut Renderer,
    world: &mut World,
    seed: u64,
    frame: FrameSettings,
) -> Vec<Vec3> {
    let frames = if frame.mode == RenderMode::Realtime {
        32
    } else {
        64
    };
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        frames,
        seed,
        frame,
    };
    blocks(&renderer.render(world, &settings).unwrap().hdr)
}

#[test]
fn the_walkthrough_matches_the_cpu_reference_along_its_path() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let reference = FrameSettings {
        mode: RenderMode::Reference,
        spp: 4,
        ..FrameSettings::default()
    };
    // The start; the doors half open and the camera a quarter of a bay on; the camera turned
    // towards the sculpture and the doors open (one bay's path lasts 4 s).
    for seconds in [0.0, 1.0, 3.5] {
        let mut world = World::new();
        load_scene(&mut world, SCENE).unwrap();
        pose_at(&mut world, seconds);
        let cpu = chiaro_reference::render_world(
            &mut world,
            &chiaro_reference::RenderSettings {
                width: SIZE,
                height: SIZE,
                spp: 512,
                seed: 7,
                sampler: chiaro_reference::Sampler::default(),
                threads: None,
                path: PathSettings::default(),
            },
            false,
        )
        .unwrap();
        let truth = blocks(&cpu.image);
        let a = gpu_image(&mut renderer, &mut world, 1, reference);
        let b = gpu_image(&mut renderer, &mut world, 2, reference);
        let cpu_noise = rel_mse(&blocks(&cpu.halves[0]), &blocks(&cpu.halves[1])) / 4.0;
        let gpu_noise = rel_mse(&a, &b) / 2.0;
        let error = rel_mse(&a, &truth);
        let bound = 3.0 * (cpu_noise + gpu_noise);
        eprintln!(
            "{seconds} s: reference mode relMSE {error:.3e} against the CPU, bound {bound:.3e} \
             (noise: GPU {gpu_noise:.3e}, CPU {cpu_noise:.3e})"
        );
        assert!(
            error < bound,
            "{seconds} s: reference mode relMSE {error} > {bound}"
        );
        let realtime = gpu_image(&mut renderer, &mut world, 1, FrameSettings::default());
        let error = rel_mse(&realtime, &truth);
        eprintln!("{seconds} s: realtime relMSE {error:.3e} against the CPU");
        assert!(error < 0.05, "{seconds} s: realtime relMSE {error}");
    }
}
