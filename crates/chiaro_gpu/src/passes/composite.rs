//! `composite`: adds the frame's radiance to the running sum and writes the mean as the
//! linear HDR image (progressive accumulation over frames; restarts when told).

use bytemuck::{Pod, Zeroable};

use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, HDR_FORMAT};

/// The pass's uniform (mirrored by `CompositeParams` in `shaders/composite.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct CompositeParams {
    /// Frames in the sum after this one (1 restarts it).
    pub frames: u32,
    /// Padding.
    pub pad: [u32; 3],
}

/// The composite pass.
pub struct CompositePass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl CompositePass {
    /// The pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, storage, texture, uniform};
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("composite layout"),
            entries: &[
                e(
                    0,
                    texture(wgpu::TextureSampleType::Float { filterable: false }),
                ),
                e(1, storage(false)),
                e(2, uniform()),
                e(3, super::storage_texture(HDR_FORMAT)),
            ],
        });
        let pipeline = super::compute_pipeline(
            device,
            "composite pipeline",
            "composite.wgsl",
            &[Some(&layout)],
        )?;
        Ok(Self { pipeline, layout })
    }

    /// The pass's bind group.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        params: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("composite bind group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&targets.direct.view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: targets.accumulation.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&targets.hdr.view),
                },
            ],
        })
    }

    /// Records the pass.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        group: &wgpu::BindGroup,
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("composite pass"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        let (x, y) = super::workgroups(targets.width, targets.height);
        pass.dispatch_workgroups(x, y, 1);
    }
}
