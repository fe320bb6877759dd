//! lib/tonemap.wgsl and lib/color.wgsl's sRGB encoding against chiaro_shading: ACES fitted, PBR
//! Neutral and clamp on random radiance from 1e-6 to 1e9 (grey, saturated, and single-channel
//! colours), exposures from 2^-10 to 2^10, and bad input (NaN, infinite and negative channels,
//! NaN, zero and negative exposures). Outputs lie in [0, 1]; they must agree within
//! [`ABS_TOL`], and their sRGB encodings too.

mod common;
mod kernel;

use bytemuck::{Pod, Zeroable};
use chiaro_shading::color::linear_to_srgb;
use chiaro_shading::rng::Pcg32;
use chiaro_shading::tonemap::Tonemapper;
use glam::Vec3;
use kernel::Kernel;

const INPUTS: usize = 200_000;
/// Absolute bound on display values in [0, 1] (an 8-bit step is 3.9e-3).
const ABS_TOL: f32 = 2e-6;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct ToneInput {
    linear: [f32; 3],
    exposure: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct ToneOutput {
    /// Per operator (ACES, Neutral, clamp): the mapped colour and 0.
    mapped: [[f32; 4]; 3],
    /// linear_to_srgb of each ACES channel.
    srgb: [f32; 4],
}

const KERNEL: &str = r#"
#import lib/tonemap.wgsl
#import lib/color.wgsl

struct ToneInput {
    linear: vec3<f32>,
    exposure: f32,
}

struct ToneOutput {
    mapped: array<vec4<f32>, 3>,
    srgb: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> inputs: array<ToneInput>;
@group(0) @binding(1) var<storage, read_write> outputs: array<ToneOutput>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    let x = inputs[i];
    var o: ToneOutput;
    let aces = tonemap_aces_fitted(x.linear, x.exposure);
    o.mapped[0] = vec4<f32>(aces, 0.0);
    o.mapped[1] = vec4<f32>(tonemap_pbr_neutral(x.linear, x.exposure), 0.0);
    o.mapped[2] = vec4<f32>(tonemap_clamp(x.linear, x.exposure), 0.0);
    o.srgb = vec4<f32>(linear_to_srgb(aces.x), linear_to_srgb(aces.y), linear_to_srgb(aces.z), 0.0);
    outputs[i] = o;
}
"#;

fn random_input(rng: &mut Pcg32) -> ToneInput {
    let scale = 10f32.powf(rng.next_f32() * 15.0 - 6.0);
    let mut linear = match rng.next_u32() % 4 {
        0 => Vec3::splat(scale),
        1 => Vec3::new(scale, 0.0, 0.0),
        _ => Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * scale,
    };
    if rng.next_u32().is_multiple_of(50) {
        let bad = [f32::NAN, f32::INFINITY, -1.0, f32::MAX];
        linear[(rng.next_u32() % 3) as usize] = bad[(rng.next_u32() % 4) as usize];
    }
    let exposure = match rng.next_u32() % 40 {
        0 => f32::NAN,
        1 => 0.0,
        2 => -1.0,
        3 => f32::INFINITY,
        _ => 2f32.powf(rng.next_f32() * 20.0 - 10.0),
    };
    ToneInput {
        linear: linear.to_array(),
        exposure,
    }
}

#[test]
fn wgsl_tonemappers_match_chiaro_shading() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let mut rng = Pcg32::new(0x70e, 5);
    let inputs: Vec<ToneInput> = (0..INPUTS).map(|_| random_input(&mut rng)).collect();
    let kernel = Kernel::new(&gpu, "tonemap parity", KERNEL);
    let outputs: Vec<ToneOutput> = kernel.map(&gpu, &inputs);
    let mut worst = [0.0f32; 4];
    for (x, g) in inputs.iter().zip(&outputs) {
        let linear = Vec3::from_array(x.linear);
        for (k, t) in [
            Tonemapper::AcesFitted,
            Tonemapper::PbrNeutral,
            Tonemapper::Clamp,
        ]
        .into_iter()
        .enumerate()
        {
            let cpu = t.apply(linear, x.exposure);
            let gv = Vec3::from_slice(&g.mapped[k][..3]);
            assert!(
                gv.is_finite() && gv.min_element() >= 0.0 && gv.max_element() <= 1.0,
                "{t:?}: {gv} for {x:?}"
            );
            let e = (gv - cpu).abs().max_element();
            assert!(e <= ABS_TOL, "{t:?}: {gv} vs {cpu} for {x:?}");
            worst[k] = worst[k].max(e);
        }
        let aces = Tonemapper::AcesFitted.apply(linear, x.exposure);
        for c in 0..3 {
            let e = (g.srgb[c] - linear_to_srgb(aces[c])).abs();
            assert!(e <= ABS_TOL, "sRGB {:?} vs {aces} for {x:?}", g.srgb);
            worst[3] = worst[3].max(e);
        }
    }
    eprintln!("{INPUTS} inputs: worst absolute error (ACES, Neutral, clamp, sRGB) {worst:?}");
}
