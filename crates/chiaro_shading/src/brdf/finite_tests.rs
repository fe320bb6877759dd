//! BRDF tests on hard inputs: horizon directions, degenerate pairs, extreme parameters and
//! uniform numbers never give NaN or infinity.

use glam::{Vec2, Vec3};

use super::tests::random_params;
use super::*;
use crate::rng::Pcg32;
use crate::sampling::uniform_sphere;

/// Hard inputs: a structured sweep of horizon directions (z = 0, 1e-8, 1e-30), wo == wi, wo == n,
/// nearly opposite grazing pairs, roughness 0, the threshold and 1, and extreme uniform numbers.
#[test]
fn hard_cases_are_finite() {
    let zs = [0.0f32, 1e-30, 1e-8, 1e-4, 0.5, 1.0];
    let mut dirs = Vec::new();
    for &z in &zs {
        for phi in [0.0f32, 1.0, 3.0, std::f32::consts::PI] {
            let r = (1.0 - z * z).sqrt();
            dirs.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
    }
    let us = [0.0f32, 1e-7, 0.5, 0.999_999_94];
    let mut count = 0;
    for roughness in [
        0.0,
        MIRROR_ALPHA.sqrt(),
        MIRROR_ALPHA.sqrt() * 1.0001,
        0.01,
        0.5,
        1.0,
    ] {
        for metallic in [0.0, 1.0] {
            for f0_dielectric in [0.0, 0.04, 1.0] {
                let p = SurfaceParams {
                    base_color: Vec3::new(1.0, 0.5, 0.0),
                    metallic,
                    roughness,
                    f0_dielectric,
                    ..SurfaceParams::default()
                };
                for &wo in &dirs {
                    for &wi in &dirs {
                        let f = eval(&p, wo, wi);
                        let d = pdf(&p, wo, wi);
                        assert!(
                            f.is_finite() && f.min_element() >= 0.0,
                            "{p:?} {wo} {wi}: {f}"
                        );
                        assert!(d.is_finite() && d >= 0.0, "{p:?} {wo} {wi}: {d}");
                        count += 1;
                    }
                    for &a in &us {
                        for &b in &us {
                            for &c in &us {
                                if let Some(s) = sample(&p, wo, a, Vec2::new(b, c)) {
                                    assert!(s.wi.is_finite() && s.wi.z != 0.0, "{p:?} {wo} {s:?}");
                                    assert!(s.weight.is_finite() && s.weight.min_element() >= 0.0);
                                    assert!(s.pdf.is_finite() && s.pdf > 0.0, "{p:?} {wo} {s:?}");
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(count > 10_000);
}

/// No NaN or infinity over two million random inputs: random materials, directions drawn over the
/// whole sphere (so both sides of the horizon) and, one time in four, squashed onto the horizon.
#[test]
fn random_inputs_are_finite() {
    let mut rng = Pcg32::new(4242, 17);
    let squash = |rng: &mut Pcg32, w: Vec3| {
        if rng.next_f32() < 0.25 {
            let z: f32 = [0.0, 1e-8, -1e-8, 1e-20][(rng.next_u32() % 4) as usize];
            let r = Vec2::new(w.x, w.y).normalize_or(Vec2::X) * (1.0 - z * z).sqrt();
            Vec3::new(r.x, r.y, z)
        } else {
            w
        }
    };
    for i in 0..2_000_000 {
        let p = random_params(&mut rng);
        let w = uniform_sphere(rng.next_vec2());
        let wo = squash(&mut rng, w);
        let w = uniform_sphere(rng.next_vec2());
        let wi = if i % 16 == 0 { wo } else { squash(&mut rng, w) };
        let f = eval(&p, wo, wi);
        assert!(
            f.is_finite() && f.min_element() >= 0.0,
            "{p:?} {wo} {wi}: {f}"
        );
        let d = pdf(&p, wo, wi);
        assert!(d.is_finite() && d >= 0.0, "{p:?} {wo} {wi}: {d}");
        if let Some(s) = sample(&p, wo, rng.next_f32(), rng.next_vec2()) {
            assert!(s.wi.is_finite() && s.wi.z != 0.0, "{p:?} {wo} {s:?}");
            assert!(
                s.weight.is_finite() && s.weight.min_element() >= 0.0,
                "{p:?} {wo} {s:?}"
            );
            assert!(s.pdf.is_finite() && s.pdf > 0.0, "{p:?} {wo} {s:?}");
        }
    }
}
