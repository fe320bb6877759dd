//! KHR_materials_volume's refraction: energy through a smooth interface from either side
//! (total internal reflection included), the generalized reciprocity of the rough BTDF, and
//! the energy a rough interface keeps.

use super::tests::{direction, sampled_albedo};
use super::*;
use crate::rng::Pcg32;

/// Clear glass: white, transmission 1, no metal, the dielectric F0 of IOR 1.5.
fn glass(roughness: f32, eta: f32) -> SurfaceParams {
    SurfaceParams {
        base_color: Vec3::ONE,
        metallic: 0.0,
        roughness,
        transmission: 1.0,
        eta,
        ..SurfaceParams::default()
    }
}

/// The share of power a sample carries: its weight, with a transmitted sample's 1 / eta^2
/// radiance scaling undone (reflected plus transmitted power is what the interface conserves).
fn power_albedo(p: &SurfaceParams, wo: Vec3, k: u32, rng: &mut Pcg32) -> f32 {
    let mut sum = 0.0f64;
    for i in 0..k * k {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let u_lobe = (i as f32 + rng.next_f32()) / (k * k) as f32;
        if let Some(s) = sample(p, wo, u_lobe, u) {
            let power = if s.wi.z < 0.0 { p.eta * p.eta } else { 1.0 };
            sum += f64::from(s.weight.x * power);
        }
    }
    (sum / f64::from(k * k)) as f32
}

/// A smooth interface reflects F and transmits 1 - F of the power, from outside (eta 1.5) and
/// from inside (eta 1 / 1.5), where past the critical angle (cos 0.745) all of it is reflected:
/// every view's power albedo is 1 within the estimate's noise.
#[test]
fn smooth_glass_conserves_power_from_both_sides() {
    let mut rng = Pcg32::new(5, 34);
    for eta in [1.5, 1.0 / 1.5] {
        for mu in [1.0, 0.9, 0.76, 0.74, 0.5, 0.1] {
            let p = glass(0.0, eta);
            let albedo = power_albedo(&p, direction(mu), 64, &mut rng);
            assert!((albedo - 1.0).abs() < 2e-3, "eta {eta} mu {mu}: {albedo}");
        }
    }
    // Past the critical angle from inside, nothing is transmitted at all.
    let inside = glass(0.0, 1.0 / 1.5);
    for _ in 0..1000 {
        let s = sample(&inside, direction(0.5), rng.next_f32(), rng.next_vec2());
        assert!(s.is_some_and(|s| s.wi.z > 0.0), "{s:?}");
    }
}

/// The rough BTDF obeys the generalized reciprocity of refraction in radiance form
/// (Veach's thesis, eq. 5.19): f(1 / eta; -wi, -wo) = eta^2 f(eta; wo, wi).
#[test]
fn rough_refraction_is_reciprocal_up_to_eta_squared() {
    let mut rng = Pcg32::new(8, 34);
    let mut checked = 0;
    for _ in 0..20_000 {
        let eta = 0.4 + 2.5 * rng.next_f32();
        let roughness = 0.1 + 0.9 * rng.next_f32();
        let wo = crate::sampling::uniform_hemisphere(rng.next_vec2());
        let mut wi = crate::sampling::uniform_hemisphere(rng.next_vec2());
        wi.z = -wi.z;
        let forward = eval(&glass(roughness, eta), wo, wi);
        let backward = eval(&glass(roughness, 1.0 / eta), -wi, -wo);
        if forward == Vec3::ZERO {
            assert_eq!(backward, Vec3::ZERO, "eta {eta} {wo} {wi}");
            continue;
        }
        let ratio = backward.x / (forward.x * eta * eta);
        assert!((ratio - 1.0).abs() < 2e-3, "eta {eta} {wo} {wi}: {ratio}");
        checked += 1;
    }
    assert!(checked > 5_000, "{checked}");
}

/// A rough interface loses only what single scattering loses: clear glass of roughness 0.2
/// keeps at least 93% of the power at every view from outside, and never more than all of it
/// from either side.
#[test]
fn rough_glass_keeps_most_of_the_power() {
    let mut rng = Pcg32::new(6, 34);
    for mu in [1.0, 0.7, 0.4, 0.15] {
        for eta in [1.5, 1.0 / 1.5] {
            let albedo = power_albedo(&glass(0.2, eta), direction(mu), 128, &mut rng);
            assert!(albedo <= 1.005, "eta {eta} mu {mu}: {albedo}");
            if eta > 1.0 {
                assert!(albedo >= 0.93, "eta {eta} mu {mu}: {albedo}");
            }
        }
    }
    // The radiance albedo of the sampler agrees with the power albedo's scaling.
    let p = glass(0.3, 1.5);
    let radiance = sampled_albedo(&p, direction(1.0), 128, &mut rng).x;
    let power = power_albedo(&p, direction(1.0), 128, &mut rng);
    assert!(radiance < power && radiance > 0.4, "{radiance} {power}");
}
