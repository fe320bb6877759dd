//! `indirect`: one frame's indirect light per pixel from the G-buffer (see
//! `shaders/indirect.wgsl`): `spp` paths from the surface the camera sees, the light they
//! gather after the first bounce.

use bytemuck::{Pod, Zeroable};
use wgpu::TextureSampleType as S;

use crate::gpu_scene::GpuScene;
use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, HDR_FORMAT};

/// The pass's uniform (mirrored by `IndirectParams` in `shaders/indirect.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct IndirectParams {
    /// Frame number: picks the random stream with the pixel.
    pub frame: u32,
    /// Seed, low 32 bits.
    pub seed_lo: u32,
    /// Seed, high 32 bits.
    pub seed_hi: u32,
    /// Paths per pixel.
    pub spp: u32,
    /// Most surfaces after the one the camera sees at which a path gathers light.
    pub bounces: u32,
    /// 1: the naive paths (uniform hemisphere directions, no light sampling).
    pub naive: u32,
    /// Test hook: when not 0, pixel (0, 0) writes NaN and pixel (1, 0) +Inf.
    pub poison: u32,
    /// Padding.
    pub pad: u32,
}

/// The indirect-light pass.
pub struct IndirectPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl IndirectPass {
    /// The pipeline for the scene's bind-group layout.
    pub fn new(device: &wgpu::Device, scene: &GpuScene) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, texture, uniform};
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("indirect layout"),
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
            "indirect pipeline",
            "indirect.wgsl",
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
            label: Some("indirect bind group"),
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
                view(5, &targets.indirect.view),
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
            label: Some("indirect pass"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, scene_group, &[]);
        pass.set_bind_group(1, group, &[]);
        let (x, y) = super::workgroups(targets.width, targets.height);
        pass.dispatch_workgroups(x, y, 1);
    }
}
