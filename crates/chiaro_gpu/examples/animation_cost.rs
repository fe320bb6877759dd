//! The per-frame cost of playing animations: N copies of a skinned, animated glTF character
//! (default: the shared sample CesiumMan, 19 joints, 3,273 vertices) walking side by side, the
//! animation time advanced by 1/30 s per frame, and each of chiaro's scene systems timed alone
//! in the order the renderer runs them: the animation (`animate_nodes`), transform propagation,
//! the mesh deformation (`deform_meshes`: re-skinning from the bind pose through the mesh
//! checks), the BVH upkeep (BLAS rebuilds of the deformed meshes, TLAS update) and the GPU
//! upload, with the bytes uploaded. Nothing is rendered.
//!
//! ```text
//! cargo run --release -p chiaro_gpu --example animation_cost -- [FILE] [--n N,N,..] [--frames F]
//! ```

use std::time::{Duration, Instant};

use bevy_ecs::hierarchy::ChildOf;
use bevy_ecs::prelude::*;
use chiaro_gpu::{GpuContext, GpuScene};
use chiaro_scene::{SpawnedScene, Time, Transform, load_scene};
use glam::Vec3;

type Error = Box<dyn std::error::Error>;

/// The systems timed, in the renderer's order, and their names.
const SYSTEMS: [&str; 5] = ["animate", "propagate", "deform", "bvh", "upload"];

fn schedules() -> [Schedule; 5] {
    let mut s: [Schedule; 5] = Default::default();
    s[0].add_systems(chiaro_scene::animate_nodes);
    s[1].add_systems(chiaro_scene::propagate_transforms);
    s[2].add_systems(chiaro_scene::deformation::deform_meshes);
    s[3].add_systems(chiaro_bvh::update_scene_bvh);
    s[4].add_systems(chiaro_gpu::upload_gpu_scene);
    s
}

/// The median of `times`.
fn median(times: &mut [Duration]) -> Duration {
    times.sort();
    times[times.len() / 2]
}

/// Loads `file` `n` times side by side (2 units apart), runs every system once, then times
/// `frames` frames; returns each system's median time and the median bytes uploaded.
fn measure(
    context: &GpuContext,
    file: &str,
    n: usize,
    frames: usize,
) -> Result<([Duration; 5], u64), Error> {
    let mut world = World::new();
    for k in 0..n {
        let SpawnedScene { entities, .. } = load_scene(&mut world, file)?;
        for entity in entities {
            if world.get::<ChildOf>(entity).is_none()
                && let Some(mut t) = world.get_mut::<Transform>(entity)
            {
                t.translation += Vec3::new(2.0 * k as f32, 0.0, 0.0);
            }
        }
    }
    world.insert_resource(GpuScene::new(context));
    world.insert_resource(Time::default());
    let mut systems = schedules();
    for s in &mut systems {
        s.run(&mut world);
    }
    let mut times: [Vec<Duration>; 5] = Default::default();
    let mut bytes = Vec::with_capacity(frames);
    for frame in 1..=frames {
        world.resource_mut::<Time>().seconds = frame as f64 / 30.0;
        for (s, t) in systems.iter_mut().zip(&mut times) {
            let start = Instant::now();
            s.run(&mut world);
            t.push(start.elapsed());
        }
        bytes.push(world.resource::<GpuScene>().last.bytes);
        context.queue.submit(std::iter::empty());
        let _ = context.device.poll(wgpu::PollType::wait_indefinitely());
    }
    bytes.sort_unstable();
    Ok((times.map(|mut t| median(&mut t)), bytes[bytes.len() / 2]))
}

fn main() -> Result<(), Error> {
    let mut args = std::env::args().skip(1);
    let mut file = String::from("../shared/scenes/animated/CesiumMan.glb");
    let mut counts = vec![1usize, 4, 16, 64];
    let mut frames = 60;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--n" => {
                counts = args
                    .next()
                    .ok_or("--n needs counts")?
                    .split(',')
                    .map(str::parse)
                    .collect::<Result<_, _>>()?;
            }
            "--frames" => frames = args.next().ok_or("--frames needs a count")?.parse()?,
            other => file = other.to_owned(),
        }
    }
    let context = GpuContext::new_headless()?;
    println!(
        "{file} on {}, {frames} frames at 30 fps; median per frame:",
        context.describe()
    );
    println!(
        "| characters | {} | total ms | uploaded |",
        SYSTEMS.map(|s| format!("{s} ms")).join(" | ")
    );
    println!("|---|{}---|---|", "---|".repeat(SYSTEMS.len()));
    for n in counts {
        let (times, bytes) = measure(&context, &file, n, frames)?;
        let ms = times.map(|t| t.as_secs_f64() * 1e3);
        println!(
            "| {n} | {} | {:.2} | {:.1} MB |",
            ms.map(|m| format!("{m:.2}")).join(" | "),
            ms.iter().sum::<f64>(),
            bytes as f64 / 1e6
        );
    }
    Ok(())
}
