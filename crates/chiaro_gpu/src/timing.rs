//! Time per pass: GPU timestamp queries at the start and end of each pass when the device has
//! them, otherwise the wall clock around each pass submitted alone and waited for. The
//! timestamps of a frame go to one of [`TIMER_SLOTS`] readback slots, so frames in flight
//! ([`crate::in_flight`]) each keep theirs until the CPU reads them.

use std::time::Instant;

/// Milliseconds per pass of one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// The frame's number since the renderer's last fresh start (see
    /// [`crate::Renderer::render`]); frames in flight report late, so this says which it was.
    pub frame: u32,
    /// (pass name, milliseconds), in frame order; empty when pass timing is off
    /// ([`PassClock::Off`]).
    pub passes: Vec<(&'static str, f64)>,
    /// True when measured by GPU timestamps, false by the wall clock.
    pub gpu_timestamps: bool,
    /// Milliseconds spent building pipelines for this frame (shader compilation: the first
    /// frame, or a frame whose scene features changed; 0 otherwise), and the one-time
    /// measurement of `--primary auto` where this frame made it.
    pub compile_ms: f64,
    /// Milliseconds of CPU from the frame's start to its submission returning: pipeline
    /// selection and builds, parameters, recording and submission (the scene systems before
    /// it not included; with the wall clock, the waits for each pass included).
    pub submit_ms: f64,
    /// Milliseconds of wall clock from the frame's start on the CPU to the CPU seeing the GPU
    /// finish it: the frame's latency, pipelines built included. With frames in flight the CPU
    /// sees a frame finish at its next look, at most one frame's recording late.
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

/// How the passes are timed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassClock {
    /// GPU timestamps at each pass's start and end; frames stay in flight.
    Gpu,
    /// The wall clock around each pass, submitted alone and waited for: every frame waits
    /// for the GPU, so only one is ever in flight.
    Wall,
    /// Passes are not timed (only each frame's latency is); frames stay in flight.
    Off,
}

impl PassClock {
    /// The clock for a device with (`timestamps`) or without GPU timestamps, as the
    /// environment variable `CHIARO_TIMER` asks: `wall` (some drivers, lavapipe among them,
    /// write timestamps that do not bracket the pass's work; the wall clock around each pass
    /// does), `off`, or unset: timestamps where the device has them, else the wall clock.
    pub fn from_env(timestamps: bool) -> Self {
        match std::env::var("CHIARO_TIMER").as_deref() {
            Ok("wall") => PassClock::Wall,
            Ok("off") => PassClock::Off,
            _ if timestamps => PassClock::Gpu,
            _ => PassClock::Wall,
        }
    }
}

/// Frames whose timestamps can wait to be read at once: the most frames in flight.
pub const TIMER_SLOTS: usize = 3;

/// One frame's timestamps: the query set, the buffer it resolves to, and the buffer the CPU
/// maps.
struct Slot {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
}

/// Timestamp queries for up to `passes` passes a frame, in [`TIMER_SLOTS`] slots.
pub struct PassTimer {
    clock: PassClock,
    slots: Vec<Slot>,
    period_ns: f32,
    wall_start: Option<Instant>,
}

impl PassTimer {
    /// A timer for `clock` (its slots are made only for [`PassClock::Gpu`]).
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, clock: PassClock, passes: u32) -> Self {
        let count = 2 * passes;
        let size = u64::from(count) * 8;
        let slots = match clock {
            PassClock::Gpu => (0..TIMER_SLOTS)
                .map(|_| Slot {
                    set: device.create_query_set(&wgpu::QuerySetDescriptor {
                        label: Some("pass timestamps"),
                        ty: wgpu::QueryType::Timestamp,
                        count,
                    }),
                    resolve: device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("pass timestamps resolve"),
                        size,
                        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                        mapped_at_creation: false,
                    }),
                    read: device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("pass timestamps readback"),
                        size,
                        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    }),
                })
                .collect(),
            PassClock::Wall | PassClock::Off => Vec::new(),
        };
        Self {
            clock,
            slots,
            period_ns: queue.get_timestamp_period(),
            wall_start: None,
        }
    }

    /// How the passes are timed.
    pub fn clock(&self) -> PassClock {
        self.clock
    }

    /// The timestamp writes of compute pass `index` into `slot`.
    pub fn compute(&self, slot: usize, index: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.slots
            .get(slot)
            .map(|s| wgpu::ComputePassTimestampWrites {
                query_set: &s.set,
                beginning_of_pass_write_index: Some(2 * index),
                end_of_pass_write_index: Some(2 * index + 1),
            })
    }

    /// The timestamp writes of render pass `index` into `slot`.
    pub fn render(&self, slot: usize, index: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.slots
            .get(slot)
            .map(|s| wgpu::RenderPassTimestampWrites {
                query_set: &s.set,
                beginning_of_pass_write_index: Some(2 * index),
                end_of_pass_write_index: Some(2 * index + 1),
            })
    }

    /// Starts the wall clock of a pass ([`PassClock::Wall`]).
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

    /// Copies the timestamps of `passes` passes in `slot` for reading (record after the
    /// passes).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder, slot: usize, passes: u32) {
        if let Some(s) = self.slots.get(slot) {
            encoder.resolve_query_set(&s.set, 0..2 * passes, &s.resolve, 0);
            encoder.copy_buffer_to_buffer(&s.resolve, 0, &s.read, 0, u64::from(passes) * 16);
        }
    }

    /// Asks for `slot`'s timestamps to be mapped once the submission that resolved them
    /// finishes (call after submitting it).
    pub fn map(&self, slot: usize, passes: u32) {
        if let Some(s) = self.slots.get(slot) {
            s.read
                .map_async(wgpu::MapMode::Read, 0..u64::from(passes) * 16, |_| {});
        }
    }

    /// Milliseconds per pass from `slot`'s timestamps, once the submission that resolved
    /// them has finished and the device was polled; unmaps the slot for its next frame.
    /// `None` without timestamps, or when the mapping failed.
    pub fn read(&self, slot: usize, passes: u32) -> Option<Vec<f64>> {
        let s = self.slots.get(slot)?;
        let size = u64::from(passes) * 16;
        let ticks: Option<Vec<u64>> = s
            .read
            .get_mapped_range(0..size)
            .ok()
            .map(|view| bytemuck::pod_collect_to_vec(&view));
        s.read.unmap();
        Some(
            ticks?
                .chunks_exact(2)
                .map(|t| t[1].saturating_sub(t[0]) as f64 * f64::from(self.period_ns) * 1e-6)
                .collect(),
        )
    }
}
