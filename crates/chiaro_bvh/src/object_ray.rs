//! A world ray carried into one instance's object space.
//!
//! The origin and direction go through the instance's inverse matrix; the direction is not
//! normalised, so `t` means the same point in world and object space and hits of different
//! instances compare directly. Traversal and the brute-force reference both build their object
//! rays here, so both run the triangle test on bit-identical inputs.

use glam::{Affine3A, Vec3};

use crate::ray::Ray;
use crate::slab::BLAS_PAD_ULPS;
use crate::watertight::WatertightRay;

/// A ray prepared for one BLAS traversal.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ObjectRay {
    pub origin: Vec3,
    pub direction: Vec3,
    pub watertight: WatertightRay,
    origin_magnitude: f32,
}

impl ObjectRay {
    /// Prepares `origin + t * direction`; `None` when the direction is zero or either is not
    /// finite (possible after a transform underflows or overflows).
    #[inline]
    pub fn new(origin: Vec3, direction: Vec3) -> Option<Self> {
        if !origin.is_finite() || !direction.is_finite() || direction.abs().max_element() == 0.0 {
            return None;
        }
        Some(Self {
            origin,
            direction,
            watertight: WatertightRay::new(origin, direction),
            origin_magnitude: origin.abs().max_element(),
        })
    }

    /// `ray` in the object space of an instance whose world-to-object matrix is `inverse`.
    #[inline]
    pub fn from_world(ray: &Ray, inverse: &Affine3A) -> Option<Self> {
        Self::new(
            inverse.transform_point3(ray.origin),
            inverse.transform_vector3(ray.direction),
        )
    }

    /// The box pad for a mesh whose largest absolute coordinate is `mesh_magnitude`.
    #[inline]
    pub fn pad(&self, mesh_magnitude: f32) -> f32 {
        BLAS_PAD_ULPS * f32::EPSILON * (self.origin_magnitude + mesh_magnitude)
    }
}
