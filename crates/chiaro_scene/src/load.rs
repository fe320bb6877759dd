//! Loading a scene by name: a glTF path or `builtin:NAME[?key=value&...]`.

use std::path::Path;

use bevy_ecs::prelude::*;

use crate::error::SceneError;
use crate::scene_builder::{SceneBuilder, SpawnedScene};

/// How a scene is loaded. The default is the safe one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Follow the URIs of a glTF's buffers and images wherever they point: absolute paths,
    /// `file:` URIs and `..` leaving the model's folder. Off by default, when a glTF reads
    /// files inside its own folder only, so that a file from elsewhere cannot make chiaro
    /// read (and show) other files on the machine.
    pub allow_outside_files: bool,
}

/// Builds the scene named by `spec` without touching any World: `builtin:...` names a built-in
/// scene (see [`crate::builtin`]), anything else is a path to a .gltf or .glb file.
pub fn scene_builder_for(spec: &str) -> Result<SceneBuilder, SceneError> {
    scene_builder_with(spec, &LoadOptions::default())
}

/// [`scene_builder_for`] with `options`.
pub fn scene_builder_with(spec: &str, options: &LoadOptions) -> Result<SceneBuilder, SceneError> {
    match spec.strip_prefix("builtin:") {
        Some(_) => crate::builtin::build(spec),
        None => crate::gltf::load_gltf_with(Path::new(spec), options),
    }
}

/// Loads the scene named by `spec` into `world` (see [`scene_builder_for`]). On error the world
/// is unchanged.
pub fn load_scene(world: &mut World, spec: &str) -> Result<SpawnedScene, SceneError> {
    load_scene_with(world, spec, &LoadOptions::default())
}

/// [`load_scene`] with `options`.
pub fn load_scene_with(
    world: &mut World,
    spec: &str,
    options: &LoadOptions,
) -> Result<SpawnedScene, SceneError> {
    Ok(scene_builder_with(spec, options)?.spawn(world))
}
