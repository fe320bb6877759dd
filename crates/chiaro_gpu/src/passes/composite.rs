//! `composite`: the frame's radiance from its parts (emission, direct and indirect light, or
//! the denoiser's filtered lighting times the albedo), added to the running sum whose mean is
//! the linear HDR image (progressive accumulation over frames; restarts when told), or, in the
//! denoised realtime mode, resolved over frames along the motion vectors.

use bytemuck::{Pod, Zeroable};
use wgpu::TextureSampleType as S;

use crate::shaders::{ShaderError, SharedConstant};
use crate::targets::{FrameTargets, HDR_FORMAT};

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

/// The pass's uniform (mirrored by `CompositeParams` in `shaders/composite.wgsl`).
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
    /// Least weight of this frame in the resolve's moving average.
    pub resolve_floor: f32,
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
        let float = S::Float { filterable: false };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("composite layout"),
            entries: &[
                e(0, texture(float)),
                e(1, texture(float)),
                e(2, texture(float)),
                e(3, texture(S::Uint)),
                e(4, texture(S::Uint)),
                e(5, texture(S::Uint)),
                e(6, storage(false)),
                e(7, uniform()),
                e(8, super::storage_texture(HDR_FORMAT)),
                e(9, texture(S::Uint)),
                e(10, storage(true)),
                e(11, storage(false)),
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

    /// The pass's bind group; `filtered` is the denoiser's output; the resolve reads
    /// `targets.resolve[parity]` and writes the other.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        filtered: &wgpu::TextureView,
        params: &wgpu::Buffer,
        parity: usize,
    ) -> wgpu::BindGroup {
        let view = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("composite bind group"),
            layout: &self.layout,
            entries: &[
                view(0, &targets.direct.view),
                view(1, &targets.indirect.view),
                view(2, filtered),
                view(3, &targets.position.view),
                view(4, &targets.surface.view),
                view(5, &targets.emission.view),
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: targets.accumulation.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: params.as_entire_binding(),
                },
                view(8, &targets.hdr.view),
                view(9, &targets.motion.view),
                wgpu::BindGroupEntry {
                    binding: 10,
                    resource: targets.resolve[parity].as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 11,
                    resource: targets.resolve[1 - parity].as_entire_binding(),
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
        super::dispatch_per_pixel(
            encoder,
            "composite pass",
            &self.pipeline,
            &[group],
            targets,
            timestamps,
        );
    }
}
