//! What each frame of `chiaro render` (and `view`) computes: the options that make a
//! [`FrameSettings`].

use clap::{Args, ValueEnum};

use chiaro::gpu::{FrameSettings, RenderMode, RestirBias, Sampler};
use chiaro::reference::LightSampling;
use chiaro::shading::tonemap::exposure_from_ev;

use crate::args;

/// What `chiaro render` computes per frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Mode {
    /// Direct and indirect light, temporal accumulation and a-trous denoising: the real-time
    /// frame (the last frame is the image).
    Realtime,
    /// Progressive unbiased path tracing on the GPU, the mean of the frames (each frame one
    /// camera ray and direct-light estimate a pixel, and --spp indirect paths from it).
    Reference,
    /// Pure path tracing with uniform hemisphere directions and no light sampling (the
    /// baseline), the mean of the frames.
    Naive,
    /// Emission and direct light with shadow rays (MIS for area lights and the environment),
    /// the mean of the frames.
    Direct,
}

impl From<Mode> for RenderMode {
    fn from(mode: Mode) -> Self {
        match mode {
            Mode::Realtime => RenderMode::Realtime,
            Mode::Reference => RenderMode::Reference,
            Mode::Naive => RenderMode::Naive,
            Mode::Direct => RenderMode::Direct,
        }
    }
}

/// What each frame of `chiaro render` computes.
#[derive(Args)]
pub struct FrameArgs {
    /// What the frame computes.
    #[arg(long, value_enum, default_value_t = Mode::Realtime)]
    mode: Mode,
    /// Indirect paths per pixel per frame (1..=64).
    #[arg(long, default_value_t = 1)]
    spp: u32,
    /// Surfaces after the first at which a realtime path gathers light (1..=64).
    #[arg(long, default_value_t = chiaro::gpu::settings::DEFAULT_BOUNCES)]
    bounces: u32,
    /// Turns the realtime mode's denoiser (temporal, variance, a-trous) off.
    #[arg(long)]
    no_denoise: bool,
    /// How next-event estimation picks a light: tree (by importance to the shading point,
    /// through light trees) or power (by power alone).
    #[arg(long, default_value = "tree")]
    light_sampling: LightSampling,
    /// Most luminance one realtime light sample (an indirect path, the direct light's BRDF
    /// sample or randomly picked light) may bring, in units of display white at the exposure, a
    /// brighter one scaled down to it (fewer fireflies, some energy lost); 0 is off.
    #[arg(long, default_value_t = chiaro::gpu::settings::DEFAULT_FIREFLY_CLAMP,
          value_parser = args::non_negative, allow_negative_numbers = true)]
    firefly_clamp: f32,
    /// Exposure in stops: linear radiance times 2^STOPS before tonemapping (-30..=30), in the
    /// PNG and the window. An EXR stays linear radiance, unscaled, so that its error against a
    /// reference means the same at any exposure (the realtime firefly clamp, in units of
    /// display white, follows the exposure).
    #[arg(long, default_value_t = 0.0, value_parser = args::exposure_stops,
          allow_negative_numbers = true)]
    exposure: f32,
    /// How the G-buffer finds the surface each pixel sees: raster (triangles drawn with a
    /// depth test), traced (a camera ray per pixel through the BVHs, in a compute pass;
    /// rasterized where the adapter cannot trace it) or auto (whichever the adapter draws
    /// faster, timed once).
    #[arg(long, value_enum, default_value_t = Primary::Raster)]
    primary: Primary,
    /// Resamples the area light of the realtime and direct modes (ReSTIR DI): candidates per
    /// pixel, merged with last frame's and, in motion, with neighbours'.
    #[arg(long)]
    restir_di: bool,
    /// Resamples the indirect light of the realtime mode (ReSTIR GI): each pixel's path is
    /// reused by its neighbours in motion (needs --spp 1).
    #[arg(long)]
    restir_gi: bool,
    /// With --restir-gi, merges each pixel's path with last frame's reservoir in motion
    /// (temporal reuse), its count capped at this many paths (0: none).
    #[arg(long, default_value_t = 0)]
    restir_gi_history: u32,
    /// With --restir-di or --restir-gi, weighs the neighbours' reservoirs without bias: direct
    /// light by the generalised balance heuristic, indirect light by pairwise MIS with a
    /// visibility ray each way (about three times the spatial pass's time on lavapipe).
    #[arg(long)]
    restir_unbiased: bool,
    /// Where the reference and direct modes' numbers come from: sobol (the frames are each
    /// pixel's samples of Owen-scrambled Sobol draws, as the CPU reference's) or independent
    /// (PCG32 streams). The realtime and naive modes draw independent numbers.
    #[arg(long, default_value = "sobol")]
    sampler: Sampler,
}

/// `--primary`'s values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Primary {
    /// Rasterized.
    Raster,
    /// Traced through the BVHs.
    Traced,
    /// The faster of the two on this adapter.
    Auto,
}

impl From<Primary> for chiaro::gpu::PrimaryVisibility {
    fn from(primary: Primary) -> Self {
        match primary {
            Primary::Raster => chiaro::gpu::PrimaryVisibility::Raster,
            Primary::Traced => chiaro::gpu::PrimaryVisibility::Traced,
            Primary::Auto => chiaro::gpu::PrimaryVisibility::Auto,
        }
    }
}

impl FrameArgs {
    /// The frame settings the options give.
    pub fn settings(&self) -> FrameSettings {
        let mut settings = FrameSettings {
            mode: self.mode.into(),
            spp: self.spp,
            bounces: self.bounces,
            light_sampling: self.light_sampling,
            firefly_clamp: self.firefly_clamp,
            exposure: exposure_from_ev(self.exposure),
            primary: self.primary.into(),
            sampler: self.sampler,
            ..FrameSettings::default()
        };
        settings.denoise.enabled = !self.no_denoise;
        settings.restir.direct = self.restir_di;
        settings.restir.indirect = self.restir_gi;
        settings.restir.indirect_history_cap = self.restir_gi_history;
        if self.restir_unbiased {
            settings.restir.bias = RestirBias::Unbiased;
        }
        settings
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Command {
        #[command(flatten)]
        frame: FrameArgs,
    }

    fn settings(args: &[&str]) -> FrameSettings {
        let all = std::iter::once("chiaro").chain(args.iter().copied());
        Command::try_parse_from(all)
            .expect("parses")
            .frame
            .settings()
    }

    #[test]
    fn resampling_options_reach_the_settings() {
        let plain = settings(&[]);
        assert!(!plain.restir.direct && !plain.restir.indirect);
        assert_eq!(plain.restir.bias, RestirBias::Biased);
        let resampled = settings(&["--restir-gi", "--restir-gi-history", "20"]);
        assert!(resampled.restir.indirect);
        assert_eq!(resampled.restir.indirect_history_cap, 20);
        assert_eq!(resampled.restir.bias, RestirBias::Biased);
        let unbiased = settings(&["--restir-di", "--restir-gi", "--restir-unbiased"]);
        assert!(unbiased.restir.direct && unbiased.restir.indirect);
        assert_eq!(unbiased.restir.bias, RestirBias::Unbiased);
    }
}
