//! BRDF tests: furnace, energy, reciprocity, sample/eval/pdf consistency, defined answers.

use super::*;
use crate::rng::Pcg32;
use crate::sampling::uniform_hemisphere;
use crate::test_util::GaussLegendre;

/// A unit direction with this cosine to the normal, in the xz plane.
pub(super) fn direction(mu: f32) -> Vec3 {
    Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu)
}

/// A white metal: F0 = 1, so F = 1 everywhere and the BRDF is single-scattering GGX alone.
fn white_metal(alpha: f32) -> SurfaceParams {
    SurfaceParams {
        base_color: Vec3::ONE,
        metallic: 1.0,
        roughness: alpha.sqrt(),
        ..SurfaceParams::default()
    }
}

/// Random material parameters, with the edge values (0, 1, the mirror threshold) drawn often.
pub(super) fn random_params(rng: &mut Pcg32) -> SurfaceParams {
    let mut pick = |edges: &[f32]| {
        let u = rng.next_f32();
        if u < 0.3 {
            edges[(rng.next_u32() as usize) % edges.len()]
        } else {
            rng.next_f32()
        }
    };
    let roughness = pick(&[
        0.0,
        1.0,
        MIRROR_ALPHA.sqrt(),
        MIRROR_ALPHA.sqrt() * 1.001,
        0.05,
    ]);
    let metallic = pick(&[0.0, 1.0]);
    let f0_dielectric = pick(&[0.0, 0.04, 1.0]);
    let absorption = pick(&[0.0, 1.0]);
    let specular = pick(&[0.0, 1.0]);
    let base_color = Vec3::new(pick(&[0.0, 1.0]), pick(&[0.0, 1.0]), pick(&[0.0, 1.0]));
    let specular_color = Vec3::new(pick(&[0.0, 1.0]), pick(&[1.0]), pick(&[0.0, 30.0]));
    // Half the materials have no coat at all.
    let clearcoat = pick(&[0.0, 1.0]) * f32::from(u8::from(pick(&[0.0, 1.0]) >= 0.5));
    let clearcoat_roughness = pick(&[0.0, 1.0, MIRROR_ALPHA.sqrt() * 1.001, 0.05]);
    // Half the materials transmit nothing; half have no sheen.
    let transmission = pick(&[0.0, 1.0]) * f32::from(u8::from(pick(&[0.0, 1.0]) >= 0.5));
    let sheen = f32::from(u8::from(pick(&[0.0, 1.0]) >= 0.5));
    let sheen_color = Vec3::new(pick(&[0.0, 1.0]), pick(&[1.0]), pick(&[0.0, 1.0])) * sheen;
    let sheen_roughness = pick(&[0.0, 1.0, 0.3]);
    // Half the materials are thin-walled; the others refract, entering a volume or leaving it.
    let eta = match rng.next_u32() % 6 {
        0..=2 => 0.0,
        3 => [1.5, 1.0 / 1.5, 1.0][(rng.next_u32() % 3) as usize],
        _ => 0.25 + 3.0 * rng.next_f32(),
    };
    // A quarter of the materials give the coat a normal of its own, tilted up to 52 degrees.
    let coat_normal = if rng.next_u32().is_multiple_of(4) {
        let tilt = (rng.next_vec2() * 2.0 - glam::Vec2::ONE) * 0.9;
        Vec3::new(tilt.x, tilt.y, 1.0).normalize()
    } else {
        Vec3::Z
    };
    SurfaceParams {
        base_color,
        metallic,
        roughness,
        f0_dielectric,
        specular,
        specular_color,
        clearcoat,
        clearcoat_roughness,
        transmission,
        sheen_color,
        sheen_roughness,
        absorption,
        eta,
        coat_normal,
    }
}

/// The directional albedo E(mu) = integral of f cos over the hemisphere, estimated with `sample`
/// on a jittered k x k grid of `u` (and a stratified `u_lobe`), including delta lobes.
pub(super) fn sampled_albedo(p: &SurfaceParams, wo: Vec3, k: u32, rng: &mut Pcg32) -> Vec3 {
    let mut sum = glam::DVec3::ZERO;
    for i in 0..k {
        for j in 0..k {
            let u = Vec2::new(
                (i as f32 + rng.next_f32()) / k as f32,
                (j as f32 + rng.next_f32()) / k as f32,
            );
            let u_lobe = ((i * k + j) as f32 + 0.5) / (k * k) as f32;
            // Decorrelate the lobe choice from the grid position.
            let u_lobe = (u_lobe + rng.next_f32()).fract();
            if let Some(s) = sample(p, wo, u_lobe, u) {
                sum += s.weight.as_dvec3();
            }
        }
    }
    (sum / (k * k) as f64).as_vec3()
}

/// Which integral [`half_vector_quadrature`] computes.
#[derive(Clone, Copy)]
pub(super) enum Quadrature {
    /// Single-scattering GGX albedo with F = 1: the weight is G2(wo, wi).
    Albedo,
    /// Mass of the visible-normal distribution whose reflection stays above the horizon: the
    /// weight is G1(wo). One minus it is the probability that VNDF sampling is rejected.
    VisibleAboveHorizon,
}

/// Integrals over half vectors by quadrature, independently of `sample`, in double precision.
///
/// The albedo with F = 1 is E(mu) = integral of D(h) G2(wo, wi) (wo.h) / mu dw_h, wi =
/// reflect(wo, h) (the change of variables dw_i = 4 (wo.h) dw_h); the visible mass is the same
/// with G1(wo) in place of G2 (the VNDF is G1(wo) (wo.h) D(h) / mu). With tan(theta_h) =
/// alpha tan(pi s / 2) the GGX measure D cos(theta_h) dw_h becomes sin(pi s) / 4 ds dphi. For
/// each phi the reflection stays above the horizon exactly for theta_h below
/// theta* = (atan2(sin_o cos(phi), cos_o) + pi/2) / 2, since
/// wi.z = sin_o cos(phi) sin(2 theta_h) + cos_o cos(2 theta_h). So s is integrated over [0, s*]
/// only, where the integrand is smooth and Gauss-Legendre converges fast.
pub(super) fn half_vector_quadrature(
    what: Quadrature,
    alpha: f32,
    mu: f32,
    rule_s: &GaussLegendre,
    rule_phi: &GaussLegendre,
) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI as PI64};
    let wo = direction(mu).as_dvec3();
    let a = alpha as f64;
    let lambda = |w: glam::DVec3| {
        let sin2 = (w.x * w.x + w.y * w.y).max(0.0);
        0.5 * ((1.0 + a * a * sin2 / (w.z * w.z)).sqrt() - 1.0)
    };
    let integrand = |s: f64, phi: f64| -> f64 {
        let q = (0.5 * PI64 * s).tan();
        let theta = (a * q).atan();
        let h = glam::DVec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        let wo_h = wo.dot(h);
        let wi = 2.0 * wo_h * h - wo;
        if wo_h <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let g = match what {
            Quadrature::Albedo => 1.0 / (1.0 + lambda(wo) + lambda(wi)),
            Quadrature::VisibleAboveHorizon => 1.0 / (1.0 + lambda(wo)),
        };
        0.25 * (PI64 * s).sin() * g * wo_h / (wo.z * h.z)
    };
    let s_max = |phi: f64| {
        let theta_max = 0.5 * ((wo.x * phi.cos()).atan2(wo.z) + FRAC_PI_2);
        (theta_max.tan() / a).atan() / FRAC_PI_2
    };
    // Symmetric in phi: integrate over [0, pi] and double. At grazing views s* changes quickly
    // around phi = pi/2 (where the reflection's horizon crossing swings across), so phi is
    // stretched there: phi = pi/2 + pi/2 sinh(k t) / sinh(k), t in [-1, 1].
    let k = 5.0f64;
    let inner = |phi: f64| rule_s.integrate(0.0, s_max(phi), |s| integrand(s, phi));
    2.0 * rule_phi.integrate(-1.0, 1.0, |t| {
        let phi = FRAC_PI_2 + FRAC_PI_2 * (k * t).sinh() / k.sinh();
        let dphi_dt = FRAC_PI_2 * k * (k * t).cosh() / k.sinh();
        inner(phi) * dphi_dt
    })
}

fn quadrature_albedo(alpha: f32, mu: f32, rule_s: &GaussLegendre, rule_phi: &GaussLegendre) -> f64 {
    half_vector_quadrature(Quadrature::Albedo, alpha, mu, rule_s, rule_phi)
}

/// At alpha = 1, D = 1/pi and, for wo = n, G2 = 2 mu_i / (1 + mu_i), so
/// E(1) = integral_0^1 mu / (1 + mu) dmu = 1 - ln 2 exactly.
#[test]
fn quadrature_reproduces_the_closed_form_at_alpha_one() {
    let (s, phi) = (GaussLegendre::new(64), GaussLegendre::new(16));
    let e = quadrature_albedo(1.0, 1.0, &s, &phi);
    let exact = 1.0 - std::f64::consts::LN_2;
    assert!((e - exact).abs() < 1e-9, "{e} vs {exact}");
}

/// White furnace for the specular lobe: with F = 1, the albedo estimated with `sample` equals
/// single-scattering GGX's albedo by quadrature within 0.5%, for alpha 0.1 to 1 and views from
/// the normal to grazing. The quadrature is checked for convergence (two resolutions agree to
/// 1e-6) before it is used.
#[test]
fn furnace_specular_albedo_matches_quadrature() {
    let coarse = (GaussLegendre::new(96), GaussLegendre::new(48));
    let fine = (GaussLegendre::new(192), GaussLegendre::new(96));
    let mut rng = Pcg32::new(2024, 1);
    let mut table = String::new();
    for alpha in [0.1f32, 0.25, 0.5, 0.75, 1.0] {
        for mu in [1.0f32, 0.7, 0.4, 0.2, 0.05] {
            let q = quadrature_albedo(alpha, mu, &fine.0, &fine.1);
            let q_coarse = quadrature_albedo(alpha, mu, &coarse.0, &coarse.1);
            assert!(
                (q - q_coarse).abs() < 1e-6,
                "alpha {alpha} mu {mu}: {q} vs {q_coarse}"
            );
            let e = sampled_albedo(&white_metal(alpha), direction(mu), 96, &mut rng);
            // F = 1 on every channel.
            assert!((e.x - e.y).abs() < 1e-6 && (e.x - e.z).abs() < 1e-6);
            let rel = (e.x as f64 - q).abs() / q;
            table.push_str(&format!(
                "alpha {alpha:4} mu {mu:4}: quadrature {q:.5}, sampled {:.5}\n",
                e.x
            ));
            assert!(
                rel < 0.005,
                "alpha {alpha} mu {mu}: sampled {} vs quadrature {q}\n{table}",
                e.x
            );
        }
    }
    println!("{table}");
}

/// A white Lambertian surface (metallic 0, specular 0, no absorption) reflects everything: every
/// sample's weight is exactly 1, whatever the view; eval is exactly 1/pi.
#[test]
fn white_lambert_returns_exactly_one() {
    let p = SurfaceParams {
        base_color: Vec3::ONE,
        metallic: 0.0,
        roughness: 0.5,
        specular: 0.0,
        ..SurfaceParams::default()
    };
    let mut rng = Pcg32::new(77, 7);
    for roughness in [0.0, 0.5, 1.0] {
        let p = SurfaceParams { roughness, ..p };
        for _ in 0..20_000 {
            let wo = uniform_hemisphere(rng.next_vec2());
            if wo.z <= 0.0 {
                continue;
            }
            if let Some(s) = sample(&p, wo, rng.next_f32(), rng.next_vec2()) {
                assert_eq!(s.weight, Vec3::ONE, "{wo} {s:?}");
                assert!(!s.delta);
                assert_eq!(eval(&p, wo, s.wi), Vec3::splat(FRAC_1_PI));
            }
        }
        assert_eq!(specular_probability(&p, Vec3::Z), 0.0);
    }
    // Albedo 0.5: weight exactly 0.5.
    let half = SurfaceParams {
        base_color: Vec3::splat(0.5),
        ..p
    };
    let s = sample(&half, direction(0.3), 0.5, Vec2::new(0.3, 0.7)).unwrap();
    assert_eq!(s.weight, Vec3::splat(0.5));
}

/// Energy: with the diffuse lobe switched off (metals, and dielectrics with a black base), no
/// material reflects more than it receives, for random parameters and views from the normal to
/// grazing. Each specular sample's weight is F G2 / G1 <= 1, checked per sample as well.
#[test]
fn specular_lobe_never_reflects_more_than_it_receives() {
    let mut rng = Pcg32::new(31, 41);
    for case in 0..24 {
        let mut p = random_params(&mut rng);
        p.clearcoat = 0.0;
        // A smooth sheen's lobe reflects more than 1 at grazing views (crate::sheen).
        p.sheen_color = Vec3::ZERO;
        if case % 2 == 0 {
            p.metallic = 1.0;
        } else {
            p.metallic = 0.0;
            p.base_color = Vec3::ZERO;
        }
        for mu in [1.0f32, 0.6, 0.3, 0.1, 0.02] {
            let wo = direction(mu);
            for _ in 0..200 {
                if let Some(s) = sample(&p, wo, rng.next_f32(), rng.next_vec2()) {
                    assert!(s.weight.max_element() <= 1.0 + 1e-4, "{p:?} {mu} {s:?}");
                }
            }
            let e = sampled_albedo(&p, wo, 24, &mut rng);
            assert!(e.max_element() <= 1.0 + 1e-3, "{p:?} mu {mu}: albedo {e}");
        }
    }
}

/// Energy of the metal and of the Lambertian base: with metallic 1, or with specular 0, no
/// material reflects more than it receives (+1% for the estimate's noise), from the normal to
/// grazing. (The dielectric's fresnel_mix can: see [`spec_albedo_at_grazing_views`].)
#[test]
fn metals_and_lambertian_bases_never_reflect_more_than_they_receive() {
    let mut rng = Pcg32::new(5, 55);
    for case in 0..40 {
        let mut p = random_params(&mut rng);
        // A smooth sheen's lobe reflects more than 1 at grazing views (crate::sheen).
        p.sheen_color = Vec3::ZERO;
        if case % 2 == 0 {
            p.metallic = 1.0;
        } else {
            p.specular = 0.0;
        }
        for mu in [1.0f32, 0.7, 0.3, 0.1, 0.02] {
            let e = sampled_albedo(&p, direction(mu), 32, &mut rng);
            assert!(e.max_element() <= 1.01, "{p:?} mu {mu}: albedo {e}");
        }
    }
}

/// Helmholtz reciprocity: f(wo, wi) = f(wi, wo) (up to rounding), for random materials without
/// a clear coat.
#[test]
fn eval_is_reciprocal() {
    let mut rng = Pcg32::new(13, 13);
    for _ in 0..100_000 {
        // The coat's blend, clearcoat F_c(n.wo), depends on the view alone (the extension's
        // fresnel_coat): coated materials are not reciprocal, by definition.
        let p = SurfaceParams {
            clearcoat: 0.0,
            ..random_params(&mut rng)
        };
        let wo = uniform_hemisphere(rng.next_vec2());
        let wi = uniform_hemisphere(rng.next_vec2());
        let a = eval(&p, wo, wi);
        let b = eval(&p, wi, wo);
        let tol = 1e-4 * a.max_element().max(1.0);
        assert!(
            (a - b).abs().max_element() <= tol,
            "{p:?} {wo} {wi}: {a} vs {b}"
        );
    }
}

/// For every non-delta sample: pdf(wo, wi) is exactly the sample's pdf, and the weight equals
/// eval cos / pdf (relative 1e-4). Delta samples: mirror direction, weight F (1 - absorption) /
/// selection probability, pdf = selection probability.
#[test]
fn sample_agrees_with_eval_and_pdf() {
    let mut rng = Pcg32::new(99, 1);
    let (mut non_delta, mut delta) = (0, 0);
    for _ in 0..100_000 {
        let p = random_params(&mut rng);
        let wo = uniform_hemisphere(rng.next_vec2());
        let Some(s) = sample(&p, wo, rng.next_f32(), rng.next_vec2()) else {
            continue;
        };
        assert!(s.wi.z != 0.0 && (s.wi.length() - 1.0).abs() < 1e-4, "{s:?}");
        if s.delta && s.wi.z < 0.0 {
            // A smooth thin-walled surface transmits straight through; a smooth volume's
            // surface refracts by Snell's law, with radiance scaled by 1 / eta^2.
            delta += 1;
            let m = Material::new(&p);
            let eta = m.eta;
            if eta > 0.0 {
                let sin_o = (1.0 - wo.z * wo.z).max(0.0).sqrt();
                let sin_i = (1.0 - s.wi.z * s.wi.z).max(0.0).sqrt();
                assert!(
                    (sin_o - eta * sin_i).abs() < 1e-4,
                    "Snell: {p:?} {wo} {s:?}"
                );
                assert!(s.wi.x * wo.x <= 0.0 && s.wi.y * wo.y <= 0.0);
            } else {
                assert!(s.wi == -wo, "{p:?} {wo} {s:?}");
            }
            assert!(m.transmission_delta, "{p:?}");
            let probabilities = m.lobe_probabilities(wo);
            assert_eq!(s.pdf, probabilities.transmission);
            let (wi_z, radiance) = if eta > 0.0 {
                (-s.wi.z, 1.0 / (eta * eta))
            } else {
                (wo.z, 1.0)
            };
            let expected = m.fresnel(wo.z).transmission
                * (m.base_weight(wo) * m.sheen_scaling(wo.z, wi_z) * m.scale * radiance / s.pdf);
            assert!(
                (s.weight - expected).abs().max_element() < 1e-5 * expected.max_element().max(1.0)
            );
            continue;
        }
        if s.delta {
            delta += 1;
            let m = Material::new(&p);
            assert!(m.mirror || m.coat_mirror);
            // Where the coat takes the shading normal every delta lobe points the same way and
            // the sample carries all of them; a coat with a normal of its own reflects about
            // it, alone.
            let shading_mirror = Vec3::new(-wo.x, -wo.y, wo.z);
            let coat_reflection = match m.coat_frame {
                Some(frame) => {
                    let n = frame.normal;
                    m.coat_mirror && (s.wi - (2.0 * wo.dot(n) * n - wo)).length() < 1e-5
                }
                None => false,
            };
            assert!(coat_reflection || (s.wi - shading_mirror).length() < 1e-6);
            let probabilities = m.lobe_probabilities(wo);
            let (mut expected, mut sp) = (Vec3::ZERO, 0.0);
            if m.mirror && !coat_reflection {
                expected +=
                    m.fresnel(wo.z).specular * (m.base_weight(wo) * m.sheen_scaling(wo.z, wo.z));
                sp += probabilities.specular;
            }
            if m.coat_mirror && (coat_reflection || m.coat_frame.is_none()) {
                expected += Vec3::splat(m.coat_weight(wo));
                sp += probabilities.coat;
            }
            assert_eq!(s.pdf, sp);
            let expected = expected * m.scale / sp;
            assert!(
                (s.weight - expected).abs().max_element() < 1e-5 * expected.max_element().max(1.0)
            );
            continue;
        }
        non_delta += 1;
        assert_eq!(pdf(&p, wo, s.wi), s.pdf, "{p:?} {wo} {s:?}");
        let expected = eval(&p, wo, s.wi) * s.wi.z.abs() / s.pdf;
        let tol = 1e-4 * expected.max_element().max(1e-3);
        assert!(
            (s.weight - expected).abs().max_element() <= tol,
            "{p:?} {wo} {s:?}: expected {expected}"
        );
    }
    assert!(non_delta > 50_000 && delta > 1_000, "{non_delta} {delta}");
}

/// The mirror: eval and pdf leave the delta lobe out; the delta sample carries F; an ideal white
/// metal mirror returns weight exactly F = 1.
#[test]
fn mirror_is_a_delta_lobe() {
    let metal = SurfaceParams {
        base_color: Vec3::ONE,
        metallic: 1.0,
        roughness: 0.0,
        ..SurfaceParams::default()
    };
    let wo = direction(0.6);
    let s = sample(&metal, wo, 0.3, Vec2::new(0.2, 0.9)).unwrap();
    assert!(s.delta);
    assert_eq!(s.weight, Vec3::ONE);
    assert_eq!(s.pdf, 1.0);
    assert_eq!(s.wi, Vec3::new(-wo.x, -wo.y, wo.z));
    assert_eq!(eval(&metal, wo, s.wi), Vec3::ZERO);
    assert_eq!(pdf(&metal, wo, s.wi), 0.0);
    // Just above the threshold the lobe is a (very sharp) GGX lobe again.
    let glossy = SurfaceParams {
        roughness: (MIRROR_ALPHA * 1.01).sqrt(),
        ..metal
    };
    let s = sample(&glossy, wo, 0.3, Vec2::new(0.2, 0.9)).unwrap();
    assert!(!s.delta);
    assert!(eval(&glossy, wo, Vec3::new(-wo.x, -wo.y, wo.z)).x > 1e4);
    // A mirror dielectric with a diffuse base picks between the two lobes.
    let plastic = SurfaceParams {
        metallic: 0.0,
        base_color: Vec3::splat(0.5),
        ..metal
    };
    let sp = specular_probability(&plastic, wo);
    assert!((MIN_LOBE_PROBABILITY..=1.0 - MIN_LOBE_PROBABILITY).contains(&sp));
    let s = sample(&plastic, wo, sp * 0.5, Vec2::new(0.2, 0.9)).unwrap();
    assert!(s.delta && s.pdf == sp);
    let s = sample(&plastic, wo, sp + (1.0 - sp) * 0.5, Vec2::new(0.2, 0.9)).unwrap();
    assert!(!s.delta && (s.pdf - (1.0 - sp) * s.wi.z * FRAC_1_PI).abs() < 1e-6);
}

/// Defined answers below the horizon and for materials that reflect nothing.
#[test]
fn below_the_horizon_is_zero() {
    let p = SurfaceParams::default();
    let up = direction(0.5);
    for down in [
        Vec3::new(0.0, 0.6, -0.8),
        Vec3::X,
        Vec3::new(1.0, 0.0, -0.0),
        -Vec3::Z,
    ] {
        assert_eq!(eval(&p, up, down), Vec3::ZERO);
        assert_eq!(eval(&p, down, up), Vec3::ZERO);
        assert_eq!(pdf(&p, up, down), 0.0);
        assert_eq!(pdf(&p, down, up), 0.0);
        assert!(sample(&p, down, 0.5, Vec2::splat(0.5)).is_none());
    }
    // A black Lambertian surface reflects nothing. (A black metal still reflects at grazing
    // angles: Schlick's F90 is 1.)
    let black = SurfaceParams {
        base_color: Vec3::ZERO,
        metallic: 0.0,
        specular: 0.0,
        ..p
    };
    assert!(sample(&black, up, 0.5, Vec2::splat(0.5)).is_none());
    assert_eq!(pdf(&black, up, up), 0.0);
    assert_eq!(eval(&black, up, up), Vec3::ZERO);
    let absorbing = SurfaceParams {
        absorption: 1.0,
        ..p
    };
    assert_eq!(eval(&absorbing, up, up), Vec3::ZERO);
    assert_eq!(
        sample(&absorbing, up, 0.5, Vec2::splat(0.5))
            .unwrap()
            .weight,
        Vec3::ZERO
    );
    assert!((f0_from_ior(1.5) - 0.04).abs() < 1e-7);
    assert_eq!(f0_from_ior(1.0), 0.0);
}

/// Clamps: out-of-range parameters behave like their clamped values.
#[test]
fn parameters_are_clamped() {
    let wo = direction(0.8);
    let wi = Vec3::new(-0.3, 0.2, 0.9).normalize();
    let wild = SurfaceParams {
        base_color: Vec3::new(2.0, -1.0, 0.5),
        metallic: 1.5,
        roughness: -0.3,
        f0_dielectric: 3.0,
        specular: 4.0,
        specular_color: Vec3::new(-1.0, 2.0, 0.5),
        clearcoat: 3.0,
        clearcoat_roughness: -1.0,
        transmission: 2.0,
        sheen_color: Vec3::new(2.0, -1.0, 0.5),
        sheen_roughness: 3.0,
        absorption: -2.0,
        eta: f32::NAN,
        coat_normal: Vec3::ZERO,
    };
    let tame = SurfaceParams {
        base_color: Vec3::new(1.0, 0.0, 0.5),
        metallic: 1.0,
        roughness: 0.0,
        f0_dielectric: 1.0,
        specular: 1.0,
        specular_color: Vec3::new(0.0, 1.0, 0.5),
        clearcoat: 1.0,
        clearcoat_roughness: 0.0,
        transmission: 1.0,
        sheen_color: Vec3::new(1.0, 0.0, 0.5),
        sheen_roughness: 1.0,
        absorption: 0.0,
        eta: 0.0,
        coat_normal: Vec3::Z,
    };
    assert_eq!(eval(&wild, wo, wi), eval(&tame, wo, wi));
    assert_eq!(pdf(&wild, wo, wi), pdf(&tame, wo, wi));
    let rough = SurfaceParams {
        roughness: 7.0,
        ..wild
    };
    let one = SurfaceParams {
        roughness: 1.0,
        ..tame
    };
    assert_eq!(eval(&rough, wo, wi), eval(&one, wo, wi));
}
