//! Rays per second of the WGSL BVH traversal (shaders/lib/bvh.wgsl) beside chiaro_bvh's CPU
//! traversal, in the same run, on the same rays.
//!
//! ```text
//! cargo run --release -p chiaro_gpu --example traversal_bench -- [--size WxH] [--n INSTANCES] [--scene SPEC]
//! ```
//!
//! The scene is `builtin:instances?n=N` by default (an 80-triangle icosphere instanced N times
//! over a ground plane; N = 12500 gives about a million instanced triangles). Three ray sets,
//! all made on the CPU and uploaded before timing:
//!
//! - primary: one ray per pixel from the scene's camera (closest hit);
//! - shadow: from every primary hit, offset off the surface, toward the sun (any hit);
//! - diffuse: from every primary hit, a cosine-weighted direction about the geometric normal
//!   (closest hit): incoherent rays.
//!
//! GPU time is the wall clock around one dispatch and its completion (after a warm-up
//! dispatch), the best of three; it includes writing 8 bytes of result per ray, not the upload.
//! CPU time is the best of three over every core (std threads, rays split evenly). The GPU's
//! answers are compared with the CPU's and the agreement printed.

use std::time::Instant;

use bevy_ecs::prelude::*;
use bytemuck::{Pod, Zeroable};
use chiaro_bvh::{GpuBvhBuffers, Ray, SceneBvh, offset_ray_origin};
use chiaro_gpu::gpu_scene::MirrorTexels;
use chiaro_gpu::shaders;
use chiaro_gpu::{GpuContext, UploadStats};
use chiaro_scene::{Camera, GlobalTransform, Light, LightKind, Projection};
use chiaro_shading::frame::Frame;
use chiaro_shading::rng::Pcg32;
use chiaro_shading::sampling::cosine_hemisphere;
use glam::{Vec2, Vec3};

const KERNEL: &str = r#"
#import lib/bvh.wgsl

struct BenchRay {
    origin: vec3<f32>,
    t_min: f32,
    direction: vec3<f32>,
    t_max: f32,
}

@group(1) @binding(0) var<storage, read> rays: array<BenchRay>;
@group(1) @binding(1) var<storage, read_write> results: array<vec2<u32>>;

fn hit_accepted(ray: Ray, instance: u32, triangle: u32, barycentrics: vec2<f32>) -> bool {
    return true;
}

@compute @workgroup_size(64)
fn closest(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&rays) {
        return;
    }
    let r = rays[i];
    let h = trace_closest(Ray(r.origin, r.t_min, r.direction), r.t_max);
    results[i] = vec2<u32>(h.instance, h.triangle);
}

@compute @workgroup_size(64)
fn occluded(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&rays) {
        return;
    }
    let r = rays[i];
    results[i] = vec2<u32>(select(0u, 1u, trace_any(Ray(r.origin, r.t_min, r.direction), r.t_max)), 0u);
}
"#;

/// Rays per dispatch (one dimension of 64-thread workgroups).
const MAX_DISPATCH: usize = 65_535 * 64;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct BenchRay {
    origin: [f32; 3],
    t_min: f32,
    direction: [f32; 3],
    t_max: f32,
}

impl From<&Ray> for BenchRay {
    fn from(r: &Ray) -> Self {
        Self {
            origin: r.origin.to_array(),
            t_min: r.t_min,
            direction: r.direction.to_array(),
            t_max: r.t_max,
        }
    }
}

struct Options {
    width: u32,
    height: u32,
    scene: String,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        width: 256,
        height: 256,
        scene: "builtin:instances?n=12500".into(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = || args.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--size" => {
                let v = value()?;
                let (w, h) = v
                    .split_once('x')
                    .ok_or(format!("--size {v}: expected WxH"))?;
                o.width = w.parse().map_err(|_| format!("--size {v}: bad width"))?;
                o.height = h.parse().map_err(|_| format!("--size {v}: bad height"))?;
            }
            "--n" => o.scene = format!("builtin:instances?n={}", value()?),
            "--scene" => o.scene = value()?,
            other => return Err(format!("unknown argument {other}")),
        }
    }
    if o.width == 0 || o.height == 0 || (o.width as usize * o.height as usize) > MAX_DISPATCH {
        return Err(format!(
            "--size {}x{}: 1 to {MAX_DISPATCH} pixels",
            o.width, o.height
        ));
    }
    Ok(o)
}

/// Primary rays through pixel centres of the active camera (glTF pinhole or orthographic).
fn primary_rays(world: &mut World, camera: Entity, width: u32, height: u32) -> Vec<Ray> {
    let projection = world.get::<Camera>(camera).map(|c| c.projection);
    let transform = world
        .get::<GlobalTransform>(camera)
        .map_or(Default::default(), |g| g.0);
    let aspect = width as f32 / height as f32;
    let mut rays = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let ndc = Vec2::new(
                2.0 * (x as f32 + 0.5) / width as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / height as f32,
            );
            let (origin, direction) = match projection {
                Some(Projection::Orthographic { xmag, ymag, .. }) => {
                    (Vec3::new(ndc.x * xmag, ndc.y * ymag, 0.0), Vec3::NEG_Z)
                }
                Some(Projection::Perspective { yfov, .. }) => {
                    let half = (0.5 * yfov).tan();
                    (
                        Vec3::ZERO,
                        Vec3::new(ndc.x * half * aspect, ndc.y * half, -1.0),
                    )
                }
                None => (Vec3::ZERO, Vec3::new(ndc.x * aspect, ndc.y, -1.0)),
            };
            rays.push(Ray::new(
                transform.transform_point3(origin),
                transform.transform_vector3(direction).normalize(),
            ));
        }
    }
    rays
}

/// Toward the first directional light (its light travels along its local -Z), or a default sun.
fn sun_direction(world: &mut World) -> Vec3 {
    let mut query = world.query::<(&Light, &GlobalTransform)>();
    query
        .iter(world)
        .find(|(l, _)| matches!(l.kind, LightKind::Directional))
        .map(|(_, g)| -g.0.transform_vector3(Vec3::NEG_Z).normalize())
        .unwrap_or(Vec3::new(0.3, 1.0, 0.2).normalize())
}

/// Runs `f` over `items` split evenly across every core; returns the results in order.
fn parallel<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = items.len().div_ceil(threads).max(1);
    std::thread::scope(|s| {
        let workers: Vec<_> = items
            .chunks(chunk)
            .map(|part| s.spawn(|| part.iter().map(&f).collect::<Vec<R>>()))
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a tracing thread panicked"))
            .collect()
    })
}

/// Bind group entries for `buffers` at bindings 0, 1, ...
fn entries<'a>(buffers: &[&'a wgpu::Buffer]) -> Vec<wgpu::BindGroupEntry<'a>> {
    buffers
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect()
}

/// The WGSL traversal with the scene's BVH bound.
struct GpuTracer {
    closest: wgpu::ComputePipeline,
    occluded: wgpu::ComputePipeline,
    /// The BVH's texel arrays at bindings 0, 1, 2 and 4.
    texels: Vec<(u32, wgpu::TextureView)>,
    /// The instances at binding 3.
    instances: wgpu::Buffer,
}

/// `records` as a texel array, uploaded as the scene uploads it.
fn texel_array<T: Pod + PartialEq>(
    gpu: &GpuContext,
    label: &'static str,
    records: &[T],
) -> Result<wgpu::TextureView, String> {
    let mut array = MirrorTexels::<T>::new(&gpu.device, label);
    array
        .update(
            &gpu.device,
            &gpu.queue,
            records,
            &mut UploadStats::default(),
        )
        .map_err(|e| e.to_string())?;
    Ok(array.view().clone())
}

fn storage(gpu: &GpuContext, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    let size = (bytes.len().max(4) as u64).next_multiple_of(4);
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | usage,
        mapped_at_creation: false,
    });
    gpu.queue.write_buffer(&buffer, 0, bytes);
    buffer
}

impl GpuTracer {
    fn new(gpu: &GpuContext, buffers: &GpuBvhBuffers) -> Result<Self, String> {
        let source = shaders::compose_with("traversal_bench.wgsl", &|name| {
            if name == "traversal_bench.wgsl" {
                Some(KERNEL.to_owned())
            } else {
                shaders::source(name)
            }
        })
        .map_err(|e| e.to_string())?;
        let module = gpu
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("traversal bench"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        let pipeline = |entry: &str| {
            gpu.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
        };
        Ok(Self {
            closest: pipeline("closest"),
            occluded: pipeline("occluded"),
            texels: vec![
                (0, texel_array(gpu, "bvh blas nodes", &buffers.blas_nodes)?),
                (1, texel_array(gpu, "bvh triangles", &buffers.triangles)?),
                (2, texel_array(gpu, "bvh tlas nodes", &buffers.tlas_nodes)?),
                (4, texel_array(gpu, "bvh instances", &buffers.instances)?),
            ],
            instances: storage(
                gpu,
                "bvh instances",
                bytemuck::cast_slice(&buffers.instances),
                wgpu::BufferUsages::empty(),
            ),
        })
    }

    /// Traces `rays` (closest hit, or any hit with `occlusion`): the best of three timed
    /// dispatches after a warm-up, in seconds, and the results.
    fn trace(&self, gpu: &GpuContext, rays: &[Ray], occlusion: bool) -> (f64, Vec<[u32; 2]>) {
        let pipeline = if occlusion {
            &self.occluded
        } else {
            &self.closest
        };
        let data: Vec<BenchRay> = rays.iter().map(BenchRay::from).collect();
        let ray_buffer = storage(
            gpu,
            "bench rays",
            bytemuck::cast_slice(&data),
            wgpu::BufferUsages::empty(),
        );
        let size = (rays.len() * 8).max(8) as u64;
        let results = storage(
            gpu,
            "bench results",
            &vec![0u8; size as usize],
            wgpu::BufferUsages::COPY_SRC,
        );
        let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bench readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut bvh_entries: Vec<_> = self
            .texels
            .iter()
            .map(|(binding, view)| wgpu::BindGroupEntry {
                binding: *binding,
                resource: wgpu::BindingResource::TextureView(view),
            })
            .collect();
        bvh_entries.push(wgpu::BindGroupEntry {
            binding: 3,
            resource: self.instances.as_entire_binding(),
        });
        let scene = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bench bvh"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &bvh_entries,
        });
        let io = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bench rays"),
            layout: &pipeline.get_bind_group_layout(1),
            entries: &entries(&[&ray_buffer, &results]),
        });
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("upload");
        let mut best = f64::INFINITY;
        for run in 0..4 {
            let mut encoder = gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("bench dispatch"),
                });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("bench trace"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &scene, &[]);
                pass.set_bind_group(1, &io, &[]);
                pass.dispatch_workgroups((rays.len() as u32).div_ceil(64).max(1), 1, 1);
            }
            let start = Instant::now();
            gpu.queue.submit([encoder.finish()]);
            gpu.device
                .poll(wgpu::PollType::wait_indefinitely())
                .expect("dispatch");
            if run > 0 {
                best = best.min(start.elapsed().as_secs_f64());
            }
        }
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("bench readback"),
            });
        encoder.copy_buffer_to_buffer(&results, 0, &readback, 0, size);
        gpu.queue.submit([encoder.finish()]);
        readback.map_async(wgpu::MapMode::Read, .., |r| r.expect("map"));
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("readback");
        let view = readback.get_mapped_range(..).expect("mapped");
        let out = bytemuck::cast_slice::<u8, [u32; 2]>(&view)[..rays.len()].to_vec();
        drop(view);
        readback.unmap();
        (best, out)
    }
}

/// CPU answers in the GPU's encoding, and the best of three times.
fn cpu_trace(bvh: &SceneBvh, rays: &[Ray], occlusion: bool) -> (f64, Vec<[u32; 2]>) {
    let mut best = f64::INFINITY;
    let mut out = Vec::new();
    for _ in 0..3 {
        let start = Instant::now();
        out = parallel(rays, |r| {
            if occlusion {
                [u32::from(bvh.any_hit(r)), 0]
            } else {
                bvh.closest_hit(r)
                    .map_or([u32::MAX, 0], |h| [h.instance, h.triangle])
            }
        });
        best = best.min(start.elapsed().as_secs_f64());
    }
    (best, out)
}

fn main() -> Result<(), String> {
    let o = options()?;
    let mut world = World::new();
    let spawned = chiaro_scene::load_scene(&mut world, &o.scene).map_err(|e| e.to_string())?;
    let build = Instant::now();
    let bvh = SceneBvh::build(&mut world);
    let build_seconds = build.elapsed().as_secs_f64();
    let triangles: usize = bvh
        .instances()
        .iter()
        .map(|r| bvh.blas(r.mesh).map_or(0, |b| b.triangle_count()))
        .sum();
    let buffers = GpuBvhBuffers::from_scene(&bvh);
    let gpu = GpuContext::new_headless().map_err(|e| e.to_string())?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("adapter: {}", gpu.describe());
    println!(
        "scene: {} ({} instances, {triangles} instanced triangles, BVH built in {build_seconds:.2} s, {:.1} MB on the GPU)",
        o.scene,
        bvh.instances().len(),
        buffers.byte_size() as f64 / 1e6
    );
    println!("image: {}x{}; CPU: {threads} threads", o.width, o.height);

    let primary = primary_rays(&mut world, spawned.camera, o.width, o.height);
    let sun = sun_direction(&mut world);
    let hits: Vec<_> = parallel(&primary, |r| bvh.closest_hit(r));
    let mut rng = Pcg32::new(7, 0);
    let mut shadow = Vec::new();
    let mut diffuse = Vec::new();
    for (ray, hit) in primary.iter().zip(&hits) {
        let Some(hit) = hit else { continue };
        let (Some(p), Some(n)) = (bvh.hit_point(hit), bvh.geometric_normal(hit)) else {
            continue;
        };
        let n = if n.dot(ray.direction) > 0.0 { -n } else { n };
        let origin = offset_ray_origin(p, n);
        shadow.push(Ray::new(origin, sun));
        let d = Frame::from_normal(n).to_world(cosine_hemisphere(rng.next_vec2()));
        diffuse.push(Ray::new(origin, d));
    }
    let tracer = GpuTracer::new(&gpu, &buffers)?;
    println!(
        "{:<8} {:>9} {:>12} {:>12} {:>9} {:>10}",
        "rays", "count", "GPU Mray/s", "CPU Mray/s", "GPU/CPU", "agreement"
    );
    for (name, rays, occlusion) in [
        ("primary", &primary, false),
        ("shadow", &shadow, true),
        ("diffuse", &diffuse, false),
    ] {
        if rays.is_empty() {
            println!("{name:<8} {:>9}", 0);
            continue;
        }
        let (gpu_seconds, gpu_out) = tracer.trace(&gpu, rays, occlusion);
        let (cpu_seconds, cpu_out) = cpu_trace(&bvh, rays, occlusion);
        let same = gpu_out.iter().zip(&cpu_out).filter(|(a, b)| a == b).count();
        let g = rays.len() as f64 / gpu_seconds / 1e6;
        let c = rays.len() as f64 / cpu_seconds / 1e6;
        println!(
            "{name:<8} {:>9} {g:>12.2} {c:>12.2} {:>9.2} {:>9.4}%",
            rays.len(),
            g / c,
            100.0 * same as f64 / rays.len() as f64
        );
    }
    Ok(())
}
