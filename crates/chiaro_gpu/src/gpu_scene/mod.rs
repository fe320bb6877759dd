//! The scene on the GPU: one storage buffer per kind of data, or a texel array
//! ([`MirrorTexels`]) for what the ray traversal, the light sampling and the shading of hits
//! read (the BVH, the light tables and trees, the environment and its importance table, the
//! vertices, indices and materials), bound as group(0) of
//! every pass, kept in step with the ECS world by [`upload_gpu_scene`], which runs after the
//! BVH systems and writes only what changed.
//!
//! Bindings of group(0) (`shaders/lib/bvh_bindings.wgsl` declares 0..4,
//! `shaders/lib/scene_bindings.wgsl` the rest):
//!
//! | binding | buffer or texture | record |
//! |---|---|---|
//! | 0 | BLAS nodes (texels) | obvhs `CwBvhNode` |
//! | 1 | BLAS triangles (texels) | `chiaro_bvh::BvhTriangle` |
//! | 2 | TLAS nodes (texels) | `chiaro_bvh::TlasNode` |
//! | 3 | instances (read for their count only) | `chiaro_bvh::GpuInstance` |
//! | 4 | instances (texels, for the traversal and the shading) | `chiaro_bvh::GpuInstance` |
//! | 8 | vertices (texels) | [`GpuVertex`] |
//! | 9 | indices (texels) | `u32`, global vertex indices, four to a texel |
//! | 10 | meshes | [`GpuMesh`] |
//! | 11 | materials (texels) | [`GpuMaterial`] |
//! | 12 | texels | `u32`, packed RGBA8 |
//! | 13 | textures | [`GpuTextureInfo`] |
//! | 14 | punctual lights (texels) | [`GpuLight`] |
//! | 15 | area-light table (texels) | [`GpuAreaLight`] |
//! | 16 | per-instance extras | [`GpuInstanceExtra`] |
//! | 17 | environment texels (texels) | `[f32; 4]`, radiance in `xyz` |
//! | 18 | environment importance table (texels) | `f32`, four to a texel |
//! | 19 | scene info | [`GpuSceneInfo`] |
//! | 20 | light tree nodes (area tree, then punctual; texels) | [`GpuLightTreeNode`] |
//!
//! Textures live in one storage buffer of texels (an atlas in a buffer) rather than a texture
//! array: an array needs every layer the same size (glTF textures differ, and resampling them
//! would change the image against the CPU reference), a binding array needs features lavapipe
//! and GL lack, and the shaders' bilinear lookup then mirrors the reference's texel for
//! texel, in the compute passes and the rasterizer alike. The price is no hardware filtering
//! and no mip-maps (the reference has none either).
//!
//! Change detection: each buffer is rebuilt on the CPU only when its source changed
//! (`Meshes`, `Materials`, `Textures`, `Environment`, lights, `SceneBvh`), and a
//! [`MirrorBuffer`] then writes only the element ranges that differ from what the GPU holds,
//! so moving one instance writes that instance's record and the TLAS nodes that moved.
//! That system, [`upload_gpu_scene`], is in `upload.rs`.
//!
//! The G-buffer's vertex stage reads no storage buffer: its vertices, their triangles' faces
//! and the instances' transforms come through vertex buffers ([`RasterVertexBuffers`]), which the
//! input assembler fetches. On lavapipe a storage load in the vertex stage is a loop over the
//! SIMD lanes, one word at a time, even where every vertex of the draw reads the same instance;
//! the fixed-function fetch cut the G-buffer of a 1M-triangle scene at 256x256 from 573 to 128 ms
//! (docs/experiments/lavapipe-storage-loads.md).

pub mod back_faces;
mod cpu_copy;
mod gather;
pub mod layout;
pub mod light_trees;
mod mirror;
pub mod raster;
pub mod texel_mirror;
mod upload;

use bevy_ecs::prelude::*;
use chiaro_bvh::{BvhTriangle, CwBvhNode, GpuInstance, TlasNode};

pub use layout::{
    GpuAreaLight, GpuInstanceExtra, GpuLight, GpuLightTreeNode, GpuMaterial, GpuMesh, GpuSceneInfo,
    GpuTextureInfo, GpuTextureSlot, GpuVertex,
};
use light_trees::FlatTree;
pub use mirror::BufferOverflow;
pub use mirror::{MirrorBuffer, UploadStats};
pub use raster::RasterVertex;
pub use texel_mirror::{MirrorTexels, TexelOverflow};

/// Why a scene does not fit the device.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SceneOverflow {
    /// A texel array larger than the device's largest texture.
    #[error(transparent)]
    Texels(#[from] TexelOverflow),
    /// A buffer larger than the device's largest storage binding.
    #[error(transparent)]
    Buffer(#[from] BufferOverflow),
}
pub use upload::upload_gpu_scene;

/// The G-buffer's vertex buffers, by what they hold; the slots and attributes are
/// `passes::gbuffer`'s.
#[derive(Clone, Copy, Debug)]
pub struct RasterVertexBuffers<'a> {
    /// Per raster vertex: the [`RasterVertex`] (its scene vertex's attributes and the face of
    /// the triangle starting at it).
    pub vertices: &'a wgpu::Buffer,
    /// Per instance: the `chiaro_bvh::GpuInstance` records (its transforms).
    pub instances: &'a wgpu::Buffer,
    /// Per instance: the [`GpuInstanceExtra`] records (the previous frame's transform).
    pub instance_extras: &'a wgpu::Buffer,
}

/// The scene's GPU buffers (a resource of the world).
#[derive(Resource)]
pub struct GpuScene {
    device: wgpu::Device,
    queue: wgpu::Queue,
    layout: wgpu::BindGroupLayout,
    bind_group: Option<wgpu::BindGroup>,
    /// Bumped whenever the bind group is remade.
    pub generation: u64,
    /// The [`crate::GpuContext::id`] of the context whose device the buffers live on.
    context: u64,
    blas_nodes: MirrorTexels<CwBvhNode>,
    triangles: MirrorTexels<BvhTriangle>,
    tlas_nodes: MirrorTexels<TlasNode>,
    instances: MirrorBuffer<GpuInstance>,
    instance_texels: MirrorTexels<GpuInstance>,
    vertices: MirrorTexels<GpuVertex>,
    indices: MirrorTexels<[u32; 4]>,
    raster_vertices: MirrorBuffer<RasterVertex>,
    raster_indices: MirrorBuffer<u32>,
    closed_bounds: Vec<Option<back_faces::ClosedBounds>>,
    cullable_boxes: Vec<Option<back_faces::ClosedBounds>>,
    meshes: MirrorBuffer<GpuMesh>,
    materials: MirrorTexels<GpuMaterial>,
    texels: MirrorBuffer<u32>,
    textures: MirrorBuffer<GpuTextureInfo>,
    lights: MirrorTexels<GpuLight>,
    area_lights: MirrorTexels<GpuAreaLight>,
    instance_extras: MirrorBuffer<GpuInstanceExtra>,
    env_texels: MirrorTexels<[f32; 4]>,
    env_table: MirrorTexels<[f32; 4]>,
    info_buffer: MirrorBuffer<GpuSceneInfo>,
    light_tree: MirrorTexels<GpuLightTreeNode>,
    area_tree: FlatTree,
    punctual_tree: FlatTree,
    /// The scene info as uploaded.
    pub info: GpuSceneInfo,
    /// Every upload since the scene was made.
    pub total: UploadStats,
    /// The uploads of the last [`upload_gpu_scene`] run.
    pub last: UploadStats,
    /// Wall-clock seconds the last [`upload_gpu_scene`] run took.
    pub last_seconds: f64,
    /// Whether the last [`upload_gpu_scene`] run saw the scene change: anything but the
    /// previous transforms catching up the frame after an instance moved (which feed motion
    /// vectors and change no image).
    pub content_changed: bool,
    uploaded: bool,
    motion_pending: bool,
    current_transforms: Vec<[[f32; 4]; 3]>,
    area_first: Vec<u32>,
    /// The BLASes the uploaded nodes and triangles hold
    /// ([`chiaro_bvh::GpuBvhBuffers::blas_placement`]).
    blas_placement: Vec<(u32, u64)>,
    mesh_runs: Vec<(u32, std::ops::Range<u32>)>,
}

const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE;
const VERTEX: wgpu::BufferUsages = wgpu::BufferUsages::VERTEX;

/// The bindings of group(0) that are texel arrays (`Rgba32Uint` textures), in order.
const TEXEL_BINDINGS: [u32; 12] = [0, 1, 2, 4, 8, 9, 11, 14, 15, 17, 18, 20];

/// The bindings of group(0) that are read-only storage buffers, in order.
const BUFFER_BINDINGS: [u32; 6] = [3, 10, 12, 13, 16, 19];

impl GpuScene {
    /// Empty buffers on `context`'s device; the first [`upload_gpu_scene`] fills them.
    pub fn new(context: &crate::GpuContext) -> Self {
        let (device, queue) = (&context.device, &context.queue);
        let texel_array = wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let entries: Vec<_> = TEXEL_BINDINGS
            .iter()
            .map(|&binding| (binding, texel_array))
            .chain(
                BUFFER_BINDINGS
                    .iter()
                    .map(|&binding| (binding, crate::passes::storage(true))),
            )
            .map(|(binding, ty)| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
                ty,
                count: None,
            })
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene bind group layout"),
            entries: &entries,
        });
        let d = device;
        Self {
            device: device.clone(),
            queue: queue.clone(),
            layout,
            bind_group: None,
            generation: 0,
            context: context.id,
            blas_nodes: MirrorTexels::bulk(d, "scene blas nodes"),
            triangles: MirrorTexels::bulk(d, "scene blas triangles"),
            tlas_nodes: MirrorTexels::new(d, "scene tlas nodes"),
            instances: MirrorBuffer::new(d, queue, "scene instances", STORAGE | VERTEX),
            instance_texels: MirrorTexels::new(d, "scene instance texels"),
            vertices: MirrorTexels::bulk(d, "scene vertices"),
            indices: MirrorTexels::bulk(d, "scene indices"),
            raster_vertices: MirrorBuffer::bulk(d, queue, "raster vertices", VERTEX),
            raster_indices: MirrorBuffer::bulk(
                d,
                queue,
                "raster indices",
                wgpu::BufferUsages::INDEX,
            ),
            closed_bounds: Vec::new(),
            cullable_boxes: Vec::new(),
            meshes: MirrorBuffer::new(d, queue, "scene meshes", STORAGE),
            materials: MirrorTexels::new(d, "scene materials"),
            texels: MirrorBuffer::new(d, queue, "scene texels", STORAGE),
            textures: MirrorBuffer::new(d, queue, "scene textures", STORAGE),
            lights: MirrorTexels::new(d, "scene lights"),
            area_lights: MirrorTexels::new(d, "scene area lights"),
            instance_extras: MirrorBuffer::new(d, queue, "scene instance extras", STORAGE | VERTEX),
            env_texels: MirrorTexels::new(d, "scene environment texels"),
            env_table: MirrorTexels::new(d, "scene environment table"),
            info_buffer: MirrorBuffer::new(d, queue, "scene info", STORAGE),
            light_tree: MirrorTexels::new(d, "scene light tree"),
            area_tree: FlatTree::default(),
            punctual_tree: FlatTree::default(),
            info: GpuSceneInfo::default(),
            total: UploadStats::default(),
            last: UploadStats::default(),
            last_seconds: 0.0,
            uploaded: false,
            content_changed: false,
            motion_pending: false,
            current_transforms: Vec::new(),
            area_first: Vec::new(),
            blas_placement: Vec::new(),
            mesh_runs: Vec::new(),
        }
    }

    /// The layout of group(0), for pipeline layouts.
    pub fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// The bind group of group(0) (after the first upload).
    pub fn bind_group(&self) -> Option<&wgpu::BindGroup> {
        self.bind_group.as_ref()
    }

    /// The materials as uploaded.
    pub fn materials(&self) -> &[GpuMaterial] {
        self.materials.contents()
    }

    /// The mesh table as uploaded.
    pub fn meshes(&self) -> &[GpuMesh] {
        self.meshes.contents()
    }

    /// Whether the buffers live on `context`'s device.
    pub fn made_by(&self, context: &crate::GpuContext) -> bool {
        self.context == context.id
    }

    /// Bytes the scene's buffers take: (on the GPU, in their CPU copies).
    pub fn memory(&self) -> (u64, u64) {
        let parts = [
            self.blas_nodes.bytes(),
            self.triangles.bytes(),
            self.tlas_nodes.bytes(),
            self.instances.bytes(),
            self.instance_texels.bytes(),
            self.vertices.bytes(),
            self.indices.bytes(),
            self.raster_vertices.bytes(),
            self.raster_indices.bytes(),
            self.meshes.bytes(),
            self.materials.bytes(),
            self.texels.bytes(),
            self.textures.bytes(),
            self.lights.bytes(),
            self.area_lights.bytes(),
            self.instance_extras.bytes(),
            self.env_texels.bytes(),
            self.env_table.bytes(),
            self.info_buffer.bytes(),
            self.light_tree.bytes(),
        ];
        parts
            .iter()
            .fold((0, 0), |(g, c), (pg, pc)| (g + pg, c + pc))
    }

    /// The instances as uploaded.
    pub fn instances(&self) -> &[GpuInstance] {
        self.instances.contents()
    }

    /// The G-buffer's vertex buffers.
    pub fn raster_vertex_buffers(&self) -> RasterVertexBuffers<'_> {
        RasterVertexBuffers {
            vertices: self.raster_vertices.buffer(),
            instances: self.instances.buffer(),
            instance_extras: self.instance_extras.buffer(),
        }
    }

    /// The G-buffer's index buffer ([`raster`]; mesh `m`'s triangles from
    /// `meshes()[m].index_base`).
    pub fn raster_indices(&self) -> &wgpu::Buffer {
        self.raster_indices.buffer()
    }

    /// Per instance, its world bounds when it may drop its back faces wherever the camera is
    /// outside them ([`back_faces::cullable_box`]), else `None`.
    pub fn cullable_boxes(&self) -> &[Option<back_faces::ClosedBounds>] {
        &self.cullable_boxes
    }

    /// The runs of consecutive instances of one mesh, as (mesh, instance range): the G-buffer
    /// draws each with one instanced draw. Made when the instances are uploaded.
    pub fn mesh_runs(&self) -> &[(u32, std::ops::Range<u32>)] {
        &self.mesh_runs
    }

    fn texel_views(&self) -> [&wgpu::TextureView; 12] {
        [
            self.blas_nodes.view(),
            self.triangles.view(),
            self.tlas_nodes.view(),
            self.instance_texels.view(),
            self.vertices.view(),
            self.indices.view(),
            self.materials.view(),
            self.lights.view(),
            self.area_lights.view(),
            self.env_texels.view(),
            self.env_table.view(),
            self.light_tree.view(),
        ]
    }

    /// Whether the scene has a light tree to pick lights through: more punctual lights than
    /// are all evaluated ([`layout::ALL_PUNCTUAL_LIGHTS_MAX`]), or more emissive triangles
    /// than are picked by power alone ([`layout::AREA_LIGHTS_BY_POWER_MAX`]).
    pub fn light_trees(&self) -> bool {
        self.info.area_tree != layout::NO_INDEX || self.info.punctual_tree != layout::NO_INDEX
    }

    /// Why the scene is not on the GPU whole: a BVH array, the vertices, indices or materials,
    /// a light table or an environment array larger than the device's largest texture, or the
    /// texture texels or another buffer larger than its largest storage binding.
    pub fn overflow(&self) -> Option<SceneOverflow> {
        let texels = self
            .blas_nodes
            .overflow()
            .or(self.triangles.overflow())
            .or(self.tlas_nodes.overflow())
            .or(self.instance_texels.overflow())
            .or(self.vertices.overflow())
            .or(self.indices.overflow())
            .or(self.materials.overflow())
            .or(self.lights.overflow())
            .or(self.area_lights.overflow())
            .or(self.light_tree.overflow())
            .or(self.env_texels.overflow())
            .or(self.env_table.overflow());
        if let Some(o) = texels {
            return Some(SceneOverflow::Texels(o.clone()));
        }
        let buffer = self
            .instances
            .overflow()
            .or(self.meshes.overflow())
            .or(self.texels.overflow())
            .or(self.textures.overflow())
            .or(self.instance_extras.overflow())
            .or(self.raster_vertices.overflow())
            .or(self.raster_indices.overflow());
        buffer.map(|o| SceneOverflow::Buffer(o.clone()))
    }

    fn buffers(&self) -> [&wgpu::Buffer; 6] {
        [
            self.instances.buffer(),
            self.meshes.buffer(),
            self.texels.buffer(),
            self.textures.buffer(),
            self.instance_extras.buffer(),
            self.info_buffer.buffer(),
        ]
    }

    fn remake_bind_group(&mut self) {
        let texels = TEXEL_BINDINGS
            .iter()
            .zip(self.texel_views())
            .map(|(&binding, view)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(view),
            });
        let buffers = BUFFER_BINDINGS
            .iter()
            .zip(self.buffers())
            .map(|(&binding, buffer)| wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            });
        let entries: Vec<_> = texels.chain(buffers).collect();
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene bind group"),
            layout: &self.layout,
            entries: &entries,
        });
        self.bind_group = Some(group);
        self.generation += 1;
    }
}

/// Adds the animation system ([`chiaro_scene::animate_nodes`]: the World's glTF animations posed
/// at its [`chiaro_scene::Time`]), the BVH systems with skinning between the transforms and the
/// BVH ([`chiaro_scene::deformation::deform_meshes`]), [`upload_gpu_scene`] after them, and the
/// scene-features system (whose [`chiaro_scene::SceneFeatures`] the frame specialises its
/// pipelines to) to `schedule`.
pub fn add_gpu_scene_systems(schedule: &mut Schedule) {
    schedule.add_systems(chiaro_scene::animate_nodes.before(chiaro_scene::propagate_transforms));
    chiaro_bvh::add_bvh_systems(schedule);
    schedule.add_systems(
        chiaro_scene::deformation::deform_meshes
            .after(chiaro_scene::propagate_transforms)
            .before(chiaro_bvh::update_scene_bvh),
    );
    schedule.add_systems(chiaro_scene::update_scene_features);
    schedule.add_systems(upload_gpu_scene.after(chiaro_bvh::update_scene_bvh));
}

/// The generated constants of the scene layout.
pub fn constants() -> Vec<crate::shaders::SharedConstant> {
    layout::constants()
}
