//! `gbuffer`, traced: the G-buffer found by one camera ray per pixel cast through the BVHs in
//! a compute pass (`shaders/gbuffer_traced.wgsl`), written to the raster pass's targets, with
//! one pipeline per feature set ([`crate::specialization`]). Its cost grows with the depth of
//! the BVH, not with the triangles drawn, and it needs no raster hardware.

use crate::gpu_scene::GpuScene;
use crate::shaders::ShaderError;
use crate::specialization::{PipelineFeatures, SpecializedPipelines};
use crate::targets::{
    EMISSION_FORMAT, FrameTargets, MOTION_FORMAT, POSITION_FORMAT, SURFACE_FORMAT, TRIANGLE_FORMAT,
};

/// The storage textures the pass writes: more than WebGPU's default of 4 per shader stage, so
/// the pass runs where the adapter has this many ([`traced_gbuffer_supported`]).
pub const TRACED_GBUFFER_STORAGE_TEXTURES: u32 = 5;

/// The formats of the targets the pass writes, in binding order (1 to 5).
const OUTPUT_FORMATS: [wgpu::TextureFormat; 5] = [
    POSITION_FORMAT,
    SURFACE_FORMAT,
    EMISSION_FORMAT,
    MOTION_FORMAT,
    TRIANGLE_FORMAT,
];

/// Whether `adapter` can run the traced G-buffer: five storage textures in a shader stage,
/// and storage writes to each target's format (llvmpipe's GL has both: 32 storage textures a
/// stage; its missing `rg32uint` storage images are why motion is packed in `r32uint`).
pub fn traced_gbuffer_supported(adapter: &wgpu::Adapter) -> bool {
    let formats = OUTPUT_FORMATS.iter().all(|f| {
        adapter
            .get_texture_format_features(*f)
            .allowed_usages
            .contains(wgpu::TextureUsages::STORAGE_BINDING)
    });
    formats
        && adapter.limits().max_storage_textures_per_shader_stage >= TRACED_GBUFFER_STORAGE_TEXTURES
}

/// The traced G-buffer pass.
pub struct TracedGbufferPass {
    /// The pass's pipelines, one per feature set.
    pub pipelines: SpecializedPipelines<wgpu::ComputePipeline>,
    layout: wgpu::BindGroupLayout,
}

impl TracedGbufferPass {
    /// The pass for the scene's bind-group layout; its pipelines are built by
    /// [`SpecializedPipelines::specialize`].
    pub fn new(device: &wgpu::Device, scene: &GpuScene) -> Result<Self, ShaderError> {
        use super::compute_entry as e;
        let mut entries = vec![e(0, super::params())];
        entries.extend(
            (1..)
                .zip(OUTPUT_FORMATS)
                .map(|(b, f)| e(b, super::storage_texture(f))),
        );
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gbuffer traced layout"),
            entries: &entries,
        });
        let module = super::shader_module(device, "gbuffer_traced.wgsl")?;
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gbuffer traced pipeline layout"),
            bind_group_layouts: &[Some(scene.layout()), Some(&layout)],
            immediate_size: 0,
        });
        Ok(Self {
            pipelines: SpecializedPipelines::new(module, pipeline_layout, build_pipeline),
            layout,
        })
    }

    /// The pass's bind group over the camera and the G-buffer targets.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        camera: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let view = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: super::view(view),
        };
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gbuffer traced bind group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: camera.as_entire_binding(),
                },
                view(1, &targets.position.view),
                view(2, &targets.surface.view),
                view(3, &targets.emission.view),
                view(4, &targets.motion.view),
                view(5, &targets.triangle.view),
            ],
        })
    }

    /// Records the pass (nothing while the scene has no bind group or no pipeline was
    /// selected).
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        group: &wgpu::BindGroup,
        targets: &FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        super::dispatch_scene_pass(
            encoder,
            "gbuffer traced pass",
            scene,
            self.pipelines.pipeline(),
            group,
            targets,
            timestamps,
        );
    }
}

/// The pass's compute pipeline compiled for `features`.
fn build_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    features: PipelineFeatures,
) -> wgpu::ComputePipeline {
    super::specialized_compute_pipeline(device, "gbuffer traced pipeline", module, layout, features)
}
