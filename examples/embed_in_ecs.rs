//! Embedding chiaro in a bevy_ecs app that owns its main loop: the app keeps its own World and
//! Schedule, adds chiaro's systems (transform propagation, BVH upkeep, GPU upload) to that
//! schedule beside its own, animates its entities with its own system, and asks chiaro for one
//! offscreen frame per loop iteration, written as PNG: each image is read back without
//! waiting, and saved once it is there, so the frames stay in flight.
//!
//! `cargo run --release --example embed_in_ecs -- [OUT_DIR] [FRAMES]` (default `embed_frames`,
//! 8 frames of 256x256).
//!
//! Here the app loads the Cornell box, spawns a small warm point light and moves it on a circle
//! under the ceiling; the frames show the light and its shadows going round. What the frame
//! computes is the world's `FrameSettings` resource, which the app could edit like any other.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use bevy_ecs::prelude::{Component, Query, Res, Resource, Schedule, World};
use bevy_ecs::schedule::IntoScheduleConfigs;
use chiaro::gpu::{FrameSettings, GpuContext, RenderOutput, RenderSettings, Renderer};
use chiaro::scene::{Light, LightKind, Name, Transform, load_scene};
use glam::Vec3;

/// An entity the app moves on a horizontal circle.
#[derive(Component)]
pub struct Orbit {
    /// Centre of the circle.
    pub centre: Vec3,
    /// Radius of the circle.
    pub radius: f32,
    /// Radians per frame.
    pub step: f32,
}

/// The app's frame counter.
#[derive(Resource, Default)]
pub struct FrameCount(pub u32);

/// The app's system: puts every orbiting entity where the frame count says.
fn orbit(count: Res<FrameCount>, mut orbiting: Query<(&Orbit, &mut Transform)>) {
    for (orbit, mut transform) in &mut orbiting {
        let angle = orbit.step * count.0 as f32;
        let offset = Vec3::new(angle.cos(), 0.0, angle.sin()) * orbit.radius;
        transform.translation = orbit.centre + offset;
    }
}

/// The app's world: the Cornell box, an orbiting point light, and the frame settings.
pub fn app_world() -> Result<World> {
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell")?;
    let centre = Vec3::new(0.278, 0.35, 0.28);
    world.spawn((
        Name::new("orbiting light"),
        Light {
            kind: LightKind::Point,
            color: Vec3::new(1.0, 0.8, 0.6),
            intensity: 0.08,
            range: None,
        },
        Transform::from_translation(centre),
        Orbit {
            centre,
            radius: 0.15,
            step: std::f32::consts::TAU / 8.0,
        },
    ));
    world.insert_resource(FrameCount::default());
    world.insert_resource(FrameSettings::default());
    Ok(world)
}

/// Runs the app for `frames` frames of `size` x `size` on `context` and returns each frame's
/// image; with `out`, also writes them there as `frame_NNN.png`.
pub fn run_app(
    context: GpuContext,
    frames: u32,
    size: u32,
    out: Option<&Path>,
) -> Result<Vec<RenderOutput>> {
    let mut world = app_world()?;
    let mut renderer = Renderer::new(context);
    renderer.attach(&mut world);
    // The app's schedule: its own system, then chiaro's.
    let mut schedule = Schedule::default();
    schedule.add_systems(orbit.before(chiaro::scene::propagate_transforms));
    chiaro::gpu::add_gpu_scene_systems(&mut schedule);
    let settings = RenderSettings {
        width: size,
        height: size,
        ..RenderSettings::default()
    };
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let mut images = Vec::new();
    let mut keep = |image: RenderOutput| -> Result<()> {
        if let Some(dir) = out {
            let path = dir.join(format!("frame_{:03}.png", images.len()));
            image::RgbaImage::from_raw(size, size, image.ldr.clone())
                .context("image size")?
                .save(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
        images.push(image);
        Ok(())
    };
    // Each frame's image is copied on the GPU after it and taken once it is there, so the
    // frames stay in flight while the app saves them.
    let mut pending = VecDeque::new();
    for frame in 0..frames {
        world.resource_mut::<FrameCount>().0 = frame;
        schedule.run(&mut world);
        renderer.render_frame(&mut world, &settings)?;
        pending.push_back(renderer.read_later(&settings)?);
        let device = &renderer.context.device;
        while pending.front().is_some_and(|p| p.ready(device)) {
            keep(pending.pop_front().expect("a pending image").wait(device)?)?;
        }
    }
    for image in pending {
        keep(image.wait(&renderer.context.device)?)?;
    }
    Ok(images)
}

// The example's entry point (a test includes this file for `run_app` and does not call it).
#[allow(dead_code)]
fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "embed_frames".into()));
    let frames = match args.next() {
        Some(n) => n.parse().context("FRAMES must be a number")?,
        None => 8,
    };
    let context = GpuContext::new_headless()?;
    let images = run_app(context, frames, 256, Some(&out))?;
    println!("wrote {} frames to {}", images.len(), out.display());
    Ok(())
}
