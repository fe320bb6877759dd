//! `atrous`: the denoiser's edge-avoiding a-trous wavelet filter (see `shaders/atrous.wgsl`),
//! one dispatch per iteration with steps 1, 2, 4, ..., all in one compute pass.

use wgpu::TextureSampleType as S;

use super::{ComputeStage, view};
use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, HDR_FORMAT};

/// The a-trous pass.
pub struct AtrousPass {
    stage: ComputeStage,
}

impl AtrousPass {
    /// The pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, params, storage_texture, texture};
        let float = || texture(S::Float { filterable: false });
        let entries = [
            e(0, params()),
            e(1, float()),
            e(2, float()),
            e(3, storage_texture(HDR_FORMAT)),
            e(4, texture(S::Uint)),
            e(5, texture(S::Uint)),
        ];
        Ok(Self {
            stage: ComputeStage::new(device, "atrous", &entries)?,
        })
    }

    /// The bind group of one iteration: its parameters (with its step), the input (colour and
    /// variance), the edge data, the output, and the G-buffer's position and surface targets
    /// (roughness and metallic).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        params: wgpu::BufferBinding<'_>,
        views: [&wgpu::TextureView; 3],
        targets: &FrameTargets,
    ) -> wgpu::BindGroup {
        let [input, edges, output] = views;
        self.stage.bind_group(
            device,
            vec![
                wgpu::BindingResource::Buffer(params),
                view(input),
                view(edges),
                view(output),
                view(&targets.position.view),
                view(&targets.surface.view),
            ],
        )
    }

    /// Records the iterations (`groups`, in order) in one compute pass.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        groups: &[&wgpu::BindGroup],
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        self.stage.record(encoder, groups, targets, timestamps);
    }
}
