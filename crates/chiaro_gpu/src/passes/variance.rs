//! `variance`: the denoiser's luminance variance per pixel (see `shaders/variance.wgsl`): from
//! the temporal moments, or a 7 x 7 spatial estimate while the history is short; writes the
//! colour with the variance in alpha for the a-trous filter.

use wgpu::TextureSampleType as S;

use super::{ComputeStage, view};
use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, HDR_FORMAT};

/// The variance pass.
pub struct VariancePass {
    stage: ComputeStage,
}

impl VariancePass {
    /// The pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, params, storage_texture, texture};
        let float = || texture(S::Float { filterable: false });
        let entries = [
            e(0, params()),
            e(1, float()),
            e(2, float()),
            e(3, float()),
            e(4, storage_texture(HDR_FORMAT)),
        ];
        Ok(Self {
            stage: ComputeStage::new(device, "variance", &entries)?,
        })
    }

    /// The pass's bind group: the parameters, the integrated colour, the moments, the edge data
    /// and the output (colour and variance).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        params: wgpu::BufferBinding<'_>,
        views: [&wgpu::TextureView; 4],
    ) -> wgpu::BindGroup {
        let mut resources = vec![wgpu::BindingResource::Buffer(params)];
        resources.extend(views.map(view));
        self.stage.bind_group(device, resources)
    }

    /// Records the pass.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        group: &wgpu::BindGroup,
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        self.stage.record(encoder, &[group], targets, timestamps);
    }
}
