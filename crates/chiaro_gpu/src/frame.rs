//! One frame, top-down: the passes in the order they run, with their uniforms and bind
//! groups, timed per pass.
//!
//! 1. `gbuffer` (raster): position, normals, material, emission, instance id, motion vectors,
//!    depth.
//! 2. `direct` (compute): emission + direct light with shadow rays, this frame's estimate.
//! 3. `composite` (compute): the running mean over frames, the linear HDR image.
//! 4. `tonemap` (compute): the HDR image to 8-bit sRGB.

use chiaro_shading::tonemap::Tonemapper;

use crate::camera::GpuCamera;
use crate::context::GpuContext;
use crate::gpu_scene::GpuScene;
use crate::passes::composite::{CompositeParams, CompositePass};
use crate::passes::direct::{DirectParams, DirectPass};
use crate::passes::gbuffer::GbufferPass;
use crate::passes::tonemap::{TonemapParams, TonemapPass};
use crate::shaders::ShaderError;
use crate::targets::FrameTargets;
use crate::timing::{PassTimer, PassTimes};

/// The passes in the order they run.
pub const PASSES: [&str; 4] = ["gbuffer", "direct", "composite", "tonemap"];

/// What one frame takes besides the scene and the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameInput {
    /// Frame number (picks the random numbers).
    pub frame: u32,
    /// Seed of the random numbers.
    pub seed: u64,
    /// Frames in the running mean including this one (1 restarts accumulation).
    pub accumulated: u32,
    /// Tonemapping operator.
    pub tonemapper: Tonemapper,
    /// Exposure multiplier before tonemapping.
    pub exposure: f32,
}

/// A uniform buffer holding one `T`.
fn uniform_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The frame's passes and their resources at one output size.
pub struct Frame {
    /// The images the passes write.
    pub targets: FrameTargets,
    gbuffer: GbufferPass,
    direct: DirectPass,
    composite: CompositePass,
    tonemap: TonemapPass,
    camera: wgpu::Buffer,
    direct_params: wgpu::Buffer,
    composite_params: wgpu::Buffer,
    tonemap_params: wgpu::Buffer,
    camera_group: wgpu::BindGroup,
    direct_group: wgpu::BindGroup,
    composite_group: wgpu::BindGroup,
    tonemap_group: wgpu::BindGroup,
    timer: PassTimer,
}

impl Frame {
    /// The passes for `scene` at `width` x `height`.
    pub fn new(
        context: &GpuContext,
        scene: &GpuScene,
        width: u32,
        height: u32,
    ) -> Result<Self, ShaderError> {
        let device = &context.device;
        let targets = FrameTargets::new(device, width, height);
        let gbuffer = GbufferPass::new(device, scene)?;
        let direct = DirectPass::new(device, scene)?;
        let composite = CompositePass::new(device)?;
        let tonemap = TonemapPass::new(device)?;
        let camera = uniform_buffer(device, "camera uniform", size_of::<GpuCamera>());
        let direct_params = uniform_buffer(device, "direct params", size_of::<DirectParams>());
        let composite_params =
            uniform_buffer(device, "composite params", size_of::<CompositeParams>());
        let tonemap_params = uniform_buffer(device, "tonemap params", size_of::<TonemapParams>());
        Ok(Self {
            camera_group: gbuffer.camera_bind_group(device, &camera),
            direct_group: direct.bind_group(device, &targets, &camera, &direct_params),
            composite_group: composite.bind_group(device, &targets, &composite_params),
            tonemap_group: tonemap.bind_group(device, &targets, &tonemap_params),
            timer: PassTimer::new(
                device,
                &context.queue,
                context.timestamps,
                PASSES.len() as u32,
            ),
            targets,
            gbuffer,
            direct,
            composite,
            tonemap,
            camera,
            direct_params,
            composite_params,
            tonemap_params,
        })
    }

    /// Renders one frame of `scene` seen by `camera` and returns the time of each pass.
    pub fn render(
        &mut self,
        context: &GpuContext,
        scene: &GpuScene,
        camera: &GpuCamera,
        input: &FrameInput,
    ) -> PassTimes {
        let (device, queue) = (&context.device, &context.queue);
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(camera));
        let direct = DirectParams {
            frame: input.frame,
            seed_lo: input.seed as u32,
            seed_hi: (input.seed >> 32) as u32,
            lights: 1,
        };
        queue.write_buffer(&self.direct_params, 0, bytemuck::bytes_of(&direct));
        let composite = CompositeParams {
            frames: input.accumulated.max(1),
            pad: [0; 3],
        };
        queue.write_buffer(&self.composite_params, 0, bytemuck::bytes_of(&composite));
        let tonemap = TonemapParams::new(input.tonemapper, input.exposure);
        queue.write_buffer(&self.tonemap_params, 0, bytemuck::bytes_of(&tonemap));

        let gpu = self.timer.gpu();
        let mut wall = Vec::new();
        let mut encoder = new_encoder(device);
        for (index, _) in PASSES.iter().enumerate() {
            let i = index as u32;
            if !gpu {
                self.timer.start_wall();
            }
            let t = &self.targets;
            match index {
                0 => self.gbuffer.record(
                    &mut encoder,
                    scene,
                    &self.camera_group,
                    t,
                    self.timer.render(i),
                ),
                1 => self.direct.record(
                    &mut encoder,
                    scene,
                    &self.direct_group,
                    t,
                    self.timer.compute(i),
                ),
                2 => self.composite.record(
                    &mut encoder,
                    &self.composite_group,
                    t,
                    self.timer.compute(i),
                ),
                _ => {
                    self.tonemap
                        .record(&mut encoder, &self.tonemap_group, t, self.timer.compute(i))
                }
            }
            if !gpu {
                queue.submit([std::mem::replace(&mut encoder, new_encoder(device)).finish()]);
                wall.push(self.timer.stop_wall(device));
            }
        }
        self.timer.resolve(&mut encoder, PASSES.len() as u32);
        queue.submit([encoder.finish()]);
        let millis = if gpu {
            self.timer
                .read(device, PASSES.len() as u32)
                .unwrap_or_else(|| vec![0.0; PASSES.len()])
        } else {
            wall
        };
        PassTimes {
            passes: PASSES.iter().copied().zip(millis).collect(),
            gpu_timestamps: gpu,
        }
    }
}

fn new_encoder(device: &wgpu::Device) -> wgpu::CommandEncoder {
    device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("frame encoder"),
    })
}
