//! The walkthrough camera: held keys and mouse motion turned into a camera placement, as pure
//! math (no window, no ECS), so it is tested on its own. The viewer writes the result into the
//! camera entity's `Transform`, so the renderer's history and motion vectors see the move.
//!
//! Conventions are glTF's: the camera looks down its local -Z with +Y up. Yaw turns about the
//! world +Y axis, pitch about the camera's right axis, clamped short of straight up or down.

use chiaro_scene::Transform;
use glam::{EulerRot, Quat, Vec3};

/// Largest pitch either way, just short of a quarter turn (looking straight up or down would
/// make yaw ambiguous).
pub const MAX_PITCH: f32 = 1.55;
/// Radians the view turns per pixel of mouse motion.
pub const LOOK_RADIANS_PER_PIXEL: f32 = 0.003;
/// Factor one scroll step multiplies the speed by.
pub const SCROLL_SPEED_STEP: f32 = 1.2;
/// Speed factor while fast (shift) is held.
pub const FAST_FACTOR: f32 = 4.0;
/// Slowest and fastest base speed, in scene units per second.
pub const SPEED_RANGE: (f32, f32) = (1e-3, 1e4);

/// Movement keys held this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MoveKeys {
    /// W: forward.
    pub forward: bool,
    /// S: backward.
    pub back: bool,
    /// A: left.
    pub left: bool,
    /// D: right.
    pub right: bool,
    /// E: up (world +Y).
    pub up: bool,
    /// Q: down.
    pub down: bool,
    /// Shift: move [`FAST_FACTOR`] times faster.
    pub fast: bool,
}

impl MoveKeys {
    /// Whether any movement key is held (shift alone moves nothing).
    pub fn any(&self) -> bool {
        self.forward || self.back || self.left || self.right || self.up || self.down
    }
}

/// A first-person camera: position, yaw and pitch, and a speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkCamera {
    /// Eye position in world space.
    pub position: Vec3,
    /// Turn about world +Y, radians (0 looks down -Z).
    pub yaw: f32,
    /// Turn about the camera's right axis, radians (positive looks up).
    pub pitch: f32,
    /// Base speed in scene units per second.
    pub speed: f32,
}

impl WalkCamera {
    /// The walkthrough camera at a placement: its position, and the yaw and pitch of its
    /// viewing direction (any roll is dropped). `speed` is the base speed (scene units/s).
    pub fn from_transform(transform: &Transform, speed: f32) -> Self {
        let forward = transform.rotation * Vec3::NEG_Z;
        let pitch = forward
            .y
            .clamp(-1.0, 1.0)
            .asin()
            .clamp(-MAX_PITCH, MAX_PITCH);
        let yaw = if forward.x.abs() + forward.z.abs() > 1e-6 {
            (-forward.x).atan2(-forward.z)
        } else {
            // Looking straight up or down: take the yaw from the camera's up axis.
            let up = transform.rotation * Vec3::Y;
            (-up.x * forward.y.signum()).atan2(-up.z * forward.y.signum())
        };
        Self {
            position: transform.translation,
            yaw,
            pitch,
            speed: speed.clamp(SPEED_RANGE.0, SPEED_RANGE.1),
        }
    }

    /// The camera's orientation: yaw about +Y, then pitch about the turned right axis.
    pub fn rotation(&self) -> Quat {
        Quat::from_euler(EulerRot::YXZ, self.yaw, self.pitch, 0.0)
    }

    /// Unit viewing direction.
    pub fn forward(&self) -> Vec3 {
        self.rotation() * Vec3::NEG_Z
    }

    /// The placement as a transform with unit scale.
    pub fn transform(&self) -> Transform {
        Transform {
            translation: self.position,
            rotation: self.rotation(),
            scale: Vec3::ONE,
        }
    }

    /// Turns the view by a mouse motion of `dx`, `dy` pixels (right and down positive).
    pub fn look(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * LOOK_RADIANS_PER_PIXEL;
        self.yaw = (self.yaw + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU)
            - std::f32::consts::PI;
        self.pitch = (self.pitch - dy * LOOK_RADIANS_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Scales the speed by [`SCROLL_SPEED_STEP`] per scroll step up (down slows).
    pub fn scroll(&mut self, steps: f32) {
        self.speed =
            (self.speed * SCROLL_SPEED_STEP.powf(steps)).clamp(SPEED_RANGE.0, SPEED_RANGE.1);
    }

    /// Moves for `dt` seconds with `keys` held: W/S along the viewing direction, A/D along the
    /// right axis, E/Q along world +Y; diagonal moves are as fast as straight ones. Returns
    /// whether the camera moved.
    pub fn advance(&mut self, keys: &MoveKeys, dt: f32) -> bool {
        let axis = |plus: bool, minus: bool| f32::from(u8::from(plus)) - f32::from(u8::from(minus));
        let rotation = self.rotation();
        let direction = rotation * Vec3::NEG_Z * axis(keys.forward, keys.back)
            + rotation * Vec3::X * axis(keys.right, keys.left)
            + Vec3::Y * axis(keys.up, keys.down);
        let Some(direction) = direction.try_normalize() else {
            return false;
        };
        let fast = if keys.fast { FAST_FACTOR } else { 1.0 };
        let step = direction * self.speed * fast * dt.max(0.0);
        self.position += step;
        step != Vec3::ZERO
    }
}

/// A base speed for a scene of bounding-box diagonal `diagonal`: crossing it takes about four
/// seconds.
pub fn speed_for_extent(diagonal: f32) -> f32 {
    if diagonal.is_finite() && diagonal > 0.0 {
        (diagonal / 4.0).clamp(SPEED_RANGE.0, SPEED_RANGE.1)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn round_trips_a_placement_without_roll() {
        let rotation = Quat::from_euler(EulerRot::YXZ, 0.7, -0.3, 0.0);
        let t = Transform {
            translation: Vec3::new(1.0, 2.0, 3.0),
            rotation,
            scale: Vec3::ONE,
        };
        let cam = WalkCamera::from_transform(&t, 2.0);
        assert!((cam.yaw - 0.7).abs() < 1e-5 && (cam.pitch + 0.3).abs() < 1e-5);
        let back = cam.transform();
        assert!(close(back.translation, t.translation));
        assert!(close(back.rotation * Vec3::NEG_Z, rotation * Vec3::NEG_Z));
        assert!(close(back.rotation * Vec3::Y, rotation * Vec3::Y));
    }

    #[test]
    fn keys_move_along_the_view_at_the_speed() {
        let mut cam = WalkCamera::from_transform(&Transform::IDENTITY, 2.0);
        let w = MoveKeys {
            forward: true,
            ..Default::default()
        };
        assert!(cam.advance(&w, 0.5));
        assert!(close(cam.position, Vec3::new(0.0, 0.0, -1.0)));
        // Shift is FAST_FACTOR times faster; D goes right (+X when looking down -Z).
        let d = MoveKeys {
            right: true,
            fast: true,
            ..Default::default()
        };
        cam.advance(&d, 0.25);
        assert!(close(cam.position, Vec3::new(2.0, 0.0, -1.0)));
        // E goes up along world +Y even when pitched down; Q down.
        cam.pitch = -1.0;
        let e = MoveKeys {
            up: true,
            ..Default::default()
        };
        cam.advance(&e, 1.0);
        assert!(close(cam.position, Vec3::new(2.0, 2.0, -1.0)));
        // A diagonal is as fast as a straight move; opposite keys cancel; no key, no move.
        let mut cam = WalkCamera::from_transform(&Transform::IDENTITY, 1.0);
        let wd = MoveKeys {
            forward: true,
            right: true,
            ..Default::default()
        };
        cam.advance(&wd, 1.0);
        assert!((cam.position.length() - 1.0).abs() < 1e-5);
        let ws = MoveKeys {
            forward: true,
            back: true,
            ..Default::default()
        };
        assert!(!cam.advance(&ws, 1.0));
        assert!(!cam.advance(&MoveKeys::default(), 1.0));
    }

    #[test]
    fn mouse_turns_and_pitch_is_clamped() {
        let mut cam = WalkCamera::from_transform(&Transform::IDENTITY, 1.0);
        // Moving the mouse right turns right: the view goes from -Z towards +X.
        cam.look(100.0, 0.0);
        assert!(cam.forward().x > 0.0 && cam.forward().z < 0.0);
        // Moving it up looks up; far up stops at MAX_PITCH.
        cam.look(0.0, -100.0);
        assert!(cam.forward().y > 0.0);
        cam.look(0.0, -1e6);
        assert_eq!(cam.pitch, MAX_PITCH);
        cam.look(0.0, 1e6);
        assert_eq!(cam.pitch, -MAX_PITCH);
        // The camera never rolls: its right axis stays horizontal.
        assert!((cam.rotation() * Vec3::X).y.abs() < 1e-6);
    }

    #[test]
    fn scroll_scales_the_speed_within_its_range() {
        let mut cam = WalkCamera::from_transform(&Transform::IDENTITY, 1.0);
        cam.scroll(2.0);
        assert!((cam.speed - SCROLL_SPEED_STEP * SCROLL_SPEED_STEP).abs() < 1e-5);
        cam.scroll(-2.0);
        assert!((cam.speed - 1.0).abs() < 1e-5);
        cam.scroll(1e4);
        assert_eq!(cam.speed, SPEED_RANGE.1);
        assert_eq!(speed_for_extent(8.0), 2.0);
        assert_eq!(speed_for_extent(f32::NAN), 1.0);
    }
}
