//! Shading normals that keep a mirror reflection above the surface.
//!
//! A normal map or interpolated normals can tilt the shading normal so far from the geometric
//! one that the view's mirror reflection about it points below the surface. Such directions
//! carry nothing (the shading-normal rule of chiaro_reference's integrator and the GPU's
//! passes), so a smooth surface there would render black. As Blender Cycles does (its
//! `ensure_valid_specular_reflection`), the shading normal is turned towards the geometric one,
//! in the plane they span, just far enough that the reflection leaves the surface at a
//! cosine of at least min(0.9 n_g.v, 0.01): the same rule, written here from the geometry.
//!
//! With v the unit view direction, n_g the geometric normal (both on the viewer's side), x the
//! unit tangent direction of the shading normal n = cos(t) n_g + sin(t) x, the reflection's
//! cosine to n_g is v_z cos(2t) + v_x sin(2t) = A cos(2t - b), with v_z = v.n_g, v_x = v.x,
//! A = |(v_z, v_x)| and b = atan2(v_x, v_z). When it is below the threshold h, the angle 2t moves
//! towards b until the cosine equals h: 2t = b + sign(2t - b) acos(h / A).

use glam::Vec3;

/// The largest cosine a corrected reflection is asked to keep to the geometric normal.
pub const MIN_REFLECTION_COSINE: f32 = 0.01;

/// `shading` (unit, on the viewer's side of `geometric`), turned towards `geometric` when the
/// mirror reflection of `view` about it would leave the surface at a cosine below
/// min(0.9 geometric.view, [`MIN_REFLECTION_COSINE`]); otherwise `shading` itself. All three are
/// unit world vectors, `view` pointing towards the viewer with geometric.view > 0.
pub fn valid_reflection_normal(geometric: Vec3, view: Vec3, shading: Vec3) -> Vec3 {
    let v_z = view.dot(geometric);
    let threshold = (0.9 * v_z).min(MIN_REFLECTION_COSINE);
    let n_dot_v = shading.dot(view);
    let reflected_z = 2.0 * n_dot_v * shading.dot(geometric) - v_z;
    if reflected_z >= threshold {
        return shading;
    }
    let tangential = shading - geometric * shading.dot(geometric);
    let length = tangential.length();
    if length.is_nan() || length <= 0.0 {
        return geometric;
    }
    let x = tangential / length;
    let v_x = view.dot(x);
    let amplitude = (v_z * v_z + v_x * v_x).sqrt();
    if amplitude.is_nan() || amplitude <= 0.0 {
        return geometric;
    }
    let b = v_x.atan2(v_z);
    let angle = 2.0 * shading.dot(x).atan2(shading.dot(geometric));
    let reach = (threshold / amplitude).clamp(-1.0, 1.0).acos();
    let side = if angle >= b { 1.0 } else { -1.0 };
    let half = 0.5 * (b + side * reach);
    (geometric * half.cos() + x * half.sin()).normalize_or(geometric)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;
    use crate::sampling::uniform_hemisphere;

    fn reflect(view: Vec3, n: Vec3) -> Vec3 {
        2.0 * n.dot(view) * n - view
    }

    /// For random views and shading normals tilted anywhere on the viewer's side: a normal
    /// whose reflection already clears the threshold is kept exactly; a corrected one is unit,
    /// stays in the plane of the original and the geometric normal, and puts the reflection at
    /// the threshold (within 1e-4); it turns towards the geometric normal, never past it.
    #[test]
    fn corrected_reflections_clear_the_surface() {
        let mut rng = Pcg32::new(17, 3);
        let (mut kept, mut corrected) = (0, 0);
        for _ in 0..100_000 {
            let view = uniform_hemisphere(rng.next_vec2());
            let shading = uniform_hemisphere(rng.next_vec2());
            if view.z < 1e-3 || shading.dot(view) <= 0.0 {
                continue;
            }
            let threshold = (0.9 * view.z).min(MIN_REFLECTION_COSINE);
            let n = valid_reflection_normal(Vec3::Z, view, shading);
            if reflect(view, shading).z >= threshold {
                assert_eq!(n, shading);
                kept += 1;
                continue;
            }
            corrected += 1;
            assert!((n.length() - 1.0).abs() < 1e-5, "{n}");
            let r = reflect(view, n).z;
            assert!(
                (r - threshold).abs() < 1e-4,
                "{view} {shading}: {r} vs {threshold}"
            );
            assert!(
                n.cross(shading).dot(Vec3::Z).abs() < 1e-4,
                "left the plane: {n}"
            );
            assert!(n.z >= shading.z - 1e-6, "turned away: {n} from {shading}");
        }
        assert!(kept > 10_000 && corrected > 10_000, "{kept} {corrected}");
    }

    /// Straight down onto a normal tilted 60 degrees: the reflection would point 30 degrees
    /// below the surface; the corrected normal is tilted by acos(0.01) / 2 (44.7 degrees).
    #[test]
    fn a_steep_tilt_is_turned_back_just_enough() {
        let tilted = Vec3::new(60f32.to_radians().sin(), 0.0, 60f32.to_radians().cos());
        let n = valid_reflection_normal(Vec3::Z, Vec3::Z, tilted);
        let expected = 0.5 * MIN_REFLECTION_COSINE.acos();
        assert!((n.z.acos() - expected).abs() < 1e-5, "{n}");
        assert!(n.x > 0.0 && n.y == 0.0);
    }
}
