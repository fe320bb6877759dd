//! The conservative ray/box test of the TLAS traversal, and the padding rules the BLAS
//! traversal's child-box test ([`crate::wide`]) follows too.
//!
//! It is the slab test with the rounding bound of Ize, "Robust BVH Ray Traversal", Journal of
//! Computer Graphics Techniques 2(2), 2013: the exit distance is scaled up by `1 + 2 gamma(3)` so
//! that rounding never culls a box the exact ray enters. Two things are added on top.
//!
//! * **Padding.** The watertight triangle test ([`crate::watertight`]) translates vertices by
//!   the ray origin and shears them, so in effect it tests vertices perturbed by a few ulps of
//!   `|vertex - origin|`. A ray that the exact geometry misses by that much can still be
//!   reported as a hit (that is what makes shared edges watertight). Each box is therefore grown
//!   by a pad proportional to the magnitudes involved, so that traversal never culls a triangle
//!   that the same test, run by brute force, would report. See [`BLAS_PAD_ULPS`] and
//!   [`TLAS_PAD_ULPS`].
//! * **Axis-parallel rays.** A zero direction component gives an infinite reciprocal, and
//!   `0 * inf` (an origin exactly on a slab plane) gives NaN. Such NaNs are replaced by the
//!   value that keeps the ray inside that slab (planes count as inside), explicitly rather than
//!   by relying on how a SIMD `min`/`max` happens to order NaNs.

use glam::{Vec3, Vec3A};

/// Unit roundoff of `f32` (half of `f32::EPSILON`).
const UNIT_ROUNDOFF: f32 = f32::EPSILON * 0.5;
/// `gamma(3) = 3u / (1 - 3u)` from Ize 2013 / PBRT.
const GAMMA3: f32 = 3.0 * UNIT_ROUNDOFF / (1.0 - 3.0 * UNIT_ROUNDOFF);
/// Relative growth applied to a box's exit distance (`2 gamma(3)`; the GPU traversal uses the
/// same value).
pub const TWO_GAMMA3: f32 = 2.0 * GAMMA3;

/// Pad of a bottom-level box, in units of `f32::EPSILON` times (largest origin coordinate +
/// largest coordinate of the mesh), both in object space. The watertight test's perturbation is
/// below about 4 ulps of those magnitudes; 16 leaves a margin.
pub const BLAS_PAD_ULPS: f32 = 16.0;

/// Pad of a top-level box, in units of `f32::EPSILON` times the instance's condition number
/// times (largest world origin coordinate + largest coordinate of the instance's world box and
/// translation). It covers the bottom-level pad mapped to world space plus the rounding of the
/// world-to-object ray transform and of the inverse matrix.
pub const TLAS_PAD_ULPS: f32 = 64.0;

/// A ray prepared for box tests.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BoxRay {
    origin: Vec3A,
    inv_direction: Vec3A,
    /// Some direction component is zero: NaNs are possible and must be cleaned.
    zero_component: bool,
}

impl BoxRay {
    /// Prepares `origin + t * direction`; `direction` must be finite.
    #[inline(always)]
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        // -0.0 + 0.0 = +0.0: every zero component gets a reciprocal of +inf.
        let direction = Vec3A::from(direction) + Vec3A::ZERO;
        Self {
            origin: origin.into(),
            inv_direction: Vec3A::ONE / direction,
            zero_component: direction.cmpeq(Vec3A::ZERO).any(),
        }
    }

    /// Largest absolute coordinate of the origin.
    #[inline(always)]
    pub fn origin_magnitude(&self) -> f32 {
        self.origin.abs().max_element()
    }

    /// The ray origin moved by `-pad` and `+pad` on every axis, for [`BoxRay::entry`].
    #[inline(always)]
    pub fn padded_origins(&self, pad: f32) -> (Vec3A, Vec3A) {
        let p = Vec3A::splat(pad);
        (self.origin + p, self.origin - p)
    }

    /// Entry distance into the box `[lo, hi]` grown by the pad baked into `origins` (from
    /// [`BoxRay::padded_origins`]), clipped to `[t_min, t_max]`; `f32::INFINITY` when the ray
    /// misses it in that interval.
    #[inline(always)]
    pub fn entry(
        &self,
        lo: Vec3A,
        hi: Vec3A,
        origins: (Vec3A, Vec3A),
        t_min: f32,
        t_max: f32,
    ) -> f32 {
        // lo - (o + pad) = (lo - pad) - o, and hi - (o - pad) = (hi + pad) - o.
        let mut t_lo = (lo - origins.0) * self.inv_direction;
        let mut t_hi = (hi - origins.1) * self.inv_direction;
        if self.zero_component {
            // 0 * inf: the origin lies on a plane of this slab and the ray runs inside it.
            t_lo = Vec3A::select(t_lo.is_nan_mask(), Vec3A::NEG_INFINITY, t_lo);
            t_hi = Vec3A::select(t_hi.is_nan_mask(), Vec3A::INFINITY, t_hi);
        }
        let near = t_lo.min(t_hi).max_element().max(t_min);
        let far = t_lo.max(t_hi).min_element();
        // Grow |far| (towards +inf when positive, towards 0 when negative); infinities stay.
        let far = (far * (1.0 + TWO_GAMMA3.copysign(far))).min(t_max);
        if near <= far { near } else { f32::INFINITY }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(o: Vec3, d: Vec3, pad: f32) -> f32 {
        let r = BoxRay::new(o, d);
        r.entry(
            Vec3A::ZERO,
            Vec3A::ONE,
            r.padded_origins(pad),
            0.0,
            f32::INFINITY,
        )
    }

    #[test]
    fn enters_misses_and_starts_inside() {
        assert_eq!(entry(Vec3::new(0.5, 0.5, -1.0), Vec3::Z, 0.0), 1.0);
        assert_eq!(entry(Vec3::new(0.5, 0.5, 0.5), Vec3::Z, 0.0), 0.0);
        assert!(entry(Vec3::new(2.0, 0.5, -1.0), Vec3::Z, 0.0).is_infinite());
        assert!(entry(Vec3::new(0.5, 0.5, 2.0), Vec3::Z, 0.0).is_infinite());
    }

    #[test]
    fn axis_parallel_rays_on_the_planes_are_inside() {
        // Origins exactly on the faces, direction along an axis with zero components (and -0).
        for o in [
            Vec3::new(0.0, 0.5, -1.0),
            Vec3::new(1.0, 0.5, -1.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(0.0, 0.0, -1.0),
        ] {
            for d in [Vec3::Z, Vec3::new(-0.0, -0.0, 1.0)] {
                assert_eq!(entry(o, d, 0.0), 1.0, "{o} {d}");
            }
        }
        assert!(entry(Vec3::new(1.0 + 1e-6, 0.5, -1.0), Vec3::Z, 0.0).is_infinite());
        assert_eq!(
            entry(Vec3::new(1.0 + 1e-6, 0.5, -1.0), Vec3::Z, 1e-5),
            1.0 - 1e-5
        );
    }

    #[test]
    fn far_axis_parallel_rays_are_not_culled_by_a_clamped_reciprocal() {
        // obvhs clamps 1/d to 1/EPSILON, which culls this ray (see the crate docs).
        let t = entry(Vec3::new(0.999, 0.5, 1e5), Vec3::NEG_Z, 0.0);
        assert!((t - (1e5 - 1.0)).abs() < 1.0, "{t}");
        let t = entry(Vec3::new(0.5, 0.5, 1.0), Vec3::new(0.0, 0.0, -1e-8), 0.0);
        assert!(t.is_finite());
    }
}
