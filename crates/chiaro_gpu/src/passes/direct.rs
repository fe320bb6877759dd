//! `direct`: one frame's direct-light estimate per pixel from the G-buffer (see
//! `shaders/direct.wgsl`): the light the surface reflects from punctual lights, one
//! MIS-weighted area-light sample and one BRDF sample, each light sample with one shadow ray.

use bytemuck::{Pod, Zeroable};
use wgpu::TextureSampleType as S;

use crate::gpu_scene::GpuScene;
use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, HDR_FORMAT};

/// Fraction of the distance to a sampled light point that a shadow ray tests, so that the
/// emitter does not occlude its own sample (the CPU reference's value).
pub const SHADOW_RAY_REACH: f32 = 1.0 - 1e-4;

/// The pass's uniform (mirrored by `DirectParams` in `shaders/direct.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct DirectParams {
    /// Frame number: picks the random stream with the pixel.
    pub frame: u32,
    /// Seed, low 32 bits.
    pub seed_lo: u32,
    /// Seed, high 32 bits.
    pub seed_hi: u32,
    /// 1: sample the lights; 0 (naive mode): covered pixels reflect nothing here (the naive
    /// paths of the indirect pass carry all their light).
    pub lights: u32,
}

/// The direct-light pass.
pub struct DirectPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl DirectPass {
    /// The pipeline for the scene's bind-group layout.
    pub fn new(device: &wgpu::Device, scene: &GpuScene) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, texture, uniform};
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("direct layout"),
            entries: &[
                e(0, texture(S::Uint)),
                e(1, texture(S::Uint)),
                e(2, texture(S::Uint)),
                e(3, uniform()),
                e(4, uniform()),
                e(5, super::storage_texture(HDR_FORMAT)),
            ],
        });
        let pipeline = super::compute_pipeline(
            device,
            "direct pipeline",
            "direct.wgsl",
            &[Some(scene.layout()), Some(&layout)],
        )?;
        Ok(Self { pipeline, layout })
    }

    /// The pass's bind group over `targets`, the camera and the parameters.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        camera: &wgpu::Buffer,
        params: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let view = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("direct bind group"),
            layout: &self.layout,
            entries: &[
                view(0, &targets.position.view),
                view(1, &targets.surface.view),
                view(2, &targets.emission.view),
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: camera.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: params.as_entire_binding(),
                },
                view(5, &targets.direct.view),
            ],
        })
    }

    /// Records the pass.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        group: &wgpu::BindGroup,
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let Some(scene_group) = scene.bind_group() else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("direct pass"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, scene_group, &[]);
        pass.set_bind_group(1, group, &[]);
        let (x, y) = super::workgroups(targets.width, targets.height);
        pass.dispatch_workgroups(x, y, 1);
    }
}
