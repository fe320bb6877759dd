//! `temporal`: the denoiser's temporal accumulation (see `shaders/temporal.wgsl`): this frame's
//! demodulated lighting blended into the reprojected history, with luminance moments, history
//! length, the edge data of the filters and the raw demodulated lighting.

use wgpu::TextureSampleType as S;

use super::{ComputeStage, view};
use crate::shaders::ShaderError;
use crate::targets::{FrameTargets, HDR_FORMAT};

/// What the temporal pass reads besides the frame's targets, and what it writes.
pub struct TemporalResources<'a> {
    /// The camera uniform.
    pub camera: &'a wgpu::Buffer,
    /// The denoiser's uniform (`DenoiseParams`).
    pub params: wgpu::BufferBinding<'a>,
    /// The previous frame's G-buffer position, surface and emission.
    pub previous: [&'a wgpu::TextureView; 3],
    /// Last frame's colour history.
    pub color_history: &'a wgpu::TextureView,
    /// Last frame's moments and history length.
    pub moments_history: &'a wgpu::TextureView,
    /// Out: the integrated colour.
    pub integrated: &'a wgpu::TextureView,
    /// Out: moments and history length.
    pub moments: &'a wgpu::TextureView,
    /// Out: depth, depth gradient and normal per pixel.
    pub edges: &'a wgpu::TextureView,
    /// Out: this frame's demodulated lighting, unfiltered.
    pub lighting: &'a wgpu::TextureView,
}

/// The temporal pass.
pub struct TemporalPass {
    stage: ComputeStage,
}

impl TemporalPass {
    /// The pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, params, storage_texture, texture};
        let float = || texture(S::Float { filterable: false });
        let mut entries = vec![e(0, params()), e(1, params()), e(2, float()), e(3, float())];
        entries.extend((4..=10).map(|b| e(b, texture(S::Uint))));
        entries.extend([e(11, float()), e(12, float())]);
        entries.extend((13..=16).map(|b| e(b, storage_texture(HDR_FORMAT))));
        entries.push(e(17, float()));
        Ok(Self {
            stage: ComputeStage::new(device, "temporal", &entries)?,
        })
    }

    /// The pass's bind group.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        r: &TemporalResources<'_>,
    ) -> wgpu::BindGroup {
        let views = [
            &targets.direct.view,
            &targets.indirect.view,
            &targets.position.view,
            &targets.surface.view,
            &targets.emission.view,
            &targets.motion.view,
            r.previous[0],
            r.previous[1],
            r.previous[2],
            r.color_history,
            r.moments_history,
            r.integrated,
            r.moments,
            r.edges,
            r.lighting,
            &targets.direct_punctual.view,
        ];
        let mut resources = vec![
            r.camera.as_entire_binding(),
            wgpu::BindingResource::Buffer(r.params.clone()),
        ];
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
