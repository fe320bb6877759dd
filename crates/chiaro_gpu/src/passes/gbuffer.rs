//! `gbuffer`: rasterizes every instance (one indexed, instanced draw per run of consecutive
//! instances of one mesh, over the raster lists of [`crate::gpu_scene::raster`]; vertices, faces
//! and instance transforms from vertex buffers, see [`VERTEX_LAYOUTS`]) into the G-buffer targets:
//! position, normals, base colour, metallic, roughness, emission, instance id, motion vectors and
//! the triangle's number in its mesh,
//! plus depth (reversed: the near plane at 1, infinitely far at 0; see [`crate::camera`]). A back
//! face of a single-sided material is drawn and marked as not shading, as the CPU reference treats
//! it, except in the instances whose back faces cannot be seen ([`crate::gpu_scene::back_faces`]),
//! which are drawn with a pipeline that culls them.

use std::mem::offset_of;
use std::ops::Range;

use chiaro_bvh::GpuInstance;

use crate::gpu_scene::GpuScene;
use crate::gpu_scene::RasterVertex;
use crate::gpu_scene::back_faces::{CullView, eye_outside};
use crate::gpu_scene::layout::{GpuInstanceExtra, GpuMesh, GpuVertex};
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
                clear(&targets.triangle.view),
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
        let buffers = scene.raster_vertex_buffers();
        let slots = [buffers.vertices, buffers.instances, buffers.instance_extras];
        for (slot, buffer) in (0..).zip(slots) {
            pass.set_vertex_buffer(slot, buffer.slice(..));
        }
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

/// A vertex attribute of `format` at byte `offset` of its record, at `shader_location`.
const fn attribute(
    format: wgpu::VertexFormat,
    offset: usize,
    shader_location: u32,
) -> wgpu::VertexAttribute {
    wgpu::VertexAttribute {
        format,
        offset: offset as u64,
        shader_location,
    }
}

/// The three rows of a 3x4 matrix at byte `offset`, at locations `location..location + 3`.
const fn matrix_rows(offset: usize, location: u32) -> [wgpu::VertexAttribute; 3] {
    let row = wgpu::VertexFormat::Float32x4;
    [
        attribute(row, offset, location),
        attribute(row, offset + 16, location + 1),
        attribute(row, offset + 32, location + 2),
    ]
}

/// Byte offset of `field` of the scene vertex in a [`RasterVertex`].
macro_rules! vertex_offset {
    ($field:ident) => {
        offset_of!(RasterVertex, vertex) + offset_of!(GpuVertex, $field)
    };
}

/// Locations 0 to 3: the scene vertex's position and u, normal and v, tangent, and UV set 1;
/// location 4: the face of the triangle that starts at the vertex; location 14: the vertex
/// colour (four unorm16); location 15: the number of the triangle that starts at the vertex.
const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 7] = [
    attribute(wgpu::VertexFormat::Float32x4, vertex_offset!(position), 0),
    attribute(wgpu::VertexFormat::Float32x4, vertex_offset!(normal), 1),
    attribute(wgpu::VertexFormat::Float32x4, vertex_offset!(tangent), 2),
    attribute(wgpu::VertexFormat::Float32x2, vertex_offset!(uv1), 3),
    attribute(
        wgpu::VertexFormat::Float32x3,
        offset_of!(RasterVertex, face),
        4,
    ),
    attribute(wgpu::VertexFormat::Unorm16x4, vertex_offset!(color), 14),
    attribute(
        wgpu::VertexFormat::Uint32,
        offset_of!(RasterVertex, triangle),
        15,
    ),
];

/// Locations 5 to 10: the rows of world-to-object, then of object-to-world.
const INSTANCE_ATTRIBUTES: [wgpu::VertexAttribute; 6] = {
    let to_object = matrix_rows(offset_of!(GpuInstance, world_to_object), 5);
    let to_world = matrix_rows(offset_of!(GpuInstance, object_to_world), 8);
    [
        to_object[0],
        to_object[1],
        to_object[2],
        to_world[0],
        to_world[1],
        to_world[2],
    ]
};

/// Locations 11 to 13: the rows of the previous frame's object-to-world.
const PREVIOUS_TRANSFORM_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    matrix_rows(offset_of!(GpuInstanceExtra, previous_object_to_world), 11);

/// The G-buffer's vertex buffers, slot by slot ([`GpuScene::raster_vertex_buffers`]): per raster
/// vertex its [`RasterVertex`]; per instance its `GpuInstance` and its [`GpuInstanceExtra`].
/// The input assembler fetches them, so the vertex stage loads nothing from storage buffers
/// (see [`crate::gpu_scene`] for what that saves).
pub const VERTEX_LAYOUTS: [wgpu::VertexBufferLayout<'static>; 3] = [
    wgpu::VertexBufferLayout {
        array_stride: size_of::<RasterVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    },
    wgpu::VertexBufferLayout {
        array_stride: size_of::<GpuInstance>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &INSTANCE_ATTRIBUTES,
    },
    wgpu::VertexBufferLayout {
        array_stride: size_of::<GpuInstanceExtra>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &PREVIOUS_TRANSFORM_ATTRIBUTES,
    },
];

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
            buffers: &VERTEX_LAYOUTS.map(Some),
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
                target(targets::TRIANGLE_FORMAT),
            ],
        }),
        multiview_mask: None,
        cache: None,
    })
}
