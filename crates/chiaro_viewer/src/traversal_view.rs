//! The traversal heatmap (`DebugView::Traversal`): one compute pass
//! (`shaders/traversal_view.wgsl`) that traces, per pixel, the camera ray through the frame's
//! jittered sample of that pixel with `lib/bvh.wgsl`'s closest-hit query and shows its
//! traversal steps (TLAS nodes visited + BLAS nodes visited + triangles tested) through the
//! viridis colour map, from 0 to [`MAX_STEPS`] (and above). The frame's own shaders count the
//! same steps into a variable they never read, which the compiler removes: the frame pays
//! nothing for this view.

use bytemuck::{Pod, Zeroable};
use chiaro_gpu::ShaderError;
use chiaro_gpu::gpu_scene::GpuScene;

/// The shader, composed with chiaro's shader library.
const SHADER_NAME: &str = "viewer/traversal_view.wgsl";
const SHADER: &str = include_str!("../shaders/traversal_view.wgsl");

/// Traversal steps shown as the top of the colour map (more are shown the same).
pub const MAX_STEPS: u32 = 48;

/// The viridis colour map (van der Walt and Smith, matplotlib 1.5) at 10 evenly spaced points
/// from 0 to 1, as 8-bit sRGB. Its lightness and its green channel rise monotonically, so
/// more steps always read as brighter and greener.
pub const HEAT_STOPS: [[u8; 3]; 10] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x28, 0x78],
    [0x3e, 0x4a, 0x89],
    [0x31, 0x68, 0x8e],
    [0x26, 0x82, 0x8e],
    [0x1f, 0x9e, 0x89],
    [0x35, 0xb7, 0x79],
    [0x6d, 0xcd, 0x59],
    [0xb4, 0xde, 0x2c],
    [0xfd, 0xe7, 0x25],
];

/// The colour map at `t` (clamped to [0, 1]) as sRGB in [0, 1]: linear between the two
/// nearest of [`HEAT_STOPS`] (the shader's `heat` computes the same).
pub fn heat_colour(t: f32) -> [f32; 3] {
    let last = HEAT_STOPS.len() - 1;
    let x = t.clamp(0.0, 1.0) * last as f32;
    let i = (x as usize).min(last - 1);
    let f = x - i as f32;
    let (a, b) = (HEAT_STOPS[i], HEAT_STOPS[i + 1]);
    [0, 1, 2].map(|c| (f32::from(a[c]) * (1.0 - f) + f32::from(b[c]) * f) / 255.0)
}

/// Shows the colour map as a bar labelled with its range (for the panel).
pub fn legend(ui: &mut egui::Ui) {
    ui.label(format!(
        "BVH steps per camera ray (nodes + triangles): 0 to {MAX_STEPS}+"
    ));
    let width = ui.available_width().clamp(32.0, 240.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 12.0), egui::Sense::hover());
    let columns = 48;
    for i in 0..columns {
        let [r, g, b] = heat_colour((i as f32 + 0.5) / columns as f32).map(|c| (c * 255.0) as u8);
        let x0 = rect.left() + rect.width() * i as f32 / columns as f32;
        let x1 = rect.left() + rect.width() * (i + 1) as f32 / columns as f32;
        let column = egui::Rect::from_x_y_ranges(x0..=x1, rect.y_range());
        ui.painter()
            .rect_filled(column, 0.0, egui::Color32::from_rgb(r, g, b));
    }
}

/// The shader's parameters (mirrors `TraversalParams` in `shaders/traversal_view.wgsl`).
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
#[repr(C)]
struct TraversalParams {
    stops: [[f32; 4]; 10],
    max_steps: f32,
    pad: [f32; 3],
}

/// The traversal heatmap's shader, composed.
pub fn shader_source() -> Result<String, ShaderError> {
    crate::compose_shader(SHADER_NAME, SHADER)
}

/// The pass: group(0) is the scene's, group(1) the camera, the parameters and the image.
pub struct TraversalPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
}

impl TraversalPass {
    /// The pass on `device`, for scenes bound with `scene`'s layout.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &GpuScene,
    ) -> Result<Self, ShaderError> {
        use chiaro_gpu::passes::{compute_entry as e, params, storage_texture};
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("traversal view layout"),
            entries: &[
                e(0, params()),
                e(1, params()),
                e(2, storage_texture(wgpu::TextureFormat::Rgba8Unorm)),
            ],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("traversal view shader"),
            source: wgpu::ShaderSource::Wgsl(shader_source()?.into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("traversal view pipeline layout"),
            bind_group_layouts: &[Some(scene.layout()), Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("traversal view pipeline"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let params = TraversalParams {
            stops: HEAT_STOPS.map(|[r, g, b]| [r, g, b, 255].map(|c| f32::from(c) / 255.0)),
            max_steps: MAX_STEPS as f32,
            pad: [0.0; 3],
        };
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("traversal view parameters"),
            size: std::mem::size_of::<TraversalParams>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        queue.write_buffer(&buffer, 0, bytemuck::bytes_of(&params));
        Ok(Self {
            pipeline,
            layout,
            params: buffer,
        })
    }

    /// Records the heatmap of `scene` seen by `camera` (a `GpuCamera` parameter buffer) into `output`
    /// (`width` x `height`, Rgba8Unorm). Records nothing before the scene's first upload.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera: &wgpu::Buffer,
        output: &wgpu::TextureView,
        (width, height): (u32, u32),
    ) {
        let Some(scene_group) = scene.bind_group() else {
            return;
        };
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("traversal view bind group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: camera.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(output),
                },
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("traversal view pass"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, scene_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shader_composes_and_validates() {
        let source = shader_source().unwrap();
        assert_eq!(
            crate::shader_check::struct_size(&source, "TraversalParams"),
            std::mem::size_of::<TraversalParams>()
        );
        assert!(source.contains(&format!("HEAT_STOP_COUNT: u32 = {}u", HEAT_STOPS.len())));
    }

    /// The map runs through its stops (at t = i / 9), interpolates halfway between them,
    /// clamps outside [0, 1], and brightens monotonically (green and Rec. 709 luma rise over
    /// 256 samples), so that a test reading an image can order step counts by colour.
    #[test]
    fn the_colour_map_interpolates_its_stops_and_brightens() {
        let bytes = |c: [f32; 3]| c.map(|v| (v * 255.0).round() as u8);
        for (i, stop) in HEAT_STOPS.iter().enumerate() {
            assert_eq!(bytes(heat_colour(i as f32 / 9.0)), *stop, "stop {i}");
        }
        let half = heat_colour(0.5 / 9.0);
        let expected = [0x46, 0x14, 0x66].map(|c: u8| f32::from(c) / 255.0);
        for c in 0..3 {
            assert!((half[c] - expected[c]).abs() < 0.003, "{half:?}");
        }
        assert_eq!(heat_colour(-1.0), heat_colour(0.0));
        assert_eq!(heat_colour(7.0), heat_colour(1.0));
        let luma = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let samples: Vec<[f32; 3]> = (0..256).map(|i| heat_colour(i as f32 / 255.0)).collect();
        for pair in samples.windows(2) {
            assert!(pair[1][1] > pair[0][1], "green {pair:?}");
            assert!(luma(pair[1]) > luma(pair[0]), "luma {pair:?}");
        }
    }
}
