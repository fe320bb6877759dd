//! lib/frame.wgsl, lib/sampling.wgsl, lib/color.wgsl and lib/offset.wgsl against chiaro_shading
//! and chiaro_bvh on random and edge-case inputs made in Rust.
//!
//! - frame_from_normal / to_local / to_world, concentric_disk, cosine_hemisphere,
//!   uniform_hemisphere, uniform_sphere: within [`ABS_TOL`] per component (unit-length results;
//!   WGSL's cos and sin are less exact than Rust's; for cosine_hemisphere z^2 is compared, as
//!   z is the square root of a difference that vanishes at the disk's rim); uniform_triangle and the pdf helpers within
//!   [`REL_TOL`] relative.
//! - power_heuristic: within [`REL_TOL`], with its defined answers (0, 1/2, 1, NaN and infinite
//!   pdfs) exactly.
//! - luminance, srgb_to_linear, linear_to_srgb: within [`REL_TOL`].
//! - offset_ray_origin: within one ulp of the moved coordinate (exactly the same for the ulp
//!   steps, which are integer arithmetic), on points from 1e-9 to 1e18 and both signs.

mod common;
mod kernel;

use bytemuck::{Pod, Zeroable};
use chiaro_bvh::offset_ray_origin;
use chiaro_shading::color::{linear_to_srgb, luminance, srgb_to_linear};
use chiaro_shading::frame::Frame;
use chiaro_shading::rng::Pcg32;
use chiaro_shading::sampling::{
    concentric_disk, cosine_hemisphere, cosine_hemisphere_pdf, power_heuristic, uniform_hemisphere,
    uniform_sphere, uniform_triangle,
};
use glam::{Vec2, Vec3};
use kernel::Kernel;

const INPUTS: usize = 200_000;
/// Absolute bound on components of unit vectors and disk points.
const ABS_TOL: f32 = 2e-6;
/// Relative bound on scalars.
const REL_TOL: f32 = 2e-6;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct SamplingInput {
    normal: [f32; 3],
    f_pdf: f32,
    v: [f32; 3],
    g_pdf: f32,
    point: [f32; 3],
    channel: f32,
    u: [f32; 2],
    pad: [f32; 2],
}

/// Every result, as 4-float rows.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, Default)]
struct SamplingOutput {
    /// frame_to_local(frame_from_normal(normal), v), then luminance(v).
    local: [f32; 4],
    /// frame_to_world(frame, v), then power_heuristic(1, f_pdf, 1, g_pdf).
    world: [f32; 4],
    /// The frame's tangent, then srgb_to_linear(channel).
    tangent: [f32; 4],
    /// The frame's bitangent, then linear_to_srgb(channel).
    bitangent: [f32; 4],
    /// concentric_disk(u), uniform_triangle(u).
    disk_triangle: [f32; 4],
    /// cosine_hemisphere(u), then cosine_hemisphere_pdf(v.z).
    cosine: [f32; 4],
    /// uniform_hemisphere(u), then power_heuristic(2, f_pdf, 0.5, g_pdf).
    hemisphere: [f32; 4],
    /// uniform_sphere(u), then 0.
    sphere: [f32; 4],
    /// offset_ray_origin(point, normal), then 0.
    offset: [f32; 4],
}

const KERNEL: &str = r#"
#import lib/frame.wgsl
#import lib/sampling.wgsl
#import lib/color.wgsl
#import lib/offset.wgsl

struct SamplingInput {
    normal: vec3<f32>,
    f_pdf: f32,
    v: vec3<f32>,
    g_pdf: f32,
    point: vec3<f32>,
    channel: f32,
    u: vec2<f32>,
}

struct SamplingOutput {
    local: vec4<f32>,
    world: vec4<f32>,
    tangent: vec4<f32>,
    bitangent: vec4<f32>,
    disk_triangle: vec4<f32>,
    cosine: vec4<f32>,
    hemisphere: vec4<f32>,
    sphere: vec4<f32>,
    offset: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> inputs: array<SamplingInput>;
@group(0) @binding(1) var<storage, read_write> outputs: array<SamplingOutput>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    let x = inputs[i];
    let f = frame_from_normal(x.normal);
    var o: SamplingOutput;
    o.local = vec4<f32>(frame_to_local(f, x.v), luminance(x.v));
    o.world = vec4<f32>(frame_to_world(f, x.v), power_heuristic(1.0, x.f_pdf, 1.0, x.g_pdf));
    o.tangent = vec4<f32>(f.tangent, srgb_to_linear(x.channel));
    o.bitangent = vec4<f32>(f.bitangent, linear_to_srgb(x.channel));
    o.disk_triangle = vec4<f32>(concentric_disk(x.u), uniform_triangle(x.u));
    o.cosine = vec4<f32>(cosine_hemisphere(x.u), cosine_hemisphere_pdf(x.v.z));
    o.hemisphere = vec4<f32>(uniform_hemisphere(x.u), power_heuristic(2.0, x.f_pdf, 0.5, x.g_pdf));
    o.sphere = vec4<f32>(uniform_sphere(x.u), 0.0);
    o.offset = vec4<f32>(offset_ray_origin(x.point, x.normal), 0.0);
    outputs[i] = o;
}
"#;

fn pick(rng: &mut Pcg32, edges: &[f32], p: f32, otherwise: impl FnOnce(&mut Pcg32) -> f32) -> f32 {
    if rng.next_f32() < p {
        edges[(rng.next_u32() as usize) % edges.len()]
    } else {
        otherwise(rng)
    }
}

fn random_input(rng: &mut Pcg32) -> SamplingInput {
    let normal = match rng.next_u32() % 8 {
        0 => [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            -Vec3::Y,
            Vec3::new(0.0, 1e-4, -1.0).normalize(),
        ][(rng.next_u32() % 5) as usize],
        _ => uniform_sphere(rng.next_vec2()),
    };
    let v = uniform_sphere(rng.next_vec2());
    let pdf_edges = [0.0, 1.0, f32::INFINITY, f32::NAN, -1.0, 3e30, 1e-30];
    let f_pdf = pick(rng, &pdf_edges, 0.2, |r| r.next_f32() * 10.0);
    let g_pdf = pick(rng, &pdf_edges, 0.2, |r| r.next_f32() * 10.0);
    // Points from 1e-9 to 1e18 in magnitude, both signs, and exact zeros.
    let coordinate = |rng: &mut Pcg32| {
        pick(rng, &[0.0, -0.0, 1.0 / 32.0, -1.0 / 32.0], 0.1, |r| {
            let magnitude = 10f32.powf(r.next_f32() * 27.0 - 9.0);
            if r.next_u32() % 2 == 0 {
                magnitude
            } else {
                -magnitude
            }
        })
    };
    let point = [coordinate(rng), coordinate(rng), coordinate(rng)];
    let channel = pick(rng, &[0.0, 1.0, 0.04045, 0.0031308, -0.5, 2.0], 0.1, |r| {
        r.next_f32()
    });
    let u_edges = [0.0, 0.5, 0.999_999_94];
    let u = [
        pick(rng, &u_edges, 0.1, |r| r.next_f32()),
        pick(rng, &u_edges, 0.1, |r| r.next_f32()),
    ];
    SamplingInput {
        normal: normal.to_array(),
        f_pdf,
        v: v.to_array(),
        g_pdf,
        point,
        channel,
        u,
        pad: [0.0; 2],
    }
}

fn abs_error(gpu: &[f32], cpu: &[f32]) -> f32 {
    gpu.iter()
        .zip(cpu)
        .map(|(g, c)| (g - c).abs())
        .fold(0.0, f32::max)
}

fn rel_error(gpu: f32, cpu: f32) -> f32 {
    if gpu == cpu {
        return 0.0;
    }
    (gpu - cpu).abs() / cpu.abs().max(f32::MIN_POSITIVE)
}

/// The number of representable floats between `a` and `b` (for finite values).
fn ulps_apart(a: f32, b: f32) -> u32 {
    let key = |x: f32| {
        let bits = x.to_bits() as i32;
        if bits < 0 { i32::MIN - bits } else { bits }
    };
    (i64::from(key(a)) - i64::from(key(b))).unsigned_abs() as u32
}

#[test]
fn frame_sampling_color_and_offset_match_the_cpu() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let mut rng = Pcg32::new(0x5a3, 1);
    let inputs: Vec<SamplingInput> = (0..INPUTS).map(|_| random_input(&mut rng)).collect();
    let kernel = Kernel::new(&gpu, "sampling parity", KERNEL);
    let outputs: Vec<SamplingOutput> = kernel.map(&gpu, &inputs);
    let (mut worst_abs, mut worst_rel, mut worst_ulps) = (0.0f32, 0.0f32, 0u32);
    for (x, g) in inputs.iter().zip(&outputs) {
        let n = Vec3::from_array(x.normal);
        let v = Vec3::from_array(x.v);
        let u = Vec2::from_array(x.u);
        let f = Frame::from_normal(n);
        let (b1, b2) = uniform_triangle(u);
        let vectors: [(&str, &[f32], Vec<f32>); 8] = [
            ("to_local", &g.local[..3], f.to_local(v).to_array().to_vec()),
            ("to_world", &g.world[..3], f.to_world(v).to_array().to_vec()),
            ("tangent", &g.tangent[..3], f.tangent.to_array().to_vec()),
            (
                "bitangent",
                &g.bitangent[..3],
                f.bitangent.to_array().to_vec(),
            ),
            (
                "disk",
                &g.disk_triangle[..2],
                concentric_disk(u).to_array().to_vec(),
            ),
            (
                "cosine",
                &g.cosine[..3],
                cosine_hemisphere(u).to_array().to_vec(),
            ),
            (
                "hemisphere",
                &g.hemisphere[..3],
                uniform_hemisphere(u).to_array().to_vec(),
            ),
            (
                "sphere",
                &g.sphere[..3],
                uniform_sphere(u).to_array().to_vec(),
            ),
        ];
        for (name, gv, cv) in vectors {
            let mut gv = gv.to_vec();
            let mut cv = cv;
            if name == "cosine" {
                // z = sqrt(1 - x^2 - y^2): at the disk's rim the square root of a rounding
                // difference; compare z^2, which carries the rounding itself.
                gv[2] *= gv[2];
                cv[2] *= cv[2];
            }
            let e = abs_error(&gv, &cv);
            assert!(e <= ABS_TOL, "{name}: {gv:?} vs {cv:?} for {x:?}");
            worst_abs = worst_abs.max(e);
        }
        let scalars = [
            ("triangle b1", g.disk_triangle[2], b1),
            ("triangle b2", g.disk_triangle[3], b2),
            ("cosine pdf", g.cosine[3], cosine_hemisphere_pdf(v.z)),
            (
                "power heuristic",
                g.world[3],
                power_heuristic(1.0, x.f_pdf, 1.0, x.g_pdf),
            ),
            (
                "power heuristic 2",
                g.hemisphere[3],
                power_heuristic(2.0, x.f_pdf, 0.5, x.g_pdf),
            ),
            ("srgb_to_linear", g.tangent[3], srgb_to_linear(x.channel)),
            ("linear_to_srgb", g.bitangent[3], linear_to_srgb(x.channel)),
        ];
        // Luminance is a dot product whose terms may cancel: its rounding is relative to the
        // sum of the terms' sizes, not to the result.
        let terms = luminance(v.abs());
        let e = (g.local[3] - luminance(v)).abs() / terms.max(f32::MIN_POSITIVE);
        assert!(
            e <= REL_TOL,
            "luminance: {} vs {} for {x:?}",
            g.local[3],
            luminance(v)
        );
        worst_rel = worst_rel.max(e);
        for (name, gs, cs) in scalars {
            assert!(gs.is_finite(), "{name}: {gs} for {x:?}");
            let e = rel_error(gs, cs);
            assert!(e <= REL_TOL, "{name}: {gs} vs {cs} for {x:?}");
            worst_rel = worst_rel.max(e);
        }
        let h = power_heuristic(1.0, x.f_pdf, 1.0, x.g_pdf);
        if [0.0, 0.5, 1.0].contains(&h) {
            assert_eq!(g.world[3], h, "defined answer for {x:?}");
        }
        let p = Vec3::from_array(x.point);
        let moved = offset_ray_origin(p, n).to_array();
        for k in 0..3 {
            let d = ulps_apart(g.offset[k], moved[k]);
            assert!(d <= 1, "offset {:?} vs {moved:?} for {x:?}", &g.offset[..3]);
            if x.point[k].abs() >= 1.0 / 32.0 {
                assert_eq!(g.offset[k], moved[k], "ulp step for {x:?}");
            }
            worst_ulps = worst_ulps.max(d);
        }
    }
    eprintln!(
        "{INPUTS} inputs: worst absolute {worst_abs:e}, relative {worst_rel:e}, offset {worst_ulps} ulp"
    );
}
