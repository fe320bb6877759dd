//! Helpers shared by the GPU tests.

use bevy_ecs::world::World;
use chiaro_gpu::{ContextError, GpuContext};
use chiaro_scene::{Environment, Materials, SceneBuilder};
use glam::{Vec3, Vec4};

/// A GPU context for a test, or `None` (after a message) when this machine has no adapter.
/// With the environment variable `CI` set, a missing or unusable adapter fails the test.
#[allow(dead_code)]
pub fn gpu() -> Option<GpuContext> {
    match GpuContext::new_headless() {
        Ok(context) => {
            eprintln!("GPU tests run on {}", context.describe());
            Some(context)
        }
        Err(e @ ContextError::NoAdapter { .. }) if std::env::var_os("CI").is_none() => {
            eprintln!("skipped: {e}");
            None
        }
        Err(e) => panic!("no usable GPU adapter: {e}"),
    }
}

/// relMSE as DESIGN.md defines it: mean((x - y)^2 / (y^2 + 0.01)) over pixels and channels.
#[allow(dead_code)]
pub fn rel_mse(x: &[Vec3], y: &[Vec3]) -> f64 {
    let sum: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| {
            let d = (*a - *b) * (*a - *b) / (*b * *b + Vec3::splat(0.01));
            f64::from(d.x + d.y + d.z)
        })
        .sum();
    sum / (3 * x.len()) as f64
}

/// relMSE (epsilon 0.01) over the pixels where `mask` is true; 0 for an empty mask.
#[allow(dead_code)]
pub fn masked_rel_mse(x: &[Vec3], y: &[Vec3], mask: &[bool]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for ((a, b), _) in x.iter().zip(y).zip(mask).filter(|(_, m)| **m) {
        let d = (*a - *b) * (*a - *b) / (*b * *b + Vec3::splat(0.01));
        sum += f64::from(d.x + d.y + d.z);
        n += 3;
    }
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// The pixels a comparison against a CPU reference `image` trusts: all but the `trimmed`
/// fraction whose two independent halves disagree most (fireflies of the reference: a path that
/// finds a bright emitter after a glossy bounce makes one pixel's halves differ by orders of
/// magnitude, and its relMSE then says nothing of the image compared with it).
#[allow(dead_code)]
pub fn trusted_pixels(halves: [&[Vec3]; 2], image: &[Vec3], trimmed: f64) -> Vec<bool> {
    let disagreement: Vec<f64> = halves[0]
        .iter()
        .zip(halves[1])
        .zip(image)
        .map(|((a, b), y)| {
            let d = (*a - *b) * (*a - *b) / (*y * *y + Vec3::splat(0.01));
            f64::from(d.x + d.y + d.z)
        })
        .collect();
    let mut sorted = disagreement.clone();
    sorted.sort_by(f64::total_cmp);
    let cut = sorted[((1.0 - trimmed) * sorted.len() as f64) as usize - 1];
    disagreement.iter().map(|d| *d <= cut).collect()
}

/// Renders the first frame of `world` with `settings`, then `frames - 1` more, turning the
/// active camera about the world's vertical by `degrees` more each frame from where it started
/// (a steady pan).
#[allow(dead_code)]
pub fn pan(
    renderer: &mut chiaro_gpu::Renderer,
    world: &mut bevy_ecs::world::World,
    settings: &chiaro_gpu::RenderSettings,
    frames: u32,
    degrees: f32,
) {
    use chiaro_scene::{ActiveCamera, Transform};
    let camera = world.resource::<ActiveCamera>().0;
    let start = world.get::<Transform>(camera).unwrap().rotation;
    renderer.render(world, settings).unwrap();
    for frame in 1..frames {
        let yaw = glam::Quat::from_rotation_y((degrees * frame as f32).to_radians());
        world.get_mut::<Transform>(camera).unwrap().rotation = yaw * start;
        renderer.accumulate(world, settings, 1).unwrap();
    }
}

/// Turns the Cornell box's red wall blue: an edit of `Materials` that moves nothing, so the
/// light the wall reflected onto the room changes with no motion to show it.
#[allow(dead_code)]
pub fn recolour_red_wall(world: &mut World) {
    let mut materials = world.resource_mut::<Materials>();
    let (id, _) = materials
        .iter()
        .find(|(_, m)| m.name == "red")
        .expect("the Cornell box has a red material");
    materials.get_mut(id).unwrap().base_color = Vec4::new(0.05, 0.065, 0.63, 1.0);
}

/// The scene built in `b`, seen from `eye` looking at the origin (45-degree perspective
/// camera) under a uniform white sky, spawned into a new World.
#[allow(dead_code)]
pub fn spawn_under_white_sky(mut b: SceneBuilder, eye: Vec3) -> World {
    b.add_camera(eye, Vec3::ZERO, 45.0);
    b.set_environment(Environment::constant(Vec3::ONE));
    let mut world = World::new();
    b.spawn(&mut world);
    world
}

/// The built-in Cornell box in a new world.
#[allow(dead_code)]
pub fn cornell() -> World {
    let mut world = World::new();
    chiaro_scene::load_scene(&mut world, "builtin:cornell").unwrap();
    world
}

/// A renderer, and the device and queue it renders with (for reading and writing its
/// targets); `None` where [`gpu`] is.
#[allow(dead_code)]
pub fn renderer_and_queue() -> Option<(chiaro_gpu::Renderer, wgpu::Device, wgpu::Queue)> {
    let context = gpu()?;
    let (device, queue) = (context.device.clone(), context.queue.clone());
    Some((chiaro_gpu::Renderer::new(context), device, queue))
}

/// Turns the active camera about the vertical by `degrees`.
#[allow(dead_code)]
pub fn turn(world: &mut World, degrees: f32) {
    use chiaro_scene::{ActiveCamera, Transform};
    let camera = world.resource::<ActiveCamera>().0;
    let mut transform = world.get_mut::<Transform>(camera).unwrap();
    transform.rotation = glam::Quat::from_rotation_y(degrees.to_radians()) * transform.rotation;
}

/// The words of an `rgba32uint` texture, four a texel, row by row.
#[allow(dead_code)]
pub fn read_words(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) -> Vec<u32> {
    let bytes = chiaro_gpu::readback::read_texture(device, queue, texture, 16).unwrap();
    bytemuck::pod_collect_to_vec(&bytes)
}

/// Overwrites an `rgba32uint` texture with `words`, four a texel, row by row.
#[allow(dead_code)]
pub fn write_words(queue: &wgpu::Queue, texture: &wgpu::Texture, words: &[u32]) {
    queue.write_texture(
        texture.as_image_copy(),
        bytemuck::cast_slice(words),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(16 * texture.width()),
            rows_per_image: None,
        },
        texture.size(),
    );
}
