//! lib/lights.wgsl against chiaro_shading::lights on random inputs made in Rust: point, spot,
//! directional and triangle light samples, the triangle's solid-angle pdf, the spot falloff and
//! the range window.
//!
//! Inputs include the hard cases: the shading point at the light or a hair from it, ranges that
//! are infinite (no range), zero, negative or NaN, equal inner and outer cones, zero and
//! non-finite directional lights, degenerate triangles, points on the triangle, and views from
//! behind one-sided emitters.
//!
//! What must hold: no GPU value is NaN or infinite except a directional light's distance
//! (+infinity on both sides); the same outcome (a sample or none) except within [`EDGE_TOL`] of
//! a decision (a cone edge, the range, the emitter's plane), counted and bounded by
//! [`MAX_EDGE_MISMATCH`]; where both sample, every value within [`REL_TOL`] relative (vectors:
//! relative to their largest component), except the spot falloff, within [`FALLOFF_TOL`]
//! absolute (and the spot's radiance in those units of the unattenuated radiance).

mod common;
mod kernel;

use bytemuck::{Pod, Zeroable};
use chiaro_shading::lights::{
    self, LightSample, range_window, sample_directional, sample_point, sample_spot,
    sample_triangle, spot_falloff, triangle_solid_angle_pdf,
};
use chiaro_shading::rng::Pcg32;
use chiaro_shading::sampling::uniform_sphere;
use glam::{Vec2, Vec3};
use kernel::Kernel;

const INPUTS: usize = 200_000;
/// Relative bound on every compared value.
const REL_TOL: f32 = 2e-5;
/// Absolute bound on the spot falloff (in [0, 1]), which multiplies the cosines' rounding by
/// up to 1 / MIN_SPOT_COS_DIFFERENCE = 1000.
const FALLOFF_TOL: f32 = 5e-4;
/// A decision input this close to its threshold may go either way.
const EDGE_TOL: f32 = 1e-5;
/// Most inputs whose outcomes may differ (all at an edge).
const MAX_EDGE_MISMATCH: usize = INPUTS / 1000;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct LightInput {
    position: [f32; 3],
    range: f32,
    p: [f32; 3],
    inner: f32,
    axis: [f32; 3],
    outer: f32,
    intensity: [f32; 3],
    two_sided: f32,
    v0: [f32; 3],
    ux: f32,
    v1: [f32; 3],
    uy: f32,
    v2: [f32; 3],
    cos_angle: f32,
    q: [f32; 3],
    distance: f32,
    travel: [f32; 3],
    pad: f32,
}

/// A LightSample as two rows: (wi, distance), (radiance, pdf); flags elsewhere.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct GpuSample {
    wi: [f32; 3],
    distance: f32,
    radiance: [f32; 3],
    pdf: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct LightOutput {
    point: GpuSample,
    spot: GpuSample,
    directional: GpuSample,
    triangle: GpuSample,
    /// Bit 2k: sample k valid; bit 2k + 1: delta (k = point, spot, directional, triangle).
    flags: u32,
    triangle_pdf: f32,
    falloff: f32,
    window: f32,
}

const KERNEL: &str = r#"
#import lib/lights.wgsl

struct LightInput {
    position: vec3<f32>,
    range: f32,
    p: vec3<f32>,
    inner: f32,
    axis: vec3<f32>,
    outer: f32,
    intensity: vec3<f32>,
    two_sided: f32,
    v0: vec3<f32>,
    ux: f32,
    v1: vec3<f32>,
    uy: f32,
    v2: vec3<f32>,
    cos_angle: f32,
    q: vec3<f32>,
    distance: f32,
    travel: vec3<f32>,
}

struct GpuSample {
    wi: vec3<f32>,
    distance: f32,
    radiance: vec3<f32>,
    pdf: f32,
}

struct LightOutput {
    point: GpuSample,
    spot: GpuSample,
    directional: GpuSample,
    triangle: GpuSample,
    flags: u32,
    triangle_pdf: f32,
    falloff: f32,
    window: f32,
}

@group(0) @binding(0) var<storage, read> inputs: array<LightInput>;
@group(0) @binding(1) var<storage, read_write> outputs: array<LightOutput>;

fn pack(s: LightSample, k: u32, flags: ptr<function, u32>) -> GpuSample {
    *flags |= (select(0u, 1u, s.valid) | select(0u, 2u, s.delta)) << (2u * k);
    return GpuSample(s.wi, s.distance, s.radiance, s.pdf);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    let x = inputs[i];
    var o: LightOutput;
    var flags = 0u;
    o.point = pack(sample_point(x.position, x.intensity, x.range, x.p), 0u, &flags);
    o.spot = pack(sample_spot(x.position, x.axis, x.intensity, x.inner, x.outer, x.range, x.p), 1u, &flags);
    o.directional = pack(sample_directional(x.travel, x.intensity), 2u, &flags);
    let u = vec2<f32>(x.ux, x.uy);
    o.triangle = pack(sample_triangle(x.v0, x.v1, x.v2, x.intensity, x.two_sided != 0.0, x.p, u), 3u, &flags);
    o.flags = flags;
    o.triangle_pdf = triangle_solid_angle_pdf(x.v0, x.v1, x.v2, x.p, x.q);
    o.falloff = spot_falloff(x.cos_angle, x.inner, x.outer);
    o.window = range_window(x.distance, x.range);
    outputs[i] = o;
}
"#;

fn random_point(rng: &mut Pcg32) -> Vec3 {
    (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5) * 10.0
}

fn random_input(rng: &mut Pcg32) -> LightInput {
    let p = random_point(rng);
    let position = match rng.next_u32() % 8 {
        0 => p,
        1 => p + Vec3::X * 1e-30,
        2 => p + uniform_sphere(rng.next_vec2()) * 1e-7,
        _ => random_point(rng),
    };
    let range = match rng.next_u32() % 8 {
        0 => f32::INFINITY,
        1 => 0.0,
        2 => -1.0,
        3 => f32::NAN,
        _ => rng.next_f32() * 12.0,
    };
    let outer = rng.next_f32() * 1.6;
    let inner = if rng.next_u32().is_multiple_of(4) {
        outer
    } else {
        outer * rng.next_f32()
    };
    let axis = uniform_sphere(rng.next_vec2());
    let intensity = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 100.0;
    let mut v = [random_point(rng), random_point(rng), random_point(rng)];
    match rng.next_u32() % 10 {
        0 => v[2] = v[1],
        1 => v[2] = v[0] + (v[1] - v[0]) * 0.5,
        2 => v = v.map(|c| p + (c - p) * 1e-3),
        _ => {}
    }
    let u = rng.next_vec2();
    let (b1, b2) = chiaro_shading::sampling::uniform_triangle(rng.next_vec2());
    let q = if rng.next_u32().is_multiple_of(8) {
        p
    } else {
        v[0] + (v[1] - v[0]) * b1 + (v[2] - v[0]) * b2
    };
    let travel = match rng.next_u32() % 10 {
        0 => Vec3::ZERO,
        1 => Vec3::new(f32::INFINITY, 0.0, 1.0),
        2 => Vec3::splat(1e-30),
        _ => uniform_sphere(rng.next_vec2()) * (rng.next_f32() * 5.0 + 0.01),
    };
    LightInput {
        position: position.to_array(),
        range,
        p: p.to_array(),
        inner,
        axis: axis.to_array(),
        outer,
        intensity: intensity.to_array(),
        two_sided: (rng.next_u32() % 2) as f32,
        v0: v[0].to_array(),
        ux: u.x,
        v1: v[1].to_array(),
        uy: u.y,
        v2: v[2].to_array(),
        cos_angle: rng.next_f32() * 2.0 - 1.0,
        q: q.to_array(),
        distance: rng.next_f32() * 12.0,
        travel: travel.to_array(),
        pad: 0.0,
    }
}

/// Returns an error with the message unless the condition holds.
macro_rules! ensure {
    ($cond:expr, $($fmt:tt)+) => {
        let holds: bool = $cond;
        if !holds {
            return Err(format!($($fmt)+));
        }
    };
}

fn rel(gpu: f32, cpu: f32) -> f32 {
    if gpu == cpu {
        return 0.0;
    }
    (gpu - cpu).abs() / cpu.abs().max(f32::MIN_POSITIVE)
}

fn rel3(gpu: [f32; 3], cpu: Vec3) -> f32 {
    rel3_to(gpu, cpu, cpu.abs().max_element())
}

/// The largest component error of `gpu` relative to `scale`.
fn rel3_to(gpu: [f32; 3], cpu: Vec3, scale: f32) -> f32 {
    let scale = scale.max(f32::MIN_POSITIVE);
    (Vec3::from_array(gpu) - cpu).abs().max_element() / scale
}

/// Compares one sample; `Ok(false)` for an outcome mismatch that `at_edge` excuses. The
/// radiance is compared relative to `radiance_scale` (its own largest component when `None`).
fn compare(
    name: &str,
    gpu: &GpuSample,
    flags: u32,
    cpu: Option<LightSample>,
    at_edge: bool,
    radiance_scale: Option<f32>,
) -> Result<bool, String> {
    let valid = flags & 1 != 0;
    if valid != cpu.is_some() {
        ensure!(
            at_edge,
            "{name}: gpu {gpu:?} (valid {valid}) vs cpu {cpu:?}"
        );
        return Ok(false);
    }
    let Some(c) = cpu else {
        return Ok(true);
    };
    ensure!(
        (flags & 2 != 0) == c.delta,
        "{name}: delta differs: {gpu:?} vs {c:?}"
    );
    let values = [
        gpu.wi[0],
        gpu.wi[1],
        gpu.wi[2],
        gpu.radiance[0],
        gpu.radiance[1],
        gpu.radiance[2],
        gpu.pdf,
    ];
    ensure!(
        values.iter().all(|v| v.is_finite()),
        "{name}: non-finite {gpu:?}"
    );
    let distance_ok = if c.distance.is_infinite() {
        gpu.distance == c.distance
    } else {
        rel(gpu.distance, c.distance) <= REL_TOL
    };
    ensure!(
        rel3(gpu.wi, c.wi) <= REL_TOL
            && rel3_to(
                gpu.radiance,
                c.radiance,
                radiance_scale.unwrap_or(c.radiance.abs().max_element())
            ) <= REL_TOL
            && rel(gpu.pdf, c.pdf) <= REL_TOL
            && distance_ok,
        "{name}: {gpu:?} vs {c:?}"
    );
    Ok(true)
}

fn check(x: &LightInput, g: &LightOutput, mismatches: &mut usize) -> Result<(), String> {
    let p = Vec3::from_array(x.p);
    let position = Vec3::from_array(x.position);
    let intensity = Vec3::from_array(x.intensity);
    let range = if x.range == f32::INFINITY {
        None
    } else {
        Some(x.range)
    };
    let axis = Vec3::from_array(x.axis);
    let v = [
        Vec3::from_array(x.v0),
        Vec3::from_array(x.v1),
        Vec3::from_array(x.v2),
    ];
    let u = Vec2::new(x.ux, x.uy);
    let distance = (position - p).length();
    let near_range = range.is_some_and(|r| (distance - r).abs() <= EDGE_TOL * r.abs().max(1.0));
    let cos_axis = axis.dot((p - position).normalize_or_zero());
    let cone_edge = (cos_axis - x.outer.cos()).abs() <= EDGE_TOL;
    let mut edge_count = 0;
    let point = sample_point(position, intensity, range, p);
    edge_count += usize::from(!compare(
        "point", &g.point, g.flags, point, near_range, None,
    )?);
    // The spot's falloff is a ramp of slope up to 1 / MIN_SPOT_COS_DIFFERENCE = 1000 in the
    // cosines, which WGSL computes less exactly: its radiance is compared in units of the
    // unattenuated (point) radiance, at FALLOFF_TOL.
    let unattenuated =
        point.map(|s| s.radiance.abs().max_element() * REL_TOL.recip() * FALLOFF_TOL);
    let spot = sample_spot(position, axis, intensity, x.inner, x.outer, range, p);
    edge_count += usize::from(!compare(
        "spot",
        &g.spot,
        g.flags >> 2,
        spot,
        near_range || cone_edge,
        unattenuated,
    )?);
    let directional = sample_directional(Vec3::from_array(x.travel), intensity);
    compare(
        "directional",
        &g.directional,
        g.flags >> 4,
        Some(directional),
        false,
        None,
    )?;
    let triangle = sample_triangle(v, intensity, x.two_sided != 0.0, p, u);
    let facing = lights::triangle_area_normal(v).is_some_and(|(_, n)| {
        let (b1, b2) = chiaro_shading::sampling::uniform_triangle(u);
        let q = v[0] + (v[1] - v[0]) * b1 + (v[2] - v[0]) * b2;
        n.dot((q - p).normalize_or_zero()).abs() <= EDGE_TOL
    });
    edge_count += usize::from(!compare(
        "triangle",
        &g.triangle,
        g.flags >> 6,
        triangle,
        facing,
        None,
    )?);
    let pdf = triangle_solid_angle_pdf(v, p, Vec3::from_array(x.q));
    ensure!(
        g.triangle_pdf.is_finite() && rel(g.triangle_pdf, pdf) <= REL_TOL,
        "triangle pdf {} vs {pdf} for {x:?}",
        g.triangle_pdf
    );
    let falloff = spot_falloff(x.cos_angle, x.inner, x.outer);
    // The falloff is a clamped ramp in [0, 1]: compared in absolute terms.
    ensure!(
        (g.falloff - falloff).abs() <= FALLOFF_TOL,
        "falloff {} vs {falloff} for {x:?}",
        g.falloff
    );
    let window = range_window(x.distance, range);
    ensure!(
        (g.window - window).abs() <= REL_TOL,
        "window {} vs {window} for {x:?}",
        g.window
    );
    *mismatches += edge_count;
    Ok(())
}

#[test]
fn wgsl_lights_match_chiaro_shading() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let mut rng = Pcg32::new(0x1165, 3);
    let inputs: Vec<LightInput> = (0..INPUTS).map(|_| random_input(&mut rng)).collect();
    let kernel = Kernel::new(&gpu, "lights parity", KERNEL);
    let outputs: Vec<LightOutput> = kernel.map(&gpu, &inputs);
    let mut mismatches = 0;
    let mut failures = 0;
    let mut sampled = [0usize; 4];
    for (x, g) in inputs.iter().zip(&outputs) {
        for (k, s) in sampled.iter_mut().enumerate() {
            *s += usize::from(g.flags >> (2 * k) & 1 != 0);
        }
        if let Err(e) = check(x, g, &mut mismatches) {
            if failures < 10 {
                eprintln!("{e}");
            }
            failures += 1;
        }
    }
    eprintln!(
        "{INPUTS} inputs: samples per kind {sampled:?}, {mismatches} outcomes differ at edges"
    );
    assert_eq!(failures, 0, "{failures} of {INPUTS} inputs disagree");
    assert!(
        mismatches <= MAX_EDGE_MISMATCH,
        "{mismatches} edge mismatches"
    );
    // Every kind samples often, and all but the directional light (always a sample) refuse
    // often too.
    for (k, s) in sampled.iter().enumerate() {
        assert!(*s > INPUTS / 40, "{sampled:?}");
        assert!(k == 2 || *s < INPUTS * 9 / 10, "{sampled:?}");
    }
}
