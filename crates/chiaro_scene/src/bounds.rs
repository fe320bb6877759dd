//! Axis-aligned bounding boxes.

use glam::{Affine3A, Vec3};

/// An axis-aligned box; `Aabb::EMPTY` contains nothing and is the identity of [`Aabb::union`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box.
    pub const EMPTY: Self = Self {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The smallest box holding every point; empty for no points.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, Self::including)
    }

    /// True when the box holds no point.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// This box grown to hold `point`.
    pub fn including(self, point: Vec3) -> Self {
        Self {
            min: self.min.min(point),
            max: self.max.max(point),
        }
    }

    /// The smallest box holding both.
    pub fn union(self, other: Self) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Centre point (meaningless when empty).
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Size along each axis (meaningless when empty).
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    /// The box holding this box's eight corners after `transform`.
    pub fn transformed(&self, transform: &Affine3A) -> Self {
        if self.is_empty() {
            return *self;
        }
        let corners = (0..8).map(|i| {
            let pick = |bit: usize, axis: usize| {
                if i & bit == 0 {
                    self.min[axis]
                } else {
                    self.max[axis]
                }
            };
            transform.transform_point3(Vec3::new(pick(1, 0), pick(2, 1), pick(4, 2)))
        });
        Self::from_points(corners)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn empty_box_is_the_union_identity() {
        let b = Aabb::from_points([Vec3::ZERO, Vec3::ONE]);
        assert!(Aabb::EMPTY.is_empty());
        assert!(!b.is_empty());
        assert_eq!(Aabb::EMPTY.union(b), b);
    }

    #[test]
    fn rotated_box_grows_to_hold_its_corners() {
        let b = Aabb::from_points([Vec3::splat(-1.0), Vec3::splat(1.0)]);
        let r = Affine3A::from_quat(Quat::from_rotation_y(std::f32::consts::FRAC_PI_4));
        let t = b.transformed(&r);
        assert!((t.max.x - 2f32.sqrt()).abs() < 1e-5);
        assert!((t.max.y - 1.0).abs() < 1e-6);
    }
}
