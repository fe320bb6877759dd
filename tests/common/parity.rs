//! The GPU reference mode against the CPU reference on one World: both unbiased estimates of
//! the same image, so with no bias their relMSE is about the sum of their own noises. Both
//! noises are measured (the GPU's from a second seed, the CPU's from its two halves) and the
//! bound is 3 x their sum, as `crates/chiaro_gpu/tests/direct_image.rs` argues.

use bevy_ecs::world::World;
use chiaro::eval::metrics::rel_mse;
use chiaro::gpu::{FrameSettings, RenderMode, RenderSettings, Renderer};
use chiaro::reference::{PathSettings, render_world};
use glam::Vec3;

/// Both images and what the comparison measured.
pub struct Agreement {
    /// The CPU reference.
    pub cpu: Vec<Vec3>,
    /// The GPU reference mode, seed 1.
    pub gpu: Vec<Vec3>,
    /// relMSE of the GPU image against the CPU one.
    pub error: f64,
    /// The GPU image's own relMSE (half that between seeds 1 and 2).
    pub gpu_noise: f64,
    /// The CPU image's own relMSE (a quarter of its halves').
    pub cpu_noise: f64,
}

impl Agreement {
    /// 3 x the two images' combined own noise.
    pub fn bound(&self) -> f64 {
        3.0 * (self.gpu_noise + self.cpu_noise)
    }
}

/// relMSE as DESIGN.md defines it (epsilon 0.01).
pub fn rel_mse_01(x: &[Vec3], y: &[Vec3]) -> f64 {
    rel_mse(x, y, 0.01)
}

/// Renders `world`'s active camera at `size` x `size`: on the CPU with `cpu_spp` paths per
/// pixel (seed 7), and in the GPU's reference mode over `frames` frames of 4 paths, seeds 1
/// and 2. `None` when this machine has no GPU adapter (see [`super::gpu`]).
pub fn gpu_and_cpu_references(
    world: &mut World,
    size: u32,
    cpu_spp: u32,
    frames: u32,
) -> Option<Agreement> {
    let context = super::gpu()?;
    let cpu = render_world(
        world,
        &chiaro::reference::RenderSettings {
            width: size,
            height: size,
            spp: cpu_spp,
            seed: 7,
            sampler: chiaro_reference::Sampler::default(),
            threads: None,
            path: PathSettings::default(),
        },
        false,
    )
    .unwrap();
    let mut renderer = Renderer::new(context);
    let settings = |seed| RenderSettings {
        width: size,
        height: size,
        frames,
        seed,
        frame: FrameSettings {
            mode: RenderMode::Reference,
            spp: 4,
            ..FrameSettings::default()
        },
    };
    let a = renderer.render(world, &settings(1)).unwrap().hdr;
    let b = renderer.render(world, &settings(2)).unwrap().hdr;
    Some(Agreement {
        error: rel_mse_01(&a, &cpu.image),
        gpu_noise: rel_mse_01(&a, &b) / 2.0,
        cpu_noise: cpu.halves_rel_mse() / 4.0,
        cpu: cpu.image,
        gpu: a,
    })
}
