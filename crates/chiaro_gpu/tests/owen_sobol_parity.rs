//! lib/owen_sobol.wgsl against chiaro_shading::owen_sobol: for many (seed, pixel, dimension,
//! sample index) quadruples, random and extreme, the GPU's one-, two- and three-number draws
//! equal the CPU's bit for bit.

mod common;
mod kernel;

use chiaro_shading::owen_sobol::{draw1, draw2, draw3, pixel_key};
use chiaro_shading::rng::Pcg32;
use kernel::{Input, Kernel, Output};

/// Words per quadruple: the key, draw1, draw2 (two), draw3 (three).
const WORDS: usize = 7;

const KERNEL: &str = r#"
#import lib/owen_sobol.wgsl

// (seed low, seed high, pixel, dimension) and the sample index, per quadruple.
@group(0) @binding(0) var<storage, read> inputs: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> draws: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if 2u * i >= arrayLength(&inputs) {
        return;
    }
    let q = inputs[2u * i];
    let index = inputs[2u * i + 1u].x;
    let key = owen_sobol_pixel_key(q.xy, q.z);
    let one = owen_sobol_draw1(key, q.w, index);
    let two = owen_sobol_draw2(key, q.w, index);
    let three = owen_sobol_draw3(key, q.w, index);
    let at = i * 7u;
    draws[at] = key;
    draws[at + 1u] = bitcast<u32>(one);
    draws[at + 2u] = bitcast<u32>(two.x);
    draws[at + 3u] = bitcast<u32>(two.y);
    draws[at + 4u] = bitcast<u32>(three.x);
    draws[at + 5u] = bitcast<u32>(three.y);
    draws[at + 6u] = bitcast<u32>(three.z);
}
"#;

#[test]
fn gpu_draws_equal_the_cpu_bit_for_bit() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    // (seed low, seed high, pixel, dimension, index): extreme ones first, then the first
    // samples of a few pixels and dimensions as the passes draw them, then random ones.
    let mut cases: Vec<[u32; 5]> = vec![
        [0, 0, 0, 0, 0],
        [u32::MAX, u32::MAX, u32::MAX, u32::MAX, u32::MAX],
        [1, 0, 0, 1 << 16, 1 << 31],
        [0, 1, 7, (2 << 16) | 3, 0x5555_5555],
    ];
    for pixel in 0..4 {
        for dimension in [0, 1, 1 << 16, 2 << 16, (3 << 16) | 5] {
            for index in 0..16 {
                cases.push([42, 0, pixel, dimension, index]);
            }
        }
    }
    let mut rng = Pcg32::new(2026, 12);
    while cases.len() < 4096 {
        cases.push([0; 5].map(|_| rng.next_u32()));
    }
    let inputs: Vec<[u32; 4]> = cases
        .iter()
        .flat_map(|c| [[c[0], c[1], c[2], c[3]], [c[4], 0, 0, 0]])
        .collect();
    let kernel = Kernel::new(&gpu, "owen sobol parity", KERNEL);
    let bytes = kernel.run(
        &gpu,
        &[Input {
            group: 0,
            binding: 0,
            data: bytemuck::cast_slice(&inputs),
        }],
        &Output {
            group: 0,
            binding: 1,
            size: (cases.len() * WORDS * 4) as u64,
        },
        cases.len() as u32,
    );
    let got: &[u32] = bytemuck::cast_slice(&bytes);
    for (i, &[seed_lo, seed_hi, pixel, dimension, index]) in cases.iter().enumerate() {
        let key = pixel_key(seed_lo, seed_hi, pixel);
        let two = draw2(key, dimension, index);
        let (choice, pair) = draw3(key, dimension, index);
        let expected = [
            key,
            draw1(key, dimension, index).to_bits(),
            two.x.to_bits(),
            two.y.to_bits(),
            choice.to_bits(),
            pair.x.to_bits(),
            pair.y.to_bits(),
        ];
        assert_eq!(
            &got[i * WORDS..][..WORDS],
            expected.as_slice(),
            "seed ({seed_lo:#x}, {seed_hi:#x}) pixel {pixel} dimension {dimension:#x} index {index}"
        );
    }
    eprintln!(
        "{} quadruples, {} draws identical",
        cases.len(),
        cases.len() * WORDS
    );
}
