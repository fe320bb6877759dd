//! `gbuffer`: rasterizes every instance (one indexed, instanced draw per run of consecutive
//! instances of one mesh, over the raster lists of [`crate::gpu_scene::raster`]; vertex data
//! pulled from the scene buffers) into the G-buffer targets: position, normals, base colour,
//! metallic, roughness, emission, instance id and motion vectors, plus depth (reversed: the
//! near plane at 1, infinitely far at 0; see [`crate::camera`]). No face is culled: a back face
//! of a single-sided material is drawn and marked as not shading, as the CPU reference treats
//! it.

use crate::gpu_scene::GpuScene;
use crate::shaders::ShaderError;
use crate::specialization::{PipelineFeatures, SpecializedPipelines};
use crate::targets::{self, FrameTargets};

/// The G-buffer pass, with one pipeline per feature set ([`crate::specialization`]).
pub struct GbufferPass {
    /// The pass's pipelines, one per feature set.
    pub pipelines: SpecializedPipelines<wgpu::RenderPipeline>,
    camera_layout: wgpu::BindGroupLayout,
}

impl GbufferPass {
    /// The pass for the scene's bind-group layout; its pipelines are built by
    /// [`SpecializedPipelines::specialize`].
    pub fn new(device: &wgpu::Device, scene: &GpuScene) -> Result<Self, ShaderError> {
        let module = super::shader_module(device, "gbuffer.wgsl")?;
        let camera_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gbuffer camera layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: super::params(),
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gbuffer pipeline layout"),
            bind_group_layouts: &[Some(scene.layout()), Some(&camera_layout)],
            immediate_size: 0,
        });
        Ok(Self {
            pipelines: SpecializedPipelines::new(module, pipeline_layout, build_pipeline),
            camera_layout,
        })
    }

    /// The bind group of the camera uniform.
    pub fn camera_bind_group(
        &self,
        device: &wgpu::Device,
        camera: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gbuffer camera bind group"),
            layout: &self.camera_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: camera.as_entire_binding(),
            }],
        })
    }

    /// Records the pass.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera: &wgpu::BindGroup,
        targets: &FrameTargets,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let clear = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer pass"),
            color_attachments: &[
                clear(&targets.position.view),
                clear(&targets.surface.view),
                clear(&targets.emission.view),
                clear(&targets.motion.view),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth.view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let Some(scene_group) = scene.bind_group() else {
            return;
        };
        let Some(pipeline) = self.pipelines.pipeline() else {
            return;
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, scene_group, &[]);
        pass.set_bind_group(1, camera, &[]);
        pass.set_index_buffer(scene.raster_indices().slice(..), wgpu::IndexFormat::Uint32);
        let meshes = scene.meshes();
        for (mesh, instances) in scene.mesh_runs() {
            if let Some(mesh) = meshes.get(*mesh as usize) {
                let first = mesh.index_base;
                pass.draw_indexed(first..first + 3 * mesh.triangle_count, 0, instances.clone());
            }
        }
    }
}

/// The G-buffer's render pipeline compiled for `features`.
fn build_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    features: PipelineFeatures,
) -> wgpu::RenderPipeline {
    let constants = features.constants();
    let options = || wgpu::PipelineCompilationOptions {
        constants: &constants,
        ..Default::default()
    };
    let target = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("gbuffer pipeline"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: options(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: targets::DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_main"),
            compilation_options: options(),
            targets: &[
                target(targets::POSITION_FORMAT),
                target(targets::SURFACE_FORMAT),
                target(targets::EMISSION_FORMAT),
                target(targets::MOTION_FORMAT),
            ],
        }),
        multiview_mask: None,
        cache: None,
    })
}
