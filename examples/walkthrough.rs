//! A scripted walkthrough: the camera flies along a smooth path through the Cornell box (a
//! Catmull-Rom spline through a few keyframes, eye and look-at point each), its `Transform`
//! set every frame like any other component, and each realtime frame (denoised, its history
//! reprojected along the motion) is rendered offscreen and written as a PNG.
//!
//! `cargo run --release --example walkthrough -- [OUT_DIR] [FRAMES] [SIZE]` (default
//! `walkthrough_frames`, 24 frames of 160x160: about a minute on a CPU Vulkan driver).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use bevy_ecs::prelude::World;
use chiaro::gpu::{RenderOutput, RenderSettings, Renderer};
use chiaro::scene::{ActiveCamera, Transform, load_scene};
use glam::Vec3;

/// The scene the walkthrough flies through.
pub const SCENE: &str = "builtin:cornell";

/// Keyframes: eye and look-at point, in metres. From the box's classic viewpoint in front of
/// the open side, in through it, round the blocks and up to look down on the short block.
pub const KEYFRAMES: [(Vec3, Vec3); 4] = [
    (Vec3::new(0.278, 0.273, -0.8), Vec3::new(0.278, 0.273, 0.28)),
    (Vec3::new(0.2, 0.3, -0.35), Vec3::new(0.3, 0.2, 0.35)),
    (Vec3::new(0.4, 0.35, -0.05), Vec3::new(0.15, 0.15, 0.4)),
    (Vec3::new(0.1, 0.45, 0.0), Vec3::new(0.25, 0.1, 0.3)),
];

/// The uniform Catmull-Rom spline through `p`, at `t` in [0, 1] over the whole path;
/// the end points are repeated so the path starts and ends at the first and last keyframe.
fn catmull_rom(p: &[Vec3], t: f32) -> Vec3 {
    let segments = p.len() - 1;
    let x = t.clamp(0.0, 1.0) * segments as f32;
    let i = (x.floor() as usize).min(segments - 1);
    let u = x - i as f32;
    let at = |k: isize| p[k.clamp(0, segments as isize) as usize];
    let (p0, p1, p2, p3) = (
        at(i as isize - 1),
        at(i as isize),
        at(i as isize + 1),
        at(i as isize + 2),
    );
    let (u2, u3) = (u * u, u * u * u);
    0.5 * (2.0 * p1
        + (p2 - p0) * u
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u2
        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * u3)
}

/// The camera's placement at `t` in [0, 1] along the path.
pub fn pose(t: f32) -> Transform {
    let eyes: Vec<Vec3> = KEYFRAMES.iter().map(|k| k.0).collect();
    let targets: Vec<Vec3> = KEYFRAMES.iter().map(|k| k.1).collect();
    Transform::looking_at(catmull_rom(&eyes, t), catmull_rom(&targets, t), Vec3::Y)
}

/// Where frame `frame` of `frames` lies on the path (the first at 0, the last at 1).
pub fn path_time(frame: u32, frames: u32) -> f32 {
    if frames <= 1 {
        1.0
    } else {
        frame as f32 / (frames - 1) as f32
    }
}

/// Puts the world's active camera at `transform`.
pub fn place_camera(world: &mut World, transform: Transform) -> Result<()> {
    let camera = world
        .get_resource::<ActiveCamera>()
        .context("the scene has no active camera")?
        .0;
    *world
        .get_mut::<Transform>(camera)
        .context("the camera has no transform")? = transform;
    Ok(())
}

/// Renders the walkthrough: `frames` realtime frames of `size` x `size` with `renderer`, the
/// camera moved along the path before each; with `out`, writes them there as `frame_NNN.png`.
pub fn walk(
    renderer: &mut Renderer,
    frames: u32,
    size: u32,
    out: Option<&Path>,
) -> Result<Vec<RenderOutput>> {
    let mut world = World::new();
    load_scene(&mut world, SCENE)?;
    let settings = RenderSettings {
        width: size,
        height: size,
        ..RenderSettings::default()
    };
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let mut images = Vec::with_capacity(frames as usize);
    for frame in 0..frames {
        place_camera(&mut world, pose(path_time(frame, frames)))?;
        // The renderer runs chiaro's systems (the camera's new transform propagates), then
        // renders one frame that continues the history.
        renderer.accumulate(&mut world, &settings, 1)?;
        let image = renderer.read(&settings)?;
        if let Some(dir) = out {
            let path = dir.join(format!("frame_{frame:03}.png"));
            image::RgbaImage::from_raw(size, size, image.ldr.clone())
                .context("image size")?
                .save(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
        images.push(image);
    }
    Ok(images)
}

// The example's entry point (a test includes this file for `walk` and does not call it).
#[allow(dead_code)]
fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "walkthrough_frames".into()));
    let mut number = |name: &str, default: u32| -> Result<u32> {
        match args.next() {
            Some(n) => n
                .parse()
                .with_context(|| format!("{name} must be a number")),
            None => Ok(default),
        }
    };
    let frames = number("FRAMES", 24)?;
    let size = number("SIZE", 160)?;
    let mut renderer = Renderer::new(chiaro::gpu::GpuContext::new_headless()?);
    let start = std::time::Instant::now();
    let images = walk(&mut renderer, frames, size, Some(&out))?;
    println!(
        "wrote {} frames of {size}x{size} to {} in {:.1} s",
        images.len(),
        out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
