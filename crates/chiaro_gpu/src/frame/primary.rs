//! The G-buffer pass a frame records: rasterized, or traced where the device can
//! ([`PrimaryVisibility`]), and for [`PrimaryVisibility::Auto`] the measurement that picks one.

use super::{Frame, FrameInput, new_encoder};
use crate::context::GpuContext;
use crate::gpu_scene::GpuScene;
use crate::gpu_scene::back_faces::CullView;
use crate::settings::PrimaryVisibility;

impl Frame {
    /// Records the G-buffer pass, traced (where the device can) or rasterized, with the
    /// timestamp writes of either kind of pass.
    pub(super) fn record_gbuffer(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        view: Option<CullView>,
        traced: bool,
        (render, compute): (
            Option<wgpu::RenderPassTimestampWrites<'_>>,
            Option<wgpu::ComputePassTimestampWrites<'_>>,
        ),
    ) {
        let t = &self.targets;
        match (
            &self.gbuffer_traced_group,
            &self.scene_passes.gbuffer_traced,
        ) {
            (Some(group), Some(pass)) if traced => {
                pass.record(encoder, scene, group, t, compute);
            }
            _ => {
                let pass = &self.scene_passes.gbuffer;
                pass.record(encoder, scene, &self.camera_group, view, t, render);
            }
        }
    }

    /// How this frame finds its surfaces (see [`Frame::primary`]); for
    /// [`PrimaryVisibility::Auto`], the first time at this size, both G-buffer passes are
    /// built, run alone three times each and timed by the wall clock, the best of each run
    /// counting (the first run may build the driver's own code), and the faster is kept. While
    /// a pipeline still compiles in the background the frame rasterizes and measures later.
    pub(super) fn choose_primary(
        &mut self,
        context: &GpuContext,
        scene: &GpuScene,
        view: Option<CullView>,
        input: &FrameInput,
    ) -> PrimaryVisibility {
        use PrimaryVisibility::{Auto, Raster, Traced};
        let (device, queue) = (&context.device, &context.queue);
        match input.settings.primary {
            _ if self.gbuffer_traced_group.is_none() => Raster,
            Raster => Raster,
            Traced => Traced,
            Auto => {
                if let Some(choice) = self.auto_primary {
                    return choice;
                }
                let mut best = [f64::INFINITY; 2];
                for (traced, best) in [false, true].into_iter().zip(&mut best) {
                    if self
                        .scene_passes
                        .specialize(device, input, traced)
                        .is_none()
                    {
                        return Raster;
                    }
                    for _ in 0..3 {
                        let start = std::time::Instant::now();
                        let mut encoder = new_encoder(device);
                        self.record_gbuffer(&mut encoder, scene, view, traced, (None, None));
                        queue.submit([encoder.finish()]);
                        let _ = device.poll(wgpu::PollType::wait_indefinitely());
                        *best = best.min(start.elapsed().as_secs_f64() * 1e3);
                    }
                }
                let choice = if best[1] < best[0] { Traced } else { Raster };
                log::info!(
                    "primary visibility: raster {:.3} ms, traced {:.3} ms at {}x{}: {}",
                    best[0],
                    best[1],
                    self.targets.width,
                    self.targets.height,
                    choice.name()
                );
                self.auto_primary = Some(choice);
                choice
            }
        }
    }
}
