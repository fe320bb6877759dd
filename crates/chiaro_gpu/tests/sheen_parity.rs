//! lib/sheen.wgsl against chiaro_shading::sheen on 100,000 random inputs made in Rust: eval,
//! albedo (at n.wo), albedo_scaling, pdf and sample (direction, pdf, None) per input.
//!
//! Inputs mix random roughness with its edge values (0, 1, the floor, outside [0, 1]) and
//! directions from the whole sphere (a third below the horizon), grazing ones (|z| from 1e-30 to
//! 1e-2, and 0) and the normal; sheen colours include black and channels outside [0, 1].
//!
//! What must hold, for every input:
//! - nothing the GPU returns is NaN or infinite;
//! - eval has the CPU's zero / non-zero pattern (but for D flushed from a subnormal, see
//!   [`FLUSHED_EVAL`]) and is within [`REL_EVAL`] of it: D raises
//!   sin^2 to 1 / (2 alpha), up to 500, which multiplies the GPU's `pow` error (a few ulps of
//!   log2) by as much;
//! - albedo within [`REL_ALBEDO`] (one `pow`, two `exp` and a `log` of the fit), and
//!   albedo_scaling within [`ABS_SCALING`] (it is 1 - strength E, clamped);
//! - pdf is exactly the CPU's; sample has the same outcome, its direction within [`DIR_TOL`]
//!   (`cos`, `sin` and `sqrt` on the GPU) and its pdf exactly the CPU's.

mod common;
mod kernel;

use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use chiaro_shading::ggx::VISIBILITY_DENOMINATOR_FLOOR;
use chiaro_shading::rng::Pcg32;
use chiaro_shading::sampling::uniform_sphere;
use chiaro_shading::sheen::{self, ALPHA_FLOOR};
use glam::{Vec2, Vec3};
use kernel::Kernel;

/// Inputs in the test.
const INPUTS: usize = 100_000;
/// Relative bound on eval (Vulkan lavapipe: 5.6e-5).
const REL_EVAL: f32 = 1e-3;
/// Relative bound on albedo (lavapipe: 4.4e-6).
const REL_ALBEDO: f32 = 5e-5;
/// Absolute bound on albedo_scaling (lavapipe: 3.3e-6).
const ABS_SCALING: f32 = 5e-5;
/// Absolute bound on each component of the sampled direction.
const DIR_TOL: f32 = 1e-5;
/// Where one side is exactly zero the other must be below this (GPUs may flush subnormals).
const NEGLIGIBLE: f32 = 1e-30;
/// Where the GPU's eval is exactly zero the CPU's must be below this: D's `pow` is then a
/// subnormal (below f32::MIN_POSITIVE), which GPUs may flush to zero, times D's factor
/// (2 + 1 / alpha) / (2 pi) (at most 160) over V's denominator (at least
/// VISIBILITY_DENOMINATOR_FLOOR, for a direction 1e-30 above the horizon): about 1.9e-16.
const FLUSHED_EVAL: f32 = f32::MIN_POSITIVE * (2.0 + 1.0 / ALPHA_FLOOR)
    / std::f32::consts::TAU
    / VISIBILITY_DENOMINATOR_FLOOR;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct SheenInput {
    wo: [f32; 3],
    roughness: f32,
    wi: [f32; 3],
    pad0: f32,
    sheen_color: [f32; 3],
    pad1: f32,
    u: [f32; 2],
    pad2: [f32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct SheenOutput {
    wi: [f32; 3],
    sample_pdf: f32,
    eval: f32,
    albedo: f32,
    albedo_scaling: f32,
    pdf: f32,
    /// 1 when the sample is valid.
    valid: u32,
    pad: [u32; 3],
}

const KERNEL: &str = r#"
#import lib/sheen.wgsl

struct SheenInput {
    wo: vec3<f32>,
    roughness: f32,
    wi: vec3<f32>,
    sheen_color: vec3<f32>,
    u: vec2<f32>,
}

struct SheenOutput {
    wi: vec3<f32>,
    sample_pdf: f32,
    eval: f32,
    albedo: f32,
    albedo_scaling: f32,
    pdf: f32,
    valid: u32,
}

@group(0) @binding(0) var<storage, read> inputs: array<SheenInput>;
@group(0) @binding(1) var<storage, read_write> outputs: array<SheenOutput>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    let x = inputs[i];
    var o: SheenOutput;
    o.eval = sheen_eval(x.roughness, x.wo, x.wi);
    o.albedo = sheen_albedo(x.roughness, x.wo.z);
    o.albedo_scaling = sheen_albedo_scaling(x.sheen_color, x.roughness, x.wo.z, x.wi.z);
    o.pdf = sheen_pdf(x.roughness, x.wo, x.wi);
    let s = sheen_sample(x.roughness, x.wo, x.u);
    o.wi = s.wi;
    o.sample_pdf = s.pdf;
    o.valid = select(0u, 1u, s.valid);
    outputs[i] = o;
}
"#;

fn at_cosine(mu: f32, phi: f32) -> Vec3 {
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), mu)
}

fn random_direction(rng: &mut Pcg32) -> Vec3 {
    let phi = rng.next_f32() * std::f32::consts::TAU;
    match rng.next_u32() % 8 {
        0..=2 => uniform_sphere(rng.next_vec2()),
        3 | 4 => {
            let d = uniform_sphere(rng.next_vec2());
            Vec3::new(d.x, d.y, d.z.abs())
        }
        5 | 6 => {
            let grazing = [0.0, 1e-30, 1e-7, -1e-7, 1e-5, 1e-4, 1e-3, 1e-2, -1e-2];
            at_cosine(grazing[(rng.next_u32() % 9) as usize], phi)
        }
        _ => Vec3::Z,
    }
}

fn random_input(rng: &mut Pcg32) -> SheenInput {
    let mut pick = |edges: &[f32]| {
        if rng.next_f32() < 0.3 {
            edges[(rng.next_u32() as usize) % edges.len()]
        } else {
            rng.next_f32()
        }
    };
    let roughness = pick(&[0.0, 1.0, ALPHA_FLOOR.sqrt(), 0.05, -0.5, 1.5]);
    let sheen_color = [pick(&[0.0, 1.0]), pick(&[0.0, 2.0]), pick(&[0.0, -1.0])];
    let u = [pick(&[0.0, 0.999_999_94]), pick(&[0.0, 0.5])];
    let wo = random_direction(rng);
    let wi = random_direction(rng);
    SheenInput {
        wo: wo.to_array(),
        roughness,
        wi: wi.to_array(),
        pad0: 0.0,
        sheen_color,
        pad1: 0.0,
        u,
        pad2: [0.0; 2],
    }
}

fn same_zero_pattern(gpu: f32, cpu: f32) -> bool {
    (cpu != 0.0 || gpu.abs() < NEGLIGIBLE) && (gpu != 0.0 || cpu.abs() < NEGLIGIBLE)
}

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
    ((gpu - cpu) / cpu).abs()
}

#[derive(Default, Debug)]
struct Worst {
    eval: f32,
    albedo: f32,
    albedo_scaling: f32,
    direction: f32,
    nonzero_evals: usize,
    samples: usize,
}

fn check(x: &SheenInput, g: &SheenOutput, worst: &mut Worst) -> Result<(), String> {
    let wo = Vec3::from_array(x.wo);
    let wi = Vec3::from_array(x.wi);
    let r = x.roughness;
    let all = [
        g.eval,
        g.albedo,
        g.albedo_scaling,
        g.pdf,
        g.sample_pdf,
        g.wi[0],
        g.wi[1],
        g.wi[2],
    ];
    if !all.iter().all(|v| v.is_finite()) {
        return Err(format!("non-finite for {x:?}: {g:?}"));
    }
    let eval = sheen::eval(r, wo, wi);
    let e = if g.eval == 0.0 && eval < FLUSHED_EVAL {
        0.0
    } else {
        relative_error(g.eval, eval)
    };
    if e > REL_EVAL {
        return Err(format!("eval {} vs {eval} ({e}) for {x:?}", g.eval));
    }
    worst.eval = worst.eval.max(e);
    worst.nonzero_evals += usize::from(eval > 0.0);
    let albedo = sheen::albedo(r, wo.z);
    let e = relative_error(g.albedo, albedo);
    if e > REL_ALBEDO {
        return Err(format!("albedo {} vs {albedo} ({e}) for {x:?}", g.albedo));
    }
    worst.albedo = worst.albedo.max(e);
    let scaling = sheen::albedo_scaling(Vec3::from_array(x.sheen_color), r, wo.z, wi.z);
    let e = (g.albedo_scaling - scaling).abs();
    if e > ABS_SCALING {
        return Err(format!(
            "albedo_scaling {} vs {scaling} for {x:?}",
            g.albedo_scaling
        ));
    }
    worst.albedo_scaling = worst.albedo_scaling.max(e);
    let pdf = sheen::pdf(r, wo, wi);
    if g.pdf != pdf {
        return Err(format!("pdf {} vs {pdf} for {x:?}", g.pdf));
    }
    match (sheen::sample(r, wo, Vec2::from_array(x.u)), g.valid != 0) {
        (None, false) => {}
        (Some((cpu_wi, cpu_pdf)), true) => {
            let e = (Vec3::from_array(g.wi) - cpu_wi).abs().max_element();
            if e > DIR_TOL || g.sample_pdf != cpu_pdf {
                return Err(format!(
                    "sample {:?} {} vs {cpu_wi} {cpu_pdf} for {x:?}",
                    g.wi, g.sample_pdf
                ));
            }
            worst.direction = worst.direction.max(e);
            worst.samples += 1;
        }
        (cpu, _) => return Err(format!("sample outcome {cpu:?} vs {g:?} for {x:?}")),
    }
    Ok(())
}

#[test]
fn wgsl_sheen_matches_chiaro_shading() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let start = Instant::now();
    let kernel = Kernel::new(&gpu, "sheen parity", KERNEL);
    let mut rng = Pcg32::new(0x5ee4, 11);
    let inputs: Vec<SheenInput> = (0..INPUTS).map(|_| random_input(&mut rng)).collect();
    let outputs: Vec<SheenOutput> = kernel.map(&gpu, &inputs);
    let mut worst = Worst::default();
    let mut failures = Vec::new();
    for (x, g) in inputs.iter().zip(&outputs) {
        if let Err(e) = check(x, g, &mut worst) {
            if failures.len() < 20 {
                eprintln!("{e}");
            }
            failures.push(e);
        }
    }
    eprintln!(
        "{INPUTS} inputs in {:.1} s: {worst:?}",
        start.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} of {INPUTS} inputs disagree",
        failures.len()
    );
    // The inputs exercise what they claim to.
    assert!(worst.nonzero_evals > INPUTS / 5, "{worst:?}");
    assert!(worst.samples > INPUTS / 3, "{worst:?}");
}
