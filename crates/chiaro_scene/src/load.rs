//! Loading a scene by name: a glTF path or `builtin:NAME[?key=value&...]`.

use std::path::Path;

use bevy_ecs::prelude::*;

use crate::error::SceneError;
use crate::scene_builder::{SceneBuilder, SpawnedScene};

/// Lumens per watt: the luminous efficacy that turns KHR_lights_punctual's photometric
/// intensities into radiometric ones (the peak of the eye's sensitivity, at 555 nm, as in the
/// SI definition of the candela). Blender's glTF importer and exporter use the same figure.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// How the intensities of KHR_lights_punctual lights are read. Built-in scenes define their
/// lights in code, radiometric already, and are not affected.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightUnits {
    /// As the extension defines them: candela for point and spot lights, lux for directional
    /// ones, divided by [`LUMENS_PER_WATT`] into W/sr and W/m^2. This is what Blender's glTF
    /// importer and exporter do in their "Standard" lighting mode (a point or spot light of
    /// P watts is exported as P / (4 pi) * 683 cd, a sun of E W/m^2 as E * 683 lux), so a
    /// scene exported from Blender is as bright as Blender renders it.
    #[default]
    Photometric,
    /// Intensities read as radiometric numbers: 1 cd as 1 W/sr, 1 lux as 1 W/m^2 (683 times
    /// brighter than [`LightUnits::Photometric`]); Blender's "Unitless" lighting mode.
    Unitless,
}

impl LightUnits {
    /// Radiant intensity (W/sr, point and spot) or irradiance (W/m^2, directional) of a light
    /// whose KHR_lights_punctual `intensity` is `intensity`.
    pub fn radiometric(self, intensity: f32) -> f32 {
        match self {
            Self::Photometric => intensity / LUMENS_PER_WATT,
            Self::Unitless => intensity,
        }
    }
}

/// How a scene is loaded. The default is the safe one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Follow the URIs of a glTF's buffers and images wherever they point: absolute paths,
    /// `file:` URIs and `..` leaving the model's folder. Off by default, when a glTF reads
    /// files inside its own folder only, so that a file from elsewhere cannot make chiaro
    /// read (and show) other files on the machine.
    pub allow_outside_files: bool,
    /// How KHR_lights_punctual intensities are read: photometric (cd, lux) by default.
    pub light_units: LightUnits,
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
