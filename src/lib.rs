//! chiaro: a real-time hybrid path tracer for `bevy_ecs` applications.
//!
//! This crate re-exports the workspace's crates under one name: [`scene`] (the scene as ECS
//! data, glTF import, built-in scenes), [`shading`] (the shading model), [`bvh`] (BLAS and TLAS
//! over the scene), [`reference`](mod@reference) (the CPU reference path tracer), [`gpu`] (the
//! wgpu frame and its headless renderer) and [`eval`] (image metrics against a reference).
//!
//! ```
//! use bevy_ecs::world::World;
//!
//! let mut world = World::new();
//! let spawned = chiaro::scene::load_scene(&mut world, "builtin:furnace").unwrap();
//! assert!(spawned.repairs.is_empty());
//! ```

pub use chiaro_bvh as bvh;
pub use chiaro_eval as eval;
pub use chiaro_gpu as gpu;
pub use chiaro_reference as reference;
pub use chiaro_scene as scene;
pub use chiaro_shading as shading;
