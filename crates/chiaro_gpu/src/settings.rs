//! What a frame computes: the mode, the path tracing budget, the denoiser and the display, as
//! one documented struct that is also an ECS resource (an app edits it in its World).

use bevy_ecs::prelude::Resource;
pub use chiaro_shading::light_tree::LightSampling;
pub use chiaro_shading::owen_sobol::Sampler;
use chiaro_shading::tonemap::Tonemapper;
use thiserror::Error;

use crate::specialization::PipelineChoice;

/// Most paths per pixel per frame [`FrameSettings::validate`] accepts.
pub const MAX_SPP: u32 = 64;
/// Most indirect bounces [`FrameSettings::validate`] accepts.
pub const MAX_BOUNCES: u32 = 64;
/// The bounce cap of the reference and naive modes' paths (Russian roulette ends nearly all
/// of them long before): 63 bounces after the surface the camera sees, the 64 scattering
/// surfaces of the CPU reference's default depth.
pub const REFERENCE_BOUNCES: u32 = 63;
/// The realtime mode's default bounce cap. Against the cap of 2, on the Cornell box (a closed
/// room) it more than halves the denoised frame's relMSE, for 5% more indirect-pass time; on
/// open scenes relMSE moves by -2 to +6% and FLIP is lower on all five scenes measured
/// (docs/experiments/bounce-cap.md).
pub const DEFAULT_BOUNCES: u32 = 3;

/// What each frame computes (one pipeline; the modes differ in which passes run).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RenderMode {
    /// Emission and direct light with shadow rays, accumulated over frames (no indirect light).
    Direct,
    /// The real-time frame: direct light, `spp` indirect paths of at most `bounces` bounces,
    /// temporal accumulation and a-trous denoising.
    #[default]
    Realtime,
    /// Progressive unbiased path tracing on the GPU: full depth with Russian roulette, no
    /// denoising, accumulation until the camera or the scene changes. Each frame draws one
    /// camera ray and one direct-light estimate a pixel, and `spp` indirect paths from its
    /// surface: N whole samples a pixel are N frames of `spp` 1.
    Reference,
    /// The baseline of the path tracing notes: uniform hemisphere directions (pdf 1 / 2 pi),
    /// no light sampling, no denoising; accumulated like `Reference`.
    Naive,
}

impl RenderMode {
    /// Every mode, in the order the CLI lists them.
    pub const ALL: [RenderMode; 4] = [
        RenderMode::Realtime,
        RenderMode::Reference,
        RenderMode::Naive,
        RenderMode::Direct,
    ];

    /// The mode's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            RenderMode::Direct => "direct",
            RenderMode::Realtime => "realtime",
            RenderMode::Reference => "reference",
            RenderMode::Naive => "naive",
        }
    }

    /// Whether frames are averaged with equal weights until something changes (every mode but
    /// `Realtime`, whose temporal pass keeps its own history).
    pub fn accumulates(self) -> bool {
        self != RenderMode::Realtime
    }
}

/// How the G-buffer finds the surface each pixel sees.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PrimaryVisibility {
    /// Rasterized: the scene's triangles drawn with a depth test (`shaders/gbuffer.wgsl`).
    #[default]
    Raster,
    /// Traced: one camera ray per pixel cast through the BVHs in a compute pass
    /// (`shaders/gbuffer_traced.wgsl`); its cost follows the BVH's depth rather than the
    /// triangles drawn. Where the adapter cannot run it (fewer than 5 storage textures per
    /// shader stage, or no storage writes to the targets' formats, as on GL), the frame
    /// rasterizes.
    Traced,
    /// Whichever of the two the device draws faster: measured once per frame size, the first
    /// time a frame asks ([`crate::frame::Frame::primary`] tells which). Where timing noise
    /// could flip the choice between runs, name one for reproducible images.
    Auto,
}

impl PrimaryVisibility {
    /// The choice's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            PrimaryVisibility::Raster => "raster",
            PrimaryVisibility::Traced => "traced",
            PrimaryVisibility::Auto => "auto",
        }
    }
}

/// The denoiser of the realtime mode: temporal accumulation, then variance estimation and an
/// edge-avoiding a-trous filter (SVGF: Schied et al., "Spatiotemporal Variance-Guided
/// Filtering", HPG 2017).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseSettings {
    /// Whether the temporal, variance and a-trous passes run (off: the raw 1-frame lighting).
    pub enabled: bool,
    /// Least weight of the new frame in the temporal moving average, whose weight is
    /// 1 / (history length) until it reaches this floor. Lower: less noise in motion, longer
    /// lag (ghosting) when lighting changes without motion vectors to show it, and more still
    /// frames before a still view converges ([`crate::still_view::settle_frames`]). Higher:
    /// faster response, more noise. The default is 0.2: against 0.05, along the bench's camera
    /// path (lavapipe, 128x128, the ten scenes of the default set) the error at equal time
    /// fell 22 to 59% on six scenes and 10% on many-lights, and moved by 1.5% or less on the
    /// other three: the longer history's lag was the larger error
    /// (docs/experiments/history-floor-in-motion.md).
    pub temporal_floor: f32,
    /// A-trous iterations (steps 1, 2, 4, ...). More: a wider, smoother filter and more blur
    /// of small detail; fewer: more noise left. The default is 4: with the 3 x 3 kernel a
    /// fifth iteration (step 16) added 18% to the pass's time and lowered no bench scene's
    /// error by more than 1% (docs/experiments/atrous-kernel.md).
    pub atrous_iterations: u32,
    /// Depth edge-stopping (sigma_z of SVGF, in units of the depth gradient). Higher: blurs
    /// across depth edges; lower: stops at smaller depth changes, keeping more noise on
    /// slanted surfaces.
    pub sigma_depth: f32,
    /// Normal edge-stopping exponent (sigma_n of SVGF). Higher: stops at smaller normal changes;
    /// lower: blurs across creases.
    pub sigma_normal: f32,
    /// Luminance edge-stopping in standard deviations (sigma_l of SVGF). Higher: smooths more
    /// noise and more lighting detail; lower: keeps detail and noise. The default is 2, not
    /// SVGF's 4: with 4 the filter smears the thin sun shadows of environment-lit scenes (the
    /// bench's glTF scenes err up to 6 times more after 64 frames), see
    /// docs/experiments/atrous-luminance-sigma.md.
    pub sigma_luminance: f32,
    /// Whether a still view converges: while the camera, the scene and the settings stay as
    /// they are, the temporal averages (the denoiser's and the resolve's) become running means
    /// instead of keeping `temporal_floor`'s memory; the first frame with a change goes back to
    /// the floor, and the running mean starts again once the change has faded
    /// ([`crate::still_view`]). Off: the moving average alone, still or not.
    pub converge_when_still: bool,
}

impl Default for DenoiseSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            temporal_floor: 0.2,
            atrous_iterations: 4,
            sigma_depth: 1.0,
            sigma_normal: 128.0,
            sigma_luminance: 2.0,
            converge_when_still: true,
        }
    }
}

/// How the spatial reuse of resampled light weighs its merged reservoirs: direct light's
/// (`shaders/restir_spatial.wgsl`) and indirect light's (`shaders/restir_gi_spatial.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RestirBias {
    /// Each by its count M, the sum normalised by the total (Bitterli et al. 2020): darker
    /// where a neighbour cannot produce the sample kept (below its horizon: creases; for
    /// indirect light also where it cannot see it). A still view that converges
    /// ([`DenoiseSettings::converge_when_still`]) is weighed as `Unbiased` all the same.
    #[default]
    Biased,
    /// Direct light: by the generalised balance heuristic over the reservoirs' surfaces (Lin et
    /// al. 2022), the square of the reservoirs' count in target evaluations, no extra ray.
    /// Indirect light: by pairwise MIS over targets with visibility, two rays a neighbour.
    Unbiased,
}

/// Most neighbours the spatial reuse of resampled direct light merges.
pub const MAX_RESTIR_NEIGHBOURS: u32 = 8;

/// Resampled direct light of the realtime and direct modes (ReSTIR DI: Bitterli et al.,
/// "Spatiotemporal Reservoir Resampling for Real-Time Ray Tracing with Dynamic Direct
/// Lighting", SIGGRAPH 2020): the area light (emissive triangles, an image environment; the
/// punctual lights too where there are more than the direct pass evaluates one by one) is
/// drawn as `candidates` samples resampled into a reservoir per pixel, merged with last
/// frame's along the motion vectors (when `temporal`) and with neighbours', and the survivor
/// shaded with one shadow ray. Off, the resampling passes do not run and the direct pass is
/// compiled without their code.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestirSettings {
    /// Whether the realtime (and direct) mode resamples its area light.
    pub direct: bool,
    /// Light candidates drawn per pixel per frame, 2 to 32 (each one light pick and one BRDF
    /// evaluation, no shadow ray; where the reservoirs hold punctual lights too, half of them
    /// are). More: a better reservoir, more time.
    pub candidates: u32,
    /// Whether last frame's reservoirs are merged (temporal reuse). Off by default: along the
    /// bench's camera path on many-lights (lavapipe, 128x128) it raised the error after 16
    /// frames from 2.54e-2 to 3.18e-2 (history cap 20; 2.70e-2 with cap 5), and a still view
    /// never merges history (see `passes::restir`).
    pub temporal: bool,
    /// Most weight last frame's reservoir has, in frames of candidates (its count M is capped
    /// at this times `candidates`). Higher: less noise on a still view, slower response to
    /// changed lighting.
    pub history_cap: u32,
    /// Neighbours merged per pixel (spatial reuse; 0: none), at most
    /// [`MAX_RESTIR_NEIGHBOURS`].
    pub spatial_samples: u32,
    /// Radius of the disc the neighbours are drawn from, in pixels.
    pub spatial_radius: f32,
    /// How spatial reuse is normalised, for direct and indirect light.
    pub bias: RestirBias,
    /// Whether the realtime mode resamples its indirect light (ReSTIR GI: Ouyang et al.,
    /// "ReSTIR GI: Path Resampling for Real-Time Path Tracing", HPG 2021): each pixel's path
    /// is kept as a sample of its first bounce's point and the light that point reflects,
    /// merged with last frame's reservoir (`indirect_history_cap`), and each pixel shades the
    /// survivor of its own and `indirect_spatial_samples` neighbours' reservoirs, weighted as
    /// `bias` says (`shaders/restir_gi_spatial.wgsl`). Needs `spp` = 1. A still view that
    /// converges reuses nothing, so its mean is the path tracer's.
    pub indirect: bool,
    /// Neighbours whose indirect samples each pixel resamples (0: none), at most
    /// [`MAX_RESTIR_NEIGHBOURS`], drawn in the disc of `spatial_radius`.
    pub indirect_spatial_samples: u32,
    /// Temporal reuse of the indirect samples: the most count M of last frame's reservoir
    /// merged with each pixel's new path, along the motion vectors (0: no temporal reuse).
    /// Higher: more paths behind each pixel's sample, slower response to changed lighting.
    /// Off by default: it cuts one frame's raw error (the Cornell box at 32x32, cap 20: relMSE
    /// 5.9e-2 against 1.3e-1 with spatial reuse alone), but the denoised frame along the
    /// bench's camera path does not gain (lavapipe, 128x128: up to 31% more error than with
    /// spatial reuse alone; docs/experiments/restir-gi.md).
    pub indirect_history_cap: u32,
}

impl Default for RestirSettings {
    fn default() -> Self {
        Self {
            direct: false,
            candidates: 8,
            temporal: false,
            history_cap: 20,
            spatial_samples: 2,
            spatial_radius: 16.0,
            bias: RestirBias::Biased,
            indirect: false,
            indirect_spatial_samples: 4,
            indirect_history_cap: 0,
        }
    }
}

/// The realtime mode's default firefly clamp ([`FrameSettings::firefly_clamp`]): ten times the
/// display's white.
pub const DEFAULT_FIREFLY_CLAMP: f32 = 10.0;

/// Everything a frame computes beyond the scene and the camera.
#[derive(Clone, Copy, Debug, PartialEq, Resource)]
pub struct FrameSettings {
    /// What the frame computes.
    pub mode: RenderMode,
    /// Indirect paths per pixel per frame (realtime, reference and naive). More: less noise,
    /// proportionally more time.
    pub spp: u32,
    /// Indirect bounces of the realtime mode: light is gathered at up to `bounces` surfaces
    /// after the one the camera sees (1 is one-bounce global illumination). Higher: less
    /// energy lost (a darker image is the bias of a low cap), more time. Reference and naive
    /// paths end by Russian roulette (at most [`REFERENCE_BOUNCES`]).
    pub bounces: u32,
    /// How next-event estimation picks a light where it cannot afford them all (the
    /// emissive triangles and the environment; punctual lights past
    /// `ALL_PUNCTUAL_LIGHTS_MAX`): `Tree`, by each light's importance to the shading point
    /// through light trees (less noise with many lights, a few node reads per pick), or
    /// `Power`, by power alone (the baseline). Both are unbiased. A scene with at most
    /// `AREA_LIGHTS_BY_POWER_MAX` emissive triangles has no area tree and picks them by power
    /// either way.
    pub light_sampling: LightSampling,
    /// The realtime mode's denoiser.
    pub denoise: DenoiseSettings,
    /// Tonemapping operator of the LDR image.
    pub tonemapper: Tonemapper,
    /// Multiplier of the linear radiance before tonemapping: 2^stops for an exposure in stops
    /// ([`chiaro_shading::tonemap::exposure_from_ev`]). It changes the LDR image only; the HDR
    /// image stays linear radiance, unscaled (the realtime firefly clamp, in units of display
    /// white, follows it).
    pub exposure: f32,
    /// The feature set the scene-reading passes are compiled for: by default what the scene
    /// uses, so a scene pays nothing for features it lacks.
    pub pipeline: PipelineChoice,
    /// Firefly clamp of the realtime mode's sampled light: the most luminance one indirect
    /// path may bring (all it gathers after the first bounce), and each direct-pass sample
    /// whose value can be rare and huge (the BRDF sample; the punctual light picked when there
    /// are too many to evaluate them all; not the light-sampled area or environment sample,
    /// whose value is about the light's true share), in units of the display's
    /// white at the frame's exposure (the clamp on scene luminance is this over `exposure`);
    /// a brighter sample is scaled down to it (its colour kept); 0 is off. The default,
    /// [`DEFAULT_FIREFLY_CLAMP`], is ten times white: on the bench's scenes it leaves the
    /// images without rare very bright samples as they were and divides the error of those
    /// with them (a sun glint found by a BRDF ray; a close light picked among hundreds) by up
    /// to 600. Lower: fewer fireflies and more energy lost, a darker image (bias); higher:
    /// closer to unbiased. The reference and naive modes ignore it (they stay unbiased).
    pub firefly_clamp: f32,
    /// How the G-buffer finds the surface each pixel sees: rasterized or traced.
    pub primary: PrimaryVisibility,
    /// The realtime and direct modes' resampled direct light.
    pub restir: RestirSettings,
    /// Where the reference and direct modes' random numbers come from: `Sobol` (the default),
    /// the pixel's frames accumulated being its samples of Owen-scrambled Sobol draws, as the
    /// CPU reference's default sampler (less noise at equal frames, unbiased), or
    /// `Independent` PCG32 streams. The realtime mode (whose frames are not samples of one
    /// image) and the naive mode (the notes' baseline) draw PCG32 numbers whatever it says.
    pub sampler: Sampler,
}

impl Default for FrameSettings {
    fn default() -> Self {
        Self {
            mode: RenderMode::Realtime,
            spp: 1,
            bounces: DEFAULT_BOUNCES,
            light_sampling: LightSampling::Tree,
            denoise: DenoiseSettings::default(),
            tonemapper: Tonemapper::PbrNeutral,
            exposure: 1.0,
            pipeline: PipelineChoice::Specialized,
            firefly_clamp: DEFAULT_FIREFLY_CLAMP,
            primary: PrimaryVisibility::Raster,
            restir: RestirSettings::default(),
            sampler: Sampler::Sobol,
        }
    }
}

/// A setting out of its range.
#[derive(Debug, Error, PartialEq)]
#[error("frame setting {name} = {value} is out of range: {expected}")]
pub struct SettingsError {
    /// The setting.
    pub name: &'static str,
    /// Its value, printed.
    pub value: String,
    /// What it must be.
    pub expected: &'static str,
}

impl FrameSettings {
    /// Refuses a setting out of range (each error names the setting and the range).
    pub fn validate(&self) -> Result<(), SettingsError> {
        let fail = |name, value: String, expected| {
            Err(SettingsError {
                name,
                value,
                expected,
            })
        };
        let d = &self.denoise;
        if !(1..=MAX_SPP).contains(&self.spp) {
            return fail("spp", self.spp.to_string(), "1..=64");
        }
        if !(1..=MAX_BOUNCES).contains(&self.bounces) {
            return fail("bounces", self.bounces.to_string(), "1..=64");
        }
        if !(d.temporal_floor > 0.0 && d.temporal_floor <= 1.0) {
            return fail("temporal_floor", d.temporal_floor.to_string(), "in (0, 1]");
        }
        if d.atrous_iterations as usize > crate::denoiser::MAX_ATROUS_ITERATIONS {
            return fail(
                "atrous_iterations",
                d.atrous_iterations.to_string(),
                "0..=10",
            );
        }
        for (name, value) in [
            ("sigma_depth", d.sigma_depth),
            ("sigma_normal", d.sigma_normal),
            ("sigma_luminance", d.sigma_luminance),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return fail(name, value.to_string(), "finite and above 0");
            }
        }
        if !(self.exposure.is_finite() && self.exposure > 0.0) {
            return fail("exposure", self.exposure.to_string(), "finite and above 0");
        }
        if !(self.firefly_clamp.is_finite() && self.firefly_clamp >= 0.0) {
            return fail(
                "firefly_clamp",
                self.firefly_clamp.to_string(),
                "finite and at least 0 (0 is off)",
            );
        }
        let r = &self.restir;
        if !(2..=32).contains(&r.candidates) {
            return fail("restir.candidates", r.candidates.to_string(), "2..=32");
        }
        if !(1..=100).contains(&r.history_cap) {
            return fail("restir.history_cap", r.history_cap.to_string(), "1..=100");
        }
        if r.spatial_samples > MAX_RESTIR_NEIGHBOURS {
            return fail(
                "restir.spatial_samples",
                r.spatial_samples.to_string(),
                "0..=8",
            );
        }
        if r.indirect_spatial_samples > MAX_RESTIR_NEIGHBOURS {
            return fail(
                "restir.indirect_spatial_samples",
                r.indirect_spatial_samples.to_string(),
                "0..=8",
            );
        }
        if r.indirect && self.spp != 1 {
            return fail(
                "spp",
                self.spp.to_string(),
                "1 with restir.indirect (one resampled path a pixel)",
            );
        }
        if !(1.0..=64.0).contains(&r.spatial_radius) {
            return fail(
                "restir.spatial_radius",
                r.spatial_radius.to_string(),
                "1..=64 pixels",
            );
        }
        Ok(())
    }

    /// Whether a frame of these settings resamples its direct light: the realtime and direct
    /// modes do when asked (the direct mode, which accumulates, always unbiased).
    pub fn resamples_direct_light(&self) -> bool {
        matches!(self.mode, RenderMode::Realtime | RenderMode::Direct) && self.restir.direct
    }

    /// Whether a frame of these settings resamples its indirect light (realtime mode only).
    pub fn resamples_indirect_light(&self) -> bool {
        self.mode == RenderMode::Realtime && self.restir.indirect
    }

    /// Whether a frame of these settings resamples any light (it needs the reservoirs and the
    /// resampling parameters).
    pub fn resamples(&self) -> bool {
        self.resamples_direct_light() || self.resamples_indirect_light()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        assert_eq!(FrameSettings::default().validate(), Ok(()));
        let bad = FrameSettings {
            spp: 0,
            ..Default::default()
        };
        assert_eq!(bad.validate().unwrap_err().name, "spp");
        let mut bad = FrameSettings::default();
        bad.denoise.sigma_luminance = f32::NAN;
        assert_eq!(bad.validate().unwrap_err().name, "sigma_luminance");
        let mut bad = FrameSettings::default();
        bad.denoise.temporal_floor = 0.0;
        assert_eq!(bad.validate().unwrap_err().name, "temporal_floor");
        for clamp in [-1.0, f32::INFINITY, f32::NAN] {
            let bad = FrameSettings {
                firefly_clamp: clamp,
                ..Default::default()
            };
            assert_eq!(bad.validate().unwrap_err().name, "firefly_clamp");
        }
        let off = FrameSettings {
            firefly_clamp: 0.0,
            ..Default::default()
        };
        assert_eq!(off.validate(), Ok(()));
        let mut bad = FrameSettings::default();
        bad.restir.spatial_samples = MAX_RESTIR_NEIGHBOURS + 1;
        assert_eq!(bad.validate().unwrap_err().name, "restir.spatial_samples");
        let mut bad = FrameSettings::default();
        bad.restir.spatial_samples = 2;
        bad.restir.indirect_spatial_samples = MAX_RESTIR_NEIGHBOURS + 1;
        assert_eq!(
            bad.validate().unwrap_err().name,
            "restir.indirect_spatial_samples"
        );
        bad.restir.indirect_spatial_samples = 4;
        bad.restir.indirect = true;
        bad.spp = 2;
        assert_eq!(bad.validate().unwrap_err().name, "spp");
        bad.spp = 1;
        bad.restir.spatial_radius = f32::NAN;
        assert_eq!(bad.validate().unwrap_err().name, "restir.spatial_radius");
        // The realtime mode clamps fireflies unless told not to.
        assert!(FrameSettings::default().firefly_clamp > 0.0);
    }
}
