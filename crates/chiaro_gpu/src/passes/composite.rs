//! `composite`: the frame's radiance from its parts (emission, direct and indirect light, or
//! the denoiser's filtered lighting times the albedo), added to the running sum whose mean is
//! the linear HDR image (progressive accumulation over frames; restarts when told), or, in the
//! denoised realtime mode, resolved over frames along the motion vectors.

use bytemuck::{Pod, Zeroable};
use wgpu::TextureSampleType as S;

use super::{ComputeStage, view};
use crate::shaders::{ShaderError, SharedConstant};
use crate::targets::{FrameTargets, HDR_FORMAT, RESOLVE_SURFACE_FORMAT};

/// Source of the reflected light: the direct estimate only.
pub const COMPOSITE_DIRECT: u32 = 0;
/// Source of the reflected light: the direct and indirect estimates as they are.
pub const COMPOSITE_PATHS: u32 = 1;
/// Source of the reflected light: the denoiser's filtered lighting times the albedo.
pub const COMPOSITE_FILTERED: u32 = 2;
/// Flag: resolve the colour over frames along the motion vectors (temporal anti-aliasing).
pub const COMPOSITE_RESOLVE: u32 = 1;
/// Flag: the resolve's history restarts.
pub const COMPOSITE_RESET: u32 = 2;

/// The constants `shaders/composite.wgsl` shares.
pub fn constants() -> Vec<SharedConstant> {
    vec![
        SharedConstant::U32("COMPOSITE_DIRECT", COMPOSITE_DIRECT),
        SharedConstant::U32("COMPOSITE_PATHS", COMPOSITE_PATHS),
        SharedConstant::U32("COMPOSITE_FILTERED", COMPOSITE_FILTERED),
        SharedConstant::U32("COMPOSITE_RESOLVE", COMPOSITE_RESOLVE),
        SharedConstant::U32("COMPOSITE_RESET", COMPOSITE_RESET),
    ]
}

/// The pass's parameters (mirrored by `CompositeParams` in `shaders/composite.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct CompositeParams {
    /// Frames in the sum after this one (1 restarts it).
    pub frames: u32,
    /// Where the reflected light comes from: [`COMPOSITE_DIRECT`], [`COMPOSITE_PATHS`] or
    /// [`COMPOSITE_FILTERED`].
    pub source: u32,
    /// [`COMPOSITE_RESOLVE`] and [`COMPOSITE_RESET`].
    pub flags: u32,
    /// Least weight of this frame in the resolve's moving average on a still view
    /// ([`crate::still_view::history_floor`]).
    pub resolve_floor: f32,
    /// How much of the clamp to this frame's neighbourhood the resolve's history gets on a
    /// still view, 0 to 1 ([`crate::still_view::resolve_clamp`]); under motion all of it.
    pub resolve_clamp: f32,
}

/// The composite pass.
pub struct CompositePass {
    stage: ComputeStage,
}

impl CompositePass {
    /// The pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        use super::{compute_entry as e, params, storage, texture};
        let float = S::Float { filterable: false };
        let entries = [
            e(0, texture(float)),
            e(1, texture(float)),
            e(2, texture(float)),
            e(3, texture(S::Uint)),
            e(4, texture(S::Uint)),
            e(5, texture(S::Uint)),
            e(6, storage(false)),
            e(7, params()),
            e(8, super::storage_texture(HDR_FORMAT)),
            e(9, texture(S::Uint)),
            e(10, texture(float)),
            e(11, super::storage_texture(HDR_FORMAT)),
            e(12, texture(S::Uint)),
            e(13, super::storage_texture(RESOLVE_SURFACE_FORMAT)),
            e(14, texture(float)),
            e(15, params()),
        ];
        Ok(Self {
            stage: ComputeStage::new(device, "composite", &entries)?,
        })
    }

    /// The pass's bind group; `filtered` is the denoiser's output; the resolve reads
    /// `targets.resolve[parity]` and writes the other; `camera` holds the frame's
    /// [`crate::camera::GpuCamera`] (the motion of the environment seen).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        filtered: &wgpu::TextureView,
        params: &wgpu::Buffer,
        camera: &wgpu::Buffer,
        parity: usize,
    ) -> wgpu::BindGroup {
        self.stage.bind_group(
            device,
            vec![
                view(&targets.direct.view),
                view(&targets.indirect.view),
                view(filtered),
                view(&targets.position.view),
                view(&targets.surface.view),
                view(&targets.emission.view),
                targets.accumulation.as_entire_binding(),
                params.as_entire_binding(),
                view(&targets.hdr.view),
                view(&targets.motion.view),
                view(&targets.resolve[parity].view),
                view(&targets.resolve[1 - parity].view),
                view(&targets.resolve_surface[parity].view),
                view(&targets.resolve_surface[1 - parity].view),
                view(&targets.direct_punctual.view),
                camera.as_entire_binding(),
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
