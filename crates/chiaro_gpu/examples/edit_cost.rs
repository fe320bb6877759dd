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
//!   bytes written per edit, which buffers, and what the BVH did (re-insertions, rebuilds).
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
    world.insert_resource(GpuScene::new(&context.device, &context.queue));
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
        // A different sphere each time, spread over the grid; a nudge that keeps it in its cell.
        let entity = spheres[(edit * 7919) % spheres.len()];
        let angle = edit as f32 * 2.4;
        let nudge = Vec3::new(angle.cos(), 0.0, angle.sin()) * 0.05;
        world
            .get_mut::<Transform>(entity)
            .ok_or("an instance without a transform")?
            .translation += nudge;
        let start = Instant::now();
        schedule.run(&mut world);
        move_times.push(start.elapsed());
        bvh_times.push(Duration::from_secs_f64(
            world.resource::<BvhStats>().last_work_seconds,
        ));
        move_uploads.push(world.resource::<GpuScene>().last.clone());
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
    })
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
    println!(
        "| edit | CPU median (ms) | CPU p95 (ms) | BVH median (ms) | BVH p95 (ms) | bytes written | buffers written |"
    );
    println!("|---|---|---|---|---|---|---|");
    println!(
        "| move one instance ({edits} edits) | {:.3} | {:.3} | {:.3} | {:.3} | {:.0} mean, {} max | {} |",
        ms(quantile(&cost.move_times, 0.5)),
        ms(quantile(&cost.move_times, 0.95)),
        ms(quantile(&cost.bvh_times, 0.5)),
        ms(quantile(&cost.bvh_times, 0.95)),
        mean_bytes,
        bytes.iter().max().unwrap_or(&0),
        cost.move_buffers()
            .into_iter()
            .collect::<Vec<_>>()
            .join(", "),
    );
    println!(
        "| material base colour | | | | | {} ({} material record) | {} |",
        cost.material_upload.bytes,
        cost.material_records(),
        cost.material_upload.written().join(", "),
    );
    println!(
        "| no edit | | | | | {} | {} |",
        cost.idle_upload.bytes,
        cost.idle_upload.written().join(", ")
    );
    println!(
        "BVH over the moves: {} TLAS updates, {} TLAS rebuilds, {} BLAS builds",
        a.tlas_updates - b.tlas_updates,
        a.tlas_builds - b.tlas_builds,
        a.blas_builds - b.blas_builds
    );
    Ok(())
}
