//! Time per pass: GPU timestamp queries at the start and end of each pass when the device has
//! them, otherwise the wall clock around each pass submitted alone and waited for.

use std::time::Instant;

/// Milliseconds per pass of one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// (pass name, milliseconds), in frame order.
    pub passes: Vec<(&'static str, f64)>,
    /// True when measured by GPU timestamps, false by the wall clock.
    pub gpu_timestamps: bool,
    /// Milliseconds spent building pipelines for this frame (shader compilation: the first
    /// frame, or a frame whose scene features changed; 0 otherwise).
    pub compile_ms: f64,
    /// Milliseconds of wall clock from the frame's start to its times being read back: the
    /// frame's latency on the CPU, pipelines built included.
    pub wall_ms: f64,
}

/// Where the setup of a render went: the first run of the scene systems for a new world or
/// size, before any frame (see [`crate::Renderer::setup_times`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SetupTimes {
    /// Seconds the scene systems took in all.
    pub systems: f64,
    /// Of which building the BVHs.
    pub bvh: f64,
    /// Of which uploading the scene to the GPU (its tables gathered and written).
    pub upload: f64,
}

impl PassTimes {
    /// The sum over the passes.
    pub fn total_ms(&self) -> f64 {
        self.passes.iter().map(|(_, ms)| ms).sum()
    }
}

/// Timestamp queries for up to `passes` passes.
pub struct PassTimer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    period_ns: f32,
    wall_start: Option<Instant>,
}

impl PassTimer {
    /// Timestamps when `timestamps` (the device has the feature), else the wall clock.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, timestamps: bool, passes: u32) -> Self {
        let queries = timestamps.then(|| {
            let count = 2 * passes;
            let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count,
            });
            let size = u64::from(count) * 8;
            let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pass timestamps resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pass timestamps readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            (set, resolve, read)
        });
        Self {
            queries,
            period_ns: queue.get_timestamp_period(),
            wall_start: None,
        }
    }

    /// Whether the GPU's timestamps are used.
    pub fn gpu(&self) -> bool {
        self.queries.is_some()
    }

    /// The timestamp writes of compute pass `index`.
    pub fn compute(&self, index: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.queries
            .as_ref()
            .map(|(set, _, _)| wgpu::ComputePassTimestampWrites {
                query_set: set,
                beginning_of_pass_write_index: Some(2 * index),
                end_of_pass_write_index: Some(2 * index + 1),
            })
    }

    /// The timestamp writes of render pass `index`.
    pub fn render(&self, index: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.queries
            .as_ref()
            .map(|(set, _, _)| wgpu::RenderPassTimestampWrites {
                query_set: set,
                beginning_of_pass_write_index: Some(2 * index),
                end_of_pass_write_index: Some(2 * index + 1),
            })
    }

    /// Starts the wall clock of a pass (without timestamps).
    pub fn start_wall(&mut self) {
        self.wall_start = Some(Instant::now());
    }

    /// Milliseconds since [`PassTimer::start_wall`], after waiting for the device.
    pub fn stop_wall(&mut self, device: &wgpu::Device) -> f64 {
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        self.wall_start
            .take()
            .map_or(0.0, |s| s.elapsed().as_secs_f64() * 1e3)
    }

    /// Copies the timestamps of `passes` passes for reading (record after the passes).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder, passes: u32) {
        if let Some((set, resolve, read)) = &self.queries {
            encoder.resolve_query_set(set, 0..2 * passes, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, u64::from(passes) * 16);
        }
    }

    /// Milliseconds per pass from the resolved timestamps (after the submission finished).
    pub fn read(&self, device: &wgpu::Device, passes: u32) -> Option<Vec<f64>> {
        let (_, _, read) = self.queries.as_ref()?;
        let size = u64::from(passes) * 16;
        read.map_async(wgpu::MapMode::Read, 0..size, |_| {});
        device.poll(wgpu::PollType::wait_indefinitely()).ok()?;
        let ticks: Vec<u64> = {
            let view = read.get_mapped_range(0..size).ok()?;
            bytemuck::pod_collect_to_vec(&view)
        };
        read.unmap();
        Some(
            ticks
                .chunks_exact(2)
                .map(|t| t[1].saturating_sub(t[0]) as f64 * f64::from(self.period_ns) * 1e-6)
                .collect(),
        )
    }
}
