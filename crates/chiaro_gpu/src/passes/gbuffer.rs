//! `gbuffer`: rasterizes every instance (one indexed, instanced draw per run of consecutive
//! instances of one mesh, over the raster lists of [`crate::gpu_scene::raster`]; vertex data
//! pulled from the scene buffers) into the G-buffer targets: position, normals, base colour,
//! metallic, roughness, emission, instance id and motion vectors, plus depth (reversed: the
//! near plane at 1, infinitely far at 0; see [`crate::camera`]). A back face of a single-sided
//! material is drawn and marked as not shading, as the CPU reference treats it, except in the
//! instances whose back faces cannot be seen ([`crate::gpu_scene::back_faces`]), which are
//! drawn with a pipeline that culls them.

use std::ops::Range;

use crate::gpu_scene::GpuScene;
use crate::gpu_scene::back_faces::{CullView, eye_outside};
use crate::gpu_scene::layout::GpuMesh;
use crate::shaders::ShaderError;
use crate::specialization::{PipelineFeatures, SpecializedPipelines};
use crate::targets::{self, FrameTargets};

/// The G-buffer pass, with one pair of pipelines per feature set ([`crate::specialization`]).
pub struct GbufferPass {
    /// The pass's pipelines, one pair per feature set.
    pub pipelines: SpecializedPipelines<GbufferPipelines>,
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
            pipelines: SpecializedPipelines::new(module, pipeline_layout, build_pipelines),
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

    /// Records the pass; `view` is the camera for the back-face test (`None`: draw every back
    /// face).
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera: &wgpu::BindGroup,
        view: Option<CullView>,
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
        let Some(pipelines) = self.pipelines.pipeline() else {
            return;
        };
        pass.set_bind_group(0, scene_group, &[]);
        pass.set_bind_group(1, camera, &[]);
        pass.set_index_buffer(scene.raster_indices().slice(..), wgpu::IndexFormat::Uint32);
        let mut culling = None;
        for (mesh, instances, front_only) in draws(scene, view) {
            if culling != Some(front_only) {
                culling = Some(front_only);
                pass.set_pipeline(if front_only {
                    &pipelines.front_faces
                } else {
                    &pipelines.both_faces
                });
            }
            let first = mesh.index_base;
            pass.draw_indexed(first..first + 3 * mesh.triangle_count, 0, instances);
        }
    }
}

/// The G-buffer's draws: each run of consecutive instances of one mesh, split where the back-face
/// test's answer changes, as (mesh, instances, whether back faces are culled).
fn draws(scene: &GpuScene, view: Option<CullView>) -> Vec<(GpuMesh, Range<u32>, bool)> {
    let (meshes, boxes) = (scene.meshes(), scene.cullable_boxes());
    let mut draws: Vec<(GpuMesh, Range<u32>, bool)> = Vec::new();
    for (m, run) in scene.mesh_runs() {
        let Some(mesh) = meshes.get(*m as usize) else {
            continue;
        };
        for i in run.clone() {
            let front_only = boxes
                .get(i as usize)
                .copied()
                .flatten()
                .is_some_and(|b| eye_outside(b, view));
            match draws.last_mut() {
                Some((_, range, f)) if range.end == i && *f == front_only && i != run.start => {
                    range.end = i + 1;
                }
                _ => draws.push((*mesh, i..i + 1, front_only)),
            }
        }
    }
    draws
}

/// The G-buffer's pipelines for one feature set: drawing every face, and culling back faces.
pub struct GbufferPipelines {
    /// No face culled.
    pub both_faces: wgpu::RenderPipeline,
    /// Back faces (clockwise) culled.
    pub front_faces: wgpu::RenderPipeline,
}

/// The G-buffer's pipelines compiled for `features`.
fn build_pipelines(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    features: PipelineFeatures,
) -> GbufferPipelines {
    GbufferPipelines {
        both_faces: build_pipeline(device, module, layout, features, None),
        front_faces: build_pipeline(device, module, layout, features, Some(wgpu::Face::Back)),
    }
}

/// The G-buffer's render pipeline compiled for `features`, culling `cull_mode`.
fn build_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    features: PipelineFeatures,
    cull_mode: Option<wgpu::Face>,
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
            cull_mode,
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
