//! `indirect`: one frame's indirect light per pixel from the G-buffer (see
//! `shaders/indirect.wgsl`): the mean of `spp` paths from the surface seen, with next-event
//! estimation and MIS at every later vertex and Russian roulette, up to `bounces` vertices
//! after the primary one, the first path leaving along the direct pass's BRDF ray; or, in
//! naive mode, paths of uniform hemisphere directions that carry all the light the surface
//! reflects.

use bytemuck::{Pod, Zeroable};

use super::shading_pass::{GbufferShadingPass, ShadingKind};
use crate::targets::{FrameTargets, HDR_FORMAT, Target};

/// The pass's uniform (mirrored by `IndirectParams` in `shaders/indirect.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct IndirectParams {
    /// Frame number: picks the random stream with the pixel.
    pub frame: u32,
    /// Seed, low 32 bits.
    pub seed_lo: u32,
    /// Seed, high 32 bits.
    pub seed_hi: u32,
    /// Paths per pixel (0 writes zero).
    pub spp: u32,
    /// Most vertices after the primary one at which a path gathers light: direct + indirect
    /// with `bounces` = b is the CPU reference with max_depth b + 1.
    pub bounces: u32,
    /// 1: naive path tracing (uniform hemisphere directions, no light sampling; the output is
    /// all the light the surface reflects); 0: BRDF sampling with next-event estimation.
    pub naive: u32,
    /// Test hook: nonzero writes NaN at pixel (0, 0) and +infinity at pixel (1, 0).
    pub poison: u32,
    /// How a light is picked: `LIGHT_SAMPLING_POWER` or `LIGHT_SAMPLING_TREE`
    /// (`gpu_scene::layout`).
    pub light_sampling: u32,
    /// Most luminance of one path's contribution, a brighter one scaled down to it; 0: no
    /// clamp (`FrameSettings::firefly_clamp`, realtime mode only).
    pub firefly_clamp: f32,
    /// 1: Owen-scrambled Sobol draws, `frame` being the pixel's sample index (the reference
    /// mode's frames accumulated before this one); 0: PCG32 streams.
    pub sampler: u32,
    /// Most count M of last frame's resampled-indirect reservoir merged by
    /// `restir_gi_initial` (`RestirSettings::indirect_history_cap`); 0: no temporal reuse.
    pub gi_history_cap: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}

/// Selects the indirect pass's shader, output and input (the direct pass's BRDF-ray hits).
pub struct IndirectKind;

impl ShadingKind for IndirectKind {
    const NAME: &'static str = "indirect";
    const OUTPUT_FORMATS: &'static [wgpu::TextureFormat] = &[HDR_FORMAT];
    const INPUTS: u32 = 1;

    fn outputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.indirect]
    }

    fn inputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.first_bounce]
    }
}

/// The indirect-light pass.
pub type IndirectPass = GbufferShadingPass<IndirectKind>;
