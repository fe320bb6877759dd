//! The GGX (Trowbridge-Reitz) microfacet distribution: normal distribution, Smith masking and
//! shadowing, and visible-normal sampling, in the local frame (z = shading normal).
//!
//! Sources:
//! - Trowbridge and Reitz, 1975, "Average irregularity representation of a rough surface for ray
//!   reflection"; Walter, Marschner, Li and Torrance, 2007, "Microfacet Models for Refraction
//!   through Rough Surfaces" (the GGX distribution `D`).
//! - Heitz, 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs" (Smith
//!   `Lambda` for GGX, the height-correlated `G2 = 1 / (1 + Lambda(wo) + Lambda(wi))`).
//! - Heitz, 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)): [`sample_vndf`].
//!
//! All functions take an `alpha` (= roughness^2) that the caller keeps at or above
//! [`crate::brdf::MIRROR_ALPHA`]; they clamp it to at least [`ALPHA_FLOOR`] so that a direct
//! caller passing 0 gets finite (if meaningless) numbers instead of a division by zero.
//!
//! Numerics: `D` and `Lambda` are written with `x^2 + y^2` (the squared sine) rather than
//! `1 - z^2`, which keeps full precision for directions near the normal, and the combined
//! `G2 / (4 |n.wo| |n.wi|)` ([`visibility`]) never divides by a cosine alone.

use std::f32::consts::{FRAC_1_PI, TAU};

use glam::{Vec2, Vec3};

/// The smallest alpha the functions here compute with (1e-4; D's peak 1/(pi alpha^2) is then
/// 3.2e7, far from overflow).
pub const ALPHA_FLOOR: f32 = 1e-4;

/// Alpha of the GGX distribution for a perceptual roughness: roughness^2, with roughness clamped
/// to [0, 1] (glTF's range; values outside it are texture or authoring noise).
pub fn alpha_from_roughness(roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    r * r
}

/// The GGX normal distribution D(h) for the unit half vector `h` (zero when h.z <= 0):
/// alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2), evaluated as
/// 1 / (pi alpha^2 ((h.x^2 + h.y^2) / alpha^2 + h.z^2)^2).
pub fn ndf(h: Vec3, alpha: f32) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha.max(ALPHA_FLOOR).powi(2);
    let t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
    FRAC_1_PI / (a2 * t * t)
}

/// `sqrt(z^2 + alpha^2 (x^2 + y^2))` for a unit direction: the recurring term of Smith's Lambda
/// for GGX (equal to `|z| sqrt(1 + alpha^2 tan^2 theta)`).
fn smith_root(w: Vec3, alpha: f32) -> f32 {
    let a2 = alpha.max(ALPHA_FLOOR).powi(2);
    (w.z * w.z + a2 * (w.x * w.x + w.y * w.y)).sqrt()
}

/// Smith's Lambda for GGX (Heitz 2014, eq. 72): (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2.
/// Infinite at the horizon (z = 0) and zero at the normal.
pub fn lambda(w: Vec3, alpha: f32) -> f32 {
    let z = w.z.abs();
    if z == 0.0 {
        return f32::INFINITY;
    }
    0.5 * (smith_root(w, alpha) / z - 1.0).max(0.0)
}

/// Smith's masking function G1(w) = 1 / (1 + Lambda(w)) = 2 |z| / (|z| + sqrt(z^2 + alpha^2 sin^2)).
pub fn smith_g1(w: Vec3, alpha: f32) -> f32 {
    let z = w.z.abs();
    let denominator = z + smith_root(w, alpha);
    if denominator <= 0.0 {
        return 0.0;
    }
    2.0 * z / denominator
}

/// The height-correlated masking-shadowing function G2 = 1 / (1 + Lambda(wo) + Lambda(wi))
/// (Heitz 2014, eq. 99), for directions on the same side (zero when either is at the horizon).
pub fn smith_g2(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let (zo, zi) = (wo.z.abs(), wi.z.abs());
    let denominator = zi * smith_root(wo, alpha) + zo * smith_root(wi, alpha);
    if denominator <= 0.0 {
        return 0.0;
    }
    2.0 * zo * zi / denominator
}

/// The smallest denominator [`visibility`] divides by. It only binds when both directions are
/// within about 1e-17 of the horizon, and bounds the result by 5e19.
pub const VISIBILITY_DENOMINATOR_FLOOR: f32 = 1e-20;

/// The visibility term V = G2 / (4 |n.wo| |n.wi|) with height-correlated G2, in the form
/// 0.5 / (|zi| sqrt(zo^2 + alpha^2 sin_o^2) + |zo| sqrt(zi^2 + alpha^2 sin_i^2)), which has no
/// 0/0 at grazing angles (popularised by Lagarde and de Rousiers, 2014, "Moving Frostbite to
/// Physically Based Rendering 3.0"). Its denominator is clamped to at least
/// [`VISIBILITY_DENOMINATOR_FLOOR`].
pub fn visibility(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let (zo, zi) = (wo.z.abs(), wi.z.abs());
    let denominator = zi * smith_root(wo, alpha) + zo * smith_root(wi, alpha);
    0.5 / denominator.max(VISIBILITY_DENOMINATOR_FLOOR)
}

/// Samples a microfacet normal from the distribution of normals visible from `wo` (wo.z > 0),
/// D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z (Heitz 2018, listing 1): stretch `wo` to the
/// alpha = 1 configuration, sample the projected hemisphere there, unstretch.
///
/// `u.x` sets the radius, `u.y` the angle on the projected disk. The result is unit length with
/// z >= 0 and `wo.h >= 0` up to rounding.
pub fn sample_vndf(wo: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    let a = alpha.max(ALPHA_FLOOR);
    // The view direction in the hemisphere configuration (alpha = 1).
    let v = Vec3::new(a * wo.x, a * wo.y, wo.z).normalize();
    // An orthonormal basis around v (T1 is horizontal; any choice works at v = +z).
    let len_sq = v.x * v.x + v.y * v.y;
    let t1 = if len_sq > 0.0 {
        Vec3::new(-v.y, v.x, 0.0) / len_sq.sqrt()
    } else {
        Vec3::X
    };
    let t2 = v.cross(t1);
    // A uniform point on the disk, then warp the lower half-disk onto the visible projected area.
    let r = u.x.max(0.0).sqrt();
    let phi = TAU * u.y;
    let p1 = r * phi.cos();
    let mut p2 = r * phi.sin();
    let s = 0.5 * (1.0 + v.z);
    p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
    // Reproject onto the hemisphere, then unstretch back to alpha.
    let n_h = t1 * p1 + t2 * p2 + v * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3::new(a * n_h.x, a * n_h.y, n_h.z.max(0.0)).normalize()
}

/// The solid-angle pdf of the reflected direction `wi = reflect(-wo, h)` when `h` comes from
/// [`sample_vndf`]: D_wo(h) / (4 wo.h) = D(h) G1(wo) / (4 wo.z), written as
/// D(h) / (2 (zo + sqrt(zo^2 + alpha^2 sin_o^2))) so that it stays finite as wo.z -> 0.
/// `h` is the unit half vector of `wo` and `wi`; zero when wo.z <= 0.
pub fn reflected_vndf_pdf(wo: Vec3, h: Vec3, alpha: f32) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    ndf(h, alpha) / (2.0 * (wo.z + smith_root(wo, alpha)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;
    use crate::sampling::uniform_hemisphere;
    use crate::test_util::gauss_legendre;
    use std::f32::consts::PI;

    /// The projected area of microfacets is the macro-surface: integral of D(h) cos(theta_h) over
    /// the hemisphere is 1 (Walter et al. 2007, eq. 4). Gauss-Legendre in (theta, phi) with the
    /// substitution tan(theta) = alpha tan(pi s / 2), which makes the integrand smooth.
    #[test]
    fn ndf_is_normalized() {
        for alpha in [ALPHA_FLOOR, 1e-3, 0.01, 0.1, 0.5, 1.0] {
            let total = gauss_legendre(0.0, 1.0, 256, |s| {
                let q = (0.5 * std::f64::consts::PI * s).tan();
                let theta = (alpha as f64 * q).atan();
                let dtheta_ds = alpha as f64 * 0.5 * std::f64::consts::PI * (1.0 + q * q)
                    / (1.0 + (alpha as f64 * q).powi(2));
                let h = Vec3::new(theta.sin() as f32, 0.0, theta.cos() as f32);
                ndf(h, alpha) as f64 * theta.cos() * theta.sin() * dtheta_ds * std::f64::consts::TAU
            });
            assert!((total - 1.0).abs() < 1e-4, "alpha {alpha}: {total}");
        }
    }

    /// The visible normals project to the view: integral of G1(wo) max(0, wo.h) D(h) over h is
    /// wo.z (Heitz 2014, eq. 21), checked by Monte Carlo over the hemisphere.
    #[test]
    fn masking_satisfies_the_projected_area_constraint() {
        let mut rng = Pcg32::new(8, 8);
        for alpha in [0.3, 0.6, 1.0] {
            for zo in [1.0f32, 0.7, 0.2] {
                let wo = Vec3::new((1.0 - zo * zo).sqrt(), 0.0, zo);
                let n = 200_000;
                let mut sum = 0.0f64;
                for _ in 0..n {
                    let h = uniform_hemisphere(rng.next_vec2());
                    sum += (smith_g1(wo, alpha) * wo.dot(h).max(0.0) * ndf(h, alpha)) as f64;
                }
                let estimate = sum / n as f64 * 2.0 * std::f64::consts::PI;
                let rel = (estimate - zo as f64).abs() / zo as f64;
                assert!(rel < 0.02, "alpha {alpha} zo {zo}: {estimate}");
            }
        }
    }

    #[test]
    fn smith_terms_agree_with_textbook_forms() {
        let mut rng = Pcg32::new(2, 7);
        for _ in 0..10_000 {
            let alpha = rng.next_f32().max(0.01);
            let wo = uniform_hemisphere(rng.next_vec2());
            let wi = uniform_hemisphere(rng.next_vec2());
            if wo.z < 1e-3 || wi.z < 1e-3 {
                continue;
            }
            let tan2 = |w: Vec3| (1.0 - w.z * w.z) / (w.z * w.z);
            let textbook_lambda = |w: Vec3| 0.5 * ((1.0 + alpha * alpha * tan2(w)).sqrt() - 1.0);
            assert!(
                (lambda(wo, alpha) - textbook_lambda(wo)).abs()
                    < 1e-3 * (1.0 + textbook_lambda(wo))
            );
            let g2 = 1.0 / (1.0 + textbook_lambda(wo) + textbook_lambda(wi));
            assert!((smith_g2(wo, wi, alpha) - g2).abs() < 1e-4, "{wo} {wi}");
            let v = g2 / (4.0 * wo.z * wi.z);
            assert!((visibility(wo, wi, alpha) - v).abs() < 1e-3 * v.max(1.0));
            assert!((smith_g1(wo, alpha) - 1.0 / (1.0 + textbook_lambda(wo))).abs() < 1e-4);
            let h = (wo + wi).normalize();
            let d = alpha * alpha / (PI * (h.z * h.z * (alpha * alpha - 1.0) + 1.0).powi(2));
            assert!((ndf(h, alpha) - d).abs() < 1e-3 * d.max(1.0), "{h} {alpha}");
        }
        assert_eq!(lambda(Vec3::X, 0.5), f32::INFINITY);
        assert_eq!(lambda(Vec3::Z, 0.5), 0.0);
        assert_eq!(smith_g1(Vec3::Z, 0.5), 1.0);
        assert_eq!(smith_g2(Vec3::X, Vec3::Z, 0.5), 0.0);
        assert!(visibility(Vec3::X, Vec3::X, 0.5).is_finite());
        assert_eq!(ndf(Vec3::X, 0.5), 0.0);
        assert_eq!(alpha_from_roughness(2.0), 1.0);
        assert_eq!(alpha_from_roughness(-1.0), 0.0);
        assert_eq!(alpha_from_roughness(0.5), 0.25);
    }

    /// Samples from `sample_vndf` have the density D_wo: the Monte Carlo estimate of
    /// E[g(h) / D_wo(h)] over samples equals the integral of g over the visible hemisphere (here
    /// g = 1 on the cap h.z > 0.9, entirely visible for these views: its area), and every sample
    /// is a unit, visible normal. (The BRDF's chi-square tests check the distribution in full.)
    #[test]
    fn vndf_samples_are_visible_and_weighted_by_their_density() {
        let mut rng = Pcg32::new(12, 34);
        for alpha in [0.02f32, 0.4, 1.0] {
            for zo in [1.0f32, 0.5, 0.05, 1e-6] {
                let wo = Vec3::new((1.0 - zo * zo).sqrt(), 0.0, zo);
                let n = 50_000;
                let cap_cos = 0.9f32;
                let mut sum = 0.0f64;
                for _ in 0..n {
                    let h = sample_vndf(wo, alpha, rng.next_vec2());
                    assert!((h.length() - 1.0).abs() < 1e-4 && h.z >= 0.0, "{h}");
                    assert!(wo.dot(h) >= -1e-6, "{wo} {h}");
                    let density = smith_g1(wo, alpha) * wo.dot(h).max(0.0) * ndf(h, alpha) / wo.z;
                    if h.z > cap_cos && density > 0.0 {
                        sum += 1.0 / density as f64;
                    }
                }
                if alpha >= 0.4 && zo >= 0.5 {
                    let cap = 2.0 * std::f64::consts::PI * (1.0 - cap_cos as f64);
                    let estimate = sum / n as f64;
                    assert!(
                        (estimate - cap).abs() < 0.03 * cap,
                        "alpha {alpha} zo {zo}: {estimate} vs {cap}"
                    );
                }
            }
        }
    }
}
