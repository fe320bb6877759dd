//! `variance`: the denoiser's luminance variance per pixel (see `shaders/variance.wgsl`): from
//! the temporal moments, or a 7 x 7 spatial estimate while the history is short; writes the
//! colour with the variance in alpha for the a-trous filter.

use wgpu::TextureSampleType as S;

use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, HDR_FORMAT};

/// The variance pass.
pub struct VariancePass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl VariancePass {
    /// The pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, storage_texture, texture, uniform};
        let float = || texture(S::Float { filterable: false });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("variance layout"),
            entries: &[
                e(0, uniform()),
                e(1, float()),
                e(2, float()),
                e(3, float()),
                e(4, storage_texture(HDR_FORMAT)),
            ],
        });
        let pipeline = super::compute_pipeline(
            device,
            "variance pipeline",
            "variance.wgsl",
            &[Some(&layout)],
        )?;
        Ok(Self { pipeline, layout })
    }

    /// The pass's bind group: the uniform, the integrated colour, the moments, the edge data
    /// and the output (colour and variance).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        params: wgpu::BufferBinding<'_>,
        views: [&wgpu::TextureView; 4],
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
            label: Some("variance bind group"),
            layout: &self.layout,
            entries: &entries,
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
        super::dispatch_per_pixel(
            encoder,
            "variance pass",
            &self.pipeline,
            &[group],
            targets,
            timestamps,
        );
    }
}
