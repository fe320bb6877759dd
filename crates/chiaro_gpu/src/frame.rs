//! One frame, top-down: the passes in the order they run, which of them each mode runs, their
//! parameter buffers and bind groups, timed per pass.
//!
//! 1. `gbuffer` (raster, or traced through the BVHs: [`PrimaryVisibility`]): position,
//!    normals, material, emission, instance id, motion vectors, depth.
//! 2. `restir_temporal`, `restir_spatial` (compute; realtime and direct modes with resampled
//!    direct light, [`crate::settings::RestirSettings`]): each pixel's reservoir of light
//!    candidates, merged with last frame's and with its neighbours'.
//! 3. `direct` (compute): the direct light the surface seen reflects (light samples with shadow
//!    rays, MIS with BRDF samples); the environment where no surface is seen.
//! 4. `indirect` (compute): `spp` paths from the surface seen, the light they gather after the
//!    first bounce (naive mode: all reflected light, by uniform hemisphere sampling); with
//!    resampled indirect light, `restir_gi_initial` and `restir_gi_spatial` instead: one path
//!    a pixel kept as a sample, merged with last frame's reservoir and resampled with its
//!    neighbours'; the reservoirs are then copied as the next frame's history.
//! 5. `temporal`, `variance`, `atrous` (compute; realtime mode with the denoiser on): the
//!    lighting demodulated by albedo, reprojected and accumulated, its variance estimated, and
//!    filtered edge-aware.
//! 6. `composite` (compute): emission plus reflected light; in every mode but realtime, the
//!    running mean over frames; the linear HDR image.
//! 7. `tonemap` (compute): the HDR image to 8-bit sRGB.

use crate::camera::GpuCamera;
use crate::context::GpuContext;
use crate::denoiser::Denoiser;
use crate::gpu_scene::GpuScene;
use crate::gpu_scene::back_faces::CullView;
use crate::in_flight::{FramesInFlight, SubmittedFrame};
use crate::passes::composite::{
    COMPOSITE_DIRECT, COMPOSITE_FILTERED, COMPOSITE_PATHS, COMPOSITE_RESET, COMPOSITE_RESOLVE,
    CompositeParams, CompositePass,
};
use crate::passes::direct::DirectParams;
use crate::passes::indirect::IndirectParams;
use crate::passes::restir::RestirParams;
use crate::passes::tonemap::{TonemapParams, TonemapPass};
use crate::settings::{
    FrameSettings, LightSampling, PrimaryVisibility, REFERENCE_BOUNCES, RenderMode, Sampler,
};
use crate::shaders::ShaderError;
use crate::specialization::PipelineFeatures;
use crate::still_view::{Stillness, history_weights, running_mean_frames};
use crate::targets::FrameTargets;
use crate::timing::{PassClock, PassTimer, PassTimes};

mod primary;
mod scene_passes;
mod schedule;

pub use scene_passes::ScenePasses;
use schedule::{MAX_PASSES, denoises};
pub use schedule::{Pass, passes};

/// What one frame takes besides the scene and the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameInput {
    /// Frame number (picks the random numbers).
    pub frame: u32,
    /// Seed of the random numbers.
    pub seed: u64,
    /// Frames in the running mean including this one (1 restarts accumulation; the realtime
    /// mode always passes 1).
    pub accumulated: u32,
    /// Whether the denoiser's history restarts (first frame, new size or world).
    pub reset_history: bool,
    /// How long the view has been still ([`crate::still_view`]).
    pub stillness: Stillness,
    /// What the frame computes.
    pub settings: FrameSettings,
    /// Test hook: the indirect pass writes NaN at pixel (0, 0) and +Inf at (1, 0).
    pub poison: bool,
    /// The feature set the scene-reading passes render with.
    pub features: PipelineFeatures,
    /// Whether a pipeline for new features is built on another thread while the old one
    /// renders (an interactive app), rather than before the frame (exact images).
    pub background_compile: bool,
    /// The most frames running on the GPU when the frame's submission returns plus one
    /// (1: every frame is waited for; see [`crate::in_flight`]).
    pub frames_in_flight: u32,
}

/// A parameter buffer (read-only storage; see [`crate::passes::params`]) of `size` bytes.
fn params_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The frame's passes and their resources at one output size.
pub struct Frame {
    /// The images the passes write.
    pub targets: FrameTargets,
    scene_passes: ScenePasses,
    composite: CompositePass,
    tonemap: TonemapPass,
    denoiser: Denoiser,
    /// Whether the last frame ran the denoiser (if not, its history is stale).
    denoised: bool,
    /// Whether the last frame resampled its direct light (if not, the reservoirs are stale).
    resampled: bool,
    /// Whether the frame keeps its resampled-indirect reservoirs as history (copies them to
    /// `gi_history` after its spatial pass); until the next frame's parameters are written,
    /// the last frame's (if it did not, `gi_history` is stale).
    keeps_gi_history: bool,
    camera: wgpu::Buffer,
    restir_params: wgpu::Buffer,
    direct_params: wgpu::Buffer,
    indirect_params: wgpu::Buffer,
    composite_params: wgpu::Buffer,
    tonemap_params: wgpu::Buffer,
    camera_group: wgpu::BindGroup,
    /// The traced G-buffer's bind group, where the device can trace it.
    gbuffer_traced_group: Option<wgpu::BindGroup>,
    /// How the last frame found the surfaces seen.
    primary: PrimaryVisibility,
    /// What [`PrimaryVisibility::Auto`] measured to be faster at this size, once measured.
    auto_primary: Option<PrimaryVisibility>,
    /// The resampling passes' bind groups (first, spatial).
    restir_groups: [wgpu::BindGroup; 2],
    direct_group: wgpu::BindGroup,
    indirect_group: wgpu::BindGroup,
    /// The resampled indirect light's bind groups (initial, spatial).
    restir_gi_groups: [wgpu::BindGroup; 2],
    composite_groups: [wgpu::BindGroup; 2],
    resolve_parity: usize,
    tonemap_group: wgpu::BindGroup,
    timer: PassTimer,
    in_flight: FramesInFlight,
    /// See [`Frame::features`].
    features: Option<PipelineFeatures>,
}

impl Frame {
    /// The frame at `width` x `height` over the scene passes (new ones, or those of a frame of
    /// another size: see [`Frame::into_scene_passes`]).
    pub fn new(
        context: &GpuContext,
        scene_passes: ScenePasses,
        width: u32,
        height: u32,
    ) -> Result<Self, ShaderError> {
        let device = &context.device;
        let targets = FrameTargets::new(device, width, height, context.traced_gbuffer);
        let ScenePasses {
            gbuffer,
            gbuffer_traced,
            restir_temporal,
            restir_spatial,
            direct,
            indirect,
            restir_gi_initial,
            restir_gi_spatial,
        } = &scene_passes;
        let composite = CompositePass::new(device)?;
        let tonemap = TonemapPass::new(device)?;
        let camera = params_buffer(device, "camera params", size_of::<GpuCamera>());
        let restir_params = params_buffer(device, "restir params", size_of::<RestirParams>());
        let direct_params = params_buffer(device, "direct params", size_of::<DirectParams>());
        let indirect_params = params_buffer(device, "indirect params", size_of::<IndirectParams>());
        let composite_params =
            params_buffer(device, "composite params", size_of::<CompositeParams>());
        let tonemap_params = params_buffer(device, "tonemap params", size_of::<TonemapParams>());
        let denoiser = Denoiser::new(device, &targets, &camera)?;
        let filtered = denoiser.output();
        Ok(Self {
            camera_group: gbuffer.camera_bind_group(device, &camera),
            gbuffer_traced_group: gbuffer_traced
                .as_ref()
                .map(|pass| pass.bind_group(device, &targets, &camera)),
            primary: PrimaryVisibility::Raster,
            auto_primary: None,
            restir_groups: [
                restir_temporal.bind_group(device, &targets, &camera, &restir_params),
                restir_spatial.bind_group(device, &targets, &camera, &restir_params),
            ],
            direct_group: direct.bind_group(device, &targets, &camera, &direct_params),
            indirect_group: indirect.bind_group(device, &targets, &camera, &indirect_params),
            restir_gi_groups: [
                restir_gi_initial.bind_group(device, &targets, &camera, &indirect_params),
                restir_gi_spatial.bind_group(device, &targets, &camera, &restir_params),
            ],
            composite_groups: [0, 1].map(|parity| {
                composite.bind_group(
                    device,
                    &targets,
                    filtered,
                    &composite_params,
                    &camera,
                    parity,
                )
            }),
            resolve_parity: 0,
            tonemap_group: tonemap.bind_group(device, &targets, &tonemap_params),
            timer: PassTimer::new(
                device,
                &context.queue,
                PassClock::from_env(context.timestamps),
                MAX_PASSES,
            ),
            in_flight: FramesInFlight::default(),
            features: None,
            targets,
            scene_passes,
            composite,
            tonemap,
            denoiser,
            denoised: false,
            resampled: false,
            keeps_gi_history: false,
            camera,
            restir_params,
            direct_params,
            indirect_params,
            composite_params,
            tonemap_params,
        })
    }

    /// The scene passes, with their compiled pipelines, for a frame of another size.
    pub fn into_scene_passes(self) -> ScenePasses {
        self.scene_passes
    }

    /// Pipelines the scene passes built so far.
    pub fn pipeline_builds(&self) -> u32 {
        self.scene_passes.pipeline_builds()
    }

    /// The feature set the last frame's scene passes all rendered with; `None` before the first
    /// frame, and while a new feature set compiling in the background has reached some of the
    /// passes and not yet the others.
    pub fn features(&self) -> Option<PipelineFeatures> {
        self.features
    }

    /// The camera parameters (a [`GpuCamera`]) the last frame rendered with, jitter included
    /// (for debug views that trace the frame's camera rays).
    pub fn camera(&self) -> &wgpu::Buffer {
        &self.camera
    }

    /// How the last frame found the surfaces its pixels see: as its settings asked (for
    /// [`PrimaryVisibility::Auto`], what was measured faster), or rasterized where the device
    /// cannot trace them.
    pub fn primary(&self) -> PrimaryVisibility {
        self.primary
    }

    /// The realtime mode's denoiser (its history and output, for tests and debug views).
    pub fn denoiser(&self) -> &Denoiser {
        &self.denoiser
    }

    /// Gives the reservoirs the frame's size the first time a frame resamples
    /// ([`FrameTargets::size_reservoirs`]) and binds them again.
    fn size_reservoirs(&mut self, device: &wgpu::Device) {
        if !self.targets.size_reservoirs(device) {
            return;
        }
        let (passes, t, camera) = (&self.scene_passes, &self.targets, &self.camera);
        self.restir_groups = [
            passes
                .restir_temporal
                .bind_group(device, t, camera, &self.restir_params),
            passes
                .restir_spatial
                .bind_group(device, t, camera, &self.restir_params),
        ];
        self.direct_group = passes
            .direct
            .bind_group(device, t, camera, &self.direct_params);
        self.restir_gi_groups = [
            passes
                .restir_gi_initial
                .bind_group(device, t, camera, &self.indirect_params),
            passes
                .restir_gi_spatial
                .bind_group(device, t, camera, &self.restir_params),
        ];
    }

    /// Writes the parameters of the passes for this frame.
    fn write_params(&mut self, queue: &wgpu::Queue, camera: &GpuCamera, input: &FrameInput) {
        let s = &input.settings;
        let denoised = denoises(s);
        // The denoiser's and the resolve's histories restart together.
        let reset_history = input.reset_history || !self.denoised;
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(camera));
        let (seed_lo, seed_hi) = (input.seed as u32, (input.seed >> 32) as u32);
        let naive = s.mode == RenderMode::Naive;
        // Sobol draws number the samples of a pixel from 0: the frames accumulated before.
        let sobol = matches!(s.mode, RenderMode::Reference | RenderMode::Direct)
            && s.sampler == Sampler::Sobol;
        let frame = if sobol {
            input.accumulated.saturating_sub(1)
        } else {
            input.frame
        };
        let direct = DirectParams {
            frame,
            seed_lo,
            seed_hi,
            lights: u32::from(!naive),
            light_sampling: light_sampling(s),
            firefly_clamp: firefly_clamp(s),
            restir: u32::from(s.resamples_direct_light()),
            sampler: u32::from(sobol),
        };
        queue.write_buffer(&self.direct_params, 0, bytemuck::bytes_of(&direct));
        let converging =
            s.mode.accumulates() || running_mean_frames(&s.denoise, input.stillness) > 0;
        if s.resamples() {
            // Last frame's reservoirs are this view's unless the history restarts or last
            // frame did not resample.
            let history = !input.reset_history && self.resampled;
            let restir = RestirParams::new(
                s,
                (input.frame, input.seed),
                (light_sampling(s), firefly_clamp(s)),
                history,
                converging,
            );
            queue.write_buffer(&self.restir_params, 0, bytemuck::bytes_of(&restir));
        }
        self.resampled = s.resamples_direct_light();
        // As the direct light's, last frame's indirect reservoirs are merged only in motion
        // (see `RestirParams::new`).
        let gi_history = !input.reset_history && self.keeps_gi_history && !converging;
        self.keeps_gi_history = s.resamples_indirect_light() && s.restir.indirect_history_cap > 0;
        let indirect = IndirectParams {
            frame,
            seed_lo,
            seed_hi,
            spp: s.spp,
            bounces: if s.mode == RenderMode::Realtime {
                s.bounces
            } else {
                REFERENCE_BOUNCES
            },
            naive: u32::from(naive),
            poison: u32::from(input.poison),
            light_sampling: light_sampling(s),
            firefly_clamp: firefly_clamp(s),
            sampler: u32::from(sobol),
            gi_history_cap: if gi_history {
                s.restir.indirect_history_cap
            } else {
                0
            },
            pad: 0,
        };
        queue.write_buffer(&self.indirect_params, 0, bytemuck::bytes_of(&indirect));
        let weights = history_weights(&s.denoise, input.stillness);
        let composite = CompositeParams {
            frames: if s.mode.accumulates() {
                input.accumulated.max(1)
            } else {
                1
            },
            source: match s.mode {
                RenderMode::Direct => COMPOSITE_DIRECT,
                _ if denoised => COMPOSITE_FILTERED,
                _ => COMPOSITE_PATHS,
            },
            flags: match (denoised, reset_history) {
                (false, _) => 0,
                (true, false) => COMPOSITE_RESOLVE,
                (true, true) => COMPOSITE_RESOLVE | COMPOSITE_RESET,
            },
            resolve_floor: weights.floor,
            resolve_clamp: weights.clamp,
        };
        queue.write_buffer(&self.composite_params, 0, bytemuck::bytes_of(&composite));
        let tonemap = TonemapParams::new(s.tonemapper, s.exposure);
        queue.write_buffer(&self.tonemap_params, 0, bytemuck::bytes_of(&tonemap));
        if denoised {
            self.denoiser
                .prepare(queue, &s.denoise, reset_history, weights);
        }
        self.denoised = denoised;
    }

    /// Records `pass`, timed as the `index`th of the frame in timestamp slot `slot`, for the
    /// camera `view` (the G-buffer's back-face test).
    fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        view: Option<CullView>,
        pass: Pass,
        (slot, index): (usize, u32),
    ) {
        let t = &self.targets;
        let timer = &self.timer;
        match pass {
            Pass::Gbuffer => {
                let traced = self.primary == PrimaryVisibility::Traced;
                let timestamps = (timer.render(slot, index), timer.compute(slot, index));
                self.record_gbuffer(encoder, scene, view, traced, timestamps);
            }
            Pass::RestirTemporal => self.scene_passes.restir_temporal.record(
                encoder,
                scene,
                &self.restir_groups[0],
                t,
                timer.compute(slot, index),
            ),
            Pass::RestirSpatial => self.scene_passes.restir_spatial.record(
                encoder,
                scene,
                &self.restir_groups[1],
                t,
                timer.compute(slot, index),
            ),
            Pass::Direct => self.scene_passes.direct.record(
                encoder,
                scene,
                &self.direct_group,
                t,
                timer.compute(slot, index),
            ),
            Pass::Indirect => self.scene_passes.indirect.record(
                encoder,
                scene,
                &self.indirect_group,
                t,
                timer.compute(slot, index),
            ),
            Pass::RestirGiInitial => self.scene_passes.restir_gi_initial.record(
                encoder,
                scene,
                &self.restir_gi_groups[0],
                t,
                timer.compute(slot, index),
            ),
            Pass::RestirGiSpatial => {
                self.scene_passes.restir_gi_spatial.record(
                    encoder,
                    scene,
                    &self.restir_gi_groups[1],
                    t,
                    timer.compute(slot, index),
                );
                if self.keeps_gi_history {
                    let texture = &t.gi_reservoirs.texture;
                    encoder.copy_texture_to_texture(
                        texture.as_image_copy(),
                        t.gi_history.texture.as_image_copy(),
                        texture.size(),
                    );
                }
            }
            Pass::Temporal => self
                .denoiser
                .record_temporal(encoder, t, timer.compute(slot, index)),
            Pass::Variance => self
                .denoiser
                .record_variance(encoder, t, timer.compute(slot, index)),
            Pass::Atrous => self
                .denoiser
                .record_atrous(encoder, t, timer.compute(slot, index)),
            Pass::Composite => {
                let group = &self.composite_groups[self.resolve_parity];
                self.composite
                    .record(encoder, group, t, timer.compute(slot, index));
                self.resolve_parity = 1 - self.resolve_parity;
            }
            Pass::Tonemap => {
                self.tonemap
                    .record(encoder, &self.tonemap_group, t, timer.compute(slot, index))
            }
        }
    }

    /// Submits one frame of `scene` seen by `camera` and returns the pass times of the frames
    /// the GPU has finished since the last call, oldest first: this one among them only when
    /// `input.frames_in_flight` is 1 or the passes are timed by the wall clock, which waits
    /// for each. Otherwise it returns once at most `frames_in_flight - 1` frames are running
    /// besides this one, so the CPU prepares the next frame while the GPU renders this one.
    pub fn render(
        &mut self,
        context: &GpuContext,
        scene: &GpuScene,
        camera: &GpuCamera,
        input: &FrameInput,
    ) -> Vec<PassTimes> {
        let (device, queue) = (&context.device, &context.queue);
        let start = std::time::Instant::now();
        if input.settings.resamples() {
            self.size_reservoirs(device);
        }
        self.write_params(queue, camera, input);
        let primary = self.choose_primary(context, scene, camera.cull_view(), input);
        if primary != self.primary {
            log::info!("primary visibility: {}", primary.name());
        }
        self.primary = primary;
        let traced = primary == PrimaryVisibility::Traced;
        self.features = self.scene_passes.specialize(device, input, traced);
        let compile_ms = start.elapsed().as_secs_f64() * 1e3;
        let run = passes(&input.settings);
        let wall_clock = self.timer.clock() == PassClock::Wall;
        let slot = self.in_flight.next_slot();
        let mut wall = Vec::new();
        let mut encoder = new_encoder(device);
        for (index, &pass) in run.iter().enumerate() {
            if wall_clock {
                self.timer.start_wall();
            }
            let at = (slot, index as u32);
            self.record(&mut encoder, scene, camera.cull_view(), pass, at);
            if wall_clock {
                queue.submit([std::mem::replace(&mut encoder, new_encoder(device)).finish()]);
                wall.push(self.timer.stop_wall(device));
            }
        }
        self.timer.resolve(&mut encoder, slot, run.len() as u32);
        let submission = queue.submit([encoder.finish()]);
        let frame = SubmittedFrame {
            frame: input.frame,
            slot,
            passes: run.iter().map(|p| p.name()).collect(),
            start,
            compile_ms,
            submit_ms: start.elapsed().as_secs_f64() * 1e3,
            wall: wall_clock.then_some(wall),
        };
        self.in_flight
            .submitted(queue, &self.timer, frame, submission);
        let limit = crate::in_flight::frames_in_flight(self.timer.clock(), input.frames_in_flight);
        let keep = limit as usize - 1;
        self.in_flight.collect(device, &self.timer, keep)
    }

    /// Waits for every frame in flight and returns their pass times, oldest first.
    pub fn finish(&mut self, device: &wgpu::Device) -> Vec<PassTimes> {
        self.in_flight.collect(device, &self.timer, 0)
    }

    /// Frames submitted whose times were not yet returned.
    pub fn frames_running(&self) -> usize {
        self.in_flight.running()
    }
}

fn new_encoder(device: &wgpu::Device) -> wgpu::CommandEncoder {
    device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("frame encoder"),
    })
}

/// The passes' `firefly_clamp` for `settings`: the clamp on scene luminance in realtime mode
/// (the setting is in units of display white at the exposure), 0 (off) in the other modes.
fn firefly_clamp(settings: &FrameSettings) -> f32 {
    if settings.mode == RenderMode::Realtime {
        settings.firefly_clamp / settings.exposure
    } else {
        0.0
    }
}

/// The passes' `light_sampling` for `settings`.
fn light_sampling(settings: &FrameSettings) -> u32 {
    match settings.light_sampling {
        LightSampling::Power => crate::gpu_scene::layout::LIGHT_SAMPLING_POWER,
        LightSampling::Tree => crate::gpu_scene::layout::LIGHT_SAMPLING_TREE,
    }
}
