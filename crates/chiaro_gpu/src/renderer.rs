//! The headless renderer: renders a `bevy_ecs` World to a linear HDR image and a tonemapped
//! 8-bit image, frame after frame with fresh random numbers and a fresh sub-pixel point per
//! frame. In the accumulating modes (direct, reference, naive) the image is the mean of the
//! frames since the camera, the scene or the settings last changed, so it converges to the CPU
//! reference's estimate; in the realtime mode the temporal pass keeps the history. Frames are
//! submitted without waiting for the GPU ([`crate::in_flight`]): by default the CPU prepares
//! frame N+1 while the GPU renders frame N, and waits only to read an image back.

use bevy_ecs::prelude::*;
use chiaro_scene::SceneFeatures;
use chiaro_shading::rng::Pcg32;
use glam::{Mat4, Vec2, Vec3};
use thiserror::Error;

use crate::camera::{GpuCamera, NoCamera, active_camera};
use crate::context::GpuContext;
use crate::frame::{Frame, FrameInput, ScenePasses};
pub use crate::gbuffer_image::GbufferImage;
use crate::gpu_scene::{GpuScene, add_gpu_scene_systems};
use crate::in_flight::{DEFAULT_FRAMES_IN_FLIGHT, MAX_FRAMES_IN_FLIGHT};
use crate::readback::{PendingImage, ReadbackError, read_hdr, start_read};
use crate::settings::{FrameSettings, LightSampling, SettingsError};
use crate::shaders::ShaderError;
use crate::still_view::Stillness;
use crate::timing::{PassTimes, SetupTimes};

/// Why a render failed.
#[derive(Debug, Error)]
pub enum RenderError {
    /// No camera to render from.
    #[error(transparent)]
    NoCamera(#[from] NoCamera),
    /// A shader did not compose.
    #[error(transparent)]
    Shader(#[from] ShaderError),
    /// Reading the image back failed.
    #[error(transparent)]
    Readback(#[from] ReadbackError),
    /// A setting is out of range.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// Nothing was rendered yet.
    #[error("nothing was rendered yet")]
    NotRendered,
    /// The scene's BVH, light tables or environment do not fit the device's largest texture.
    #[error("the scene is too large for this device: {0}")]
    SceneTooLarge(#[from] crate::gpu_scene::SceneOverflow),
    /// The image size is zero or beyond the device's limit.
    #[error("image size {width}x{height} is not within 1..={max} per side on this device")]
    Size {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The device's largest texture side.
        max: u32,
    },
    /// Resampled indirect light keeps three texels a pixel side by side, so the image is too
    /// wide for it on this device.
    #[error(
        "image width {width} is over {max} on this device with resampled indirect light \
         (--restir-gi keeps {texels} texels a pixel in one row)"
    )]
    ResampledIndirectWidth {
        /// Requested width.
        width: u32,
        /// The widest image resampled indirect light allows on this device.
        max: u32,
        /// Texels a pixel's reservoir takes.
        texels: u32,
    },
}

/// How to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frames to render (at least 1).
    pub frames: u32,
    /// Seed of the random numbers.
    pub seed: u64,
    /// What each frame computes.
    pub frame: FrameSettings,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 512,
            height: 512,
            frames: 64,
            seed: 0,
            frame: FrameSettings::default(),
        }
    }
}

/// A rendered image.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Linear HDR radiance per pixel, row-major, top row first.
    pub hdr: Vec<Vec3>,
    /// Tonemapped sRGB, RGBA8 per pixel.
    pub ldr: Vec<u8>,
    /// Frames in the image: accumulated since the last restart, or (realtime) rendered since
    /// the history last restarted.
    pub frames: u32,
    /// Pass times of each frame ([`Renderer::render`]: all of its frames, in order;
    /// [`Renderer::read`]: none).
    pub times: Vec<PassTimes>,
}

/// The sub-pixel point of frame `frame`: Roberts's R2 low-discrepancy sequence ("The
/// Unreasonable Effectiveness of Quasirandom Sequences", 2018) rotated by a random offset drawn
/// from `seed` (Cranley and Patterson, 1976), so every frame's point is uniform over the pixel
/// and the points of consecutive frames cover it evenly.
pub fn jitter(seed: u64, frame: u32) -> Vec2 {
    const R2: Vec2 = Vec2::new(0.754_877_7, 0.569_840_3);
    let mut rng = Pcg32::new(seed, 0x6a69_7474_6572);
    let offset = Vec2::new(rng.next_f32(), rng.next_f32());
    // In f64: frame x alpha must keep its fraction for large frame numbers.
    let f = f64::from(frame);
    let x = (f64::from(offset.x) + f * f64::from(R2.x)).fract();
    let y = (f64::from(offset.y) + f * f64::from(R2.y)).fract();
    Vec2::new(x as f32, y as f32).min(Vec2::splat(1.0 - f32::EPSILON))
}

/// The number of frame `frame` under `seed` that the G-buffer hashes into the coverage of
/// alpha-blended fragments ([`GpuCamera::frame_seed`]): distinct frames and seeds give
/// unrelated numbers, so the fragments' coverage decisions are fresh every frame.
pub fn coverage_frame_seed(seed: u64, frame: u32) -> u32 {
    chiaro_shading::coverage::hash_words(&[seed as u32, (seed >> 32) as u32, frame])
}

/// Renders worlds on one GPU context.
pub struct Renderer {
    /// The device.
    pub context: GpuContext,
    schedule: Schedule,
    world: Option<bevy_ecs::world::WorldId>,
    frame: Option<Frame>,
    accumulated: u32,
    frame_index: u32,
    previous: Option<Mat4>,
    last_settings: Option<FrameSettings>,
    reset_history: bool,
    stillness: Stillness,
    poison: bool,
    background_compile: bool,
    setup: Option<SetupTimes>,
    systems_seconds: f64,
    frames_in_flight: u32,
    /// Times of frames a replaced frame (another size or world) finished, not yet returned.
    finished: Vec<PassTimes>,
}

impl Renderer {
    /// A renderer on `context`, with [`DEFAULT_FRAMES_IN_FLIGHT`] frames in flight on a GPU
    /// and one on a CPU adapter (lavapipe, llvmpipe): there a submission runs only once the
    /// one before has finished, so a second frame in flight doubles the latency for at most a
    /// few percent of throughput (`docs/experiments/frames-in-flight.md`).
    pub fn new(context: GpuContext) -> Self {
        let frames_in_flight = if context.runs_on_cpu() {
            1
        } else {
            DEFAULT_FRAMES_IN_FLIGHT
        };
        Self {
            context,
            schedule: Self::schedule(),
            world: None,
            frame: None,
            accumulated: 0,
            frame_index: 0,
            previous: None,
            last_settings: None,
            reset_history: true,
            stillness: Stillness::default(),
            poison: false,
            background_compile: false,
            setup: None,
            systems_seconds: 0.0,
            frames_in_flight,
            finished: Vec::new(),
        }
    }

    /// How many frames may be in flight (clamped to 1..=[`MAX_FRAMES_IN_FLIGHT`]; the default
    /// is [`Renderer::new`]'s): a call that renders a frame returns once at most `n - 1`
    /// earlier frames are still running on the GPU, so with 2 the CPU runs the scene systems
    /// and records frame N+1 while the GPU renders frame N; 1 waits for every frame (lowest
    /// latency, no overlap). Pass times taken by the wall clock ([`crate::PassClock::Wall`])
    /// wait for every pass, so they keep one frame in flight whatever this says.
    pub fn set_frames_in_flight(&mut self, n: u32) {
        self.frames_in_flight = n.clamp(1, MAX_FRAMES_IN_FLIGHT);
    }

    /// The most frames in flight: as set ([`Renderer::set_frames_in_flight`]), or 1 where
    /// the passes are timed by the wall clock.
    pub fn frames_in_flight(&self) -> u32 {
        let clock = crate::timing::PassClock::from_env(self.context.timestamps);
        crate::in_flight::frames_in_flight(clock, self.frames_in_flight)
    }

    /// Frames submitted whose pass times were not yet returned (they may have finished).
    pub fn frames_running(&self) -> usize {
        self.frame.as_ref().map_or(0, Frame::frames_running)
    }

    /// Waits for every frame in flight and returns the pass times not yet returned, oldest
    /// first.
    pub fn finish(&mut self) -> Vec<PassTimes> {
        let mut times = std::mem::take(&mut self.finished);
        if let Some(frame) = self.frame.as_mut() {
            times.extend(frame.finish(&self.context.device));
        }
        times
    }

    /// Test hook: while on, the indirect pass writes NaN at pixel (0, 0) and +Inf at (1, 0),
    /// so tests can check that no non-finite value reaches the history or the image.
    pub fn inject_non_finite(&mut self, on: bool) {
        self.poison = on;
    }

    /// Whether a pipeline for a scene's new feature set ([`crate::specialization`]) is built
    /// on another thread while the old one goes on rendering (on: an interactive app never
    /// stalls on an edit), or before the frame (off, the default: every image is exact).
    pub fn compile_in_background(&mut self, on: bool) {
        self.background_compile = on;
    }

    /// Where the setup of the last new world or size went (its first run of the scene
    /// systems: BVH build and upload); `None` before any, or when the app runs the systems
    /// itself ([`Renderer::render_frame`]).
    pub fn setup_times(&self) -> Option<SetupTimes> {
        self.setup
    }

    /// Wall-clock seconds the scene systems (animation, skinning, BVH update, upload) took
    /// before the last frame [`Renderer::render`] or [`Renderer::accumulate`] drew: what the
    /// scene's changes cost the CPU that frame.
    pub fn last_systems_seconds(&self) -> f64 {
        self.systems_seconds
    }

    fn schedule() -> Schedule {
        let mut schedule = Schedule::default();
        add_gpu_scene_systems(&mut schedule);
        schedule
    }

    /// Renders `settings.frames` frames of `world` from a fresh accumulation (and a fresh
    /// denoiser history), waits for them, and reads the images back with their pass times
    /// (frames numbered from 0 again; earlier frames' times not yet returned are dropped).
    pub fn render(
        &mut self,
        world: &mut World,
        settings: &RenderSettings,
    ) -> Result<RenderOutput, RenderError> {
        self.render_with(world, settings, |_, _| {})
    }

    /// [`Renderer::render`], calling `before_frame(world, k)` before frame k's scene systems
    /// run: an edit made there (a new animation time, a moved object) shows up in that frame.
    pub fn render_with(
        &mut self,
        world: &mut World,
        settings: &RenderSettings,
        before_frame: impl FnMut(&mut World, u32),
    ) -> Result<RenderOutput, RenderError> {
        self.finish();
        self.accumulated = 0;
        self.frame_index = 0;
        self.reset_history = true;
        let mut times =
            self.accumulate_with(world, settings, settings.frames.max(1), before_frame)?;
        times.extend(self.finish());
        let mut output = self.read(settings)?;
        output.times = times;
        Ok(output)
    }

    /// Renders `frames` more frames of `world`, the scene systems running before each (edits
    /// show up). In the accumulating modes a frame whose camera, scene uploads or settings
    /// differ from the last one's restarts the mean. Another world than the last one, or
    /// another size, restarts everything. Returns the pass times of the frames the GPU has
    /// finished by then, oldest first, earlier calls' included: with frames in flight the last
    /// ones come with a later call, or with [`Renderer::finish`].
    pub fn accumulate(
        &mut self,
        world: &mut World,
        settings: &RenderSettings,
        frames: u32,
    ) -> Result<Vec<PassTimes>, RenderError> {
        self.accumulate_with(world, settings, frames, |_, _| {})
    }

    fn accumulate_with(
        &mut self,
        world: &mut World,
        settings: &RenderSettings,
        frames: u32,
        mut before_frame: impl FnMut(&mut World, u32),
    ) -> Result<Vec<PassTimes>, RenderError> {
        self.prepare(world, settings, true)?;
        // Grown as frames finish, not reserved up front: a count of frames costs no memory
        // before they are drawn.
        let mut times = std::mem::take(&mut self.finished);
        for k in 0..frames {
            before_frame(world, k);
            let start = std::time::Instant::now();
            self.schedule.run(world);
            self.systems_seconds = start.elapsed().as_secs_f64();
            times.extend(self.draw(world, settings)?);
        }
        Ok(times)
    }

    /// Gives `world` the [`GpuScene`] resource that chiaro's systems upload into, unless it
    /// holds one this renderer's context made: an app that runs those systems in its own
    /// schedule calls this once before that schedule first runs. A world last drawn by a
    /// renderer on another device gets new buffers on this one, which the next upload fills
    /// whole.
    pub fn attach(&self, world: &mut World) {
        let ours = world
            .get_resource::<GpuScene>()
            .is_some_and(|scene| scene.made_by(&self.context));
        if !ours {
            world.insert_resource(GpuScene::new(&self.context));
        }
    }

    /// Renders one frame of `world` for an app that owns its main loop and its `Schedule`:
    /// the app added chiaro's systems to that schedule ([`add_gpu_scene_systems`]) and ran it
    /// this frame, so this renders without running any system. When the world holds a
    /// [`FrameSettings`] resource, it decides what the frame computes (the app edits it like
    /// any other resource); otherwise `settings.frame` does. Read the image with
    /// [`Renderer::read`]. Returns the pass times of the frames the GPU has finished, as
    /// [`Renderer::accumulate`] does.
    pub fn render_frame(
        &mut self,
        world: &mut World,
        settings: &RenderSettings,
    ) -> Result<Vec<PassTimes>, RenderError> {
        let settings = RenderSettings {
            frame: world
                .get_resource::<FrameSettings>()
                .copied()
                .unwrap_or(settings.frame),
            ..*settings
        };
        self.prepare(world, &settings, false)?;
        let mut times = std::mem::take(&mut self.finished);
        times.extend(self.draw(world, &settings)?);
        Ok(times)
    }

    /// Checks the settings, gives the world its [`GpuScene`] and (re)makes the frame for a new
    /// world or size; `own_systems`: this renderer runs the scene systems itself.
    fn prepare(
        &mut self,
        world: &mut World,
        settings: &RenderSettings,
        own_systems: bool,
    ) -> Result<(), RenderError> {
        settings.frame.validate()?;
        let max = self.context.device.limits().max_texture_dimension_2d;
        let (width, height) = (settings.width, settings.height);
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::Size { width, height, max });
        }
        let texels = crate::targets::GI_RESERVOIR_TEXELS;
        if settings.frame.resamples_indirect_light() && width > max / texels {
            let max = max / texels;
            return Err(RenderError::ResampledIndirectWidth { width, max, texels });
        }
        self.attach(world);
        if self.world != Some(world.id()) {
            // A schedule's systems belong to one world: a new world gets new ones.
            self.finished = self.finish();
            self.schedule = Self::schedule();
            self.world = Some(world.id());
            self.frame = None;
            self.previous = None;
            self.reset_history = true;
        }
        let resized = self
            .frame
            .as_ref()
            .is_none_or(|f| (f.targets.width, f.targets.height) != (width, height));
        if resized {
            if own_systems {
                let start = std::time::Instant::now();
                self.schedule.run(world);
                self.setup = Some(SetupTimes {
                    systems: start.elapsed().as_secs_f64(),
                    bvh: world
                        .get_resource::<chiaro_bvh::BvhStats>()
                        .map_or(0.0, |s| s.last_work_seconds),
                    upload: world.resource::<GpuScene>().last_seconds,
                });
            }
            // A new size keeps the scene passes and every pipeline they compiled.
            self.finished = self.finish();
            let scene_passes = match self.frame.take() {
                Some(old) => old.into_scene_passes(),
                None => ScenePasses::new(
                    &self.context.device,
                    world.resource::<GpuScene>(),
                    self.context.traced_gbuffer,
                )?,
            };
            self.frame = Some(Frame::new(&self.context, scene_passes, width, height)?);
            self.accumulated = 0;
            self.reset_history = true;
        }
        Ok(())
    }

    /// Submits one frame of `world` as its systems left it; returns the times of the frames
    /// the GPU finished meanwhile.
    fn draw(
        &mut self,
        world: &World,
        settings: &RenderSettings,
    ) -> Result<Vec<PassTimes>, RenderError> {
        let (width, height) = (settings.width, settings.height);
        let (camera, global) = active_camera(world)?;
        let jitter = jitter(settings.seed, self.frame_index);
        let mut gpu_camera = GpuCamera::new(&camera, &global, width, height, jitter, self.previous);
        gpu_camera.frame_seed = coverage_frame_seed(settings.seed, self.frame_index);
        let scene = world.resource::<GpuScene>();
        if let Some(overflow) = scene.overflow() {
            return Err(overflow.into());
        }
        let changed = self.previous != Some(gpu_camera.unjittered())
            || scene.content_changed
            || self.last_settings != Some(settings.frame);
        if self.reset_history || (changed && settings.frame.mode.accumulates()) {
            self.accumulated = 0;
        }
        self.stillness = if self.reset_history || changed {
            Stillness {
                frames: 0,
                since_reset: self.reset_history,
            }
        } else {
            Stillness {
                frames: self.stillness.frames.saturating_add(1),
                ..self.stillness
            }
        };
        self.previous = Some(gpu_camera.unjittered());
        self.last_settings = Some(settings.frame);
        self.accumulated += 1;
        let input = FrameInput {
            frame: self.frame_index,
            seed: settings.seed,
            accumulated: self.accumulated,
            reset_history: self.reset_history,
            stillness: self.stillness,
            settings: settings.frame,
            poison: self.poison,
            features: settings.frame.pipeline.features(
                world.get_resource::<SceneFeatures>(),
                scene.light_trees() && settings.frame.light_sampling == LightSampling::Tree,
                settings.frame.resamples_direct_light(),
            ),
            background_compile: self.background_compile,
            frames_in_flight: self.frames_in_flight,
        };
        let frame = self.frame.as_mut().ok_or(RenderError::NotRendered)?;
        let times = frame.render(&self.context, scene, &gpu_camera, &input);
        self.reset_history = false;
        self.frame_index += 1;
        Ok(times)
    }

    /// The last frame's G-buffer: world positions, instance ids and motion vectors.
    pub fn read_gbuffer(&self) -> Result<GbufferImage, RenderError> {
        let frame = self.frame.as_ref().ok_or(RenderError::NotRendered)?;
        let context = &self.context;
        Ok(GbufferImage::read(
            &context.device,
            &context.queue,
            &frame.targets,
        )?)
    }

    /// The last frame's direct light reflected by the surfaces seen (the environment where
    /// none is seen), before accumulation.
    pub fn direct_light(&self) -> Result<Vec<Vec3>, RenderError> {
        let frame = self.frame.as_ref().ok_or(RenderError::NotRendered)?;
        let (device, queue) = (&self.context.device, &self.context.queue);
        Ok(read_hdr(device, queue, &frame.targets.direct.texture)?)
    }

    /// The last frame's indirect light reflected by the surfaces seen, before accumulation.
    pub fn indirect_light(&self) -> Result<Vec<Vec3>, RenderError> {
        let frame = self.frame.as_ref().ok_or(RenderError::NotRendered)?;
        let (device, queue) = (&self.context.device, &self.context.queue);
        Ok(read_hdr(device, queue, &frame.targets.indirect.texture)?)
    }

    /// The frame's passes and images (after the first render).
    pub fn frame(&self) -> Option<&Frame> {
        self.frame.as_ref()
    }

    /// The accumulated images of the last frame submitted, after waiting for the GPU.
    pub fn read(&self, settings: &RenderSettings) -> Result<RenderOutput, RenderError> {
        Ok(self.read_later(settings)?.wait(&self.context.device)?)
    }

    /// The accumulated images of the last frame submitted, copied on the GPU after it and
    /// read back without waiting: rendering goes on, and the images are taken with
    /// [`PendingImage::wait`] once [`PendingImage::ready`] says they are there (an app that
    /// saves every frame keeps its frames in flight this way).
    pub fn read_later(&self, settings: &RenderSettings) -> Result<PendingImage, RenderError> {
        let frame = self.frame.as_ref().ok_or(RenderError::NotRendered)?;
        let (device, queue) = (&self.context.device, &self.context.queue);
        Ok(PendingImage::new(
            start_read(device, queue, &frame.targets.hdr.texture, 16),
            start_read(device, queue, &frame.targets.ldr.texture, 4),
            (settings.width, settings.height),
            self.accumulated,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jitter_covers_the_pixel_evenly() {
        // Every cell of a 4 x 4 grid over the pixel gets one of the first 16 points or two.
        let mut cells = [0u32; 16];
        for frame in 0..16 {
            let j = jitter(3, frame);
            assert!(j.cmpge(Vec2::ZERO).all() && j.cmplt(Vec2::ONE).all());
            cells[(j.y * 4.0) as usize * 4 + (j.x * 4.0) as usize] += 1;
        }
        assert!(cells.iter().all(|&c| c <= 2), "{cells:?}");
        assert!(cells.iter().filter(|&&c| c == 0).count() <= 3, "{cells:?}");
        assert_ne!(jitter(3, 0), jitter(4, 0));
    }
}
