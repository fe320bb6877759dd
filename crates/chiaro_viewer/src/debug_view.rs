//! Debug views: one compute pass (`shaders/debug_view.wgsl`) that turns a part of the frame
//! (G-buffer base colour, normals, distance, motion, instance ids; this frame's direct and raw
//! indirect light; the denoiser's filtered lighting, variance and history length) into an
//! 8-bit image the window shows instead of the frame; and the BVH traversal heatmap, which
//! traces the scene and has a pass of its own ([`crate::traversal_view`]).

use bytemuck::{Pod, Zeroable};
use chiaro_gpu::ShaderError;
use chiaro_gpu::frame::Frame;
use chiaro_gpu::gpu_scene::GpuScene;
use glam::Vec3;

use crate::traversal_view::TraversalPass;

/// The viewer's own shader, composed with chiaro's shader library.
const SHADER_NAME: &str = "viewer/debug_view.wgsl";
const SHADER: &str = include_str!("../shaders/debug_view.wgsl");

/// What the window shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DebugView {
    /// The frame itself (tonemapped).
    #[default]
    Frame,
    /// The G-buffer's base colour.
    Albedo,
    /// The shading normal, as 0.5 + 0.5 n.
    Normal,
    /// Distance from the camera: s / (s + d), s a scene-sized scale.
    Depth,
    /// Motion vectors: 0.5 + 0.5 m / 8 pixels in red and green.
    Motion,
    /// This frame's direct light, Reinhard-tonemapped.
    Direct,
    /// This frame's indirect light before any filtering, Reinhard-tonemapped.
    Indirect,
    /// A colour per instance.
    Instances,
    /// The denoiser's filtered lighting (demodulated: over the albedo), Reinhard-tonemapped.
    Filtered,
    /// The luminance standard deviation of the denoiser's moments history over its mean.
    Variance,
    /// The denoiser's history length in frames, as a linear grey: length / 32 (white from 32).
    History,
    /// BVH traversal steps of each pixel's camera ray, as a heatmap
    /// ([`crate::traversal_view`]).
    Traversal,
}

impl DebugView {
    /// Every view, in the order of their shader indices.
    pub const ALL: [DebugView; 12] = [
        DebugView::Frame,
        DebugView::Albedo,
        DebugView::Normal,
        DebugView::Depth,
        DebugView::Motion,
        DebugView::Direct,
        DebugView::Indirect,
        DebugView::Instances,
        DebugView::Filtered,
        DebugView::Variance,
        DebugView::History,
        DebugView::Traversal,
    ];

    /// The view's name (in the panel and in scripts).
    pub fn name(self) -> &'static str {
        match self {
            DebugView::Frame => "frame",
            DebugView::Albedo => "albedo",
            DebugView::Normal => "normal",
            DebugView::Depth => "depth",
            DebugView::Motion => "motion",
            DebugView::Direct => "direct",
            DebugView::Indirect => "indirect",
            DebugView::Instances => "instances",
            DebugView::Filtered => "filtered",
            DebugView::Variance => "variance",
            DebugView::History => "history",
            DebugView::Traversal => "traversal",
        }
    }

    /// The view named `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|v| v.name() == name)
    }

    fn index(self) -> u32 {
        Self::ALL.iter().position(|&v| v == self).unwrap_or(0) as u32
    }
}

/// The shader's parameters (mirrors `DebugParams` in `shaders/debug_view.wgsl`).
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
#[repr(C)]
struct DebugParams {
    view: u32,
    depth_scale: f32,
    motion_scale: f32,
    pad: f32,
    eye: [f32; 4],
}

/// Pixels of motion shown at full saturation.
const MOTION_SCALE: f32 = 8.0;

/// The debug view shader, composed (its `#import`s resolved from chiaro's shader library).
pub fn shader_source() -> Result<String, ShaderError> {
    crate::compose_shader(SHADER_NAME, SHADER)
}

/// The pass and its output image.
pub struct DebugPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    output: Option<(wgpu::Texture, wgpu::TextureView)>,
    /// Made when the traversal view is first shown (its shader traces rays: slower to compile).
    traversal: Option<TraversalPass>,
}

impl DebugPass {
    /// The pass on `device`.
    pub fn new(device: &wgpu::Device) -> Result<Self, ShaderError> {
        let uint = wgpu::TextureSampleType::Uint;
        let float = wgpu::TextureSampleType::Float { filterable: false };
        use chiaro_gpu::passes::{compute_entry as e, params, storage_texture, texture};
        let entries = [
            e(0, texture(uint)),
            e(1, texture(uint)),
            e(2, texture(uint)),
            e(3, texture(uint)),
            e(4, texture(float)),
            e(5, texture(float)),
            e(6, storage_texture(wgpu::TextureFormat::Rgba8Unorm)),
            e(7, params()),
            e(8, texture(float)),
            e(9, texture(float)),
        ];
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("debug view layout"),
            entries: &entries,
        });
        let source = shader_source()?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("debug view shader"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("debug view pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("debug view pipeline"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("debug view parameters"),
            size: std::mem::size_of::<DebugParams>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Self {
            pipeline,
            layout,
            params,
            output: None,
            traversal: None,
        })
    }

    /// The last image rendered.
    pub fn image(&self) -> Option<&wgpu::Texture> {
        self.output.as_ref().map(|(t, _)| t)
    }

    /// Renders `view` of `frame` (of `scene`) seen from `eye` (`depth_scale`: the distance
    /// shown as mid grey) and returns the image (the size of the frame); fails only when the
    /// traversal view's shader, made on its first use, does not compose.
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame: &Frame,
        scene: &GpuScene,
        view: DebugView,
        eye: Vec3,
        depth_scale: f32,
    ) -> Result<(&wgpu::Texture, &wgpu::TextureView), ShaderError> {
        let targets = &frame.targets;
        let size = (targets.width, targets.height);
        let stale = self
            .output
            .as_ref()
            .is_none_or(|(t, _)| (t.width(), t.height()) != size);
        if stale {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("debug view image"),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8Unorm,
                usage: wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            let texture_view = texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("debug view image view"),
                ..Default::default()
            });
            self.output = Some((texture, texture_view));
        }
        if view == DebugView::Traversal {
            if self.traversal.is_none() {
                self.traversal = Some(TraversalPass::new(device, queue, scene)?);
            }
            let pass = self.traversal.as_ref().expect("made above");
            let (texture, output) = self.output.as_ref().expect("made above");
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("traversal view"),
            });
            pass.record(device, &mut encoder, scene, frame.camera(), output, size);
            queue.submit([encoder.finish()]);
            return Ok((texture, output));
        }
        let params = DebugParams {
            view: view.index(),
            depth_scale: depth_scale.max(1e-6),
            motion_scale: MOTION_SCALE,
            pad: 0.0,
            eye: eye.extend(1.0).to_array(),
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let (texture, output) = self.output.as_ref().expect("made above");
        let views = [
            &targets.position.view,
            &targets.surface.view,
            &targets.emission.view,
            &targets.motion.view,
            &targets.direct.view,
            &targets.indirect.view,
            output,
        ];
        let mut entries: Vec<wgpu::BindGroupEntry> = views
            .iter()
            .zip(0..)
            .map(|(view, binding)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(view),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: 7,
            resource: self.params.as_entire_binding(),
        });
        let denoiser = frame.denoiser();
        for (binding, view) in [(8, denoiser.output()), (9, denoiser.moments())] {
            entries.push(wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(view),
            });
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("debug view bind group"),
            layout: &self.layout,
            entries: &entries,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("debug view"),
        });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("debug view pass"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(size.0.div_ceil(8), size.1.div_ceil(8), 1);
        }
        queue.submit([encoder.finish()]);
        Ok((texture, output))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shader_composes_and_validates() {
        let source = shader_source().unwrap();
        // The parameters' layout matches the Rust struct.
        assert_eq!(
            crate::shader_check::struct_size(&source, "DebugParams"),
            std::mem::size_of::<DebugParams>()
        );
    }

    #[test]
    fn views_are_named_and_indexed_in_order() {
        for (index, view) in DebugView::ALL.into_iter().enumerate() {
            assert_eq!(view.index() as usize, index);
            assert_eq!(DebugView::from_name(view.name()), Some(view));
        }
        assert_eq!(DebugView::from_name("heat"), None);
    }
}
