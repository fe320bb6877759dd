//! What the hard-case suite's test files share: each case's camera, render settings by mode,
//! the CPU reference, metrics over a mask of pixels.

use bevy_ecs::prelude::{Entity, Name, World};
use chiaro_gpu::{FrameSettings, RenderMode, RenderSettings};
use chiaro_scene::builtin::{CASES_ALONE, hard_case_scene};
use chiaro_scene::{ActiveCamera, Camera, load_scene};
use glam::Vec3;

use crate::common::{masked_rel_mse, rel_mse};

/// Makes the camera of `case` the active one.
#[allow(dead_code)]
pub fn view_case(world: &mut World, case: &str) {
    let name = format!("{case} camera");
    let mut cameras = world.query::<(Entity, &Name, &Camera)>();
    let entity = cameras
        .iter(world)
        .find(|(_, n, _)| n.as_str() == name)
        .map(|(e, _, _)| e)
        .unwrap_or_else(|| panic!("no camera named '{name}'"));
    world.insert_resource(ActiveCamera(entity));
}

/// The worlds the suite sees its cases in: one of `builtin:hard-cases` for every case it holds
/// (so a renderer switches cameras, not scenes, between them), and one of its own for each case
/// it leaves out (`CASES_ALONE`).
#[allow(dead_code)]
pub struct CaseWorlds {
    combined: World,
    alone: Vec<(&'static str, World)>,
}

#[allow(dead_code)]
impl CaseWorlds {
    /// Loads the combined scene and each case that lives alone.
    pub fn load() -> Self {
        let mut combined = World::new();
        load_scene(&mut combined, "builtin:hard-cases").unwrap();
        let alone = CASES_ALONE
            .into_iter()
            .map(|case| {
                let mut world = World::new();
                load_scene(&mut world, &hard_case_scene(case)).unwrap();
                (case, world)
            })
            .collect();
        Self { combined, alone }
    }

    /// The world `case` is seen in, its camera made the active one.
    pub fn view(&mut self, case: &str) -> &mut World {
        let world = match self.alone.iter_mut().find(|(c, _)| *c == case) {
            Some((_, world)) => world,
            None => &mut self.combined,
        };
        view_case(world, case);
        world
    }
}

/// `frames` frames of `size` x `size` with `seed`.
#[allow(dead_code)]
pub fn settings(size: u32, frames: u32, seed: u64, frame: FrameSettings) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        frames,
        seed,
        frame,
    }
}

/// The default frame settings in `mode`.
#[allow(dead_code)]
pub fn mode(mode: RenderMode) -> FrameSettings {
    FrameSettings {
        mode,
        ..FrameSettings::default()
    }
}

/// The CPU reference of the active camera's view: `size` x `size`, `spp` paths, seed 7.
#[allow(dead_code)]
pub fn cpu_reference(
    world: &mut World,
    size: u32,
    spp: u32,
    path: chiaro_reference::PathSettings,
) -> chiaro_reference::RenderOutput {
    let settings = chiaro_reference::RenderSettings {
        width: size,
        height: size,
        spp,
        seed: 7,
        sampler: chiaro_reference::Sampler::default(),
        threads: None,
        path,
    };
    chiaro_reference::render_world(world, &settings, false).unwrap()
}

/// The CPU reference of `world` (`cpu_reference`, default path settings) once `without` (the
/// same view lacking `feature`) is found more than 100 times the reference's own noise away
/// from it: a renderer that ignored the feature would then fail a comparison with it.
#[allow(dead_code)]
pub fn cpu_reference_unlike(
    world: &mut World,
    without: &mut World,
    feature: &str,
    size: u32,
    spp: u32,
) -> chiaro_reference::RenderOutput {
    let path = chiaro_reference::PathSettings::default();
    let cpu = cpu_reference(world, size, spp, path);
    let plain = cpu_reference(without, size, spp, path);
    let noise = rel_mse(&cpu.halves[0], &cpu.halves[1]) / 4.0;
    let distance = rel_mse(&plain.image, &cpu.image);
    eprintln!("CPU: own noise {noise:.3e}; without {feature} {distance:.3e} away");
    assert!(
        distance > 100.0 * noise,
        "{feature} barely changes the image: {distance} against noise {noise}"
    );
    cpu
}

/// The GPU against `cpu` (a CPU reference of the same view, `size` x `size`) over the pixels
/// the G-buffer covers, eroded: the reference mode (two runs of `frames` frames of 4 paths,
/// seeds 1 and 2, their difference its own noise) within three times the combined noise, and
/// the realtime frame (32 frames; its denoiser blurs) within relMSE 0.05.
#[allow(dead_code)]
pub fn gpu_modes_match_the_cpu(
    renderer: &mut chiaro_gpu::Renderer,
    world: &mut World,
    cpu: &chiaro_reference::RenderOutput,
    size: u32,
    frames: u32,
) {
    let reference = FrameSettings {
        spp: 4,
        ..mode(RenderMode::Reference)
    };
    let a = renderer
        .render(world, &settings(size, frames, 1, reference))
        .unwrap();
    let g = renderer.read_gbuffer().unwrap();
    let b = renderer
        .render(world, &settings(size, frames, 2, reference))
        .unwrap();
    let covered: Vec<bool> = g.instance.iter().map(|i| i.is_some()).collect();
    let mask = erode(&covered, size as usize);
    let cpu_noise = masked_rel_mse(&cpu.halves[0], &cpu.halves[1], &mask) / 4.0;
    let gpu_noise = masked_rel_mse(&a.hdr, &b.hdr, &mask) / 2.0;
    let error = masked_rel_mse(&a.hdr, &cpu.image, &mask);
    let bound = 3.0 * (cpu_noise + gpu_noise);
    eprintln!(
        "reference mode: relMSE {error:.3e} against the CPU, bound {bound:.3e} (noise: GPU \
         {gpu_noise:.3e}, CPU {cpu_noise:.3e})"
    );
    assert!(error < bound, "reference mode: relMSE {error} > {bound}");
    let realtime = renderer
        .render(world, &settings(size, 32, 1, mode(RenderMode::Realtime)))
        .unwrap();
    let error = masked_rel_mse(&realtime.hdr, &cpu.image, &mask);
    eprintln!("realtime: relMSE {error:.3e} against the CPU");
    assert!(error < 0.05, "realtime: relMSE {error}");
}

/// The mean of all channels over the pixels where `mask` is true.
#[allow(dead_code)]
pub fn masked_mean(x: &[Vec3], mask: &[bool]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (p, _) in x.iter().zip(mask).filter(|(_, m)| **m) {
        sum += f64::from(p.x + p.y + p.z);
        n += 3;
    }
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// `mask` (`width` pixels a row) less every pixel with a 4-neighbour outside it or on the
/// image's border: pixels whose whole footprint (under any sub-pixel jitter) is inside.
#[allow(dead_code)]
pub fn erode(mask: &[bool], width: usize) -> Vec<bool> {
    let height = mask.len() / width;
    (0..mask.len())
        .map(|i| {
            let (x, y) = (i % width, i / width);
            x > 0
                && y > 0
                && x + 1 < width
                && y + 1 < height
                && [i, i - 1, i + 1, i - width, i + width]
                    .iter()
                    .all(|&j| mask[j])
        })
        .collect()
}
