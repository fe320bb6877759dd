//! `direct`: one frame's direct-light estimate per pixel from the G-buffer (see
//! `shaders/direct.wgsl`): the light the surface reflects from punctual lights, one
//! MIS-weighted area-light sample and one BRDF sample, each light sample with one shadow ray;
//! and apart, the punctual lights' part when it has no sampling noise (every light evaluated),
//! and the BRDF ray's hit for the indirect pass. With resampled direct light, the area-light
//! sample is the pixel's final reservoir's (`passes::restir`).

use bytemuck::{Pod, Zeroable};

use super::shading_pass::{GbufferShadingPass, ShadingKind};
use crate::targets::{FIRST_BOUNCE_FORMAT, FrameTargets, HDR_FORMAT, Target};

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
    /// How a light is picked: `LIGHT_SAMPLING_POWER` or `LIGHT_SAMPLING_TREE`
    /// (`gpu_scene::layout`).
    pub light_sampling: u32,
    /// Most luminance of the BRDF sample and of the punctual light picked at random, a
    /// brighter one scaled down to it; 0: no clamp (`FrameSettings::firefly_clamp`, realtime
    /// mode only).
    pub firefly_clamp: f32,
    /// 1: the area-light sample is the final reservoir's of the resampling passes
    /// (`passes::restir`), where the pipeline has their code.
    pub restir: u32,
    /// 1: Owen-scrambled Sobol draws, `frame` being the pixel's sample index (the reference
    /// mode's frames accumulated before this one); 0: PCG32 streams.
    pub sampler: u32,
}

/// Selects the direct pass's shader and outputs: the direct light, the part of it from
/// punctual lights when every one is evaluated, and where its BRDF ray hit; its input, the
/// resampled reservoirs.
pub struct DirectKind;

impl ShadingKind for DirectKind {
    const NAME: &'static str = "direct";
    const OUTPUT_FORMATS: &'static [wgpu::TextureFormat] =
        &[HDR_FORMAT, HDR_FORMAT, FIRST_BOUNCE_FORMAT];
    const INPUTS: u32 = 1;

    fn outputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![
            &targets.direct,
            &targets.direct_punctual,
            &targets.first_bounce,
        ]
    }

    fn inputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.reservoirs]
    }
}

/// The direct-light pass.
pub type DirectPass = GbufferShadingPass<DirectKind>;
