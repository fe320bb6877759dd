//! lib/rng.wgsl against chiaro_shading::rng::Pcg32: for many (seed, stream) pairs, random and
//! extreme, the GPU's sequences of u32, f32 and vec2 draws equal the CPU's bit for bit.

mod common;
mod kernel;

use chiaro_shading::rng::Pcg32;
use kernel::{Input, Kernel, Output};

/// Draws per generator: next_u32 outputs, then next_f32 outputs, then next_vec2 outputs (two
/// floats each), all as raw bits.
const U32_DRAWS: usize = 16;
const F32_DRAWS: usize = 4;
const VEC2_DRAWS: usize = 4;
const WORDS: usize = U32_DRAWS + F32_DRAWS + 2 * VEC2_DRAWS;

const KERNEL: &str = r#"
#import lib/rng.wgsl

// (seed low, seed high, stream low, stream high) per generator.
@group(0) @binding(0) var<storage, read> seeds: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> draws: array<u32>;

const U32_DRAWS: u32 = 16u;
const F32_DRAWS: u32 = 4u;
const VEC2_DRAWS: u32 = 4u;
const WORDS: u32 = U32_DRAWS + F32_DRAWS + 2u * VEC2_DRAWS;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&seeds) {
        return;
    }
    let s = seeds[i];
    var rng = pcg32_new(s.xy, s.zw);
    var at = i * WORDS;
    for (var k = 0u; k < U32_DRAWS; k++) {
        draws[at] = pcg32_next_u32(&rng);
        at += 1u;
    }
    for (var k = 0u; k < F32_DRAWS; k++) {
        draws[at] = bitcast<u32>(pcg32_next_f32(&rng));
        at += 1u;
    }
    for (var k = 0u; k < VEC2_DRAWS; k++) {
        let v = pcg32_next_vec2(&rng);
        draws[at] = bitcast<u32>(v.x);
        draws[at + 1u] = bitcast<u32>(v.y);
        at += 2u;
    }
}
"#;

fn split(x: u64) -> [u32; 2] {
    [x as u32, (x >> 32) as u32]
}

#[test]
fn gpu_sequences_equal_the_cpu_bit_for_bit() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    // Extreme pairs first, then random ones.
    let mut pairs: Vec<(u64, u64)> = vec![
        (0, 0),
        (42, 54),
        (u64::MAX, u64::MAX),
        (u64::MAX, 0),
        (0, u64::MAX),
        (1, 1 << 63),
        (0x853c_49e6_748f_ea9b, 0xda3e_39cb_94b9_5bdb),
        (0xffff_ffff, 0xffff_ffff),
        (1 << 32, 1 << 31),
    ];
    let mut source = Pcg32::new(2024, 11);
    let mut next_u64 = || (u64::from(source.next_u32()) << 32) | u64::from(source.next_u32());
    while pairs.len() < 8192 {
        // Every fourth pair is a small consecutive seed/stream, as passes use them.
        let n = pairs.len() as u64;
        if n.is_multiple_of(4) {
            pairs.push((n, n / 4));
        } else {
            pairs.push((next_u64(), next_u64()));
        }
    }
    let seeds: Vec<[u32; 4]> = pairs
        .iter()
        .map(|&(seed, stream)| {
            let [a, b] = split(seed);
            let [c, d] = split(stream);
            [a, b, c, d]
        })
        .collect();
    let kernel = Kernel::new(&gpu, "rng parity", KERNEL);
    let bytes = kernel.run(
        &gpu,
        &[Input {
            group: 0,
            binding: 0,
            data: bytemuck::cast_slice(&seeds),
        }],
        &Output {
            group: 0,
            binding: 1,
            size: (pairs.len() * WORDS * 4) as u64,
        },
        pairs.len() as u32,
    );
    let got: &[u32] = bytemuck::cast_slice(&bytes);
    let mut compared = 0usize;
    for (i, &(seed, stream)) in pairs.iter().enumerate() {
        let mut rng = Pcg32::new(seed, stream);
        let mut expected = Vec::with_capacity(WORDS);
        expected.extend((0..U32_DRAWS).map(|_| rng.next_u32()));
        expected.extend((0..F32_DRAWS).map(|_| rng.next_f32().to_bits()));
        for _ in 0..VEC2_DRAWS {
            let v = rng.next_vec2();
            expected.extend([v.x.to_bits(), v.y.to_bits()]);
        }
        let actual = &got[i * WORDS..][..WORDS];
        assert_eq!(
            actual,
            expected.as_slice(),
            "seed {seed:#x} stream {stream:#x}"
        );
        compared += WORDS;
    }
    assert_eq!(compared, pairs.len() * WORDS);
    eprintln!("{} generators, {compared} draws identical", pairs.len());
}
