//! Chi-square goodness of fit of [`sample`] against [`pdf`], as in Mitsuba's and pbrt's test
//! suites: sampled directions are binned on a (theta, phi) grid over the upper hemisphere, the
//! pdf is integrated over each bin numerically for the expected counts, small expected counts are
//! pooled, and the statistic is judged at 1% significance with the Sidak correction for all the
//! configurations tested. Samples that `sample` rejects (reflections below the horizon) form one
//! more cell, whose expected count is the specular lobe's probability times the visible-normal
//! mass that reflects below the horizon, integrated by quadrature (and checked to complete the
//! bins' total to one).
//!
//! The grid is uniform in neither angle: half of the bin edges in theta (and in phi) follow a
//! Cauchy distribution centred on the mirror direction with the lobe's width, the other half are
//! spread uniformly. So a sharp lobe (roughness 0.05, alpha 0.0025) is resolved by many bins
//! instead of falling into one, while the broad diffuse lobe still gets its share; the horizon
//! stays a bin edge (theta = pi/2).

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::tests::{Quadrature, direction, half_vector_quadrature};
use super::*;
use crate::rng::Pcg32;
use crate::test_util::{GaussLegendre, Rect, adaptive_simpson_2d, chi_square_test};

const THETA_BINS: usize = 16;
const PHI_BINS: usize = 32;
/// Every configuration of the three roughness tests below, for the Sidak correction.
const TESTS_IN_FAMILY: usize = 3 * 4 * 4;
/// Azimuth of the view, so that nothing lines up with the axes.
const VIEW_AZIMUTH: f32 = 0.37;

fn view(mu: f32) -> Vec3 {
    let d = direction(mu);
    Vec3::new(d.x * VIEW_AZIMUTH.cos(), d.x * VIEW_AZIMUTH.sin(), d.z)
}

fn spherical(theta: f64, phi: f64) -> Vec3 {
    Vec3::new(
        (theta.sin() * phi.cos()) as f32,
        (theta.sin() * phi.sin()) as f32,
        theta.cos() as f32,
    )
}

/// `n + 1` bin edges over [lo, hi]: quantiles of an equal mix of the uniform distribution and a
/// Cauchy distribution of this centre and scale, truncated to [lo, hi].
fn edges(n: usize, lo: f64, hi: f64, centre: f64, scale: f64) -> Vec<f64> {
    let cauchy = |x: f64| ((x - centre) / scale).atan();
    let (c_lo, c_hi) = (cauchy(lo), cauchy(hi));
    let cdf = |x: f64| 0.5 * (x - lo) / (hi - lo) + 0.5 * (cauchy(x) - c_lo) / (c_hi - c_lo);
    (0..=n)
        .map(|i| {
            let target = i as f64 / n as f64;
            let (mut a, mut b) = (lo, hi);
            for _ in 0..80 {
                let m = 0.5 * (a + b);
                if cdf(m) < target { a = m } else { b = m }
            }
            if i == 0 {
                lo
            } else if i == n {
                hi
            } else {
                0.5 * (a + b)
            }
        })
        .collect()
}

/// The grid for a view and a lobe width: theta edges over [0, pi/2], phi edges over one turn
/// centred on the mirror direction's azimuth.
struct Grid {
    theta: Vec<f64>,
    phi: Vec<f64>,
}

impl Grid {
    fn new(wo: Vec3, alpha: f64) -> Self {
        let theta_r = (wo.z as f64).clamp(-1.0, 1.0).acos();
        let phi_r = (-(wo.y as f64)).atan2(-(wo.x as f64));
        let width = (2.0 * alpha).max(1e-3);
        // Near the pole, azimuth means little: the phi scale grows to cover the turn.
        let phi_scale = (width / theta_r.sin().max(1e-6)).min(10.0);
        Self {
            theta: edges(THETA_BINS, 0.0, FRAC_PI_2, theta_r, width),
            phi: edges(PHI_BINS, phi_r - PI, phi_r + PI, phi_r, phi_scale),
        }
    }

    /// The cell of a sampled direction, or the last cell for a rejection.
    fn cell(&self, s: Option<BrdfSample>) -> usize {
        let Some(s) = s else {
            return THETA_BINS * PHI_BINS;
        };
        assert!(!s.delta);
        // atan2 rather than acos(z): near the pole z = 1 - theta^2 / 2 has too few f32 digits.
        let (x, y, z) = (s.wi.x as f64, s.wi.y as f64, s.wi.z as f64);
        let theta = (x * x + y * y).sqrt().atan2(z);
        let mut phi = (s.wi.y as f64).atan2(s.wi.x as f64);
        let (lo, hi) = (self.phi[0], self.phi[PHI_BINS]);
        phi = lo + (phi - lo).rem_euclid(TAU);
        let find = |edges: &[f64], x: f64| {
            let bins = edges.len() - 1;
            edges[1..bins].partition_point(|&e| e <= x).min(bins - 1)
        };
        debug_assert!(phi >= lo && phi <= hi + 1e-9);
        find(&self.theta, theta) * PHI_BINS + find(&self.phi, phi)
    }
}

/// Expected counts per cell (the lost mass last) for `n` samples drawn with `pdf_params`.
fn expected_counts(grid: &Grid, pdf_params: &SurfaceParams, wo: Vec3, n: usize) -> Vec<f64> {
    let alpha = ggx::alpha_from_roughness(pdf_params.roughness) as f64;
    let mirror = Vec3::new(-wo.x, -wo.y, wo.z).as_dvec3();
    // A coat on a normal of its own peaks about its own mirror direction.
    let coat_alpha = ggx::alpha_from_roughness(pdf_params.clearcoat_roughness) as f64;
    let n_c = pdf_params.coat_normal.normalize().as_dvec3();
    let coat_mirror = 2.0 * wo.as_dvec3().dot(n_c) * n_c - wo.as_dvec3();
    // Make sure the specular peaks are seen: rectangles near a mirror direction are subdivided
    // until they are about the lobe's width, whatever the error estimate says; the error estimate
    // takes over from there.
    let force = |r: Rect| {
        let size = (r.x1 - r.x0).max((r.y1 - r.y0) * r.x1.sin());
        let centre = spherical(0.5 * (r.x0 + r.x1), 0.5 * (r.y0 + r.y1)).as_dvec3();
        let near = |peak: glam::DVec3, alpha: f64| {
            size > 2.0 * alpha && centre.dot(peak).clamp(-1.0, 1.0).acos() < 4.0 * alpha + size
        };
        near(mirror, alpha) || (pdf_params.clearcoat > 0.0 && near(coat_mirror, coat_alpha))
    };
    let mut expected = Vec::with_capacity(THETA_BINS * PHI_BINS + 1);
    let mut total = 0.0;
    for i in 0..THETA_BINS {
        for j in 0..PHI_BINS {
            let rect = Rect {
                x0: grid.theta[i],
                x1: grid.theta[i + 1],
                y0: grid.phi[j],
                y1: grid.phi[j + 1],
            };
            let mut f = |theta: f64, phi: f64| {
                pdf(pdf_params, wo, spherical(theta, phi)) as f64 * theta.sin()
            };
            let mass = adaptive_simpson_2d(&mut f, rect, 1e-6, &force, 12);
            total += mass;
            expected.push(mass * n as f64);
        }
    }
    // Rejections: the specular lobe's VNDF reflections below the horizon. Integrating that mass
    // directly is far more accurate than one minus the bins' total when it is tiny.
    let rules = (GaussLegendre::new(96), GaussLegendre::new(48));
    let above = |roughness: f32| {
        half_vector_quadrature(
            Quadrature::VisibleAboveHorizon,
            ggx::alpha_from_roughness(roughness),
            wo.z,
            &rules.0,
            &rules.1,
        )
    };
    let probabilities = Material::new(pdf_params).lobe_probabilities(wo);
    if pdf_params.coat_normal != Vec3::Z {
        // A coat on a normal of its own loses the reflections that leave below either surface,
        // which the quadrature below does not cover: the rejections are what the pdf leaves out
        // of the hemisphere.
        expected.push((1.0 - total).max(0.0) * n as f64);
        return expected;
    }
    let mut lost = probabilities.specular as f64 * (1.0 - above(pdf_params.roughness)).max(0.0);
    if probabilities.coat > 0.0 {
        lost += probabilities.coat as f64 * (1.0 - above(pdf_params.clearcoat_roughness)).max(0.0);
    }
    assert!(
        (total + lost - 1.0).abs() < 1e-3,
        "bins {total} + rejections {lost} != 1"
    );
    expected.push(lost * n as f64);
    expected
}

/// Observed counts of `n` samples of `params`; `u_lobe` is multiplied by `lobe_scale` (1 for the
/// real thing, less to skew the lobe choice on purpose).
fn observed_counts(
    grid: &Grid,
    params: &SurfaceParams,
    wo: Vec3,
    n: usize,
    seed: u64,
    lobe_scale: f32,
) -> Vec<f64> {
    let mut rng = Pcg32::new(seed, 3);
    let mut counts = vec![0.0; THETA_BINS * PHI_BINS + 1];
    for _ in 0..n {
        let u_lobe = rng.next_f32() * lobe_scale;
        counts[grid.cell(sample(params, wo, u_lobe, rng.next_vec2()))] += 1.0;
    }
    counts
}

fn materials(roughness: f32) -> [(&'static str, SurfaceParams); 2] {
    let metal = SurfaceParams {
        base_color: Vec3::new(0.9, 0.6, 0.3),
        metallic: 1.0,
        roughness,
        ..SurfaceParams::default()
    };
    let plastic = SurfaceParams {
        base_color: Vec3::new(0.2, 0.5, 0.8),
        metallic: 0.0,
        ..metal
    };
    [("metal", metal), ("plastic", plastic)]
}

/// Runs the test for a metal, a plastic (both lobes) and a clear-coated plastic of this
/// roughness, its coat on the shading normal or on a normal of its own, for views from the
/// normal to grazing (cos 0.05).
fn check_roughness(roughness: f32, n: usize) {
    let mut failures = Vec::new();
    // A clear coat of another roughness over the plastic: three lobes.
    let coated = SurfaceParams {
        clearcoat: 1.0,
        clearcoat_roughness: 0.2,
        ..materials(roughness)[1].1
    };
    // The coat on a normal of its own, tilted 30 degrees.
    let tilted = SurfaceParams {
        coat_normal: Vec3::new(0.3, -0.4, 0.75f32.sqrt()),
        ..coated
    };
    for (name, params) in materials(roughness)
        .into_iter()
        .chain([("coated plastic", coated), ("tilted coat", tilted)])
    {
        for (k, mu) in [1.0f32, 0.7, 0.3, 0.05].into_iter().enumerate() {
            let wo = view(mu);
            let grid = Grid::new(wo, ggx::alpha_from_roughness(roughness) as f64);
            let expected = expected_counts(&grid, &params, wo, n);
            let observed = observed_counts(&grid, &params, wo, n, 1000 + k as u64, 1.0);
            match chi_square_test(&observed, &expected, TESTS_IN_FAMILY) {
                Ok(p) => println!("{name}, roughness {roughness}, mu {mu}: p = {p:.3}"),
                Err(e) => failures.push(format!("{name}, roughness {roughness}, mu {mu}: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn chi_square_sample_matches_pdf_roughness_0_05() {
    check_roughness(0.05, 60_000);
}

#[test]
fn chi_square_sample_matches_pdf_roughness_0_3() {
    check_roughness(0.3, 60_000);
}

#[test]
fn chi_square_sample_matches_pdf_roughness_1() {
    check_roughness(1.0, 60_000);
}

/// The test has power: samples judged against the pdf of a 10% larger roughness are rejected
/// (sharp and medium lobes, metal and plastic), and so are samples that pick the specular lobe
/// 1.5 times too often; the right pdf passes on the same samples.
#[test]
fn chi_square_rejects_a_mismatched_pdf() {
    let n = 60_000;
    for roughness in [0.05f32, 0.3] {
        for (name, params) in materials(roughness) {
            for mu in [1.0f32, 0.7] {
                let wo = view(mu);
                let grid = Grid::new(wo, ggx::alpha_from_roughness(roughness) as f64);
                let observed = observed_counts(&grid, &params, wo, n, 5, 1.0);
                let wrong = SurfaceParams {
                    roughness: roughness * 1.1,
                    ..params
                };
                let result = chi_square_test(&observed, &expected_counts(&grid, &wrong, wo, n), 1);
                assert!(
                    result.is_err(),
                    "{name} roughness {roughness} mu {mu}: {result:?}"
                );
                chi_square_test(&observed, &expected_counts(&grid, &params, wo, n), 1).unwrap();
            }
        }
    }
    let (_, plastic) = materials(0.3)[1];
    let wo = view(0.7);
    let grid = Grid::new(wo, 0.09);
    let sp = specular_probability(&plastic, wo);
    assert!(sp * 1.5 < 1.0);
    let skewed = observed_counts(&grid, &plastic, wo, n, 6, 1.0 / 1.5);
    assert!(chi_square_test(&skewed, &expected_counts(&grid, &plastic, wo, n), 1).is_err());
}
