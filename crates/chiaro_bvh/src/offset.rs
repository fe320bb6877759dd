//! Origins of secondary rays that cannot hit the surface they leave: Wächter and Binder, "A Fast
//! and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems, chapter 6, 2019.

use glam::Vec3;

/// Below this magnitude a coordinate is offset by a fixed amount instead of in ulps.
pub const ORIGIN: f32 = 1.0 / 32.0;
/// Fixed offset scale near the origin.
pub const FLOAT_SCALE: f32 = 1.0 / 65536.0;
/// Offset in ulps per unit of normal component.
pub const INT_SCALE: f32 = 256.0;

/// Moves a surface point `p` off its surface along `geometric_normal`, so that a ray started
/// there does not hit the surface it starts on.
///
/// `geometric_normal` is the unit geometric normal of the surface at `p`, pointing to the side
/// the new ray leaves from (flip it for transmission or for a ray leaving the back face).
/// Each coordinate moves by `256 * n` ulps of itself, or by `n / 65536` for coordinates closer
/// to zero than 1/32, where single-precision ulps become meaningless. The offset grows with the
/// coordinates' magnitude, so it is safe far from the origin (at 1e5 it is about 2 units per
/// unit of normal component) and small near it.
///
/// `p` should carry only the error of its own coordinates, such as
/// [`crate::SceneBvh::hit_point`] (vertices interpolated by barycentrics); `ray.at(hit.t)` adds
/// an error that grows with the ray's length. Non-finite input returns `p` unchanged.
pub fn offset_ray_origin(p: Vec3, geometric_normal: Vec3) -> Vec3 {
    if !p.is_finite() || !geometric_normal.is_finite() {
        return p;
    }
    let n = geometric_normal.to_array();
    let pa = p.to_array();
    let offset = |k: usize| -> f32 {
        if pa[k].abs() < ORIGIN {
            return pa[k] + FLOAT_SCALE * n[k];
        }
        let ulps = (INT_SCALE * n[k]) as i32;
        // Moving the bits of a negative number up moves it down: flip the step's sign.
        let step = if pa[k] < 0.0 { -ulps } else { ulps };
        let moved = f32::from_bits((pa[k].to_bits() as i32).wrapping_add(step) as u32);
        if moved.is_finite() { moved } else { pa[k] }
    };
    Vec3::new(offset(0), offset(1), offset(2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moves_to_the_normal_side_by_a_relative_amount() {
        let n = Vec3::new(0.0, 1.0, 0.0);
        for y in [-1e5f32, -3.0, -0.01, 0.0, 0.01, 3.0, 1e5] {
            let p = Vec3::new(1.0, y, -2.0);
            let q = offset_ray_origin(p, n);
            assert!(q.y > p.y, "{y}: {}", q.y);
            assert_eq!((q.x, q.z), (p.x, p.z));
            assert!(q.y - p.y <= 256.0 * f32::EPSILON * y.abs().max(1.0) * 2.0);
        }
        let q = offset_ray_origin(Vec3::new(0.0, 5.0, 0.0), -n);
        assert!(q.y < 5.0);
    }

    #[test]
    fn non_finite_input_is_returned_unchanged() {
        let p = Vec3::new(f32::NAN, 1.0, 2.0);
        assert!(offset_ray_origin(p, Vec3::Y).x.is_nan());
        assert_eq!(offset_ray_origin(Vec3::ONE, Vec3::NAN), Vec3::ONE);
    }
}
