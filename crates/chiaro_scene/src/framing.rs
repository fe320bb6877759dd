//! The camera a scene without one gets, so that any model renders without setup.
//!
//! Rule: a perspective camera with a vertical field of view of [`AUTO_YFOV`], looking down -Z at
//! the centre of the scene's world bounds, placed on the +Z side at the distance where the
//! bounds' enclosing sphere just fits the vertical field of view (for any output aspect of at
//! least 1 it then fits horizontally too). Near plane at 1/1000 of that distance, far plane
//! infinite. An empty scene gets the same camera at the origin.

use glam::Vec3;

use crate::bounds::Aabb;
use crate::components::{Camera, Projection};
use crate::transform::Transform;

/// Vertical field of view of the automatic camera: 45 degrees.
pub const AUTO_YFOV: f32 = std::f32::consts::FRAC_PI_4;

/// The automatic camera for `bounds`: its transform and its camera component.
pub fn frame_bounds(bounds: &Aabb) -> (Transform, Camera) {
    let (center, radius) = if bounds.is_empty() {
        (Vec3::ZERO, 1.0)
    } else {
        let r = 0.5 * bounds.size().length();
        (bounds.center(), if r > 0.0 { r } else { 1.0 })
    };
    let distance = radius / (0.5 * AUTO_YFOV).sin();
    let transform = Transform::from_translation(center + Vec3::Z * distance);
    let camera = Camera {
        projection: Projection::Perspective {
            yfov: AUTO_YFOV,
            aspect_ratio: None,
            znear: distance * 1e-3,
            zfar: None,
        },
    };
    (transform, camera)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn framed_sphere_touches_the_view_cone() {
        let bounds = Aabb::from_points([Vec3::new(-1.0, 0.0, -2.0), Vec3::new(3.0, 2.0, 0.0)]);
        let (t, _) = frame_bounds(&bounds);
        let center = bounds.center();
        assert!(
            (t.translation.x - center.x).abs() < 1e-6 && (t.translation.y - center.y).abs() < 1e-6
        );
        let radius = 0.5 * bounds.size().length();
        let d = t.translation.z - center.z;
        // The sphere's tangent from the eye makes half the field of view with the axis.
        assert!(((radius / d).asin() - 0.5 * AUTO_YFOV).abs() < 1e-5);
        assert_eq!(t.rotation, glam::Quat::IDENTITY);
    }
}
