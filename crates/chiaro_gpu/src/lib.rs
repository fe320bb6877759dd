//! chiaro's GPU frame on wgpu: the device ([`context`]), the WGSL sources and their
//! composition ([`shaders`]), the scene's buffers
//! ([`gpu_scene`]).
//!
//! It runs on any adapter wgpu offers, CPU rasterizers such as lavapipe included: rays are
//! traversed in compute shaders over the BVHs `chiaro_bvh` builds, with no hardware ray tracing.

#![warn(missing_docs)]

pub mod camera;
pub mod context;
pub mod frame;
pub mod gpu_scene;
pub mod passes;
pub mod readback;
pub mod renderer;
pub mod shaders;
pub mod targets;
pub mod timing;

pub use context::{ContextError, GpuContext};
pub use gpu_scene::{GpuScene, UploadStats, add_gpu_scene_systems, upload_gpu_scene};
pub use renderer::{GbufferImage, RenderError, RenderOutput, RenderSettings, Renderer};
pub use shaders::{ShaderError, compose};
