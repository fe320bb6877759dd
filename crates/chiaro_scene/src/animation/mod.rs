//! Keyframe animation of node transforms, as glTF 2.0 defines it (section 3.11, "Animations";
//! Appendix C, "Interpolation"): a clip's channels each drive one node's translation, rotation or
//! scale through a sampler of key times and values, stepped, linear (rotations by spherical
//! linear interpolation) or a cubic Hermite spline with the file's tangents.
//!
//! A [`Time`] resource holds the scene's time; [`animate_nodes`] writes every animated node's
//! [`Transform`] for it (only those whose value changes, so change detection stays exact: the
//! BVH and GPU systems downstream update only what moved). Every clip plays at once and loops
//! over its own length; before a channel's first key it holds the first value, after its last
//! key the last, as the specification says. Without a [`Time`] resource nothing is animated and
//! the scene keeps the pose its files describe.

use bevy_ecs::prelude::*;
use glam::{Quat, Vec4};

use crate::morph::MorphWeights;
use crate::transform::Transform;

/// The scene's time, in seconds: [`animate_nodes`] poses the animations there.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct Time {
    /// Seconds since the animations' start.
    pub seconds: f64,
}

/// How a sampler goes from one key to the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The value of the last key reached, held until the next.
    Step,
    /// Linear between keys; rotations by spherical linear interpolation.
    Linear,
    /// A cubic Hermite spline through the keys with the file's in- and out-tangents.
    CubicSpline,
}

/// Which part of a node's transform a channel drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// The translation (x, y, z).
    Translation,
    /// The rotation, a unit quaternion (x, y, z, w).
    Rotation,
    /// The scale (x, y, z).
    Scale,
    /// The weight of one morph target (in x) of the node's [`MorphWeights`].
    MorphWeight(usize),
}

/// A sampler's keys: times in seconds, strictly increasing, and one value per key (three per
/// key for a cubic spline: in-tangent, value, out-tangent), each as four numbers (x, y, z and,
/// for rotations, w).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframes {
    /// Key times, finite and strictly increasing.
    pub times: Vec<f32>,
    /// Values: `times.len()` of them, or `3 * times.len()` for [`Interpolation::CubicSpline`].
    pub values: Vec<Vec4>,
    /// How values between keys are found.
    pub interpolation: Interpolation,
}

impl Keyframes {
    /// Checked keyframes: at least one key, finite times strictly increasing, finite values of
    /// the count the interpolation needs. The error says what is wrong.
    pub fn new(
        times: Vec<f32>,
        values: Vec<Vec4>,
        interpolation: Interpolation,
    ) -> Result<Self, String> {
        if times.is_empty() {
            return Err("has no keys".into());
        }
        if let Some(k) = times.iter().position(|t| !t.is_finite()) {
            return Err(format!("key time {k} is not finite"));
        }
        if let Some(k) = times.windows(2).position(|w| w[1] <= w[0]) {
            return Err(format!(
                "key times are not increasing: key {} at {} s follows {} s",
                k + 1,
                times[k + 1],
                times[k]
            ));
        }
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        if values.len() != per_key * times.len() {
            return Err(format!(
                "has {} keys but {} values ({per_key} per key expected)",
                times.len(),
                values.len()
            ));
        }
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!("value {k} is not finite"));
        }
        Ok(Self {
            times,
            values,
            interpolation,
        })
    }

    /// The time of the last key.
    pub fn end(&self) -> f32 {
        self.times[self.times.len() - 1]
    }

    /// The key's value (the middle one of a cubic spline's three).
    fn value(&self, key: usize) -> Vec4 {
        match self.interpolation {
            Interpolation::CubicSpline => self.values[3 * key + 1],
            _ => self.values[key],
        }
    }

    /// The value at time `t`: the first key's before it, the last key's after the last, and in
    /// between as the interpolation says. Rotations come back as unit quaternions when
    /// `rotation` is set (spherical interpolation for [`Interpolation::Linear`], normalised
    /// splines).
    pub fn sample(&self, t: f32, rotation: bool) -> Vec4 {
        let last = self.times.len() - 1;
        if t.is_nan() || t <= self.times[0] {
            return self.finish(self.value(0), rotation);
        }
        if t >= self.times[last] {
            return self.finish(self.value(last), rotation);
        }
        // The segment [times[k], times[k + 1]) holding t.
        let k = self.times.partition_point(|&key| key <= t) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let dt = t1 - t0;
        let s = (t - t0) / dt;
        let value = match self.interpolation {
            Interpolation::Step => self.value(k),
            Interpolation::Linear if rotation => {
                let a = Quat::from_vec4(self.value(k)).normalize();
                let b = Quat::from_vec4(self.value(k + 1)).normalize();
                Vec4::from(a.slerp(b, s))
            }
            Interpolation::Linear => self.value(k).lerp(self.value(k + 1), s),
            Interpolation::CubicSpline => {
                // glTF 2.0, Appendix C: p(s) = (2s^3 - 3s^2 + 1) v_k + dt (s^3 - 2s^2 + s) b_k
                // + (-2s^3 + 3s^2) v_k+1 + dt (s^3 - s^2) a_k+1, b_k the out-tangent of key k
                // and a_k+1 the in-tangent of key k + 1.
                let (s2, s3) = (s * s, s * s * s);
                let v0 = self.values[3 * k + 1];
                let b0 = self.values[3 * k + 2];
                let a1 = self.values[3 * (k + 1)];
                let v1 = self.values[3 * (k + 1) + 1];
                v0 * (2.0 * s3 - 3.0 * s2 + 1.0)
                    + b0 * (dt * (s3 - 2.0 * s2 + s))
                    + v1 * (-2.0 * s3 + 3.0 * s2)
                    + a1 * (dt * (s3 - s2))
            }
        };
        self.finish(value, rotation)
    }

    /// A rotation normalised (the identity when it has no direction); other values as they are.
    fn finish(&self, value: Vec4, rotation: bool) -> Vec4 {
        if !rotation {
            return value;
        }
        let length = value.length();
        if length > 1e-12 && length.is_finite() {
            value / length
        } else {
            Vec4::W
        }
    }
}

/// One channel: keyframes driving one property of one target (a node's index in a
/// [`crate::SceneBuilder`] before spawning, its entity after).
#[derive(Clone, Debug, PartialEq)]
pub struct Channel<T> {
    /// The node driven.
    pub target: T,
    /// The part of its transform driven.
    pub property: Property,
    /// The keys.
    pub keyframes: Keyframes,
}

/// An animation: channels played together, over `[0, duration]`.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationClip<T> {
    /// Its name (the glTF animation's, or its index).
    pub name: String,
    /// Its channels.
    pub channels: Vec<Channel<T>>,
}

impl<T> AnimationClip<T> {
    /// The clip's length: its last key's time (0 for a clip without channels).
    pub fn duration(&self) -> f32 {
        self.channels
            .iter()
            .map(|c| c.keyframes.end())
            .fold(0.0, f32::max)
    }

    /// The clip's local time at scene time `seconds`: looped over its duration (a clip of
    /// length 0 stays at 0).
    pub fn local_time(&self, seconds: f64) -> f32 {
        let duration = f64::from(self.duration());
        if duration <= 0.0 || !seconds.is_finite() {
            return 0.0;
        }
        seconds.rem_euclid(duration) as f32
    }

    /// The same clip with its targets mapped by `f`.
    pub fn map_targets<U>(self, mut f: impl FnMut(T) -> U) -> AnimationClip<U> {
        AnimationClip {
            name: self.name,
            channels: self
                .channels
                .into_iter()
                .map(|c| Channel {
                    target: f(c.target),
                    property: c.property,
                    keyframes: c.keyframes,
                })
                .collect(),
        }
    }
}

/// The World's animation clips, their channels targeting entities.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct Animations {
    /// Every clip, each playing at once.
    pub clips: Vec<AnimationClip<Entity>>,
}

impl Animations {
    /// The longest clip's duration (0 without clips).
    pub fn duration(&self) -> f32 {
        self.clips
            .iter()
            .map(AnimationClip::duration)
            .fold(0.0, f32::max)
    }
}

/// Applies channel `channel` (a transform's) at its clip's local time `t` to `transform`.
fn apply(channel: &Channel<Entity>, t: f32, transform: &mut Transform) {
    let rotation = channel.property == Property::Rotation;
    let value = channel.keyframes.sample(t, rotation);
    match channel.property {
        Property::Translation => transform.translation = value.truncate(),
        Property::Rotation => transform.rotation = Quat::from_vec4(value),
        Property::Scale => transform.scale = value.truncate(),
        Property::MorphWeight(_) => {}
    }
}

/// Poses every animated node at the [`Time`]: writes the [`Transform`] of each channel's target
/// when the time or the clips changed, and only where the value differs. Does nothing without a
/// [`Time`] or [`Animations`] resource. Run it before [`crate::propagate_transforms`].
pub fn animate_nodes(
    time: Option<Res<Time>>,
    animations: Option<Res<Animations>>,
    mut transforms: Query<&mut Transform>,
    mut weights: Query<&mut MorphWeights>,
) {
    let (Some(time), Some(animations)) = (time, animations) else {
        return;
    };
    if !time.is_changed() && !animations.is_changed() {
        return;
    }
    for clip in &animations.clips {
        let t = clip.local_time(time.seconds);
        for channel in &clip.channels {
            if let Property::MorphWeight(k) = channel.property {
                let value = channel.keyframes.sample(t, false).x;
                if let Ok(mut w) = weights.get_mut(channel.target)
                    && w.0.get(k).is_some_and(|&old| old != value)
                    && value.is_finite()
                {
                    w.0[k] = value;
                }
                continue;
            }
            let Ok(mut transform) = transforms.get_mut(channel.target) else {
                continue;
            };
            let mut posed = *transform;
            apply(channel, t, &mut posed);
            // A zero scale is a legitimate key (it hides a node): the BVH leaves such an
            // instance out until it grows again.
            if posed.translation.is_finite()
                && posed.rotation.is_finite()
                && posed.scale.is_finite()
            {
                transform.set_if_neq(posed);
            }
        }
    }
}

/// Sets the World's [`Time`] to `seconds` and poses its animations there at once, skinned and
/// morphed meshes included (for a renderer that does not run [`animate_nodes`] in a schedule, such as
/// the CPU reference).
pub fn pose_at(world: &mut World, seconds: f64) {
    world.insert_resource(Time { seconds });
    let mut schedule = Schedule::default();
    schedule.add_systems(
        (
            animate_nodes,
            crate::propagate_transforms,
            crate::deformation::deform_meshes,
        )
            .chain(),
    );
    schedule.run(world);
}

#[cfg(test)]
mod tests;
