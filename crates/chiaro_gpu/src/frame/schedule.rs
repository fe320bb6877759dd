//! The passes a frame runs, in order, by its settings.

use crate::settings::{FrameSettings, RenderMode};

/// A pass of the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// G-buffer, rasterized or traced.
    Gbuffer,
    /// Resampled direct light: candidates and temporal reuse.
    RestirTemporal,
    /// Resampled direct light: spatial reuse.
    RestirSpatial,
    /// Direct light with shadow rays.
    Direct,
    /// Indirect paths.
    Indirect,
    /// Resampled indirect light: one path a pixel kept as a sample.
    RestirGiInitial,
    /// Resampled indirect light: spatial reuse, written as the indirect light.
    RestirGiSpatial,
    /// Denoiser: temporal accumulation.
    Temporal,
    /// Denoiser: variance estimation.
    Variance,
    /// Denoiser: a-trous filter, all iterations.
    Atrous,
    /// Composite and accumulation.
    Composite,
    /// Tonemapping.
    Tonemap,
}

impl Pass {
    /// The pass's name (its file names and its entry in [`PassTimes`]).
    pub fn name(self) -> &'static str {
        match self {
            Pass::Gbuffer => "gbuffer",
            Pass::RestirTemporal => "restir_temporal",
            Pass::RestirSpatial => "restir_spatial",
            Pass::Direct => "direct",
            Pass::Indirect => "indirect",
            Pass::RestirGiInitial => "restir_gi_initial",
            Pass::RestirGiSpatial => "restir_gi_spatial",
            Pass::Temporal => "temporal",
            Pass::Variance => "variance",
            Pass::Atrous => "atrous",
            Pass::Composite => "composite",
            Pass::Tonemap => "tonemap",
        }
    }
}

/// Most passes a frame runs.
pub(crate) const MAX_PASSES: u32 = 11;

/// The passes a frame of `settings` runs, in order.
pub fn passes(settings: &FrameSettings) -> Vec<Pass> {
    let mut passes = vec![Pass::Gbuffer];
    if settings.resamples_direct_light() {
        passes.extend([Pass::RestirTemporal, Pass::RestirSpatial]);
    }
    passes.push(Pass::Direct);
    if settings.resamples_indirect_light() {
        passes.extend([Pass::RestirGiInitial, Pass::RestirGiSpatial]);
    } else if settings.mode != RenderMode::Direct {
        passes.push(Pass::Indirect);
    }
    if denoises(settings) {
        passes.extend([Pass::Temporal, Pass::Variance, Pass::Atrous]);
    }
    passes.extend([Pass::Composite, Pass::Tonemap]);
    passes
}

/// Whether a frame of `settings` runs the denoiser.
pub(crate) fn denoises(settings: &FrameSettings) -> bool {
    settings.mode == RenderMode::Realtime && settings.denoise.enabled
}
