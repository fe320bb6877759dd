//! What the `direct` and `indirect` passes share: a compute shader over the G-buffer, one
//! invocation per pixel, with the scene in group 0 and, in group 1, the G-buffer's position,
//! surface, emission and triangle targets, the camera (`shaders/lib/gbuffer_inputs.wgsl`), the
//! pass's parameters, the images it writes and the images of an earlier pass it reads.

use std::marker::PhantomData;

use wgpu::TextureSampleType as S;

use crate::gpu_scene::GpuScene;
use crate::shaders::ShaderError;
use crate::specialization::{PipelineFeatures, SpecializedPipelines};
use crate::targets::{FrameTargets, Target};

/// The binding of the G-buffer's triangle target in group 1 (`gbuffer_triangle` in
/// `shaders/lib/gbuffer_inputs.wgsl`), past the passes' own.
const TRIANGLE_BINDING: u32 = 15;

/// Which G-buffer shading pass: its shader and the images it writes.
pub trait ShadingKind {
    /// The pass's name: its shader is `shaders/NAME.wgsl`, its wgpu objects are labelled with it.
    const NAME: &'static str;
    /// The formats of the images [`Self::outputs`] gives, in its order.
    const OUTPUT_FORMATS: &'static [wgpu::TextureFormat];
    /// The images the pass writes, bound from binding 5 on in this order.
    fn outputs(targets: &FrameTargets) -> Vec<&Target>;
    /// How many images [`Self::inputs`] gives.
    const INPUTS: u32;
    /// The formats of the first inputs, which are bound as read-only storage textures rather
    /// than sampled ones (the scene and the G-buffer leave a pass one sampled texture of the
    /// 16 it may bind).
    const STORAGE_INPUT_FORMATS: &'static [wgpu::TextureFormat] = &[];
    /// The unsigned-integer images of an earlier pass that the pass reads with `textureLoad`,
    /// bound after the outputs in this order.
    fn inputs(targets: &FrameTargets) -> Vec<&Target>;
}

/// A compute pass that shades the G-buffer's pixels (see [`ShadingKind`]), with one pipeline
/// per feature set ([`crate::specialization`]).
pub struct GbufferShadingPass<K> {
    /// The pass's pipelines, one per feature set.
    pub pipelines: SpecializedPipelines<wgpu::ComputePipeline>,
    layout: wgpu::BindGroupLayout,
    kind: PhantomData<K>,
}

impl<K: ShadingKind> GbufferShadingPass<K> {
    /// The pass for the scene's bind-group layout; its pipelines are built by
    /// [`SpecializedPipelines::specialize`].
    pub fn new(device: &wgpu::Device, scene: &GpuScene) -> Result<Self, ShaderError> {
        let name = K::NAME;
        use super::{compute_entry as e, params, texture};
        let mut entries = vec![
            e(0, texture(S::Uint)),
            e(1, texture(S::Uint)),
            e(2, texture(S::Uint)),
            e(3, params()),
            e(4, params()),
            e(
                TRIANGLE_BINDING,
                super::read_only_storage_texture(crate::targets::TRIANGLE_FORMAT),
            ),
        ];
        let outputs = K::OUTPUT_FORMATS.iter().map(|f| super::storage_texture(*f));
        let inputs = (0..K::INPUTS).map(|i| match K::STORAGE_INPUT_FORMATS.get(i as usize) {
            Some(format) => super::read_only_storage_texture(*format),
            None => texture(S::Uint),
        });
        entries.extend((5..).zip(outputs.chain(inputs)).map(|(b, ty)| e(b, ty)));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(&format!("{name} layout")),
            entries: &entries,
        });
        let module = super::shader_module(device, &format!("{name}.wgsl"))?;
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&format!("{name} pipeline layout")),
            bind_group_layouts: &[Some(scene.layout()), Some(&layout)],
            immediate_size: 0,
        });
        Ok(Self {
            pipelines: SpecializedPipelines::new(module, pipeline_layout, build_pipeline::<K>),
            layout,
            kind: PhantomData,
        })
    }

    /// The pass's bind group over `targets`, the camera and the parameters.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        targets: &FrameTargets,
        camera: &wgpu::Buffer,
        params: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let view = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let mut entries = vec![
            view(0, &targets.position.view),
            view(1, &targets.surface.view),
            view(2, &targets.emission.view),
            wgpu::BindGroupEntry {
                binding: 3,
                resource: camera.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: params.as_entire_binding(),
            },
            view(TRIANGLE_BINDING, &targets.triangle.view),
        ];
        entries.extend(
            (5..)
                .zip(K::outputs(targets).into_iter().chain(K::inputs(targets)))
                .map(|(b, t)| view(b, &t.view)),
        );
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("{} bind group", K::NAME)),
            layout: &self.layout,
            entries: &entries,
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
            &format!("{} pass", K::NAME),
            scene,
            self.pipelines.pipeline(),
            group,
            targets,
            timestamps,
        );
    }
}

/// The pass's compute pipeline compiled for `features`.
fn build_pipeline<K: ShadingKind>(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    features: PipelineFeatures,
) -> wgpu::ComputePipeline {
    let label = format!("{} pipeline", K::NAME);
    super::specialized_compute_pipeline(device, &label, module, layout, features)
}
