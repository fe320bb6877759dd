//! The cost of an edit: CPU time of chiaro's scene systems (transform propagation, BVH upkeep,
//! GPU upload: the schedule [`chiaro_gpu::Renderer`] runs before each frame) when one instance
//! moves, and the bytes each edit writes to the GPU. Nothing is rendered.
//!
//! ```text
//! cargo run --release -p chiaro_gpu --example edit_cost -- [--n INSTANCES] [--edits EDITS]
//! ```
//!
//! On `builtin:instances?n=N` (default N = 10000, an icosphere instanced N times over a ground
//! plane), after the first upload and one idle frame:
//!
//! - move: `EDITS` times (default 200), one sphere (a different one each time, round the grid)
//!   is nudged by a few centimetres and the schedule runs once; the wall time of that run is
//!   the edit's cost. Each run also writes the previous move's instance extras (its previous
//!   transform catching up), as a frame does while an object is dragged. Reported: median and
//!   p95 of the schedule's time and of the BVH system's own time (`BvhStats::last_work_seconds`),
//!   the medians of each system's time over a second series of moves (each run alone),
//!   bytes written per edit, which buffers, and what the BVH did (re-insertions, rebuilds).
//!   After each timed run the queue is submitted and the device waited on, untimed, as a frame
//!   would (otherwise wgpu's staging for the writes piles up and some runs pay for it).
//! - material: one material's base colour changes; reported: bytes written, which buffers, and
//!   how many material records that is.
//! - idle: a run with no edit; reported: bytes written (none).
//!
//! `measure` is also run by `tests/edit_cost.rs` (counters only, not the timing).

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use bevy_ecs::prelude::*;
use chiaro_bvh::BvhStats;
use chiaro_gpu::gpu_scene::GpuMaterial;
use chiaro_gpu::{GpuContext, GpuScene, UploadStats, add_gpu_scene_systems};
use chiaro_scene::{MaterialId, Materials, MeshInstance, Transform, load_scene};
use glam::{Vec3, Vec4};

/// Any error of the example.
pub type Error = Box<dyn std::error::Error>;

/// What the edits cost.
#[derive(Debug)]
pub struct EditCost {
    /// Instances in the scene's TLAS.
    pub instances: u64,
    /// Wall time of the scheduled systems per move.
    pub move_times: Vec<Duration>,
    /// The BVH system's own time per move.
    pub bvh_times: Vec<Duration>,
    /// What each move's run uploaded.
    pub move_uploads: Vec<UploadStats>,
    /// The BVH counters before the first move and after the last.
    pub bvh_before: BvhStats,
    /// See `bvh_before`.
    pub bvh_after: BvhStats,
    /// What the material edit uploaded.
    pub material_upload: UploadStats,
    /// What a run without edits uploaded.
    pub idle_upload: UploadStats,
    /// Bytes the first upload wrote (the whole scene).
    pub first_upload_bytes: u64,
    /// Per move of a second series: the time of transform propagation, of the BVH update and
    /// of the upload, each run alone.
    pub part_times: Vec<[Duration; 3]>,
}

impl EditCost {
    /// Every buffer any move wrote to.
    pub fn move_buffers(&self) -> BTreeSet<&'static str> {
        self.move_uploads.iter().flat_map(|s| s.written()).collect()
    }

    /// Material records the material edit wrote.
    pub fn material_records(&self) -> u64 {
        self.material_upload.bytes_of("scene materials") / size_of::<GpuMaterial>() as u64
    }
}

/// The `q`-quantile (0..=1) of `times`, nearest rank.
pub fn quantile(times: &[Duration], q: f64) -> Duration {
    let mut sorted = times.to_vec();
    sorted.sort();
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

/// Loads `builtin:instances?n=N`, uploads it, then moves one sphere per run `edits` times,
/// edits one material and runs once idle, recording times and uploads.
pub fn measure(context: &GpuContext, n: usize, edits: usize) -> Result<EditCost, Error> {
    let mut world = World::new();
    load_scene(&mut world, &format!("builtin:instances?n={n}"))?;
    world.insert_resource(GpuScene::new(context));
    let mut schedule = Schedule::default();
    add_gpu_scene_systems(&mut schedule);
    schedule.run(&mut world);
    let first_upload_bytes = world.resource::<GpuScene>().last.bytes;
    schedule.run(&mut world);

    // The spheres share one mesh; the ground is the other.
    let mut query = world.query::<(Entity, &MeshInstance)>();
    let mut by_mesh: std::collections::HashMap<u32, Vec<Entity>> = Default::default();
    for (entity, instance) in query.iter(&world) {
        by_mesh.entry(instance.mesh.0).or_default().push(entity);
    }
    let spheres = by_mesh
        .into_values()
        .max_by_key(Vec::len)
        .ok_or("the scene has no instances")?;

    let bvh_before = world.resource::<BvhStats>().clone();
    let mut move_times = Vec::with_capacity(edits);
    let mut bvh_times = Vec::with_capacity(edits);
    let mut move_uploads = Vec::with_capacity(edits);
    for edit in 0..edits {
        nudge(&mut world, &spheres, edit)?;
        let start = Instant::now();
        schedule.run(&mut world);
        move_times.push(start.elapsed());
        bvh_times.push(Duration::from_secs_f64(
            world.resource::<BvhStats>().last_work_seconds,
        ));
        move_uploads.push(world.resource::<GpuScene>().last.clone());
        settle(context);
    }
    // The last move's previous transform catches up.
    schedule.run(&mut world);
    let bvh_after = world.resource::<BvhStats>().clone();

    let material = MaterialId(1);
    world
        .resource_mut::<Materials>()
        .get_mut(material)
        .ok_or("the scene has no material 1")?
        .base_color = Vec4::new(0.9, 0.1, 0.1, 1.0);
    schedule.run(&mut world);
    let material_upload = world.resource::<GpuScene>().last.clone();

    schedule.run(&mut world);
    let idle_upload = world.resource::<GpuScene>().last.clone();

    // The same moves again, the three systems each in a schedule of its own (in the same
    // order), to see where the time goes. A new system first sees everything as changed: one
    // untimed run each before the moves.
    let mut parts = [
        Schedule::default(),
        Schedule::default(),
        Schedule::default(),
    ];
    parts[0].add_systems(chiaro_scene::propagate_transforms);
    parts[1].add_systems(chiaro_bvh::update_scene_bvh);
    parts[2].add_systems(chiaro_gpu::upload_gpu_scene);
    for part in &mut parts {
        part.run(&mut world);
    }
    settle(context);
    let mut part_times = Vec::with_capacity(edits);
    for edit in 0..edits {
        nudge(&mut world, &spheres, edits + edit)?;
        part_times.push(parts.each_mut().map(|part| {
            let start = Instant::now();
            part.run(&mut world);
            start.elapsed()
        }));
        settle(context);
    }

    Ok(EditCost {
        instances: bvh_after.instances,
        move_times,
        bvh_times,
        move_uploads,
        bvh_before,
        bvh_after,
        material_upload,
        idle_upload,
        first_upload_bytes,
        part_times,
    })
}

/// Moves sphere number `edit` (a different one each time, spread over the grid) by a few
/// centimetres, within its cell.
fn nudge(world: &mut World, spheres: &[Entity], edit: usize) -> Result<(), Error> {
    let entity = spheres[(edit * 7919) % spheres.len()];
    let angle = edit as f32 * 2.4;
    world
        .get_mut::<Transform>(entity)
        .ok_or("an instance without a transform")?
        .translation += Vec3::new(angle.cos(), 0.0, angle.sin()) * 0.05;
    Ok(())
}

/// What a frame does after the systems, untimed: submit (the writes go with it) and wait;
/// otherwise wgpu's staging for the writes piles up and some runs pay for it.
fn settle(context: &GpuContext) {
    context.queue.submit(std::iter::empty());
    let _ = context.device.poll(wgpu::PollType::wait_indefinitely());
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

// The example's entry point (a test includes this file for `measure` and does not call it).
#[allow(dead_code)]
fn main() -> Result<(), Error> {
    let mut n = 10_000;
    let mut edits = 200;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let value = args.next().ok_or(format!("{arg} needs a value"))?;
        match arg.as_str() {
            "--n" => n = value.parse()?,
            "--edits" => edits = value.parse()?,
            _ => return Err(format!("unknown argument {arg} (expected --n or --edits)").into()),
        }
    }
    let context = GpuContext::new_headless()?;
    println!("adapter: {}", context.describe());
    let cost = measure(&context, n, edits)?;
    let moves = &cost.move_uploads;
    let bytes: Vec<u64> = moves.iter().map(|s| s.bytes).collect();
    let mean_bytes = bytes.iter().sum::<u64>() as f64 / bytes.len().max(1) as f64;
    let (b, a) = (&cost.bvh_before, &cost.bvh_after);
    println!(
        "builtin:instances?n={n}: {} instances, first upload {} bytes",
        cost.instances, cost.first_upload_bytes
    );
    let part = |k: usize| {
        let times: Vec<Duration> = cost.part_times.iter().map(|p| p[k]).collect();
        ms(quantile(&times, 0.5))
    };
    println!(
        "| edit | CPU median (ms) | CPU p95 (ms) | propagation / BVH / upload, medians (ms) | bytes written | buffers written |"
    );
    println!("|---|---|---|---|---|---|");
    println!(
        "| move one instance ({edits} edits) | {:.3} | {:.3} | {:.3} / {:.3} / {:.3} | {:.0} mean, {} max | {} |",
        ms(quantile(&cost.move_times, 0.5)),
        ms(quantile(&cost.move_times, 0.95)),
        part(0),
        part(1),
        part(2),
        mean_bytes,
        bytes.iter().max().unwrap_or(&0),
        cost.move_buffers()
            .into_iter()
            .collect::<Vec<_>>()
            .join(", "),
    );
    println!(
        "| material base colour | | | | {} ({} material record) | {} |",
        cost.material_upload.bytes,
        cost.material_records(),
        cost.material_upload.written().join(", "),
    );
    println!(
        "| no edit | | | | {} | {} |",
        cost.idle_upload.bytes,
        cost.idle_upload.written().join(", ")
    );
    println!(
        "BVH system's own time per move (BvhStats): median {:.3} ms, p95 {:.3} ms",
        ms(quantile(&cost.bvh_times, 0.5)),
        ms(quantile(&cost.bvh_times, 0.95))
    );
    println!(
        "BVH over the timed moves: {} TLAS updates, {} TLAS rebuilds, {} BLAS builds",
        a.tlas_updates - b.tlas_updates,
        a.tlas_builds - b.tlas_builds,
        a.blas_builds - b.blas_builds
    );
    Ok(())
}
