//! A compute-shader harness for the parity tests: composes a test kernel (WGSL text that may
//! `#import lib/...` modules), binds plain byte buffers as storage buffers (or as texel arrays,
//! uploaded as the scene uploads its BVH), runs the kernel once per item and reads one output
//! buffer back.
//!
//! Kernels use `@workgroup_size(64)` and index items by `global_invocation_id.x`; a run covers
//! at most [`MAX_ITEMS`] items (the parity tests batch larger inputs).

use chiaro_gpu::gpu_scene::MirrorTexels;
use chiaro_gpu::shaders::{self, ShaderError};
use chiaro_gpu::{GpuContext, UploadStats};

/// Threads per workgroup every test kernel declares.
pub const WORKGROUP_SIZE: u32 = 64;

/// Most items one [`Kernel::run`] covers (one dispatch dimension).
pub const MAX_ITEMS: u32 = 65_535 * WORKGROUP_SIZE;

/// Name under which the kernel's own text is composed.
const KERNEL_NAME: &str = "test-kernel.wgsl";

/// `kernel` with its imports resolved against the embedded shaders.
pub fn compose_kernel(kernel: &str) -> Result<String, ShaderError> {
    shaders::compose_with(KERNEL_NAME, &|name| {
        if name == KERNEL_NAME {
            Some(kernel.to_owned())
        } else {
            shaders::source(name)
        }
    })
}

/// A storage buffer the kernel reads: its group, binding and bytes.
pub struct Input<'a> {
    /// Bind group index.
    pub group: u32,
    /// Binding index.
    pub binding: u32,
    /// Contents (padded to 4 bytes, and to at least 4).
    pub data: &'a [u8],
}

/// The read-write storage buffer the kernel writes, read back after the run.
pub struct Output {
    /// Bind group index.
    pub group: u32,
    /// Binding index.
    pub binding: u32,
    /// Size in bytes (a multiple of 4).
    pub size: u64,
}

/// A compiled compute kernel with the layout derived from its WGSL.
pub struct Kernel {
    pipeline: wgpu::ComputePipeline,
    label: String,
}

fn padded(data: &[u8]) -> Vec<u8> {
    let mut bytes = data.to_vec();
    bytes.resize(data.len().max(4).next_multiple_of(4), 0);
    bytes
}

impl Kernel {
    /// Composes and compiles `kernel` (entry point `main`). Panics with the composition error.
    pub fn new(gpu: &GpuContext, label: &str, kernel: &str) -> Self {
        let source = compose_kernel(kernel).unwrap_or_else(|e| panic!("{label}: {e}"));
        let module = gpu
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        let pipeline = gpu
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: None,
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
        Self {
            pipeline,
            label: label.to_owned(),
        }
    }

    /// Runs one invocation per element of `inputs` (bound read-only at group 0, binding 0) and
    /// returns as many `O` read back from the output at group 0, binding 1.
    #[allow(dead_code, reason = "the kernels with several buffers use `run`")]
    pub fn map<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        gpu: &GpuContext,
        inputs: &[I],
    ) -> Vec<O> {
        let input = Input {
            group: 0,
            binding: 0,
            data: bytemuck::cast_slice(inputs),
        };
        let output = Output {
            group: 0,
            binding: 1,
            size: (inputs.len() * size_of::<O>()) as u64,
        };
        let bytes = self.run(gpu, &[input], &output, inputs.len() as u32);
        bytemuck::pod_collect_to_vec(&bytes[..inputs.len() * size_of::<O>()])
    }

    /// Runs `items` invocations with `inputs` bound read-only and `output` read-write, and
    /// returns the output buffer's bytes.
    pub fn run(&self, gpu: &GpuContext, inputs: &[Input], output: &Output, items: u32) -> Vec<u8> {
        self.run_with_texels(gpu, inputs, &[], output, items)
    }

    /// [`Kernel::run`] with `texels` bound as texel arrays (`texture_2d<u32>`, the scene's
    /// [`MirrorTexels`] layout; each input's bytes padded to whole texels).
    pub fn run_with_texels(
        &self,
        gpu: &GpuContext,
        inputs: &[Input],
        texels: &[Input],
        output: &Output,
        items: u32,
    ) -> Vec<u8> {
        assert!(
            items <= MAX_ITEMS,
            "{}: {items} items in one run",
            self.label
        );
        let device = &gpu.device;
        let label = Some(self.label.as_str());
        let mut buffers = Vec::new();
        for input in inputs {
            let bytes = padded(input.data);
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label,
                size: bytes.len() as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            gpu.queue.write_buffer(&buffer, 0, &bytes);
            buffers.push((input.group, input.binding, buffer));
        }
        let mut arrays = Vec::new();
        for input in texels {
            let mut bytes = input.data.to_vec();
            bytes.resize(input.data.len().next_multiple_of(16), 0);
            let records: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
            let mut array = MirrorTexels::new(device, "test texels");
            array
                .update(device, &gpu.queue, &records, &mut UploadStats::default())
                .unwrap_or_else(|e| panic!("{}: {e}", self.label));
            arrays.push((input.group, input.binding, array));
        }
        let size = output.size.max(4).next_multiple_of(4);
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label,
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label,
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let groups: Vec<u32> = {
            let mut g: Vec<u32> = buffers.iter().map(|b| b.0).collect();
            g.extend(arrays.iter().map(|a| a.0));
            g.push(output.group);
            g.sort_unstable();
            g.dedup();
            g
        };
        let bind_groups: Vec<(u32, wgpu::BindGroup)> =
            groups
                .iter()
                .map(|&group| {
                    let mut entries: Vec<wgpu::BindGroupEntry> =
                        buffers
                            .iter()
                            .filter(|b| b.0 == group)
                            .map(|(_, binding, buffer)| wgpu::BindGroupEntry {
                                binding: *binding,
                                resource: buffer.as_entire_binding(),
                            })
                            .chain(arrays.iter().filter(|a| a.0 == group).map(
                                |(_, binding, array)| wgpu::BindGroupEntry {
                                    binding: *binding,
                                    resource: wgpu::BindingResource::TextureView(array.view()),
                                },
                            ))
                            .collect();
                    if output.group == group {
                        entries.push(wgpu::BindGroupEntry {
                            binding: output.binding,
                            resource: out.as_entire_binding(),
                        });
                    }
                    let layout = self.pipeline.get_bind_group_layout(group);
                    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label,
                        layout: &layout,
                        entries: &entries,
                    });
                    (group, bind_group)
                })
                .collect();
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label,
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            for (group, bind_group) in &bind_groups {
                pass.set_bind_group(*group, bind_group, &[]);
            }
            pass.dispatch_workgroups(items.div_ceil(WORKGROUP_SIZE).max(1), 1, 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &readback, 0, size);
        gpu.queue.submit([encoder.finish()]);
        readback.map_async(wgpu::MapMode::Read, .., |result| {
            result.expect("mapping the readback buffer");
        });
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("waiting for the kernel");
        let bytes = readback
            .get_mapped_range(..)
            .expect("mapped readback")
            .to_vec();
        readback.unmap();
        bytes
    }
}
