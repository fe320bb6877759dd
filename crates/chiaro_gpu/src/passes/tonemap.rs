//! `tonemap`: the HDR image through a tonemapping operator and the sRGB transfer function
//! into the 8-bit image.

use bytemuck::{Pod, Zeroable};
use chiaro_shading::tonemap::Tonemapper;

use super::{ComputeStage, view};
use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, LDR_FORMAT};

/// The pass's parameters (mirrored by `TonemapParams` in `shaders/tonemap.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct TonemapParams {
    /// 0 ACES fitted, 1 PBR Neutral, 2 clamp.
    pub operator: u32,
    /// Multiplies the linear radiance first.
    pub exposure: f32,
    /// Padding.
    pub pad: [u32; 2],
}

impl TonemapParams {
    /// The parameters for `tonemapper` at `exposure`.
    pub fn new(tonemapper: Tonemapper, exposure: f32) -> Self {
        let operator = match tonemapper {
            Tonemapper::AcesFitted => 0,
            Tonemapper::PbrNeutral => 1,
            Tonemapper::Clamp => 2,
        };
        Self {
            operator,
            exposure,
            pad: [0; 2],
        }
    }
}

/// The tonemap pass.
pub struct TonemapPass {
    stage: ComputeStage,
}

impl TonemapPass {
    /// The pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, params, texture};
        let entries = [
            e(
                0,
                texture(wgpu::TextureSampleType::Float { filterable: false }),
            ),
            e(1, params()),
            e(2, super::storage_texture(LDR_FORMAT)),
        ];
        Ok(Self {
            stage: ComputeStage::new(device, "tonemap", &entries)?,
        })
    }

    /// The pass's bind group.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        params: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        self.stage.bind_group(
            device,
            vec![
                view(&targets.hdr.view),
                params.as_entire_binding(),
                view(&targets.ldr.view),
            ],
        )
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
