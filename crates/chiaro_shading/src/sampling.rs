//! Warping uniform numbers to directions and points, and the multiple importance sampling weight.
//!
//! Every function takes its uniform numbers (in [0, 1)) as arguments, so results are
//! deterministic, testable by chi-square, and reproducible in WGSL from the same [`crate::rng`]
//! stream. Directions are in a local frame with z up unless stated otherwise.

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, TAU};

use glam::{Vec2, Vec3};

/// The pdf of [`uniform_hemisphere`]: 1 / (2 pi) per steradian.
pub const UNIFORM_HEMISPHERE_PDF: f32 = 0.5 * FRAC_1_PI;

/// The pdf of [`uniform_sphere`]: 1 / (4 pi) per steradian.
pub const UNIFORM_SPHERE_PDF: f32 = 0.25 * FRAC_1_PI;

/// Maps the unit square to the unit disk with Shirley and Chiu, 1997, "A Low Distortion Map
/// Between Disk and Square" (the concentric map, in the single-branch polar form). Area-preserving
/// up to a constant, so uniform in gives uniform out.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let a = 2.0 * u.x - 1.0;
    let b = 2.0 * u.y - 1.0;
    if a == 0.0 && b == 0.0 {
        return Vec2::ZERO;
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, FRAC_PI_2 - FRAC_PI_4 * (a / b))
    };
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// A cosine-weighted direction on the hemisphere z >= 0 (Malley's method: a uniform point on the
/// disk from [`concentric_disk`], lifted to the hemisphere). pdf = cos(theta) / pi, see
/// [`cosine_hemisphere_pdf`]. z is at least 0; it is exactly 0 only on the disk's rim.
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// The pdf of [`cosine_hemisphere`] for a direction with this cosine to the normal: cos / pi,
/// zero for cos <= 0.
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// A uniformly distributed direction on the hemisphere z >= 0; pdf [`UNIFORM_HEMISPHERE_PDF`].
/// `u.x` sets z, `u.y` the azimuth.
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// A uniformly distributed direction on the unit sphere; pdf [`UNIFORM_SPHERE_PDF`].
/// `u.x` sets z = 1 - 2 u.x, `u.y` the azimuth.
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// A uniformly distributed point on a triangle, as barycentrics `(b1, b2)` of vertices 1 and 2
/// (the point is `v0 + b1 (v1 - v0) + b2 (v2 - v0)`; b0 = 1 - b1 - b2).
///
/// Heitz, 2019, "A Low-Distortion Map Between Triangle and Square": the square is folded along its
/// diagonal and each half sheared onto the triangle, which keeps neighbouring uniform samples
/// neighbours (stratification survives) and needs no square root.
pub fn uniform_triangle(u: Vec2) -> (f32, f32) {
    // (s, t) are Heitz's barycentrics of the two legs.
    let (s, t) = if u.y > u.x {
        let s = 0.5 * u.x;
        (s, u.y - s)
    } else {
        let t = 0.5 * u.y;
        (u.x - t, t)
    };
    (s, t)
}

/// The power heuristic with beta = 2 (Veach and Guibas, 1995, "Optimally Combining Sampling
/// Techniques for Monte Carlo Rendering"): the MIS weight of a sample drawn from strategy f (taken
/// `nf` times, pdf `f_pdf`) when strategy g (taken `ng` times, pdf `g_pdf`) could also have drawn it.
///
/// Robust by construction: it compares the ratio of the two products, so large pdfs never
/// overflow when squared. Negative or NaN products count as 0. Defined answers: both products 0
/// gives 0 (the sample could not have been drawn); f infinite (a delta strategy) gives 1 unless g
/// is infinite too, which gives 1/2; g infinite and f finite gives 0.
pub fn power_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    // `max` returns the non-NaN operand, so NaN becomes 0.
    let f = (nf * f_pdf).max(0.0);
    let g = (ng * g_pdf).max(0.0);
    if f == g {
        return if f == 0.0 { 0.0 } else { 0.5 };
    }
    if f > g {
        if f.is_infinite() {
            return 1.0;
        }
        let r = g / f;
        1.0 / (1.0 + r * r)
    } else {
        if g.is_infinite() {
            return 0.0;
        }
        let r = f / g;
        let r2 = r * r;
        r2 / (1.0 + r2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;
    use std::f32::consts::PI;

    #[test]
    fn directions_are_unit_and_on_the_right_side() {
        let mut rng = Pcg32::new(1, 2);
        for _ in 0..100_000 {
            let u = rng.next_vec2();
            for (name, w) in [
                ("cosine", cosine_hemisphere(u)),
                ("uniform", uniform_hemisphere(u)),
            ] {
                assert!((w.length() - 1.0).abs() < 1e-5, "{name} {u} {w}");
                assert!(w.z >= 0.0, "{name} {u} {w}");
            }
            let s = uniform_sphere(u);
            assert!((s.length() - 1.0).abs() < 1e-5);
            let d = concentric_disk(u);
            assert!(d.length() <= 1.0 + 1e-6);
            let (b1, b2) = uniform_triangle(u);
            assert!(
                b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 + 1e-6,
                "{u} {b1} {b2}"
            );
        }
        for u in [Vec2::ZERO, Vec2::splat(0.5), Vec2::new(0.0, 0.999_999_9)] {
            assert!(cosine_hemisphere(u).is_finite());
            assert!(cosine_hemisphere(u).z >= 0.0);
        }
        assert_eq!(cosine_hemisphere(Vec2::splat(0.5)), Vec3::Z);
    }

    /// Moments of the cosine-weighted hemisphere: E[z] = 2/3, E[z^2] = 1/2, E[x] = E[y] = 0.
    #[test]
    fn cosine_hemisphere_has_the_right_moments() {
        let mut rng = Pcg32::new(9, 9);
        let n = 200_000;
        let (mut z1, mut z2, mut x1, mut y1) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for _ in 0..n {
            let w = cosine_hemisphere(rng.next_vec2());
            z1 += w.z as f64;
            z2 += (w.z * w.z) as f64;
            x1 += w.x as f64;
            y1 += w.y as f64;
        }
        let n = n as f64;
        // Standard errors ~ 0.24/sqrt(n) = 5e-4 for z; 0.5/sqrt(n) = 1.1e-3 for x and y.
        assert!((z1 / n - 2.0 / 3.0).abs() < 3e-3, "{}", z1 / n);
        assert!((z2 / n - 0.5).abs() < 3e-3, "{}", z2 / n);
        assert!((x1 / n).abs() < 6e-3 && (y1 / n).abs() < 6e-3);
    }

    /// Uniform hemisphere: E[z] = 1/2; uniform sphere: E[z] = 0, E[z^2] = 1/3.
    #[test]
    fn uniform_maps_have_the_right_moments() {
        let mut rng = Pcg32::new(11, 3);
        let n = 200_000;
        let (mut h, mut s1, mut s2) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..n {
            h += uniform_hemisphere(rng.next_vec2()).z as f64;
            let s = uniform_sphere(rng.next_vec2());
            s1 += s.z as f64;
            s2 += (s.z * s.z) as f64;
        }
        let n = n as f64;
        assert!((h / n - 0.5).abs() < 4e-3);
        assert!((s1 / n).abs() < 8e-3);
        assert!((s2 / n - 1.0 / 3.0).abs() < 4e-3);
    }

    /// The triangle map is uniform: the k^2 equal-area sub-triangles of a regular subdivision
    /// (k = 4) get equal counts, none fall outside, and the mean barycentrics are 1/3.
    #[test]
    fn triangle_map_is_uniform() {
        let mut rng = Pcg32::new(21, 0);
        let n = 160_000;
        let k = 4usize;
        // Cell (i, j) of the k x k grid over (b1, b2) holds a lower sub-triangle (fractional
        // parts summing to at most 1) and an upper one; slot = 2 (i k + j) + upper.
        let mut counts = vec![0u32; 2 * k * k];
        let (mut m1, mut m2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let (b1, b2) = uniform_triangle(rng.next_vec2());
            m1 += b1 as f64;
            m2 += b2 as f64;
            // k is a power of two, so these products are exact.
            let (x, y) = (b1 * k as f32, b2 * k as f32);
            let (i, j) = ((x as usize).min(k - 1), (y as usize).min(k - 1));
            let upper = (x - i as f32) + (y - j as f32) > 1.0;
            counts[2 * (i * k + j) + upper as usize] += 1;
        }
        let expected = n as f64 / (k * k) as f64;
        for i in 0..k {
            for j in 0..k {
                for upper in 0..2 {
                    let c = counts[2 * (i * k + j) + upper] as f64;
                    if i + j + upper < k {
                        // sd = sqrt(10000 * 15 / 16) ~ 97.
                        assert!((c - expected).abs() < 500.0, "({i}, {j}, {upper}): {c}");
                    } else {
                        assert_eq!(c, 0.0, "({i}, {j}, {upper}) is outside the triangle");
                    }
                }
            }
        }
        let n = n as f64;
        assert!((m1 / n - 1.0 / 3.0).abs() < 3e-3 && (m2 / n - 1.0 / 3.0).abs() < 3e-3);
    }

    #[test]
    fn power_heuristic_cases() {
        assert_eq!(power_heuristic(1.0, 1.0, 1.0, 1.0), 0.5);
        assert!((power_heuristic(1.0, 2.0, 1.0, 1.0) - 0.8).abs() < 1e-6);
        assert!((power_heuristic(1.0, 1.0, 1.0, 2.0) - 0.2).abs() < 1e-6);
        assert_eq!(power_heuristic(1.0, 0.0, 1.0, 0.0), 0.0);
        assert_eq!(power_heuristic(1.0, 0.0, 1.0, 3.0), 0.0);
        assert_eq!(power_heuristic(1.0, 3.0, 1.0, 0.0), 1.0);
        assert_eq!(power_heuristic(1.0, f32::INFINITY, 1.0, 3.0), 1.0);
        assert_eq!(power_heuristic(1.0, 3.0, 1.0, f32::INFINITY), 0.0);
        assert_eq!(power_heuristic(1.0, f32::INFINITY, 1.0, f32::INFINITY), 0.5);
        assert_eq!(power_heuristic(1.0, f32::NAN, 1.0, 1.0), 0.0);
        assert_eq!(power_heuristic(1.0, -1.0, 1.0, 1.0), 0.0);
        // Huge but finite pdfs do not overflow.
        let w = power_heuristic(1.0, 3e30, 1.0, 1e30);
        assert!((w - 0.9).abs() < 1e-6, "{w}");
        // Complementary weights sum to one.
        let mut rng = Pcg32::new(4, 4);
        for _ in 0..1000 {
            let (a, b) = (rng.next_f32() * 10.0, rng.next_f32() * 10.0);
            let s = power_heuristic(1.0, a, 1.0, b) + power_heuristic(1.0, b, 1.0, a);
            assert!((s - 1.0).abs() < 1e-5 || (a == 0.0 && b == 0.0));
        }
    }

    #[test]
    fn pdf_helpers() {
        assert!((cosine_hemisphere_pdf(1.0) - FRAC_1_PI).abs() < 1e-7);
        assert_eq!(cosine_hemisphere_pdf(-0.5), 0.0);
        assert!((UNIFORM_HEMISPHERE_PDF * 2.0 * PI - 1.0).abs() < 1e-6);
        assert!((UNIFORM_SPHERE_PDF * 4.0 * PI - 1.0).abs() < 1e-6);
    }
}
