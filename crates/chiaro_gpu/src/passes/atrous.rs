//! `atrous`: the denoiser's edge-avoiding a-trous wavelet filter (see `shaders/atrous.wgsl`),
//! one dispatch per iteration with steps 1, 2, 4, ..., all in one compute pass.

use wgpu::TextureSampleType as S;

use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, HDR_FORMAT};

/// The a-trous pass.
pub struct AtrousPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl AtrousPass {
    /// The pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, storage_texture, texture, uniform};
        let float = || texture(S::Float { filterable: false });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("atrous layout"),
            entries: &[
                e(0, uniform()),
                e(1, float()),
                e(2, float()),
                e(3, storage_texture(HDR_FORMAT)),
            ],
        });
        let pipeline =
            super::compute_pipeline(device, "atrous pipeline", "atrous.wgsl", &[Some(&layout)])?;
        Ok(Self { pipeline, layout })
    }

    /// The bind group of one iteration: its uniform (with its step), the input (colour and
    /// variance), the edge data and the output.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        params: wgpu::BufferBinding<'_>,
        views: [&wgpu::TextureView; 3],
    ) -> wgpu::BindGroup {
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(params),
        }];
        entries.extend(
            views
                .iter()
                .zip(1..)
                .map(|(view, binding)| wgpu::BindGroupEntry {
                    binding,
                    resource: wgpu::BindingResource::TextureView(view),
                }),
        );
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("atrous bind group"),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Records the iterations (`groups`, in order) in one compute pass.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        groups: &[&wgpu::BindGroup],
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        super::dispatch_per_pixel(
            encoder,
            "atrous pass",
            &self.pipeline,
            groups,
            targets,
            timestamps,
        );
    }
}
