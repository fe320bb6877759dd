//! lib/environment.wgsl against chiaro_shading::lights::EnvironmentLight: importance sampling
//! (direction, radiance, pdf), radiance lookup and pdf, for a rotated equirectangular image with
//! black rows and columns and a few very bright texels, a black image and a constant colour,
//! on random numbers and directions (the poles and a zero vector included).
//!
//! Sampling picks the same texel on both sides (the CDF search compares the same floats), so its
//! radiance must be identical; directions within [`ABS_TOL`], pdfs within [`REL_TOL`]. Lookups
//! by direction go through atan2, which WGSL computes less exactly than Rust: a direction
//! within [`EDGE_TOL`] (in texels) of a texel border may land in the neighbour, counted and
//! bounded by [`MAX_EDGE_MISMATCH`]; elsewhere radiance and pdf agree within [`REL_TOL`].

mod common;
mod kernel;

use bytemuck::{Pod, Zeroable};
use chiaro_shading::lights::EnvironmentLight;
use chiaro_shading::rng::Pcg32;
use chiaro_shading::sampling::uniform_sphere;
use glam::{Vec2, Vec3};
use kernel::{Input, Kernel, Output};

const INPUTS: usize = 100_000;
const ABS_TOL: f32 = 1e-5;
const REL_TOL: f32 = 1e-5;
/// Distance to a texel border (in texels) below which a lookup may land either side.
const EDGE_TOL: f32 = 1e-3;
const MAX_EDGE_MISMATCH: usize = INPUTS / 1000;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct EnvInfo {
    radiance: [f32; 3],
    image: u32,
    black: u32,
    width: u32,
    height: u32,
    cos_rotation: f32,
    sin_rotation: f32,
    pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct EnvInput {
    dir: [f32; 3],
    ux: f32,
    uy: f32,
    pad: [f32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct EnvOutput {
    wi: [f32; 3],
    pdf: f32,
    radiance: [f32; 3],
    lookup_pdf: f32,
    lookup: [f32; 3],
    pad: f32,
}

const KERNEL: &str = r#"
#import lib/environment.wgsl

struct EnvInfo {
    radiance: vec3<f32>,
    image: u32,
    black: u32,
    width: u32,
    height: u32,
    cos_rotation: f32,
    sin_rotation: f32,
}

struct EnvInput {
    dir: vec3<f32>,
    ux: f32,
    uy: f32,
}

struct EnvOutput {
    wi: vec3<f32>,
    pdf: f32,
    radiance: vec3<f32>,
    lookup_pdf: f32,
    lookup: vec3<f32>,
}

@group(0) @binding(0) var<storage, read> texels: array<f32>;
@group(0) @binding(1) var<storage, read> marginal_cdf: array<f32>;
@group(0) @binding(2) var<storage, read> marginal_pmf: array<f32>;
@group(0) @binding(3) var<storage, read> conditional_cdf: array<f32>;
@group(0) @binding(4) var<storage, read> conditional_pmf: array<f32>;
@group(0) @binding(5) var<storage, read> info: EnvInfo;
@group(0) @binding(6) var<storage, read> inputs: array<EnvInput>;
@group(0) @binding(7) var<storage, read_write> outputs: array<EnvOutput>;

fn env_texel(column: u32, row: u32) -> vec3<f32> {
    let i = 3u * (row * info.width + column);
    return vec3<f32>(texels[i], texels[i + 1u], texels[i + 2u]);
}

fn env_marginal_cdf(i: u32) -> f32 {
    return marginal_cdf[i];
}

fn env_marginal_pmf(row: u32) -> f32 {
    return marginal_pmf[row];
}

fn env_conditional_cdf(row: u32, i: u32) -> f32 {
    return conditional_cdf[row * (info.width + 1u) + i];
}

fn env_conditional_pmf(row: u32, column: u32) -> f32 {
    return conditional_pmf[row * info.width + column];
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    let x = inputs[i];
    let env = Environment(info.radiance, info.image != 0u, info.black != 0u, info.width, info.height, info.cos_rotation, info.sin_rotation);
    let s = environment_sample(env, vec2<f32>(x.ux, x.uy));
    var o: EnvOutput;
    o.wi = s.wi;
    o.pdf = s.pdf;
    o.radiance = s.radiance;
    o.lookup = environment_radiance(env, x.dir);
    o.lookup_pdf = environment_pdf(env, x.dir);
    outputs[i] = o;
}
"#;

/// The GPU-side copies of an environment: info, texels, marginal CDF and masses, conditional
/// CDFs and masses.
struct Tables {
    info: EnvInfo,
    texels: Vec<f32>,
    marginal_cdf: Vec<f32>,
    marginal_pmf: Vec<f32>,
    conditional_cdf: Vec<f32>,
    conditional_pmf: Vec<f32>,
}

fn tables(env: &EnvironmentLight) -> Tables {
    let (cos_rotation, sin_rotation) = env.rotation_cos_sin();
    let mut t = Tables {
        info: EnvInfo {
            radiance: env.constant_radiance().unwrap_or(Vec3::ZERO).to_array(),
            image: 0,
            black: 0,
            width: 1,
            height: 1,
            cos_rotation,
            sin_rotation,
            pad: [0; 3],
        },
        texels: vec![0.0; 3],
        marginal_cdf: vec![0.0, 1.0],
        marginal_pmf: vec![1.0],
        conditional_cdf: vec![0.0, 1.0],
        conditional_pmf: vec![1.0],
    };
    if let Some((texels, width, height)) = env.texels() {
        t.info.image = 1;
        t.info.width = width as u32;
        t.info.height = height as u32;
        t.texels = texels.iter().flat_map(|c| c.to_array()).collect();
        match env.distribution() {
            None => t.info.black = 1,
            Some(d) => {
                t.marginal_cdf = d.marginal().cdf().to_vec();
                t.marginal_pmf = (0..height).map(|y| d.marginal().pmf(y)).collect();
                t.conditional_cdf.clear();
                t.conditional_pmf.clear();
                for y in 0..height {
                    let row = d.conditional(y).expect("a row");
                    t.conditional_cdf.extend_from_slice(row.cdf());
                    t.conditional_pmf.extend((0..width).map(|x| row.pmf(x)));
                }
            }
        }
    }
    t
}

/// A 48 x 24 image: smooth sky, black bottom rows and one black column, a few texels 1e4 times
/// brighter.
fn image(rng: &mut Pcg32) -> Vec<Vec3> {
    let (w, h) = (48, 24);
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            if y >= h - 4 || x == 7 {
                Vec3::ZERO
            } else if rng.next_f32() < 0.01 {
                Vec3::splat(1e4)
            } else {
                Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * (1.0 + y as f32)
            }
        })
        .collect()
}

fn rel(gpu: f32, cpu: f32) -> f32 {
    if gpu == cpu {
        return 0.0;
    }
    (gpu - cpu).abs() / cpu.abs().max(f32::MIN_POSITIVE)
}

fn rel3(gpu: [f32; 3], cpu: Vec3) -> f32 {
    let scale = cpu.abs().max_element().max(f32::MIN_POSITIVE);
    (Vec3::from_array(gpu) - cpu).abs().max_element() / scale
}

/// How close an image-frame direction is to a texel border, in texels.
fn border_distance(env: &EnvironmentLight, dir: Vec3) -> f32 {
    let Some((_, width, height)) = env.texels() else {
        return f32::INFINITY;
    };
    let (c, s) = env.rotation_cos_sin();
    let d = dir.try_normalize().unwrap_or(Vec3::Y);
    let d = Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
    let u = (0.5 + d.z.atan2(d.x) / std::f32::consts::TAU) * width as f32;
    let v = (d.x * d.x + d.z * d.z).sqrt().atan2(d.y) / std::f32::consts::PI * height as f32;
    let frac = |x: f32| (x - x.round()).abs();
    frac(u).min(frac(v))
}

fn check_environment(
    gpu: &chiaro_gpu::GpuContext,
    kernel: &Kernel,
    name: &str,
    env: &EnvironmentLight,
) {
    let t = tables(env);
    let mut rng = Pcg32::new(0xe4, name.len() as u64);
    let inputs: Vec<EnvInput> = (0..INPUTS)
        .map(|i| {
            let dir = match i % 16 {
                0 => Vec3::Y,
                1 => -Vec3::Y,
                2 => Vec3::ZERO,
                _ => uniform_sphere(rng.next_vec2()) * (0.5 + rng.next_f32()),
            };
            let u = rng.next_vec2();
            EnvInput {
                dir: dir.to_array(),
                ux: if i % 97 == 0 { 0.999_999_94 } else { u.x },
                uy: u.y,
                pad: [0.0; 3],
            }
        })
        .collect();
    let bytes = kernel.run(
        gpu,
        &[
            Input {
                group: 0,
                binding: 0,
                data: bytemuck::cast_slice(&t.texels),
            },
            Input {
                group: 0,
                binding: 1,
                data: bytemuck::cast_slice(&t.marginal_cdf),
            },
            Input {
                group: 0,
                binding: 2,
                data: bytemuck::cast_slice(&t.marginal_pmf),
            },
            Input {
                group: 0,
                binding: 3,
                data: bytemuck::cast_slice(&t.conditional_cdf),
            },
            Input {
                group: 0,
                binding: 4,
                data: bytemuck::cast_slice(&t.conditional_pmf),
            },
            Input {
                group: 0,
                binding: 5,
                data: bytemuck::bytes_of(&t.info),
            },
            Input {
                group: 0,
                binding: 6,
                data: bytemuck::cast_slice(&inputs),
            },
        ],
        &Output {
            group: 0,
            binding: 7,
            size: (INPUTS * size_of::<EnvOutput>()) as u64,
        },
        INPUTS as u32,
    );
    let outputs: &[EnvOutput] = bytemuck::cast_slice(&bytes);
    let mut edge = 0;
    let (mut worst_dir, mut worst_pdf) = (0.0f32, 0.0f32);
    for (x, g) in inputs.iter().zip(outputs) {
        let (wi, radiance, pdf) = env.sample(Vec2::new(x.ux, x.uy));
        let e = (Vec3::from_array(g.wi) - wi).abs().max_element();
        assert!(
            e <= ABS_TOL,
            "{name}: sample direction {:?} vs {wi} for {x:?}",
            g.wi
        );
        worst_dir = worst_dir.max(e);
        assert_eq!(
            Vec3::from_array(g.radiance),
            radiance,
            "{name}: sample radiance for {x:?}"
        );
        let e = rel(g.pdf, pdf);
        assert!(
            g.pdf.is_finite() && g.pdf > 0.0 && e <= REL_TOL,
            "{name}: sample pdf {} vs {pdf} for {x:?}",
            g.pdf
        );
        worst_pdf = worst_pdf.max(e);

        let dir = Vec3::from_array(x.dir);
        let lookup = env.radiance(dir);
        let lookup_pdf = env.pdf(dir);
        let agree = rel3(g.lookup, lookup) <= REL_TOL && rel(g.lookup_pdf, lookup_pdf) <= REL_TOL;
        if !agree {
            assert!(
                border_distance(env, dir) <= EDGE_TOL,
                "{name}: lookup {:?} / {} vs {lookup} / {lookup_pdf} away from a texel border for {x:?}",
                g.lookup,
                g.lookup_pdf
            );
            edge += 1;
        } else {
            worst_pdf = worst_pdf.max(rel(g.lookup_pdf, lookup_pdf));
        }
    }
    eprintln!(
        "{name}: {INPUTS} inputs, worst direction {worst_dir:e}, pdf {worst_pdf:e}, {edge} lookups at texel borders"
    );
    assert!(
        edge <= MAX_EDGE_MISMATCH,
        "{name}: {edge} border mismatches"
    );
}

#[test]
fn wgsl_environment_matches_chiaro_shading() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let kernel = Kernel::new(&gpu, "environment parity", KERNEL);
    let mut rng = Pcg32::new(77, 7);
    let texels = image(&mut rng);
    let environments = [
        ("image", EnvironmentLight::new(&texels, 48, 24, 2.5, 0.7)),
        (
            "black image",
            EnvironmentLight::new(&vec![Vec3::ZERO; 8 * 4], 8, 4, 1.0, 0.0),
        ),
        (
            "constant",
            EnvironmentLight::constant(Vec3::new(0.2, 0.4, 0.8)),
        ),
    ];
    for (name, env) in &environments {
        check_environment(&gpu, &kernel, name, env);
    }
}
