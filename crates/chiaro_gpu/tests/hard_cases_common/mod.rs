//! What the hard-case suite's test files share: each case's camera, render settings by mode.

use bevy_ecs::prelude::{Entity, Name, World};
use chiaro_gpu::{FrameSettings, RenderMode, RenderSettings};
use chiaro_scene::{ActiveCamera, Camera};

/// Makes the camera of `case` the active one.
pub fn view_case(world: &mut World, case: &str) {
    let name = format!("{case} camera");
    let mut cameras = world.query::<(Entity, &Name, &Camera)>();
    let entity = cameras
        .iter(world)
        .find(|(_, n, _)| n.as_str() == name)
        .map(|(e, _, _)| e)
        .unwrap_or_else(|| panic!("no camera named '{name}'"));
    world.insert_resource(ActiveCamera(entity));
}

/// `frames` frames of `size` x `size` with `seed`.
pub fn settings(size: u32, frames: u32, seed: u64, frame: FrameSettings) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        frames,
        seed,
        frame,
    }
}

/// The default frame settings in `mode`.
pub fn mode(mode: RenderMode) -> FrameSettings {
    FrameSettings {
        mode,
        ..FrameSettings::default()
    }
}
