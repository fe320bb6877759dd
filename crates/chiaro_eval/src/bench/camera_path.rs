//! The scripted camera path of `chiaro bench`: between one checkpoint and the next the scene's
//! camera pans about its own up axis away from its pose at [`PAN_DEGREES_PER_FRAME`] and back
//! at the same rate (a look to the side and back, as in a walkthrough), so every frame but the
//! checkpoints moves the view, and every checkpoint sees the scene from the camera's own pose.
//! The realtime frame's reprojection, history rejection at the newly seen edge and denoiser work
//! as they do in an interactive pan, and the run is measured against the static camera's
//! converged reference: the path needs no reference of its own. A pan needs no scale: it moves
//! any scene by the same fraction of its field of view.

use bevy_ecs::world::World;
use chiaro_scene::{ActiveCamera, Transform};
use glam::Quat;

use super::BenchError;

/// The configuration name of the realtime run along the path.
pub const PATH_CONFIG: &str = "realtime-path";

/// How fast the camera turns, degrees per frame (15 degrees a second at 60 frames a second).
pub const PAN_DEGREES_PER_FRAME: f32 = 0.25;

/// The pan at frame `frame` of a run measured after each of `checkpoints` frames (increasing),
/// degrees: 0 at every checkpoint and before the first, and between two checkpoints a and b
/// the distance to the nearer of them times the rate, so the camera turns out for half the
/// interval and back for the other half.
pub fn pan_at(frame: u32, checkpoints: &[u32]) -> f32 {
    let mut start = 0;
    for &checkpoint in checkpoints {
        if frame <= checkpoint {
            if start == 0 {
                return 0.0;
            }
            let frames = (frame - start).min(checkpoint - frame);
            return PAN_DEGREES_PER_FRAME * frames as f32;
        }
        start = checkpoint;
    }
    0.0
}

/// The largest pan of a run measured after each of `checkpoints` frames, degrees.
pub fn largest_pan(checkpoints: &[u32]) -> f32 {
    let last = checkpoints.last().copied().unwrap_or(0);
    (1..=last)
        .map(|frame| pan_at(frame, checkpoints))
        .fold(0.0, f32::max)
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

    const CHECKPOINTS: [u32; 4] = [1, 4, 16, 64];

    #[test]
    fn every_checkpoint_is_at_the_cameras_own_pose() {
        for checkpoint in CHECKPOINTS {
            assert_eq!(pan_at(checkpoint, &CHECKPOINTS), 0.0);
        }
    }

    #[test]
    fn the_camera_turns_out_and_back_between_checkpoints() {
        let r = PAN_DEGREES_PER_FRAME;
        let pans: Vec<f32> = (1..=16).map(|f| pan_at(f, &CHECKPOINTS)).collect();
        let expected = [
            0.0,
            r,
            r,
            0.0,
            r,
            2.0 * r,
            3.0 * r,
            4.0 * r,
            5.0 * r,
            6.0 * r,
            5.0 * r,
            4.0 * r,
            3.0 * r,
            2.0 * r,
            r,
            0.0,
        ];
        assert_eq!(pans, expected);
        // Between 16 and 64 the turn peaks at frame 40, 24 frames out.
        assert_eq!(pan_at(40, &CHECKPOINTS), 24.0 * r);
        assert_eq!(largest_pan(&CHECKPOINTS), 24.0 * r);
        // Every frame between checkpoints moves the view.
        for frame in 2..64 {
            if !CHECKPOINTS.contains(&frame) {
                assert!(pan_at(frame, &CHECKPOINTS) > 0.0, "frame {frame}");
            }
        }
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
