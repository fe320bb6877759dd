//! `restir_temporal` and `restir_spatial`: resampled direct light (ReSTIR DI; see
//! [`crate::settings::RestirSettings`] and `shaders/restir_temporal.wgsl`,
//! `shaders/restir_spatial.wgsl`). The first draws each pixel's light candidates into a
//! reservoir and merges last frame's along the motion vectors; the second merges neighbours'.
//! The direct pass then shades each pixel's final reservoir. The resampled indirect light's
//! spatial pass ([`super::restir_gi`]) reads the same parameters.

use bytemuck::{Pod, Zeroable};

use super::shading_pass::{GbufferShadingPass, ShadingKind};
use crate::settings::{FrameSettings, RestirBias};
use crate::targets::{FrameTargets, RESERVOIR_FORMAT, Target};

/// The two passes' parameters (mirrored by `RestirParams` in `shaders/lib/reservoir.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RestirParams {
    /// Frame number: picks the random stream with the pixel.
    pub frame: u32,
    /// Seed, low 32 bits.
    pub seed_lo: u32,
    /// Seed, high 32 bits.
    pub seed_hi: u32,
    /// How a light is picked: `LIGHT_SAMPLING_POWER` or `LIGHT_SAMPLING_TREE`.
    pub light_sampling: u32,
    /// Light candidates per pixel.
    pub candidates: u32,
    /// 1: merge last frame's reservoirs.
    pub temporal: u32,
    /// Most count M of last frame's reservoir.
    pub history_cap: u32,
    /// Neighbours merged by the spatial pass.
    pub spatial_samples: u32,
    /// Radius of their disc, in pixels.
    pub spatial_radius: f32,
    /// 1: spatial reuse weighted by the generalised balance heuristic (unbiased); 0: by M.
    pub unbiased: u32,
    /// Neighbours whose indirect samples `restir_gi_spatial` resamples (0 where the frame
    /// converges: see [`RestirParams::new`]).
    pub indirect_spatial_samples: u32,
    /// Most luminance of a pixel's resampled indirect light; 0: no clamp.
    pub firefly_clamp: f32,
}

impl RestirParams {
    /// The parameters of a frame of `settings`: `history` says last frame's reservoirs belong
    /// to this view (not the first frame, nor after a reset); `converging` says the frame is
    /// averaged into a running mean (the direct mode, a still view), which merges no history
    /// and weighs spatial reuse by the balance heuristic, so that the mean converges to the
    /// unbiased image:
    /// last frame's reservoir, normalised by M, belongs to another jittered point whose
    /// target's support differs a little (measured on the hard cases in the direct mode, 256
    /// frames: the lit interior 0.27% dark, 4.4 standard errors), and the running mean itself
    /// is the temporal reuse a still view needs. Where it converges, resampled indirect light
    /// draws no neighbours: a neighbour's sample assumes a diffuse point, a bias no weighting
    /// removes, and each pixel's own path is the path tracer's estimate. `firefly_clamp` is the
    /// frame's clamp on a pixel's indirect light (0: none).
    pub fn new(
        settings: &FrameSettings,
        (frame, seed): (u32, u64),
        (light_sampling, firefly_clamp): (u32, f32),
        history: bool,
        converging: bool,
    ) -> Self {
        let r = &settings.restir;
        Self {
            frame,
            seed_lo: seed as u32,
            seed_hi: (seed >> 32) as u32,
            light_sampling,
            candidates: r.candidates,
            temporal: u32::from(r.temporal && history && !converging),
            history_cap: r.history_cap * r.candidates,
            spatial_samples: r.spatial_samples,
            spatial_radius: r.spatial_radius,
            unbiased: u32::from(r.bias == RestirBias::Unbiased || converging),
            indirect_spatial_samples: if converging {
                0
            } else {
                r.indirect_spatial_samples
            },
            firefly_clamp,
        }
    }
}

/// Selects the first resampling pass: candidates and temporal reuse.
pub struct RestirTemporalKind;

impl ShadingKind for RestirTemporalKind {
    const NAME: &'static str = "restir_temporal";
    const OUTPUT_FORMATS: &'static [wgpu::TextureFormat] = &[RESERVOIR_FORMAT];
    const INPUTS: u32 = 3;
    const STORAGE_INPUT_FORMATS: &'static [wgpu::TextureFormat] =
        &[RESERVOIR_FORMAT, RESERVOIR_FORMAT];

    fn outputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.reservoirs_temporal]
    }

    fn inputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![
            &targets.reservoirs,
            &targets.reservoir_surfaces,
            &targets.motion,
        ]
    }
}

/// Selects the second resampling pass: spatial reuse.
pub struct RestirSpatialKind;

impl ShadingKind for RestirSpatialKind {
    const NAME: &'static str = "restir_spatial";
    const OUTPUT_FORMATS: &'static [wgpu::TextureFormat] = &[RESERVOIR_FORMAT, RESERVOIR_FORMAT];
    const INPUTS: u32 = 1;

    fn outputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.reservoirs, &targets.reservoir_surfaces]
    }

    fn inputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.reservoirs_temporal]
    }
}

/// The first resampling pass.
pub type RestirTemporalPass = GbufferShadingPass<RestirTemporalKind>;
/// The second resampling pass.
pub type RestirSpatialPass = GbufferShadingPass<RestirSpatialKind>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_converging_frame_merges_no_history_and_reuses_no_indirect_sample() {
        let mut settings = FrameSettings::default();
        settings.restir.temporal = true;
        settings.restir.indirect = true;
        let moving = RestirParams::new(&settings, (3, 7), (0, 1.5), true, false);
        assert_eq!(moving.temporal, 1);
        assert_eq!(moving.unbiased, 0);
        assert_eq!(
            moving.indirect_spatial_samples,
            settings.restir.indirect_spatial_samples
        );
        assert_eq!(moving.firefly_clamp, 1.5);
        let still = RestirParams::new(&settings, (3, 7), (0, 1.5), true, true);
        assert_eq!(
            (
                still.temporal,
                still.unbiased,
                still.indirect_spatial_samples
            ),
            (0, 1, 0)
        );
    }
}
