// PCG32 (XSH-RR 64/32): O'Neill, 2014, "PCG: A Family of Simple Fast Space-Efficient
// Statistically Good Algorithms for Random Number Generation".
//
// Mirrors chiaro_shading::rng::Pcg32 bit for bit. WGSL has no 64-bit integers: the state and
// the increment are vec2<u32> (x = low 32 bits, y = high 32 bits), and the LCG step
// state * PCG32_MULTIPLIER + inc (mod 2^64) is built from 32x32 -> 64 products on 16-bit limbs.

#import lib/generated.wgsl

// 2^-24 exactly: maps a 24-bit integer to [0, 1) without rounding.
const PCG32_INV_2_POW_24: f32 = 0x1p-24f;

struct Pcg32 {
    // 64-bit LCG state, (low, high).
    state: vec2<u32>,
    // 64-bit increment, (low, high); always odd.
    inc: vec2<u32>,
}

// The full 64-bit product of two u32, as (low, high).
fn pcg32_mul_wide(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    // Below 3 * 2^16 + 2^16: no overflow.
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    let lo = (mid << 16u) | (p00 & 0xffffu);
    let hi = p11 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
    return vec2<u32>(lo, hi);
}

// a * b + c (mod 2^64) on (low, high) pairs.
fn pcg32_mul_add64(a: vec2<u32>, b: vec2<u32>, c: vec2<u32>) -> vec2<u32> {
    let low = pcg32_mul_wide(a.x, b.x);
    // The cross terms only reach the high word; their high halves wrap out.
    let product = vec2<u32>(low.x, low.y + a.x * b.y + a.y * b.x);
    let sum_lo = product.x + c.x;
    let carry = select(0u, 1u, sum_lo < product.x);
    return vec2<u32>(sum_lo, product.y + c.y + carry);
}

// Advances the LCG by one step.
fn pcg32_step(rng: ptr<function, Pcg32>) {
    let multiplier = vec2<u32>(PCG32_MULTIPLIER_LO, PCG32_MULTIPLIER_HI);
    (*rng).state = pcg32_mul_add64((*rng).state, multiplier, (*rng).inc);
}

// The generator for `seed` on `stream` (both 64-bit, (low, high)); only the low 63 bits of the
// stream matter. Same as the reference pcg32_srandom_r(seed, stream) and Pcg32::new.
fn pcg32_new(seed: vec2<u32>, stream: vec2<u32>) -> Pcg32 {
    var rng: Pcg32;
    rng.state = vec2<u32>(0u, 0u);
    rng.inc = vec2<u32>((stream.x << 1u) | 1u, (stream.y << 1u) | (stream.x >> 31u));
    pcg32_step(&rng);
    let sum_lo = rng.state.x + seed.x;
    let carry = select(0u, 1u, sum_lo < rng.state.x);
    rng.state = vec2<u32>(sum_lo, rng.state.y + seed.y + carry);
    pcg32_step(&rng);
    return rng;
}

// The next 32 uniformly distributed bits.
fn pcg32_next_u32(rng: ptr<function, Pcg32>) -> u32 {
    let old = (*rng).state;
    pcg32_step(rng);
    // x = (old >> 18) ^ old as a 64-bit value, then bits 27..58 of it.
    let shifted_lo = (old.x >> 18u) | (old.y << 14u);
    let shifted_hi = old.y >> 18u;
    let x_lo = shifted_lo ^ old.x;
    let x_hi = shifted_hi ^ old.y;
    let xorshifted = (x_lo >> 27u) | (x_hi << 5u);
    // old >> 59.
    let rotation = old.y >> 27u;
    return (xorshifted >> rotation) | (xorshifted << ((32u - rotation) & 31u));
}

// A uniform float in [0, 1): the top 24 bits times 2^-24, exact, never 1.
fn pcg32_next_f32(rng: ptr<function, Pcg32>) -> f32 {
    return f32(pcg32_next_u32(rng) >> 8u) * PCG32_INV_2_POW_24;
}

// Two uniform floats in [0, 1): x drawn first, then y.
fn pcg32_next_vec2(rng: ptr<function, Pcg32>) -> vec2<f32> {
    let x = pcg32_next_f32(rng);
    let y = pcg32_next_f32(rng);
    return vec2<f32>(x, y);
}
