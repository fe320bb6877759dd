//! `restir_gi_initial` and `restir_gi_spatial`: resampled indirect light (ReSTIR GI; see
//! [`crate::settings::RestirSettings::indirect`], `shaders/restir_gi_initial.wgsl` and
//! `shaders/restir_gi_spatial.wgsl`). The first traces each pixel's path, keeps it as a
//! sample of its first bounce's point and the light reflected there, and merges last frame's
//! reservoir along the motion vectors where temporal reuse is on; the second resamples each
//! pixel's reservoir with its neighbours' and writes the frame's indirect light in place of the
//! indirect pass. The first reads [`super::indirect::IndirectParams`], the second
//! [`super::restir::RestirParams`].

use super::shading_pass::{GbufferShadingPass, ShadingKind};
use crate::targets::{FIRST_BOUNCE_FORMAT, FrameTargets, HDR_FORMAT, RESERVOIR_FORMAT, Target};

/// Selects the first pass: one path a pixel, kept as a sample and merged with last frame's
/// reservoir.
pub struct RestirGiInitialKind;

impl ShadingKind for RestirGiInitialKind {
    const NAME: &'static str = "restir_gi_initial";
    const OUTPUT_FORMATS: &'static [wgpu::TextureFormat] = &[RESERVOIR_FORMAT];
    const INPUTS: u32 = 3;
    const STORAGE_INPUT_FORMATS: &'static [wgpu::TextureFormat] =
        &[RESERVOIR_FORMAT, FIRST_BOUNCE_FORMAT];

    fn outputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.gi_reservoirs]
    }

    fn inputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.gi_history, &targets.first_bounce, &targets.motion]
    }
}

/// Selects the second pass: spatial resampling and shading.
pub struct RestirGiSpatialKind;

impl ShadingKind for RestirGiSpatialKind {
    const NAME: &'static str = "restir_gi_spatial";
    const OUTPUT_FORMATS: &'static [wgpu::TextureFormat] = &[HDR_FORMAT];
    const INPUTS: u32 = 1;
    const STORAGE_INPUT_FORMATS: &'static [wgpu::TextureFormat] = &[RESERVOIR_FORMAT];

    fn outputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.indirect]
    }

    fn inputs(targets: &FrameTargets) -> Vec<&Target> {
        vec![&targets.gi_reservoirs]
    }
}

/// The first resampled-indirect pass.
pub type RestirGiInitialPass = GbufferShadingPass<RestirGiInitialKind>;
/// The second resampled-indirect pass.
pub type RestirGiSpatialPass = GbufferShadingPass<RestirGiSpatialKind>;
