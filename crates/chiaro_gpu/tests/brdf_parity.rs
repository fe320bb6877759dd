//! lib/brdf.wgsl against chiaro_shading::brdf on a million random inputs made in Rust: eval,
//! pdf, specular_probability and sample (direction, weight, pdf, delta, None) per input.
//!
//! Inputs mix random materials with their edge values (roughness 0, 1 and around the mirror
//! threshold; metallic, F0, absorption and colour 0 and 1) and directions from the whole sphere
//! (half below the horizon), grazing ones (|z| from 1e-7 to 1e-2, and 0), the normal, and the
//! exact and near mirror reflection of the view.
//!
//! What must hold, for every input:
//! - nothing the GPU returns is NaN or infinite;
//! - eval, pdf and specular_probability have the same zero / non-zero pattern as the CPU and
//!   are within [`REL_EVAL`] of it (relative to the CPU value, each colour channel to at least
//!   [`CHANNEL_FLOOR`] of the colour's largest, values below [`ABSOLUTE_FLOOR`] in absolute
//!   terms; looser for a sheen and for grazing transmission: [`rel_eval`]); where either side
//!   is exactly 0 the other is below [`NEGLIGIBLE`];
//! - sample: the same outcome (None, delta or not). Where both drew a direction, it is within
//!   [`DIR_TOL`] of the CPU's, and weight and pdf are within [`REL_SAMPLE`]. The sampled
//!   direction goes through `cos`, `sin` and `sqrt`, which WGSL computes less exactly than Rust;
//!   the weight and pdf are then also checked against the CPU's eval and pdf *at the GPU's
//!   direction*, within [`REL_EVAL`]: the two sides agree on the function, and differ only
//!   by the direction's rounding.
//! - Outcomes may differ only where the CPU's direction lies within [`DIR_TOL`] of the horizon
//!   (one side lands just above, the other at or below) or `u_lobe` is within 1e-6 (1e-4 with a
//!   sheen) of a boundary between lobes; such cases are counted and must stay below [`MAX_OUTCOME_MISMATCH`].

mod brdf_parity_inputs;
mod common;
mod kernel;

use std::time::Instant;

use brdf_parity_inputs::{BrdfInput, params, random_input};
use bytemuck::{Pod, Zeroable};
use chiaro_shading::brdf;
use chiaro_shading::rng::Pcg32;
use glam::{Vec2, Vec3};
use kernel::Kernel;

/// Inputs in the test.
const INPUTS: usize = 1_000_000;
/// Inputs per GPU run.
const BATCH: usize = 250_000;
/// Relative error bound of eval, pdf and specular_probability (same inputs on both sides): a
/// few ulps, amplified at grazing angles; fused multiply-adds (which WGSL allows, and
/// llvmpipe's GL path makes) gave 1.3e-5 at a view 1e-4 above the horizon.
const REL_EVAL: f32 = 2e-5;
/// The same bound for a material with a sheen: its Charlie lobe and albedo fit go through
/// `pow`, `exp` and `log`, which the GPU computes less exactly, the more so at grazing views
/// (measured worst here 1.3e-3, at a view 1e-3 above the horizon).
const REL_EVAL_SHEEN: f32 = 2e-3;

/// Below this a sheen material's values are compared in absolute terms: far from its grazing
/// peak the Charlie lobe is sin^(1/alpha) of an angle, with 1/alpha up to 1000, whose
/// relative rounding grows as the value vanishes (the values there are below 3e-4).
const SHEEN_FLOOR: f32 = 1e-3;

/// The error of a colour for this input's material: [`relative_error3`], or for a sheen
/// material each channel's difference over max(|cpu|, [`SHEEN_FLOOR`]).
fn error3(x: &BrdfInput, gpu: [f32; 3], cpu: Vec3) -> f32 {
    if rel_eval(x) != REL_EVAL_SHEEN {
        return relative_error3(gpu, cpu);
    }
    (0..3)
        .map(|k| {
            if !same_zero_pattern(gpu[k], cpu[k]) {
                f32::INFINITY
            } else {
                (gpu[k] - cpu[k]).abs() / cpu[k].abs().max(SHEEN_FLOOR)
            }
        })
        .fold(0.0, f32::max)
}

/// The same bound for the transmission lobe seen or leaving within 1e-3 of the horizon: its
/// mirrored direction's cosines there are differences of nearly equal numbers, which GL's fused
/// multiply-adds round differently (measured worst 4.4e-4 on llvmpipe's GL, at a view 1e-4 above
/// the horizon).
const REL_EVAL_GRAZING_TRANSMISSION: f32 = 1e-3;

/// The same bound for a volume's surface (KHR_materials_volume): inside it the Fresnel term goes
/// through the refracted cosine sqrt(1 - sin^2 / eta^2), whose rounding grows without bound
/// towards the critical angle, and a refraction's half vector through a sum of nearly opposite
/// directions (measured worst 1.6e-4 on llvmpipe's GL).
const REL_EVAL_VOLUME: f32 = 1e-3;

/// The same bound for two directions both within 1e-3 of the horizon and nearly opposite: their
/// half vector is the sum of nearly opposite vectors, rounded differently with fused
/// multiply-adds (measured 1.2e-4 on llvmpipe's GL at 1e-5 and 7e-4 above the horizon).
const REL_EVAL_OPPOSITE_AT_THE_HORIZON: f32 = 1e-3;

/// The same bound for a coat on a normal of its own: both sides turn the directions into the
/// coat's frame, a few roundings that GGX's D amplifies by up to 1 / alpha^2 near a sharp
/// coat's peak, and GL's fused multiply-adds round them differently (measured worst 2.2e-3 on
/// llvmpipe's GL, for coats at the mirror threshold).
const REL_EVAL_TILTED_COAT: f32 = 5e-3;

/// The relative bound of eval, pdf and the weights for this input's material and directions.
fn rel_eval(x: &BrdfInput) -> f32 {
    let tilted_coat = x.clearcoat > 0.0 && x.coat_normal != [0.0, 0.0, 1.0];
    let grazing = x.wo[2].abs() < 1e-3 || x.wi[2].abs() < 1e-3;
    let both_grazing = x.wo[2].abs() < 1e-3 && x.wi[2].abs() < 1e-3;
    let opposite = Vec3::from_array(x.wo).dot(Vec3::from_array(x.wi)) < -0.99;
    if x.sheen_color.iter().any(|c| *c > 0.0) {
        REL_EVAL_SHEEN
    } else if tilted_coat {
        REL_EVAL_TILTED_COAT
    } else if x.eta > 0.0 {
        REL_EVAL_VOLUME
    } else if both_grazing && opposite {
        REL_EVAL_OPPOSITE_AT_THE_HORIZON
    } else if x.transmission > 0.0 && grazing {
        REL_EVAL_GRAZING_TRANSMISSION
    } else {
        REL_EVAL
    }
}
/// Absolute bound on each component of the sampled direction (its x and y go through `cos`,
/// `sin` and square roots of differences near 0, which WGSL computes less exactly than Rust).
const DIR_TOL: f32 = 5e-4;
/// Channels below this fraction of a colour's largest channel are compared in absolute terms
/// (see [`relative_error3`]).
const CHANNEL_FLOOR: f32 = 1e-3;
/// Directions with z below this are "at the horizon": z = sqrt(1 - x^2 - y^2) there turns a
/// rounding difference of 1e-7 in x or y into one of about 5e-4 in z.
const HORIZON_TOL: f32 = 2e-3;
/// Above this u.x the visible normal lies at the rim of the projected disk (see check).
const RIM_U: f32 = 1.0 - 1e-6;
/// Relative bound on the sampled weight and pdf against the CPU's sample.
const REL_SAMPLE: f32 = 5e-3;
/// Most samples whose outcome (None / delta / lobe) may differ, all near a decision boundary:
/// 0.2% of the inputs (a fifth of them are seen at grazing angles, where drawn directions
/// often end within rounding of the horizon).
const MAX_OUTCOME_MISMATCH: usize = INPUTS / 500;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct BrdfOutput {
    eval: [f32; 3],
    pdf: f32,
    wi: [f32; 3],
    sample_pdf: f32,
    weight: [f32; 3],
    /// Bit 0: the sample is valid; bit 1: it is a delta.
    flags: u32,
    specular_probability: f32,
    pad: [f32; 3],
}

const KERNEL: &str = r#"
#import lib/brdf.wgsl

struct BrdfInput {
    base_color: vec3<f32>,
    metallic: f32,
    wo: vec3<f32>,
    roughness: f32,
    wi: vec3<f32>,
    f0_dielectric: f32,
    u: vec2<f32>,
    u_lobe: f32,
    absorption: f32,
    specular_color: vec3<f32>,
    specular: f32,
    clearcoat: f32,
    clearcoat_roughness: f32,
    transmission: f32,
    sheen_roughness: f32,
    sheen_color: vec3<f32>,
    eta: f32,
    coat_normal: vec3<f32>,
    pad: u32,
}

struct BrdfOutput {
    eval: vec3<f32>,
    pdf: f32,
    wi: vec3<f32>,
    sample_pdf: f32,
    weight: vec3<f32>,
    flags: u32,
    specular_probability: f32,
}

@group(0) @binding(0) var<storage, read> inputs: array<BrdfInput>;
@group(0) @binding(1) var<storage, read_write> outputs: array<BrdfOutput>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    let x = inputs[i];
    let p = SurfaceParams(x.base_color, x.metallic, x.roughness, x.f0_dielectric, x.specular,
        x.specular_color, x.clearcoat, x.clearcoat_roughness, x.transmission, x.sheen_color,
        x.sheen_roughness, x.absorption, x.eta, x.coat_normal);
    var o: BrdfOutput;
    o.eval = brdf_eval(p, x.wo, x.wi);
    o.pdf = brdf_pdf(p, x.wo, x.wi);
    o.specular_probability = specular_probability(p, x.wo);
    let s = brdf_sample(p, x.wo, x.u_lobe, x.u);
    o.wi = s.wi;
    o.sample_pdf = s.pdf;
    o.weight = s.weight;
    o.flags = select(0u, 1u, s.valid) | select(0u, 2u, s.delta);
    outputs[i] = o;
}
"#;

/// Where one side is exactly zero (or negligible) the other must be below this. GPUs may flush
/// subnormals, and a Fresnel term (1 - cos)^5 whose cosine is one rounding step from 1 lands
/// around 1e-35 on one side and at exactly 0 on the other; times a sharp lobe's D, GL's fused
/// multiply-adds gave 1.5e-30 against 4.6e-32.
const NEGLIGIBLE: f32 = 1e-28;

/// The zero / non-zero pattern: where either side is exactly 0, the other is negligible.
fn same_zero_pattern(gpu: f32, cpu: f32) -> bool {
    (cpu != 0.0 || gpu.abs() < NEGLIGIBLE) && (gpu != 0.0 || cpu.abs() < NEGLIGIBLE)
}

/// Relative error of `gpu` against `cpu`: 0 when both are negligible, infinite when only the
/// CPU's is, or when the zero pattern differs.
fn relative_error(gpu: f32, cpu: f32) -> f32 {
    if !same_zero_pattern(gpu, cpu) {
        return f32::INFINITY;
    }
    if cpu.abs() < NEGLIGIBLE {
        return if gpu.abs() < NEGLIGIBLE {
            0.0
        } else {
            f32::INFINITY
        };
    }
    ((gpu - cpu) / cpu.abs().max(ABSOLUTE_FLOOR)).abs()
}

/// Values below this are compared in absolute terms (the error over this floor): a Fresnel term
/// (1 - cos)^5 of F0 0 at a cosine near 1 makes values of 1e-12 to 1e-20, whose last digits
/// GL's fused multiply-adds move by 1e-4 of themselves, and which weigh nothing in an image.
const ABSOLUTE_FLOOR: f32 = 1e-6;

/// Returns an error with the message unless the condition holds.
macro_rules! ensure {
    ($cond:expr, $($fmt:tt)+) => {
        let holds: bool = $cond;
        if !holds {
            return Err(format!($($fmt)+));
        }
    };
}

/// The largest relative error over the components of a colour (see [`relative_error`]), each
/// measured against at least [`CHANNEL_FLOOR`] times the largest channel: a channel a thousand
/// times dimmer than another (say 1e-31 next to 0.5, where metallic 1 meets a zero base colour
/// channel) is held to the same absolute error as that floor, not to its own digits. The zero
/// pattern is checked per channel all the same.
fn relative_error3(gpu: [f32; 3], cpu: Vec3) -> f32 {
    let floor = CHANNEL_FLOOR * cpu.abs().max_element();
    (0..3)
        .map(|k| {
            if !same_zero_pattern(gpu[k], cpu[k]) {
                f32::INFINITY
            } else if cpu[k].abs() < floor {
                (gpu[k] - cpu[k]).abs() / floor
            } else {
                relative_error(gpu[k], cpu[k])
            }
        })
        .fold(0.0, f32::max)
}

#[derive(Default, Debug)]
struct Worst {
    eval: f32,
    pdf: f32,
    specular_probability: f32,
    direction: f32,
    weight: f32,
    sample_pdf: f32,
    weight_at_gpu_direction: f32,
    pdf_at_gpu_direction: f32,
    outcome_mismatches: usize,
    samples_compared: usize,
    zeros: usize,
}

fn check(x: &BrdfInput, g: &BrdfOutput, worst: &mut Worst) -> Result<(), String> {
    let p = params(x);
    let wo = Vec3::from_array(x.wo);
    let wi = Vec3::from_array(x.wi);
    let all = [
        g.eval[0],
        g.eval[1],
        g.eval[2],
        g.pdf,
        g.wi[0],
        g.wi[1],
        g.wi[2],
        g.sample_pdf,
        g.weight[0],
        g.weight[1],
        g.weight[2],
        g.specular_probability,
    ];
    ensure!(
        all.iter().all(|v| v.is_finite()),
        "non-finite for {x:?}: {g:?}"
    );

    let eval = brdf::eval(&p, wo, wi);
    let e = error3(x, g.eval, eval);
    ensure!(
        e <= rel_eval(x),
        "eval {:?} vs {eval} ({e}) for {x:?}",
        g.eval
    );
    worst.eval = worst.eval.max(e);
    worst.zeros += usize::from(eval == Vec3::ZERO);
    let pdf = brdf::pdf(&p, wo, wi);
    let e = relative_error(g.pdf, pdf);
    ensure!(e <= rel_eval(x), "pdf {} vs {pdf} ({e}) for {x:?}", g.pdf);
    worst.pdf = worst.pdf.max(e);
    let sp = brdf::specular_probability(&p, wo);
    let e = relative_error(g.specular_probability, sp);
    ensure!(
        e <= rel_eval(x),
        "specular probability {} vs {sp} for {x:?}",
        g.specular_probability
    );
    worst.specular_probability = worst.specular_probability.max(e);

    let cpu = brdf::sample(&p, wo, x.u_lobe, Vec2::from_array(x.u));
    let valid = g.flags & 1 != 0;
    let delta = g.flags & 2 != 0;
    let same_outcome = match cpu {
        None => !valid,
        Some(s) => valid && s.delta == delta,
    };
    // A volume's refraction about a visible normal drawn at the rim of the projected disk
    // (u.x within rounding of 1): there h is at 90 degrees to wo up to the square root of a
    // rounding error, and unlike a reflection, the refracted direction follows h.
    let refracted_at_the_rim = p.eta > 0.0 && x.u[0] > RIM_U;
    let near_boundary = |s: Option<brdf::BrdfSample>| {
        let horizon =
            s.is_some_and(|s| s.wi.z.abs() < HORIZON_TOL) || (valid && g.wi[2].abs() < HORIZON_TOL);
        // The boundaries between lobes: the running sums of their probabilities, in the
        // order sample compares u_lobe against them, and 1 (where the last lobe with a
        // probability ends). A sheen's probability goes through its albedo fit's `exp`.
        let l = brdf::lobe_probabilities(&p, wo);
        let sheen_bound = l.coat + l.sheen;
        let bounds = [
            l.coat,
            sheen_bound,
            sheen_bound + l.specular,
            sheen_bound + l.specular + l.transmission,
            1.0,
        ];
        let tolerance = if rel_eval(x) == REL_EVAL_SHEEN {
            1e-4
        } else {
            1e-6
        };
        let lobe = bounds.iter().any(|b| (x.u_lobe - b).abs() < tolerance);
        // A None from a direction below the horizon: the GPU's direction is near it too.
        let none_at_horizon = s.is_none() && valid && g.wi[2].abs() < HORIZON_TOL;
        horizon || lobe || none_at_horizon || refracted_at_the_rim
    };
    if !same_outcome {
        ensure!(
            near_boundary(cpu),
            "sample outcome differs away from any boundary for {x:?}: cpu {cpu:?}, gpu {g:?}"
        );
        worst.outcome_mismatches += 1;
        return Ok(());
    }
    let Some(s) = cpu else {
        return Ok(());
    };
    if refracted_at_the_rim {
        // The direction, and f and the pdf there (through wo.h, a rounding error), follow h.
        return Ok(());
    }
    let gwi = Vec3::from_array(g.wi);
    // At the horizon z is the square root of a rounding difference (see HORIZON_TOL).
    let dz_tol = if s.wi.z.abs() < HORIZON_TOL {
        HORIZON_TOL
    } else {
        DIR_TOL
    };
    let d = (gwi - s.wi).abs();
    let e = d.x.max(d.y).max(d.z * DIR_TOL / dz_tol);
    if e > DIR_TOL {
        // Both sides drew, but different lobes: only at the lobe boundary.
        ensure!(
            near_boundary(cpu),
            "direction {gwi} vs {} ({e}) for {x:?}",
            s.wi
        );
        worst.outcome_mismatches += 1;
        return Ok(());
    }
    worst.direction = worst.direction.max(e);
    worst.samples_compared += 1;
    if s.delta {
        // The mirror: F(wo.z) (1 - absorption) / p, no trigonometry involved.
        let e = error3(x, g.weight, s.weight);
        ensure!(
            e <= rel_eval(x),
            "mirror weight {:?} vs {} ({e}) for {x:?}",
            g.weight,
            s.weight
        );
        let e = relative_error(g.sample_pdf, s.pdf);
        ensure!(
            e <= rel_eval(x),
            "mirror pdf {} vs {} ({e}) for {x:?}",
            g.sample_pdf,
            s.pdf
        );
        worst.weight = worst.weight.max(e);
        return Ok(());
    }
    // The same function at the GPU's own direction: f cos / pdf and pdf.
    let f = brdf::eval(&p, wo, gwi);
    let pdf = brdf::pdf(&p, wo, gwi);
    ensure!(
        pdf > 0.0,
        "the GPU drew {gwi}, where the CPU's pdf is 0, for {x:?}"
    );
    let e = error3(x, g.weight, f * gwi.z.abs() / pdf);
    ensure!(
        e <= rel_eval(x),
        "weight {:?} vs the CPU's f cos / pdf {} at the GPU's {gwi} ({e}) for {x:?}",
        g.weight,
        f * gwi.z.abs() / pdf
    );
    worst.weight_at_gpu_direction = worst.weight_at_gpu_direction.max(e);
    let e = relative_error(g.sample_pdf, pdf);
    ensure!(
        e <= rel_eval(x),
        "sample pdf {} vs the CPU's {pdf} at {gwi} for {x:?}",
        g.sample_pdf
    );
    worst.pdf_at_gpu_direction = worst.pdf_at_gpu_direction.max(e);
    if s.wi.z.abs() < HORIZON_TOL {
        // There the weight and pdf depend on z, which is the square root of a rounding error.
        return Ok(());
    }
    let e = error3(x, g.weight, s.weight);
    ensure!(
        e <= REL_SAMPLE,
        "weight {:?} vs {} ({e}) at {gwi} vs {} for {x:?}",
        g.weight,
        s.weight,
        s.wi
    );
    worst.weight = worst.weight.max(e);
    let e = relative_error(g.sample_pdf, s.pdf);
    ensure!(
        e <= REL_SAMPLE,
        "sample pdf {} vs {} ({e}) for {x:?}",
        g.sample_pdf,
        s.pdf
    );
    worst.sample_pdf = worst.sample_pdf.max(e);
    Ok(())
}

#[test]
fn wgsl_brdf_matches_chiaro_shading_on_a_million_inputs() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let start = Instant::now();
    let kernel = Kernel::new(&gpu, "brdf parity", KERNEL);
    let mut rng = Pcg32::new(0xb2d5, 7);
    let mut coat_rng = Pcg32::new(0xc0a7, 7);
    let mut worst = Worst::default();
    let mut gpu_time = 0.0;
    let mut done = 0;
    let mut failures = Vec::new();
    while done < INPUTS {
        let n = BATCH.min(INPUTS - done);
        let inputs: Vec<BrdfInput> = (0..n)
            .map(|_| random_input(&mut rng, &mut coat_rng))
            .collect();
        let t = Instant::now();
        let outputs: Vec<BrdfOutput> = kernel.map(&gpu, &inputs);
        gpu_time += t.elapsed().as_secs_f64();
        for (x, g) in inputs.iter().zip(&outputs) {
            if let Err(e) = check(x, g, &mut worst) {
                if failures.len() < 20 {
                    eprintln!("{e}");
                }
                failures.push(e);
            }
        }
        done += n;
    }
    eprintln!(
        "{INPUTS} inputs in {:.1} s ({gpu_time:.1} s on the GPU): {worst:?}",
        start.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} of {INPUTS} inputs disagree",
        failures.len()
    );
    assert!(
        worst.outcome_mismatches <= MAX_OUTCOME_MISMATCH,
        "{} sample outcomes differ",
        worst.outcome_mismatches
    );
    // The inputs exercise what they claim to: many zeros (below the horizon) and many samples.
    assert!(worst.zeros > INPUTS / 10, "{worst:?}");
    assert!(worst.samples_compared > INPUTS / 3, "{worst:?}");
}
