//! chiaro's CPU reference path tracer: the converged ground truth every speed figure is weighed
//! against, rendered with the same shading model (`chiaro_shading`) as the GPU frame.
//!
//! Unbiased: camera rays jittered over the pixel (box filter); next-event estimation to every
//! light kind with MIS against BRDF sampling (the light picked through a light tree, or by power
//! alone); emission on hit; the environment; Russian roulette
//! (unbiased) after a few bounces; alpha masks, normal maps and bilinear textures honoured. Tiles
//! run on rayon and the image for a seed does not depend on the thread count. Two independent
//! halves of the samples are kept, so the reference's own residual noise can be reported.
//! For light that camera paths rarely reach (through a door ajar, from inside a lamp shade, in
//! caustics) [`Integrator::PtLt`] adds light tracing to the camera, [`Integrator::Bdpt`] traces
//! bidirectionally, and [`Integrator::Mlt`] and [`Integrator::Mmlt`] run Metropolis light
//! transport over the bidirectional tracer (every strategy per mutation, or multiplexed: one).
//!
//! ```
//! use bevy_ecs::world::World;
//! use chiaro_reference::{RenderSettings, render_world};
//!
//! let mut world = World::new();
//! chiaro_scene::load_scene(&mut world, "builtin:furnace").unwrap();
//! let settings = RenderSettings { width: 8, height: 8, spp: 16, ..RenderSettings::default() };
//! let out = render_world(&mut world, &settings, false).unwrap();
//! let mean = out.image.iter().map(|p| p.x).sum::<f32>() / out.image.len() as f32;
//! assert!((mean - 1.0).abs() < 0.1, "the furnace glows with radiance 1: {mean}");
//! ```

mod bdpt;
mod camera;
mod error;
mod integrator;
mod light_table;
mod mlt;
mod output;
mod random;
mod render;
mod scene;
mod sobol;
mod surface;
mod texture_sampling;

pub use camera::{CameraImportance, CameraRays};
pub use error::ReferenceError;
pub use integrator::{Integrator, PathSettings};
pub use light_table::{LightEntry, LightSampling, LightTable};
pub use output::{read_exr, write_exr, write_png, write_png_pixels};
pub use random::Sampler;
pub use render::{MAX_THREADS, RenderOutput, RenderSettings, TILE, rel_mse, render};
pub use scene::{RenderScene, prepare};

use bevy_ecs::world::World;

/// Renders the scene in `world` from its active camera (building its BVH and light table).
pub fn render_world(
    world: &mut World,
    settings: &RenderSettings,
    progress: bool,
) -> Result<RenderOutput, ReferenceError> {
    let prepared = prepare(world, settings.path.light_sampling);
    let scene = RenderScene::new(world, prepared, settings.width, settings.height)?;
    render(&scene, settings, progress)
}
