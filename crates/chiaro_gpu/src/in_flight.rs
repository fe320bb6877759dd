//! Frames in flight: the CPU runs the scene systems and records frame N+1 while the GPU renders
//! frame N. A frame is submitted without waiting; the renderer waits only when more frames
//! than its limit would be running, and then for the oldest. Each frame's pass times come back
//! when the GPU has finished it, tagged with its number.

use std::collections::VecDeque;
use std::sync::{Arc, OnceLock};
use std::time::Instant;

use crate::timing::{PassClock, PassTimer, PassTimes, TIMER_SLOTS};

/// Frames the renderer keeps in flight on a GPU unless told otherwise
/// ([`crate::Renderer::new`], [`crate::Renderer::set_frames_in_flight`]).
pub const DEFAULT_FRAMES_IN_FLIGHT: u32 = 2;

/// The most frames in flight (one timestamp slot each).
pub const MAX_FRAMES_IN_FLIGHT: u32 = TIMER_SLOTS as u32;

/// The most frames in flight when `n` are asked for and the passes are timed by `clock`:
/// `n` within 1..=[`MAX_FRAMES_IN_FLIGHT`], or 1 with the wall clock, which waits for every
/// pass.
pub fn frames_in_flight(clock: PassClock, n: u32) -> u32 {
    match clock {
        PassClock::Wall => 1,
        PassClock::Gpu | PassClock::Off => n.clamp(1, MAX_FRAMES_IN_FLIGHT),
    }
}

/// A frame on its way to the GPU: what its times need once it has finished.
pub struct SubmittedFrame {
    /// The frame's number.
    pub frame: u32,
    /// The timestamp slot its passes wrote.
    pub slot: usize,
    /// The passes it ran, in order.
    pub passes: Vec<&'static str>,
    /// When the CPU began it.
    pub start: Instant,
    /// Milliseconds its pipelines took to build.
    pub compile_ms: f64,
    /// Milliseconds from its start to its submission returning.
    pub submit_ms: f64,
    /// Milliseconds per pass when measured on the CPU (the wall clock), or `None`.
    pub wall: Option<Vec<f64>>,
}

/// A submitted frame, and when the GPU was seen to finish it.
struct Running {
    frame: SubmittedFrame,
    submission: wgpu::SubmissionIndex,
    finished: Arc<OnceLock<Instant>>,
}

/// The frames submitted and not yet collected, oldest first.
#[derive(Default)]
pub struct FramesInFlight {
    running: VecDeque<Running>,
    next_slot: usize,
}

impl FramesInFlight {
    /// The timestamp slot the next frame writes.
    pub fn next_slot(&self) -> usize {
        self.next_slot
    }

    /// Frames submitted whose times were not yet collected.
    pub fn running(&self) -> usize {
        self.running.len()
    }

    /// Notes `frame`, just submitted as `submission`: its timestamps are mapped, and the time
    /// the GPU finishes it is kept.
    pub fn submitted(
        &mut self,
        queue: &wgpu::Queue,
        timer: &PassTimer,
        frame: SubmittedFrame,
        submission: wgpu::SubmissionIndex,
    ) {
        timer.map(frame.slot, frame.passes.len() as u32);
        let finished = Arc::new(OnceLock::new());
        let seen = Arc::clone(&finished);
        queue.on_submitted_work_done(move || {
            let _ = seen.set(Instant::now());
        });
        self.next_slot = (frame.slot + 1) % TIMER_SLOTS;
        self.running.push_back(Running {
            frame,
            submission,
            finished,
        });
    }

    /// The times of every frame the GPU has finished, oldest first, after waiting for the
    /// oldest ones until at most `keep` frames are running.
    pub fn collect(
        &mut self,
        device: &wgpu::Device,
        timer: &PassTimer,
        keep: usize,
    ) -> Vec<PassTimes> {
        let _ = device.poll(wgpu::PollType::Poll);
        let mut times = Vec::new();
        while let Some(oldest) = self.running.front() {
            if oldest.finished.get().is_none() && self.running.len() <= keep {
                break;
            }
            // Returns at once when the frame has finished; its timestamps are mapped then.
            let _ = device.poll(wgpu::PollType::Wait {
                submission_index: Some(oldest.submission.clone()),
                timeout: None,
            });
            let Running {
                frame, finished, ..
            } = self.running.pop_front().expect("the oldest frame is there");
            let end = finished.get().copied().unwrap_or_else(Instant::now);
            let millis = match frame.wall {
                Some(wall) => Some(wall),
                None => timer.read(frame.slot, frame.passes.len() as u32),
            };
            times.push(PassTimes {
                frame: frame.frame,
                passes: millis
                    .map(|ms| frame.passes.iter().copied().zip(ms).collect())
                    .unwrap_or_default(),
                gpu_timestamps: timer.clock() == PassClock::Gpu,
                compile_ms: frame.compile_ms,
                submit_ms: frame.submit_ms,
                wall_ms: end.duration_since(frame.start).as_secs_f64() * 1e3,
            });
        }
        times
    }
}
