//! Loading a scene by name: a glTF path or `builtin:NAME[?key=value&...]`.

use std::path::Path;

use bevy_ecs::prelude::*;

use crate::error::SceneError;
use crate::scene_builder::{SceneBuilder, SpawnedScene};

/// Builds the scene named by `spec` without touching any World: `builtin:...` names a built-in
/// scene (see [`crate::builtin`]), anything else is a path to a .gltf or .glb file.
pub fn scene_builder_for(spec: &str) -> Result<SceneBuilder, SceneError> {
    match spec.strip_prefix("builtin:") {
        Some(_) => crate::builtin::build(spec),
        None => crate::gltf::load_gltf(Path::new(spec)),
    }
}

/// Loads the scene named by `spec` into `world` (see [`scene_builder_for`]). On error the world
/// is unchanged.
pub fn load_scene(world: &mut World, spec: &str) -> Result<SpawnedScene, SceneError> {
    Ok(scene_builder_for(spec)?.spawn(world))
}
