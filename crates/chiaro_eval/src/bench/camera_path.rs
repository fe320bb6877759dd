//! The scripted camera path of `chiaro bench`: the scene's camera pans about its own up axis,
//! [`PAN_DEGREES`] over the run at a steady rate (frame f of F at PAN_DEGREES x f / F), so
//! every frame moves the view and the realtime frame's reprojection, history rejection at the
//! newly seen edge and denoiser work as they do in an interactive pan. A pan needs no scale:
//! it moves any scene by the same fraction of its field of view.

use bevy_ecs::world::World;
use chiaro_scene::{ActiveCamera, Transform};
use glam::Quat;

use super::BenchError;

/// The configuration name of the realtime run along the path.
pub const PATH_CONFIG: &str = "realtime-path";

/// How far the camera turns over a run, degrees.
pub const PAN_DEGREES: f32 = 8.0;

/// The pan at frame `frame` of a run of `last` frames, degrees.
pub fn pan_at(frame: u32, last: u32) -> f32 {
    PAN_DEGREES * frame as f32 / last.max(1) as f32
}

/// The active camera's transform as the scene set it.
pub fn camera_transform(world: &mut World, scene: &str) -> Result<Transform, BenchError> {
    let camera = world
        .get_resource::<ActiveCamera>()
        .map(|c| c.0)
        .and_then(|entity| world.get::<Transform>(entity).copied());
    camera.ok_or_else(|| BenchError::Scene {
        scene: scene.to_owned(),
        message: "no active camera to move along the path".into(),
    })
}

/// Turns the active camera to `degrees` of pan from `base` (its own transform, see
/// [`camera_transform`]).
pub fn set_pan(world: &mut World, base: &Transform, degrees: f32) {
    let Some(entity) = world.get_resource::<ActiveCamera>().map(|c| c.0) else {
        return;
    };
    if let Some(mut transform) = world.get_mut::<Transform>(entity) {
        *transform = Transform {
            rotation: base.rotation * Quat::from_rotation_y(degrees.to_radians()),
            ..*base
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pan_grows_steadily_to_its_full_angle() {
        assert_eq!(pan_at(0, 64), 0.0);
        assert_eq!(pan_at(32, 64), PAN_DEGREES / 2.0);
        assert_eq!(pan_at(64, 64), PAN_DEGREES);
    }

    #[test]
    fn set_pan_turns_the_active_camera_about_its_up_axis() {
        let mut world = World::new();
        chiaro_scene::load_scene(&mut world, "builtin:cornell").unwrap();
        let base = camera_transform(&mut world, "cornell").unwrap();
        set_pan(&mut world, &base, 90.0);
        let turned = camera_transform(&mut world, "cornell").unwrap();
        assert_eq!(turned.translation, base.translation);
        // The camera looks down its -Z: after 90 degrees about its up, down its old -X.
        let forward = turned.rotation * glam::Vec3::NEG_Z;
        let old_left = base.rotation * glam::Vec3::NEG_X;
        assert!(
            forward.distance(old_left) < 1e-5,
            "{forward} against {old_left}"
        );
    }
}
