//! Light tests: falloffs, pdf normalisation and sample/pdf consistency for every kind.

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, FRAC_PI_6, PI};

use super::*;
use crate::rng::Pcg32;
use crate::sampling::uniform_sphere;

#[test]
fn point_light_falls_off_with_the_square_of_distance() {
    let p = Vec3::new(1.0, 2.0, 3.0);
    let light = p + Vec3::new(0.0, 0.0, 2.0);
    let s = sample_point(light, Vec3::new(8.0, 4.0, 0.0), None, p).unwrap();
    assert_eq!(s.wi, Vec3::Z);
    assert_eq!(s.distance, 2.0);
    assert_eq!(s.radiance, Vec3::new(2.0, 1.0, 0.0));
    assert!(s.delta && s.pdf == 1.0);
    assert!(sample_point(p, Vec3::ONE, None, p).is_none());
    // Next to the light: large but finite.
    let near = sample_point(Vec3::X * 1e-30, Vec3::ONE, None, Vec3::ZERO).unwrap();
    assert!(near.radiance.is_finite() && near.radiance.x == 1e12);
}

#[test]
fn range_window_follows_khr_lights_punctual() {
    assert_eq!(range_window(5.0, None), 1.0);
    assert_eq!(range_window(0.0, Some(2.0)), 1.0);
    assert!((range_window(1.0, Some(2.0)) - (1.0 - 1.0 / 16.0)).abs() < 1e-7);
    assert_eq!(range_window(2.0, Some(2.0)), 0.0);
    assert_eq!(range_window(3.0, Some(2.0)), 0.0);
    assert_eq!(range_window(1.0, Some(0.0)), 0.0);
    assert_eq!(range_window(1.0, Some(f32::NAN)), 0.0);
    assert_eq!(range_window(1.0, Some(f32::INFINITY)), 1.0);
    let mut last = 1.0;
    for i in 0..=100 {
        let w = range_window(i as f32 * 0.02, Some(2.0));
        assert!(w <= last && (0.0..=1.0).contains(&w));
        last = w;
    }
    // The window multiplies the inverse-square law; beyond the range there is no sample.
    let p = Vec3::ZERO;
    let s = sample_point(Vec3::X, Vec3::ONE, Some(2.0), p).unwrap();
    assert!((s.radiance.x - 15.0 / 16.0).abs() < 1e-6);
    assert!(sample_point(Vec3::X * 3.0, Vec3::ONE, Some(2.0), p).is_none());
}

/// Spot falloff: exactly 1 inside the inner cone, 0 outside the outer cone, monotone between.
#[test]
fn spot_falloff_is_one_inside_zero_outside_and_monotone() {
    for (inner, outer) in [
        (0.0, FRAC_PI_4),
        (FRAC_PI_6, FRAC_PI_4),
        (0.2, 0.25),
        (0.0, FRAC_PI_2),
    ] {
        let steps = 2000;
        let mut last = 0.0;
        for i in 0..=steps {
            // From outside the outer cone to the axis.
            let angle = (1.0 - i as f32 / steps as f32) * (outer + 0.3).min(PI);
            let f = spot_falloff(angle.cos(), inner, outer);
            assert!((0.0..=1.0).contains(&f));
            assert!(f >= last - 1e-6, "not monotone at {angle}: {f} < {last}");
            last = f;
            if angle > outer + 1e-4 {
                assert_eq!(f, 0.0, "inner {inner} outer {outer} angle {angle}");
            }
            if angle < inner - 1e-4 || angle == 0.0 {
                assert!(
                    (f - 1.0).abs() < 1e-5,
                    "inner {inner} outer {outer} angle {angle}: {f}"
                );
            }
        }
    }
    // Between the cones the recommended curve: saturate((cd - cos_o) / (cos_i - cos_o))^2.
    let (inner, outer) = (0.3f32, 0.6f32);
    let cd = 0.45f32.cos();
    let t = (cd - outer.cos()) / (inner.cos() - outer.cos());
    assert!((spot_falloff(cd, inner, outer) - t * t).abs() < 1e-5);
    // Equal cones: a steep but finite ramp, no division by zero.
    assert_eq!(spot_falloff(0.5f32.cos(), 0.5, 0.5), 0.0);
    assert_eq!(spot_falloff(1.0, 0.5, 0.5), 1.0);
}

#[test]
fn spot_light_is_a_point_light_times_its_falloff() {
    let position = Vec3::new(0.0, 4.0, 0.0);
    let axis = -Vec3::Y;
    let intensity = Vec3::new(10.0, 20.0, 30.0);
    let (inner, outer) = (0.2, 0.5);
    let mut rng = Pcg32::new(1, 9);
    let mut lit = 0;
    for _ in 0..1000 {
        let p = Vec3::new(rng.next_f32() * 6.0 - 3.0, 0.0, rng.next_f32() * 6.0 - 3.0);
        let point = sample_point(position, intensity, Some(8.0), p).unwrap();
        let cd = axis.dot(-point.wi);
        match sample_spot(position, axis, intensity, inner, outer, Some(8.0), p) {
            Some(s) => {
                lit += 1;
                assert_eq!(s.wi, point.wi);
                let expected = point.radiance * spot_falloff(cd, inner, outer);
                assert!((s.radiance - expected).abs().max_element() < 1e-5);
                assert!(s.delta && s.pdf == 1.0);
            }
            None => assert_eq!(spot_falloff(cd, inner, outer), 0.0),
        }
    }
    assert!(lit > 50);
    // Straight below: full intensity.
    let s = sample_spot(position, axis, intensity, inner, outer, None, Vec3::ZERO).unwrap();
    assert!((s.radiance - intensity / 16.0).abs().max_element() < 1e-5);
}

#[test]
fn directional_light_comes_from_against_its_travel() {
    let s = sample_directional(Vec3::new(0.0, -2.0, 0.0), Vec3::splat(3.0));
    assert_eq!(s.wi, Vec3::Y);
    assert_eq!(s.distance, f32::INFINITY);
    assert_eq!(s.radiance, Vec3::splat(3.0));
    assert!(s.delta && s.pdf == 1.0);
    let degenerate = sample_directional(Vec3::ZERO, Vec3::ONE);
    assert_eq!(degenerate.radiance, Vec3::ZERO);
    assert!(degenerate.wi.is_finite());
}

/// Van Oosterom and Strackee, 1983, "The Solid Angle of a Plane Triangle": the solid angle of the
/// triangle seen from p.
fn triangle_solid_angle(v: [Vec3; 3], p: Vec3) -> f64 {
    let [a, b, c] = v.map(|x| (x - p).as_dvec3());
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let numerator = a.dot(b.cross(c)).abs();
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * numerator.atan2(denominator)
}

/// Moller and Trumbore, 1997, ray-triangle intersection: the hit point, if any.
fn intersect(v: [Vec3; 3], origin: Vec3, dir: Vec3) -> Option<Vec3> {
    let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-12 {
        return None;
    }
    let t_vec = origin - v[0];
    let b1 = t_vec.dot(pv) / det;
    let qv = t_vec.cross(e1);
    let b2 = dir.dot(qv) / det;
    let t = e2.dot(qv) / det;
    (b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 && t > 0.0).then(|| origin + dir * t)
}

fn test_triangles() -> Vec<([Vec3; 3], Vec3)> {
    vec![
        // Facing p (normal toward -z, p below): close, far, slanted, skinny.
        (
            [
                Vec3::new(-1.0, -1.0, 2.0),
                Vec3::new(0.0, 1.0, 2.0),
                Vec3::new(1.0, -1.0, 2.0),
            ],
            Vec3::ZERO,
        ),
        (
            [
                Vec3::new(-1.0, -1.0, 0.5),
                Vec3::new(0.0, 1.0, 0.5),
                Vec3::new(1.0, -1.0, 0.5),
            ],
            Vec3::ZERO,
        ),
        (
            [
                Vec3::new(0.0, 0.0, 3.0),
                Vec3::new(0.5, 2.0, 1.0),
                Vec3::new(2.0, 0.0, 2.0),
            ],
            Vec3::new(0.2, 0.1, -0.3),
        ),
        (
            [
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(4.0, 0.1, 1.0),
                Vec3::new(0.0, 0.2, 1.2),
            ],
            Vec3::new(1.0, -1.0, 0.0),
        ),
    ]
}

/// sample_triangle is unbiased for the solid angle: E[1 / pdf] = the analytic solid angle, and
/// its pdf equals triangle_solid_angle_pdf at the sampled point.
#[test]
fn triangle_samples_integrate_to_the_solid_angle() {
    let mut rng = Pcg32::new(77, 3);
    for (v, p) in test_triangles() {
        let omega = triangle_solid_angle(v, p);
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let s = sample_triangle(v, Vec3::ONE, true, p, rng.next_vec2()).unwrap();
            assert!((s.wi.length() - 1.0).abs() < 1e-5 && !s.delta);
            let q = p + s.wi * s.distance;
            let again = triangle_solid_angle_pdf(v, p, q);
            assert!(
                (again - s.pdf).abs() <= 1e-3 * s.pdf,
                "{again} vs {}",
                s.pdf
            );
            sum += 1.0 / s.pdf as f64;
        }
        let estimate = sum / n as f64;
        assert!(
            (estimate - omega).abs() < 0.01 * omega,
            "{v:?} from {p}: {estimate} vs {omega}"
        );
    }
}

/// triangle_solid_angle_pdf integrates to one over the directions that hit the triangle: uniform
/// directions on the sphere, intersected with the triangle, weighted by 4 pi.
#[test]
fn triangle_pdf_integrates_to_one_over_the_sphere() {
    let mut rng = Pcg32::new(5, 31);
    for (v, p) in test_triangles() {
        let n = 200_000;
        let (mut sum, mut hits) = (0.0f64, 0usize);
        for _ in 0..n {
            let dir = uniform_sphere(rng.next_vec2());
            if let Some(q) = intersect(v, p, dir) {
                hits += 1;
                sum += triangle_solid_angle_pdf(v, p, q) as f64;
            }
        }
        let integral = sum / n as f64 * 4.0 * std::f64::consts::PI;
        // Standard error ~ 1/sqrt(hits) relative.
        let tol = 4.0 / (hits as f64).sqrt() + 0.003;
        assert!(
            (integral - 1.0).abs() < tol,
            "{v:?} from {p}: {integral} ({hits} hits)"
        );
        let omega_mc = hits as f64 / n as f64 * 4.0 * std::f64::consts::PI;
        let omega = triangle_solid_angle(v, p);
        assert!(
            (omega_mc - omega).abs() < tol * omega,
            "{omega_mc} vs {omega}"
        );
    }
}

#[test]
fn triangle_emits_on_its_front_unless_two_sided() {
    let v = [Vec3::ZERO, Vec3::X, Vec3::Y]; // normal +z
    let u = Vec2::new(0.3, 0.2);
    let above = Vec3::new(0.2, 0.2, 1.0);
    let below = Vec3::new(0.2, 0.2, -1.0);
    assert!(sample_triangle(v, Vec3::ONE, false, above, u).is_some());
    assert!(sample_triangle(v, Vec3::ONE, false, below, u).is_none());
    let s = sample_triangle(v, Vec3::splat(5.0), true, below, u).unwrap();
    assert_eq!(s.radiance, Vec3::splat(5.0));
    // Edge-on and degenerate.
    assert!(sample_triangle(v, Vec3::ONE, true, Vec3::new(-1.0, 0.5, 0.0), u).is_none());
    let flat = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
    assert!(sample_triangle(flat, Vec3::ONE, true, above, u).is_none());
    assert_eq!(triangle_solid_angle_pdf(flat, above, Vec3::X), 0.0);
    assert_eq!(triangle_solid_angle_pdf(v, above, above), 0.0);
    // Area pdf conversion by hand: straight above a unit right triangle's point at distance 1.
    let q = Vec3::new(0.2, 0.2, 0.0);
    let pdf = triangle_solid_angle_pdf(v, q + Vec3::Z, q);
    assert!((pdf - 1.0 / 0.5).abs() < 1e-6);
    assert_eq!(triangle_area_normal(v), Some((0.5, Vec3::Z)));
}

/// A small equirectangular test image with structure in both directions.
fn test_image(width: usize, height: usize) -> Vec<Vec3> {
    (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let bright = if x == 3 && y == 2 { 50.0 } else { 0.0 };
            Vec3::new(0.1 + x as f32 * 0.05, 0.2 + y as f32 * 0.1, 0.3) + Vec3::splat(bright)
        })
        .collect()
}

#[test]
fn environment_convention_top_row_is_up_and_u_half_is_plus_x() {
    let (w, h) = (8, 4);
    let mut texels = vec![Vec3::ZERO; w * h];
    texels[0] = Vec3::X; // top-left: up
    texels[(h - 1) * w] = Vec3::Y; // bottom-left: down
    texels[w + w / 2] = Vec3::Z; // u in [0.5, 0.625), second row: +X, a bit above the horizon
    texels[w + 3 * w / 4] = Vec3::ONE; // u in [0.75, 0.875): +Z side
    let env = EnvironmentLight::new(&texels, w, h, 2.0, 0.0);
    // Column 0 holds longitudes just past -X (atan2(z, x) just above -pi).
    assert_eq!(env.radiance(Vec3::new(-0.01, 1.0, -1e-4)), Vec3::X * 2.0);
    assert_eq!(env.radiance(Vec3::new(-0.01, -1.0, -1e-4)), Vec3::Y * 2.0);
    let plus_x_up = Vec3::new(1.0, 0.5, 0.05).normalize();
    assert_eq!(env.radiance(plus_x_up), Vec3::Z * 2.0);
    let plus_z_up = Vec3::new(-0.05, 0.5, 1.0).normalize();
    assert_eq!(env.radiance(plus_z_up), Vec3::ONE * 2.0);
    // Rotation by a quarter turn about +Y carries what was at +X to R_y(pi/2) (+X) = -Z.
    let turned = EnvironmentLight::new(&texels, w, h, 2.0, FRAC_PI_2);
    let q = glam::Quat::from_rotation_y(FRAC_PI_2);
    assert_eq!(turned.radiance(q * plus_x_up), Vec3::Z * 2.0);
    assert!((q * Vec3::X - (-Vec3::Z)).length() < 1e-6);
    // Everywhere else too, except within rounding of a texel edge.
    let mut rng = Pcg32::new(3, 3);
    let mismatched = (0..10_000)
        .filter(|_| {
            let d = uniform_sphere(rng.next_vec2());
            env.radiance(d) != turned.radiance(q * d)
        })
        .count();
    assert!(mismatched < 10, "{mismatched}");
}

/// The environment's pdf integrates to one over the sphere (quadrature on a grid fine enough to
/// resolve texels), and the sampled texels follow luminance x sin(theta).
#[test]
fn environment_pdf_integrates_to_one() {
    let (w, h) = (16, 8);
    for rotation in [0.0, 1.3] {
        let env = EnvironmentLight::new(&test_image(w, h), w, h, 1.5, rotation);
        let (nt, np) = (400, 800);
        let mut total = 0.0f64;
        for i in 0..nt {
            let theta = (i as f64 + 0.5) / nt as f64 * std::f64::consts::PI;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                let d = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    theta.cos() as f32,
                    (theta.sin() * phi.sin()) as f32,
                );
                total += env.pdf(d) as f64 * theta.sin();
            }
        }
        total *= (std::f64::consts::PI / nt as f64) * (std::f64::consts::TAU / np as f64);
        assert!((total - 1.0).abs() < 2e-3, "rotation {rotation}: {total}");
    }
}

/// Samples are consistent with pdf and radiance, and radiance / pdf is an unbiased estimate of the
/// environment's integral (the exact sum of texel radiance times texel solid angle).
#[test]
fn environment_sampling_is_consistent_and_unbiased() {
    let (w, h) = (16, 8);
    let texels = test_image(w, h);
    let strength = 1.5;
    let env = EnvironmentLight::new(&texels, w, h, strength, 0.7);
    let exact: glam::DVec3 = texels
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let row = (i / w) as f64;
            let solid = std::f64::consts::TAU / w as f64
                * ((row * std::f64::consts::PI / h as f64).cos()
                    - ((row + 1.0) * std::f64::consts::PI / h as f64).cos());
            t.as_dvec3() * strength as f64 * solid
        })
        .sum();
    let mut rng = Pcg32::new(10, 20);
    let n = 200_000;
    let mut sum = glam::DVec3::ZERO;
    let mut mismatched = 0;
    for _ in 0..n {
        let (d, radiance, pdf) = env.sample(rng.next_vec2());
        assert!((d.length() - 1.0).abs() < 1e-5);
        assert!(pdf > 0.0 && pdf.is_finite());
        let again = env.pdf(d);
        if env.radiance(d) != radiance || (again - pdf).abs() > 1e-3 * pdf {
            // Only possible for a direction on a texel edge, within rounding.
            mismatched += 1;
        }
        sum += radiance.as_dvec3() / pdf as f64;
    }
    assert!(mismatched < n / 10_000, "{mismatched}");
    let estimate = sum / n as f64;
    let rel = ((estimate - exact) / exact).abs().max_element();
    assert!(rel < 0.01, "{estimate} vs {exact}");
}

#[test]
fn constant_and_black_environments() {
    let c = EnvironmentLight::constant(Vec3::new(0.5, 1.0, 2.0));
    assert!(!c.is_black());
    let (d, radiance, pdf) = c.sample(Vec2::new(0.3, 0.8));
    assert!((d.length() - 1.0).abs() < 1e-6);
    assert_eq!(radiance, Vec3::new(0.5, 1.0, 2.0));
    assert_eq!(pdf, 1.0 / (4.0 * PI));
    assert_eq!(c.pdf(Vec3::X), pdf);
    assert_eq!(c.radiance(-Vec3::Y), radiance);
    assert!(EnvironmentLight::constant(Vec3::ZERO).is_black());
    assert_eq!(
        EnvironmentLight::constant(Vec3::new(f32::NAN, -1.0, 1.0)).radiance(Vec3::Y),
        Vec3::Z
    );
    // Black images, bad sizes and bad strengths are black and still sample finitely.
    for env in [
        EnvironmentLight::new(&[Vec3::ZERO; 8], 4, 2, 1.0, 0.0),
        EnvironmentLight::new(&[Vec3::ONE; 8], 4, 2, 0.0, 0.0),
        EnvironmentLight::new(&[Vec3::ONE; 8], 4, 2, f32::NAN, 0.0),
        EnvironmentLight::new(&[Vec3::ONE; 8], 3, 2, 1.0, 0.0),
        EnvironmentLight::new(&[], 0, 0, 1.0, 0.0),
    ] {
        assert!(env.is_black());
        let (d, radiance, pdf) = env.sample(Vec2::new(0.5, 0.5));
        assert!(d.is_finite() && radiance == Vec3::ZERO && pdf > 0.0);
        assert_eq!(env.radiance(Vec3::X), Vec3::ZERO);
    }
    // Hard directions.
    let env = EnvironmentLight::new(&test_image(16, 8), 16, 8, 1.0, f32::NAN);
    for d in [
        Vec3::ZERO,
        Vec3::Y,
        -Vec3::Y,
        Vec3::splat(f32::NAN),
        Vec3::new(0.0, 1.0, -0.0),
    ] {
        assert!(env.radiance(d).is_finite());
        assert!(env.pdf(d).is_finite());
    }
    for u in [
        Vec2::ZERO,
        Vec2::new(0.999_999_9, 0.999_999_9),
        Vec2::new(0.0, 0.999_999_9),
    ] {
        let (d, r, pdf) = env.sample(u);
        assert!(
            d.is_finite() && r.is_finite() && pdf.is_finite() && pdf > 0.0,
            "{u}"
        );
    }
}
