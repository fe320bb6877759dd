//! The frame's passes, one file each with one `shaders/NAME.wgsl`, and what they share:
//! shader modules from composed WGSL and bind-group layout entries.

pub mod atrous;
pub mod composite;
pub mod direct;
pub mod gbuffer;
pub mod gbuffer_traced;
pub mod indirect;
pub mod restir;
pub mod restir_gi;
pub mod shading_pass;
pub mod temporal;
pub mod tonemap;
pub mod variance;

use crate::shaders::{self, ShaderError};

/// The shader module of `name` (composed with its imports), labelled with its name.
pub fn shader_module(device: &wgpu::Device, name: &str) -> Result<wgpu::ShaderModule, ShaderError> {
    let source = shaders::compose(name)?;
    Ok(device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(name),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    }))
}

/// A bind-group layout entry for a compute shader.
pub fn compute_entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty,
        count: None,
    }
}

/// A pass's parameter block (camera, settings): a read-only storage buffer. chiaro binds no
/// uniform buffers: lavapipe (Mesa 22) specialises a shader to the values of the uniforms its
/// branches and loops read, compiling it again at every dispatch and keeping each copy until
/// the process exits (6 to 10 MB a frame at 256x256); parameters in storage buffers are read
/// as they are. The WGSL side declares them `var<storage, read>`.
pub fn params() -> wgpu::BindingType {
    storage(true)
}

/// A storage buffer binding.
pub fn storage(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

/// A 2D texture read with `textureLoad`.
pub fn texture(sample_type: wgpu::TextureSampleType) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type,
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled: false,
    }
}

/// A read-only 2D storage texture: what a pass reads where the stage's sampled textures run
/// out (16 in WebGPU's downlevel limits; the scene and the indirect pass use them all).
pub fn read_only_storage_texture(format: wgpu::TextureFormat) -> wgpu::BindingType {
    wgpu::BindingType::StorageTexture {
        access: wgpu::StorageTextureAccess::ReadOnly,
        format,
        view_dimension: wgpu::TextureViewDimension::D2,
    }
}

/// A write-only 2D storage texture.
pub fn storage_texture(format: wgpu::TextureFormat) -> wgpu::BindingType {
    wgpu::BindingType::StorageTexture {
        access: wgpu::StorageTextureAccess::WriteOnly,
        format,
        view_dimension: wgpu::TextureViewDimension::D2,
    }
}

/// A compute pipeline of entry point `main` of `shader` over `layouts`.
pub fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    shader: &str,
    layouts: &[Option<&wgpu::BindGroupLayout>],
) -> Result<wgpu::ComputePipeline, ShaderError> {
    let module = shader_module(device, shader)?;
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: layouts,
        immediate_size: 0,
    });
    Ok(
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        }),
    )
}

/// A compute shader with one bind group whose bindings are numbered 0, 1, 2, ... in order:
/// `shaders/NAME.wgsl`, its layout and its pipeline, labelled by its name.
pub struct ComputeStage {
    name: &'static str,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl ComputeStage {
    /// The stage of `shaders/{name}.wgsl` over `entries` (bindings 0, 1, 2, ...).
    pub fn new(
        device: &wgpu::Device,
        name: &'static str,
        entries: &[wgpu::BindGroupLayoutEntry],
    ) -> Result<Self, ShaderError> {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(&format!("{name} layout")),
            entries,
        });
        let pipeline = compute_pipeline(
            device,
            &format!("{name} pipeline"),
            &format!("{name}.wgsl"),
            &[Some(&layout)],
        )?;
        Ok(Self {
            name,
            pipeline,
            layout,
        })
    }

    /// A bind group of `resources`, the `i`th at binding `i`.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        resources: Vec<wgpu::BindingResource<'_>>,
    ) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
            .into_iter()
            .zip(0..)
            .map(|(resource, binding)| wgpu::BindGroupEntry { binding, resource })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("{} bind group", self.name)),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Records one compute pass over every pixel of `targets`, one dispatch per bind group.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        groups: &[&wgpu::BindGroup],
        targets: &crate::targets::FrameTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        dispatch_per_pixel(
            encoder,
            &format!("{} pass", self.name),
            &self.pipeline,
            groups,
            targets,
            timestamps,
        );
    }
}

/// A compute pipeline of entry point `main` of `module`, compiled for `features`.
pub fn specialized_compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    features: crate::specialization::PipelineFeatures,
) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        module,
        entry_point: Some("main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &features.constants(),
            ..Default::default()
        },
        cache: None,
    })
}

/// Records one compute pass of a pass that reads the scene: `pipeline` over every pixel of
/// `targets`, the scene's bind group at index 0 and `group` at 1 (nothing while the scene has
/// no bind group or no pipeline was selected).
pub fn dispatch_scene_pass(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    scene: &crate::gpu_scene::GpuScene,
    pipeline: Option<&wgpu::ComputePipeline>,
    group: &wgpu::BindGroup,
    targets: &crate::targets::FrameTargets,
    timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
) {
    let (Some(scene_group), Some(pipeline)) = (scene.bind_group(), pipeline) else {
        return;
    };
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: timestamps,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, scene_group, &[]);
    pass.set_bind_group(1, group, &[]);
    let (x, y) = workgroups(targets.width, targets.height);
    pass.dispatch_workgroups(x, y, 1);
}

/// A texture view as a binding.
pub fn view(view: &wgpu::TextureView) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::TextureView(view)
}

/// Records one compute pass of `pipeline` over every pixel of `targets`: for each of `groups`
/// in turn, the group at index 0 and one dispatch (passes with a single bind group pass one;
/// the a-trous iterations pass one per iteration).
fn dispatch_per_pixel(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    groups: &[&wgpu::BindGroup],
    targets: &crate::targets::FrameTargets,
    timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: timestamps,
    });
    pass.set_pipeline(pipeline);
    let (x, y) = workgroups(targets.width, targets.height);
    for group in groups {
        pass.set_bind_group(0, *group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}

/// Workgroups of 8 x 8 covering `width` x `height`.
pub fn workgroups(width: u32, height: u32) -> (u32, u32) {
    (width.div_ceil(8), height.div_ceil(8))
}
