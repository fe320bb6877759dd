//! Rays and hits: what a query asks and what it answers.

use glam::{Vec2, Vec3};

/// Largest absolute coordinate of a ray origin the BVH accepts, and the largest direction
/// component: the same bound chiaro_scene puts on mesh coordinates.
pub const MAX_RAY_COORDINATE: f32 = 1.0e18;

/// Smallest largest-component of a ray direction the BVH accepts. Below it, distances in units
/// of the direction could overflow `f32` inside a scene of coordinates up to
/// [`MAX_RAY_COORDINATE`].
pub const MIN_RAY_DIRECTION: f32 = 1.0e-18;

/// A ray: the points `origin + t * direction` for `t` in the open interval `(t_min, t_max)`.
///
/// The direction need not be unit length; `t` is measured in units of it. A ray whose origin or
/// direction is non-finite, whose origin has a coordinate beyond [`MAX_RAY_COORDINATE`], whose
/// direction's largest component is outside [`MIN_RAY_DIRECTION`]..=[`MAX_RAY_COORDINATE`], or
/// whose `t_min` or `t_max` is NaN, is refused: every query answers "no hit" for it (see
/// [`Ray::is_valid`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts (at `t = 0`).
    pub origin: Vec3,
    /// Where it goes; any non-zero length.
    pub direction: Vec3,
    /// Hits at or before this `t` are ignored.
    pub t_min: f32,
    /// Hits at or beyond this `t` are ignored; `f32::INFINITY` for an unbounded ray.
    pub t_max: f32,
}

impl Ray {
    /// A ray over `(0, infinity)`.
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        Self {
            origin,
            direction,
            t_min: 0.0,
            t_max: f32::INFINITY,
        }
    }

    /// This ray with its interval replaced by `(t_min, t_max)`.
    pub fn with_interval(self, t_min: f32, t_max: f32) -> Self {
        Self {
            t_min,
            t_max,
            ..self
        }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.direction * t
    }

    /// Whether the BVH will trace this ray (see the type's documentation). An empty interval
    /// (`t_min >= t_max`) is valid and simply hits nothing.
    pub fn is_valid(&self) -> bool {
        let largest = self.direction.abs().max_element();
        self.origin.is_finite()
            && self.origin.abs().max_element() <= MAX_RAY_COORDINATE
            && self.direction.is_finite()
            && (MIN_RAY_DIRECTION..=MAX_RAY_COORDINATE).contains(&largest)
            && !self.t_min.is_nan()
            && !self.t_max.is_nan()
    }
}

/// A ray's hit on a triangle of an instance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit, in units of the ray's direction.
    pub t: f32,
    /// Index of the instance into [`crate::SceneBvh::instances`].
    pub instance: u32,
    /// Index of the triangle in its mesh's triangle list (`indices()[3 * triangle..][..3]`).
    pub triangle: u32,
    /// Barycentric weights `(b1, b2)` of the triangle's vertices 1 and 2; vertex 0 weighs
    /// `1 - b1 - b2`.
    pub barycentrics: Vec2,
}

impl Hit {
    /// All three barycentric weights `(b0, b1, b2)`, for vertices 0, 1 and 2.
    pub fn weights(&self) -> Vec3 {
        Vec3::new(
            1.0 - self.barycentrics.x - self.barycentrics.y,
            self.barycentrics.x,
            self.barycentrics.y,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validity_refuses_non_finite_and_degenerate_rays() {
        let good = Ray::new(Vec3::ZERO, Vec3::X);
        assert!(good.is_valid());
        assert!(good.with_interval(5.0, 1.0).is_valid(), "empty is valid");
        let bad = [
            Ray::new(Vec3::NAN, Vec3::X),
            Ray::new(Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0)),
            Ray::new(Vec3::ZERO, Vec3::ZERO),
            Ray::new(Vec3::ZERO, Vec3::splat(1e-20)),
            Ray::new(Vec3::splat(2e18), Vec3::X),
            good.with_interval(f32::NAN, 1.0),
            good.with_interval(0.0, f32::NAN),
        ];
        for ray in bad {
            assert!(!ray.is_valid(), "{ray:?}");
        }
    }

    #[test]
    fn weights_sum_to_one() {
        let hit = Hit {
            t: 1.0,
            instance: 0,
            triangle: 0,
            barycentrics: Vec2::new(0.25, 0.5),
        };
        assert_eq!(hit.weights(), Vec3::new(0.25, 0.25, 0.5));
    }
}
