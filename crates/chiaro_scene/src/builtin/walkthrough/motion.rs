//! What moves in the walkthrough, as animation clips played by the ECS animation system
//! ([`crate::animation::animate_nodes`]): the camera's scripted path down the street, a fan
//! turning, the doors at the end opening and closing, and two balls travelling the street.

use std::f32::consts::TAU;

use glam::{Quat, Vec3, Vec4};

use crate::animation::{AnimationClip, Channel, Interpolation, Keyframes, Property};
use crate::scene_builder::NodeIndex;
use crate::transform::Transform;

use super::pieces::BAY;

/// Seconds the camera takes to walk one bay (1.5 m/s).
pub const SECONDS_PER_BAY: f32 = 4.0;
/// Height of the camera's eye.
pub const EYE_HEIGHT: f32 = 1.7;

fn channel(target: NodeIndex, property: Property, keys: Keyframes) -> Channel<NodeIndex> {
    Channel {
        target,
        property,
        keyframes: keys,
    }
}

/// Linear keys (times in seconds, values as glTF stores them).
fn linear(times: Vec<f32>, values: Vec<Vec4>) -> Keyframes {
    Keyframes::new(times, values, Interpolation::Linear).expect("walkthrough keys are valid")
}

/// The camera's pose `k` keys along its path through `bays` bays: on the street's axis, a key
/// per bay, looking down the street and turning 20 degrees to one side then the other (towards
/// the sculptures, which alternate sides).
fn camera_key(k: usize) -> Transform {
    let eye = Vec3::new(0.0, EYE_HEIGHT, 3.0 - BAY * k as f32);
    let yaw = if k == 0 {
        0.0
    } else if k % 2 == 1 {
        20f32.to_radians()
    } else {
        -20f32.to_radians()
    };
    Transform::from_translation(eye).with_rotation(Quat::from_rotation_y(yaw))
}

/// The camera's transform at the start of its path.
pub fn camera_start() -> Transform {
    camera_key(0)
}

/// The camera's path through `bays` bays, [`SECONDS_PER_BAY`] a bay.
pub fn camera_path(camera: NodeIndex, bays: u32) -> AnimationClip<NodeIndex> {
    let keys: Vec<Transform> = (0..=bays as usize).map(camera_key).collect();
    let times: Vec<f32> = (0..keys.len())
        .map(|k| k as f32 * SECONDS_PER_BAY)
        .collect();
    AnimationClip {
        name: "camera path".into(),
        channels: vec![
            channel(
                camera,
                Property::Translation,
                linear(
                    times.clone(),
                    keys.iter().map(|t| t.translation.extend(0.0)).collect(),
                ),
            ),
            channel(
                camera,
                Property::Rotation,
                linear(times, keys.iter().map(|t| Vec4::from(t.rotation)).collect()),
            ),
        ],
    }
}

/// A fan turning once a second about its Z axis.
pub fn fan_turning(fan: NodeIndex) -> AnimationClip<NodeIndex> {
    let times: Vec<f32> = (0..=3).map(|k| k as f32 / 3.0).collect();
    let values = (0..=3)
        .map(|k| Vec4::from(Quat::from_rotation_z(TAU * k as f32 / 3.0)))
        .collect();
    AnimationClip {
        name: "fan".into(),
        channels: vec![channel(fan, Property::Rotation, linear(times, values))],
    }
}

/// The two door hinges swinging open by 80 degrees over 2 s, held open 2 s, closing over 2 s
/// and held shut 2 s; the hinge at -X turns one way, the one at +X the other.
pub fn doors(hinges: [NodeIndex; 2]) -> AnimationClip<NodeIndex> {
    let times = vec![0.0, 2.0, 4.0, 6.0, 8.0];
    let channels = hinges
        .iter()
        .zip([1.0f32, -1.0])
        .map(|(&hinge, sign)| {
            let open = Vec4::from(Quat::from_rotation_y(sign * 80f32.to_radians()));
            let shut = Vec4::from(Quat::IDENTITY);
            channel(
                hinge,
                Property::Rotation,
                linear(times.clone(), vec![shut, open, open, shut, shut]),
            )
        })
        .collect();
    AnimationClip {
        name: "doors".into(),
        channels,
    }
}

/// A ball travelling down the street along `x` from `start` to `end` and back in `period`
/// seconds: linear keys, or with `eased` a cubic spline slowing to rest at each end.
pub fn ball_path(
    ball: NodeIndex,
    start: Vec3,
    end: Vec3,
    period: f32,
    eased: bool,
) -> AnimationClip<NodeIndex> {
    let times = vec![0.0, 0.5 * period, period];
    let points = [start, end, start].map(|p| p.extend(0.0));
    let keys = if eased {
        // In-tangent, value, out-tangent per key; zero tangents ease in and out.
        let values = points
            .iter()
            .flat_map(|&p| [Vec4::ZERO, p, Vec4::ZERO])
            .collect();
        Keyframes::new(times, values, Interpolation::CubicSpline).expect("valid keys")
    } else {
        linear(times, points.to_vec())
    };
    AnimationClip {
        name: "ball".into(),
        channels: vec![channel(ball, Property::Translation, keys)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_walks_a_bay_per_key_and_keeps_level() {
        let clip = camera_path(0, 3);
        assert_eq!(clip.duration(), 3.0 * SECONDS_PER_BAY);
        let at = |t: f32| clip.channels[0].keyframes.sample(t, false).truncate();
        assert_eq!(at(0.0), Vec3::new(0.0, EYE_HEIGHT, 3.0));
        let halfway = at(1.5 * SECONDS_PER_BAY);
        assert!((halfway.z - (3.0 - 1.5 * BAY)).abs() < 1e-4, "{halfway}");
        assert_eq!(halfway.y, EYE_HEIGHT);
        let turn = Quat::from_vec4(clip.channels[1].keyframes.sample(SECONDS_PER_BAY, true));
        let forward = turn * Vec3::NEG_Z;
        assert!((forward.y).abs() < 1e-6 && forward.z < -0.9, "{forward}");
    }

    #[test]
    fn the_eased_ball_stops_at_its_ends() {
        let clip = ball_path(0, Vec3::ZERO, Vec3::Z * -10.0, 8.0, true);
        let z = |t: f32| clip.channels[0].keyframes.sample(t, false).z;
        assert!((z(4.0) + 10.0).abs() < 1e-5);
        // Zero tangents: slow near the end, fast in the middle.
        assert!((z(4.0) - z(3.9)).abs() < (z(2.1) - z(2.0)).abs());
    }
}
