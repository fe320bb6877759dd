//! The passes that read the scene, with their pipelines for every feature set they have
//! rendered with: kept across output sizes.

use super::FrameInput;
use crate::gpu_scene::GpuScene;
use crate::passes::direct::DirectPass;
use crate::passes::gbuffer::GbufferPass;
use crate::passes::gbuffer_traced::TracedGbufferPass;
use crate::passes::indirect::IndirectPass;
use crate::passes::restir::{RestirSpatialPass, RestirTemporalPass};
use crate::passes::restir_gi::{RestirGiInitialPass, RestirGiSpatialPass};
use crate::settings::RenderMode;
use crate::shaders::ShaderError;
use crate::specialization::{PipelineFeatures, SpecializedPipelines};

/// The passes that read the scene (G-buffer, resampling, direct, indirect), each with its
/// pipelines for every feature set it has rendered with. They do not depend on the output
/// size, so a resized frame keeps them and recompiles nothing. A pass builds its pipelines only
/// once a frame runs it: the resampling passes cost nothing to a frame without them.
pub struct ScenePasses {
    pub(super) gbuffer: GbufferPass,
    /// The traced G-buffer, where the device can run it.
    pub(super) gbuffer_traced: Option<TracedGbufferPass>,
    pub(super) restir_temporal: RestirTemporalPass,
    pub(super) restir_spatial: RestirSpatialPass,
    pub(super) direct: DirectPass,
    pub(super) indirect: IndirectPass,
    pub(super) restir_gi_initial: RestirGiInitialPass,
    pub(super) restir_gi_spatial: RestirGiSpatialPass,
}

impl ScenePasses {
    /// The passes for `scene`'s bind-group layout (their pipelines are built on first use),
    /// the traced G-buffer among them where the device can run it (`traced_gbuffer`:
    /// [`crate::context::GpuContext::traced_gbuffer`]).
    pub fn new(
        device: &wgpu::Device,
        scene: &GpuScene,
        traced_gbuffer: bool,
    ) -> Result<Self, ShaderError> {
        Ok(Self {
            gbuffer: GbufferPass::new(device, scene)?,
            gbuffer_traced: traced_gbuffer
                .then(|| TracedGbufferPass::new(device, scene))
                .transpose()?,
            restir_temporal: RestirTemporalPass::new(device, scene)?,
            restir_spatial: RestirSpatialPass::new(device, scene)?,
            direct: DirectPass::new(device, scene)?,
            indirect: IndirectPass::new(device, scene)?,
            restir_gi_initial: RestirGiInitialPass::new(device, scene)?,
            restir_gi_spatial: RestirGiSpatialPass::new(device, scene)?,
        })
    }

    /// Selects each pass's pipeline for the frame's features (see
    /// [`crate::specialization::PipelineCache::select`]), the G-buffer's traced one when
    /// `traced`; returns the feature set every pass the frame runs now has, or `None` while
    /// they differ.
    pub(super) fn specialize(
        &mut self,
        device: &wgpu::Device,
        input: &FrameInput,
        traced: bool,
    ) -> Option<PipelineFeatures> {
        let (features, background) = (input.features, input.background_compile);
        let first = match &mut self.gbuffer_traced {
            Some(pass) if traced => {
                pass.pipelines.specialize(device, features, background);
                pass.pipelines.features()
            }
            _ => {
                let pipelines = &mut self.gbuffer.pipelines;
                pipelines.specialize(device, features, background);
                pipelines.features()
            }
        };
        self.direct
            .pipelines
            .specialize(device, features, background);
        let s = &input.settings;
        let mut others = vec![self.direct.pipelines.features()];
        let mut pass = |pipelines: &mut SpecializedPipelines<wgpu::ComputePipeline>| {
            pipelines.specialize(device, features, background);
            others.push(pipelines.features());
        };
        if s.resamples_direct_light() {
            pass(&mut self.restir_temporal.pipelines);
            pass(&mut self.restir_spatial.pipelines);
        }
        if s.resamples_indirect_light() {
            pass(&mut self.restir_gi_initial.pipelines);
            pass(&mut self.restir_gi_spatial.pipelines);
        } else if s.mode != RenderMode::Direct {
            pass(&mut self.indirect.pipelines);
        }
        first.filter(|_| others.iter().all(|&f| f == first))
    }

    /// Pipelines built so far by the scene passes.
    pub fn pipeline_builds(&self) -> u32 {
        self.gbuffer.pipelines.builds()
            + self
                .gbuffer_traced
                .as_ref()
                .map_or(0, |pass| pass.pipelines.builds())
            + self.restir_temporal.pipelines.builds()
            + self.restir_spatial.pipelines.builds()
            + self.direct.pipelines.builds()
            + self.indirect.pipelines.builds()
            + self.restir_gi_initial.pipelines.builds()
            + self.restir_gi_spatial.pipelines.builds()
    }
}
