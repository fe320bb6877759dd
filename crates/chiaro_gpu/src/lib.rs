//! chiaro's GPU frame on wgpu: the device ([`context`]), the WGSL sources and their
//! composition ([`shaders`]), the scene's buffers kept in step with the ECS world
//! ([`gpu_scene`]), the passes ([`passes`]) run in order by [`frame`] as the mode in
//! [`FrameSettings`] asks, and the headless [`Renderer`] that renders frames, for a World it
//! updates itself or for an app that runs chiaro's systems in its own schedule, with frames in
//! flight ([`in_flight`]), and reads the images back; [`still_view`] lets a still image
//! converge.
//!
//! It runs on any adapter wgpu offers, CPU rasterizers such as lavapipe included: rays are
//! traversed in compute shaders over the BVHs `chiaro_bvh` builds, with no hardware ray tracing.
//!
//! ```
//! use bevy_ecs::world::World;
//! use chiaro_gpu::{GpuContext, RenderSettings, Renderer};
//!
//! let Ok(context) = GpuContext::new_headless() else {
//!     return; // no GPU adapter on this machine
//! };
//! let mut world = World::new();
//! chiaro_scene::load_scene(&mut world, "builtin:cornell").unwrap();
//! let mut renderer = Renderer::new(context);
//! let settings = RenderSettings { width: 16, height: 16, frames: 2, ..Default::default() };
//! let image = renderer.render(&mut world, &settings).unwrap();
//! assert_eq!(image.hdr.len(), 16 * 16);
//! assert_eq!(image.ldr.len(), 16 * 16 * 4);
//! assert!(image.hdr.iter().any(|p| p.max_element() > 0.0));
//! ```

#![warn(missing_docs)]

pub mod camera;
pub mod context;
pub mod denoiser;
pub mod frame;
pub mod gbuffer_image;
pub mod gpu_scene;
pub mod in_flight;
pub mod passes;
pub mod readback;
pub mod renderer;
pub mod settings;
pub mod shaders;
pub mod specialization;
pub mod still_view;
pub mod targets;
pub mod timing;

pub use context::{ContextError, GpuContext};
pub use denoiser::Denoiser;
pub use gpu_scene::{GpuScene, UploadStats, add_gpu_scene_systems, upload_gpu_scene};
pub use in_flight::{DEFAULT_FRAMES_IN_FLIGHT, MAX_FRAMES_IN_FLIGHT};
pub use readback::PendingImage;
pub use renderer::{GbufferImage, RenderError, RenderOutput, RenderSettings, Renderer};
pub use settings::{
    DenoiseSettings, FrameSettings, PrimaryVisibility, RenderMode, RestirBias, RestirSettings,
    Sampler, SettingsError,
};
pub use shaders::{ShaderError, compose};
pub use specialization::{PipelineChoice, PipelineFeatures};
pub use timing::{PassClock, PassTimes, SetupTimes};
