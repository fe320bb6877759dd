//! `direct`: one frame's direct-light estimate per pixel from the G-buffer (see
//! `shaders/direct.wgsl`): emission, punctual lights, one MIS-weighted area-light sample and
//! one BRDF sample, each light sample with one shadow ray.

use bytemuck::{Pod, Zeroable};

use super::shading_pass::GbufferShadingPass;
use crate::gpu_scene::GpuScene;
use crate::shaders::ShaderError;
use crate::targets::FrameTargets;

/// Fraction of the distance to a sampled light point that a shadow ray tests, so that the
/// emitter does not occlude its own sample (the CPU reference's value).
pub const SHADOW_RAY_REACH: f32 = 1.0 - 1e-4;

/// The pass's uniform (mirrored by `DirectParams` in `shaders/direct.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct DirectParams {
    /// Frame number: picks the random stream with the pixel.
    pub frame: u32,
    /// Seed, low 32 bits.
    pub seed_lo: u32,
    /// Seed, high 32 bits.
    pub seed_hi: u32,
    /// 1: light sampling (every mode but naive); 0 (naive mode): covered pixels reflect no
    /// light in this pass (the indirect pass's paths carry all of it), uncovered pixels still
    /// show the environment.
    pub lights: u32,
}

/// The direct-light pass.
pub struct DirectPass {
    pass: GbufferShadingPass,
}

impl DirectPass {
    /// The pipeline for the scene's bind-group layout.
    pub fn new(device: &wgpu::Device, scene: &GpuScene) -> Result<Self, ShaderError> {
        Ok(Self {
            pass: GbufferShadingPass::new(device, scene, "direct")?,
        })
    }

    /// The pass's bind group over `targets`, the camera and the parameters.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        camera: &wgpu::Buffer,
        params: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        self.pass
            .bind_group(device, targets, camera, params, &targets.direct.view)
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
        self.pass.record(encoder, scene, group, targets, timestamps);
    }
}
