//! lib/gbuffer_packing.wgsl's motion vectors, two f16 packed by hand in a u32: on the GPU each
//! component comes back within f16's rounding (half an ulp, 2^-11 relative; below f16's least
//! normal, zero), its bits decode on the CPU (`half`) to what the GPU decodes, and a motion out
//! of f16's range or not finite comes back infinite, so the readers take no history there.

mod common;
mod kernel;

use chiaro_shading::rng::Pcg32;
use kernel::Kernel;

const KERNEL: &str = r#"
#import lib/gbuffer_packing.wgsl

@group(0) @binding(0) var<storage, read> motions: array<vec2<f32>>;
// Per motion: the packed bits, then the unpacked x and y bits.
@group(0) @binding(1) var<storage, read_write> out: array<vec4<u32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&motions) {
        return;
    }
    let packed = motion_pack(motions[i]);
    out[i] = vec4<u32>(packed, bitcast<vec2<u32>>(motion_unpack(packed)), 0u);
}
"#;

/// f16's least normal.
const LEAST_NORMAL: f32 = 6.103_515_6e-5;

#[test]
fn motion_vectors_round_trip_within_f16_rounding() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let mut motions = vec![
        [0.0, -0.0],
        [0.5, -0.25],
        [1e-6, -3e-5],
        [64.3, -1000.7],
        [64_999.0, -64_999.0],
        [0.499_9, 3.999_9],
    ];
    let mut rng = Pcg32::new(7, 3);
    while motions.len() < 4096 {
        let component = |rng: &mut Pcg32| {
            let magnitude = 10f32.powf(rng.next_f32() * 9.0 - 5.0);
            if rng.next_f32() < 0.5 {
                -magnitude
            } else {
                magnitude
            }
        };
        let m = [component(&mut rng), component(&mut rng)];
        if m.iter().all(|c| c.abs() < 65_000.0) {
            motions.push(m);
        }
    }
    let bad = [
        [70_000.0, 0.0],
        [0.0, -1e9],
        [f32::INFINITY, 1.0],
        [f32::NAN, 1.0],
    ];
    let inputs: Vec<[f32; 2]> = motions.iter().chain(&bad).copied().collect();
    let kernel = Kernel::new(&gpu, "motion parity", KERNEL);
    let out: Vec<[u32; 4]> = kernel.map(&gpu, &inputs);
    for (m, o) in motions.iter().zip(&out) {
        for k in 0..2 {
            let (x, back) = (m[k], f32::from_bits(o[1 + k]));
            let tolerance = if x.abs() < LEAST_NORMAL {
                LEAST_NORMAL
            } else {
                x.abs() * 2f32.powi(-11)
            };
            assert!((back - x).abs() <= tolerance, "{x} came back {back}");
            let bits = (o[0] >> (16 * k)) as u16;
            assert_eq!(
                half::f16::from_bits(bits).to_f32(),
                back,
                "{x}: bits {bits:#06x}"
            );
        }
    }
    for (m, o) in bad.iter().zip(&out[motions.len()..]) {
        let back = [f32::from_bits(o[1]), f32::from_bits(o[2])];
        assert!(
            back.iter().all(|c| c.is_infinite()),
            "{m:?} came back {back:?}"
        );
    }
}
