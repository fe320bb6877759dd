//! lib/coverage.wgsl against chiaro_shading::coverage: for random and extreme inputs, the GPU's
//! coverage numbers of rays and fragments equal the CPU's bit for bit.

mod common;
mod kernel;

use chiaro_shading::coverage::{fragment_number, ray_number};
use chiaro_shading::rng::Pcg32;
use glam::{UVec2, Vec3};
use kernel::{Input, Kernel, Output};

const KERNEL: &str = r#"
#import lib/coverage.wgsl

// Per case: origin xyz, instance; direction xyz, triangle (f32 bits as u32).
@group(0) @binding(0) var<storage, read> cases: array<array<vec4<u32>, 2>>;
@group(0) @binding(1) var<storage, read_write> numbers: array<vec2<u32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&cases) {
        return;
    }
    let a = cases[i][0];
    let b = cases[i][1];
    let ray = coverage_ray_number(bitcast<vec3<f32>>(a.xyz), bitcast<vec3<f32>>(b.xyz), a.w, b.w);
    let fragment = coverage_fragment_number(a.xy, a.z, a.w, bitcast<f32>(b.x));
    numbers[i] = vec2<u32>(bitcast<u32>(ray), bitcast<u32>(fragment));
}
"#;

#[test]
fn gpu_coverage_numbers_equal_the_cpu_bit_for_bit() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    // Finite floats only (a NaN's bits need not survive a driver's float registers); the two
    // indices take any value.
    let big = f32::MAX.to_bits();
    let mut cases: Vec<[u32; 8]> = vec![[0; 8], [big, big, big, u32::MAX, big, big, big, u32::MAX]];
    let mut rng = Pcg32::new(34, 1);
    while cases.len() < 4096 {
        let mut float = || ((rng.next_f32() - 0.5) * 2e3).to_bits();
        let (o, d) = ([float(), float(), float()], [float(), float(), float()]);
        cases.push([
            o[0],
            o[1],
            o[2],
            rng.next_u32(),
            d[0],
            d[1],
            d[2],
            rng.next_u32(),
        ]);
    }
    let kernel = Kernel::new(&gpu, "coverage parity", KERNEL);
    let bytes = kernel.run(
        &gpu,
        &[Input {
            group: 0,
            binding: 0,
            data: bytemuck::cast_slice(&cases),
        }],
        &Output {
            group: 0,
            binding: 1,
            size: (cases.len() * 8) as u64,
        },
        cases.len() as u32,
    );
    let got: &[[u32; 2]] = bytemuck::cast_slice(&bytes);
    for (c, g) in cases.iter().zip(got) {
        let f = |k: usize| f32::from_bits(c[k]);
        let ray = ray_number(
            Vec3::new(f(0), f(1), f(2)),
            Vec3::new(f(4), f(5), f(6)),
            c[3],
            c[7],
        );
        let fragment = fragment_number(UVec2::new(c[0], c[1]), c[2], c[3], f(4));
        assert_eq!(*g, [ray.to_bits(), fragment.to_bits()], "case {c:?}");
    }
}
