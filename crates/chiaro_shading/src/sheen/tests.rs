//! The sheen lobe against the spec's formulas written out independently in f64, its albedo fit
//! against quadrature, sampling against its pdf (chi-square), the layer's energy, and hard
//! inputs.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::{DVec3, Vec2, Vec3};

use super::*;
use crate::rng::Pcg32;
use crate::test_util::{GaussLegendre, chi_square_test};

/// KHR_materials_sheen's implementation notes, transcribed in f64: the Charlie distribution
/// with alphaG = sheenRoughness^2 (floored as chiaro floors it), its visibility with the fitted
/// Lambda, f = D V.
fn spec_sheen(roughness: f64, wo: DVec3, wi: DVec3) -> f64 {
    let alpha_g = (roughness * roughness).max(ALPHA_FLOOR as f64);
    let n_dot_v = wo.z;
    let n_dot_l = wi.z;
    let h = (wo + wi).normalize();
    let inv_r = 1.0 / alpha_g;
    let cos2h = h.z * h.z;
    let sin2h = 1.0 - cos2h;
    let distribution = (2.0 + inv_r) * sin2h.max(0.0).powf(inv_r * 0.5) / (2.0 * PI);
    let l = |x: f64| {
        let mix = |a: f64, b: f64, t: f64| a * (1.0 - t) + b * t;
        let one_minus_alpha_sq = (1.0 - alpha_g) * (1.0 - alpha_g);
        let a = mix(21.5473, 25.3245, one_minus_alpha_sq);
        let b = mix(3.82987, 3.32435, one_minus_alpha_sq);
        let c = mix(0.19823, 0.16801, one_minus_alpha_sq);
        let d = mix(-1.97760, -1.27393, one_minus_alpha_sq);
        let e = mix(-4.32054, -4.85967, one_minus_alpha_sq);
        a / (1.0 + b * x.powf(c)) + d * x + e
    };
    let lambda_sheen = |cos_theta: f64| {
        if cos_theta.abs() < 0.5 {
            l(cos_theta).exp()
        } else {
            (2.0 * l(0.5) - l(1.0 - cos_theta)).exp()
        }
    };
    let visibility =
        1.0 / ((1.0 + lambda_sheen(n_dot_v) + lambda_sheen(n_dot_l)) * (4.0 * n_dot_v * n_dot_l));
    distribution * visibility
}

fn at_cosine(mu: f64, phi: f64) -> DVec3 {
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    DVec3::new(s * phi.cos(), s * phi.sin(), mu)
}

/// E(mu) of the spec's lobe by Gauss-Legendre quadrature in f64: theta_i over [0, pi/2] and phi
/// over [0, pi] (the lobe is even in phi), each in 16 segments of 12 points (the sharpest lobe,
/// alpha 1e-3, is about 0.05 rad wide).
fn albedo_by_quadrature(roughness: f64, mu: f64) -> f64 {
    let rule = GaussLegendre::new(12);
    let wo = at_cosine(mu, 0.0);
    let segments = 16;
    let mut total = 0.0;
    for i in 0..segments {
        let (t0, t1) = (
            FRAC_PI_2 * i as f64 / segments as f64,
            FRAC_PI_2 * (i + 1) as f64 / segments as f64,
        );
        total += rule.integrate(t0, t1, |theta| {
            let mut ring = 0.0;
            for j in 0..segments {
                let (p0, p1) = (
                    PI * j as f64 / segments as f64,
                    PI * (j + 1) as f64 / segments as f64,
                );
                ring += rule.integrate(p0, p1, |phi| {
                    let wi = at_cosine(theta.cos(), phi);
                    spec_sheen(roughness, wo, wi) * wi.z
                });
            }
            2.0 * ring * theta.sin()
        });
    }
    total
}

/// Random unit directions: the sphere, the upper hemisphere, grazing ones, the normal.
fn random_direction(rng: &mut Pcg32) -> Vec3 {
    let phi = rng.next_f32() * std::f32::consts::TAU;
    let at = |mu: f32| {
        let s = (1.0 - mu * mu).max(0.0).sqrt();
        Vec3::new(s * phi.cos(), s * phi.sin(), mu)
    };
    match rng.next_u32() % 6 {
        0 | 1 => crate::sampling::uniform_sphere(rng.next_vec2()),
        2 => uniform_hemisphere(rng.next_vec2()),
        3 | 4 => {
            let grazing = [0.0, 1e-30, 1e-20, 1e-7, -1e-7, 1e-5, 1e-4, 1e-3, 1e-2];
            at(grazing[(rng.next_u32() % 9) as usize])
        }
        _ => Vec3::Z,
    }
}

fn random_roughness(rng: &mut Pcg32) -> f32 {
    let edges = [0.0, 1.0, ALPHA_FLOOR.sqrt(), 0.01, 0.1, -0.5, 2.0];
    if rng.next_f32() < 0.3 {
        edges[(rng.next_u32() % 7) as usize]
    } else {
        rng.next_f32()
    }
}

#[test]
fn eval_matches_the_spec_formula() {
    let mut rng = Pcg32::new(0x5ee4, 1);
    let mut compared = 0;
    for _ in 0..20_000 {
        let r = rng.next_f32();
        let wo = uniform_hemisphere(rng.next_vec2());
        let wi = uniform_hemisphere(rng.next_vec2());
        if wo.z < 1e-3 || wi.z < 1e-3 {
            continue;
        }
        let got = eval(r, wo, wi) as f64;
        let want = spec_sheen(r as f64, wo.as_dvec3(), wi.as_dvec3());
        // D's exponent 1 / (2 alpha) turns f32 rounding of sin^2 into up to 1e-4 (alpha 1e-3).
        let tolerance = 2e-4 * want + 1e-30;
        assert!(
            (got - want).abs() <= tolerance,
            "r {r} wo {wo} wi {wi}: {got} vs {want}"
        );
        compared += 1;
    }
    assert!(compared > 15_000);
    // Reciprocity, and the floor: r = 0 is r = sqrt(ALPHA_FLOOR).
    let (wo, wi) = (
        Vec3::new(0.8, 0.0, 0.6),
        Vec3::new(-0.6, 0.48, 0.64).normalize(),
    );
    assert_eq!(eval(0.4, wo, wi), eval(0.4, wi, wo));
    assert_eq!(eval(0.0, wo, wi), eval(ALPHA_FLOOR.sqrt(), wo, wi));
    assert_eq!(alpha_from_roughness(-1.0), ALPHA_FLOOR);
    assert_eq!(alpha_from_roughness(3.0), 1.0);
}

#[test]
fn albedo_fit_is_within_its_bound_of_quadrature() {
    let mus = [
        1e-4, 3e-4, 1e-3, 4e-3, 0.01, 0.03, 0.07, 0.15, 0.25, 0.4, 0.55, 0.7, 0.85, 1.0,
    ];
    let roughnesses = [0.0, 0.045, 0.08, 0.13, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0];
    let mut worst = (0.0f64, 0.0, 0.0);
    for &r in &roughnesses {
        for &mu in &mus {
            let want = albedo_by_quadrature(r, mu);
            let got = albedo(r as f32, mu as f32) as f64;
            let error = (got - want).abs();
            if error > worst.0 {
                worst = (error, mu, r);
            }
        }
    }
    eprintln!("largest |fit - quadrature| {worst:?}");
    assert!(
        worst.0 <= ALBEDO_FIT_MAX_ERROR as f64,
        "{worst:?} exceeds {ALBEDO_FIT_MAX_ERROR}"
    );
    // Below the smallest cosine the fit holds its value there.
    assert_eq!(albedo(0.5, 0.0), albedo(0.5, ALBEDO_MIN_COSINE));
    assert_eq!(albedo(0.5, 2.0), albedo(0.5, 1.0));
}

#[test]
fn sample_and_pdf_agree() {
    let mut rng = Pcg32::new(0x5ee4, 2);
    for _ in 0..10_000 {
        let r = random_roughness(&mut rng);
        let wo = random_direction(&mut rng);
        match sample(r, wo, rng.next_vec2()) {
            Some((wi, p)) => {
                assert!(wo.z > 0.0 && wi.z > 0.0, "{wo} {wi}");
                assert!((wi.length() - 1.0).abs() < 1e-5);
                assert_eq!(p, pdf(r, wo, wi));
                assert!(p > 0.0);
            }
            None => assert!(wo.z <= 0.0, "{wo}"),
        }
    }
    assert!(sample(0.5, Vec3::Z, Vec2::new(0.0, 0.3)).is_none());
    assert_eq!(pdf(0.5, Vec3::Z, Vec3::new(1.0, 0.0, 0.0)), 0.0);
}

/// Chi-square over (cos theta, phi) cells: the expected count of a cell is the pdf's integral
/// over it, (dz dphi) / (2 pi) for the uniform hemisphere, exact.
#[test]
fn sample_distribution_matches_pdf() {
    let (z_bins, phi_bins, n) = (16, 32, 200_000);
    let views = [
        Vec3::Z,
        Vec3::new(0.6, 0.0, 0.8),
        Vec3::new(0.0, -0.9999, 0.0141),
    ];
    let mut rng = Pcg32::new(0x5ee4, 3);
    for (k, &wo) in views.iter().enumerate() {
        let wo = wo.normalize();
        let mut observed = vec![0.0; z_bins * phi_bins];
        for _ in 0..n {
            let (wi, _) = sample(0.3, wo, rng.next_vec2()).expect("above the horizon");
            let z = ((wi.z as f64) * z_bins as f64).min(z_bins as f64 - 1.0) as usize;
            let phi = (wi.y as f64).atan2(wi.x as f64).rem_euclid(TAU);
            let p = ((phi / TAU) * phi_bins as f64).min(phi_bins as f64 - 1.0) as usize;
            observed[z * phi_bins + p] += 1.0;
        }
        let mut expected = vec![0.0; z_bins * phi_bins];
        for z in 0..z_bins {
            for p in 0..phi_bins {
                let dz = 1.0 / z_bins as f64;
                let dphi = TAU / phi_bins as f64;
                let integral: f64 = dz * dphi * pdf(0.3, wo, Vec3::Z) as f64;
                expected[z * phi_bins + p] = n as f64 * integral;
            }
        }
        let total: f64 = expected.iter().sum();
        assert!((total - n as f64).abs() < 1e-3 * n as f64, "{total}");
        if let Err(e) = chi_square_test(&observed, &expected, views.len()) {
            panic!("view {k}: {e}");
        }
    }
}

/// The estimator f cos / pdf of the sampled directions averages to the quadrature's albedo.
#[test]
fn sampled_albedo_matches_quadrature() {
    let mut rng = Pcg32::new(0x5ee4, 4);
    for (r, mu) in [(0.3f32, 0.2f32), (1.0, 0.7), (0.6, 0.05)] {
        let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        let n = 200_000;
        let mut sum = 0.0f64;
        let mut sum2 = 0.0f64;
        for _ in 0..n {
            if let Some((wi, p)) = sample(r, wo, rng.next_vec2()) {
                let w = (eval(r, wo, wi) * wi.z / p) as f64;
                sum += w;
                sum2 += w * w;
            }
        }
        let mean = sum / n as f64;
        let sigma = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        let want = albedo_by_quadrature(r as f64, mu as f64);
        assert!(
            (mean - want).abs() < 5.0 * sigma + 1e-4,
            "r {r} mu {mu}: {mean} +- {sigma} vs {want}"
        );
    }
}

/// The layer over a white Lambertian base: sheen_color f + albedo_scaling / pi, integrated
/// against n.wi by quadrature, reflects at most 1 (plus the fit's error) where the lobe's own
/// albedo is at most 1; where it is above 1, the scaling is 0 and the base adds nothing.
#[test]
fn albedo_scaling_keeps_the_layer_within_one() {
    let rule = GaussLegendre::new(24);
    for (r, mu) in [
        (0.3, 0.2),
        (0.5, 0.05),
        (0.5, 1.0),
        (1.0, 0.01),
        (1.0, 0.5),
        (0.7, 0.3),
    ] {
        for color in [Vec3::ONE, Vec3::new(1.0, 0.2, 0.0), Vec3::splat(0.5)] {
            let lobe = albedo_by_quadrature(r, mu);
            assert!(lobe <= 1.0, "r {r} mu {mu}: E {lobe}");
            // The base's part depends on wi only through its cosine.
            let base = rule.integrate(0.0, 1.0, |mu_i| {
                albedo_scaling(color, r as f32, mu as f32, mu_i as f32) as f64 * 2.0 * mu_i
            });
            let layer = color.max_element() as f64 * lobe + base;
            assert!(
                layer <= 1.0 + ALBEDO_FIT_MAX_ERROR as f64,
                "r {r} mu {mu} colour {color}: {layer}"
            );
        }
    }
    let grazing_smooth = albedo_by_quadrature(0.1, 0.01);
    assert!(grazing_smooth > 1.5, "{grazing_smooth}");
    assert_eq!(albedo_scaling(Vec3::ONE, 0.1, 0.01, 0.5), 0.0);
    assert_eq!(albedo_scaling(Vec3::ZERO, 0.1, 0.01, 0.5), 1.0);
    assert_eq!(albedo_scaling(Vec3::splat(-1.0), 0.5, 0.5, 0.5), 1.0);
}

#[test]
fn nothing_is_nan_or_infinite() {
    let mut rng = Pcg32::new(0x5ee4, 5);
    for _ in 0..200_000 {
        let r = random_roughness(&mut rng);
        let wo = random_direction(&mut rng);
        let wi = random_direction(&mut rng);
        let color = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32() * 2.0);
        let f = eval(r, wo, wi);
        assert!(f.is_finite() && f >= 0.0, "eval {f} for {r} {wo} {wi}");
        assert!(
            (f == 0.0) || (wo.z > 0.0 && wi.z > 0.0),
            "below the horizon {wo} {wi}"
        );
        for mu in [wo.z, wi.z] {
            let e = albedo(r, mu);
            assert!(e.is_finite() && e > 0.0, "albedo {e} for {r} {mu}");
        }
        let s = albedo_scaling(color, r, wo.z, wi.z);
        assert!((0.0..=1.0).contains(&s), "scaling {s}");
        let p = pdf(r, wo, wi);
        assert!(p.is_finite() && p >= 0.0);
        if let Some((w, p)) = sample(r, wo, rng.next_vec2()) {
            assert!(w.is_finite() && p.is_finite() && p > 0.0);
            assert!(eval(r, wo, w).is_finite());
        }
    }
}
