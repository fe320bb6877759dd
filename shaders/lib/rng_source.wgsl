// Where a pass's random numbers come from: a PCG32 stream (the realtime and naive modes, and
// the reference mode with FrameSettings::sampler independent) or Owen-scrambled Sobol draws
// (the reference mode's default; lib/owen_sobol.wgsl), as chiaro_reference's samplers.
//
// With Sobol, a pixel's samples are the frames accumulated (the sample index), every draw is a
// dimension of its own, and the dimensions are numbered by stream: the direct pass's draws at
// the primary surface, the BRDF sample there that both passes take (lib/first_bounce.wgsl), and
// each indirect path's draws, each stream from its own first dimension. Both passes draw the
// same numbers for the same dimension, and every dimension's samples are the sequence's first
// points, so each draw stays stratified over the frames.

#import lib/rng.wgsl
#import lib/owen_sobol.wgsl

// Dimension streams (the stream number is the high half of a dimension's number).
const RNG_STREAM_DIRECT: u32 = 0u;
const RNG_STREAM_FIRST_BOUNCE: u32 = 1u;
// Indirect path k (0 first) draws from stream RNG_STREAM_PATHS + k.
const RNG_STREAM_PATHS: u32 = 2u;

struct Rng {
    pcg: Pcg32,
    // 1: Sobol draws (key, index, dimension); 0: the PCG32 stream.
    sobol: u32,
    key: u32,
    index: u32,
    dimension: u32,
}

// The numbers of pixel `pixel` at sample `index` (the frame): `pcg` with sobol 0, else the
// Sobol draws of the seed's sequence for the pixel, from the start of `stream`.
fn rng_new(pcg: Pcg32, sobol: u32, seed: vec2<u32>, pixel: u32, index: u32, stream: u32) -> Rng {
    var key = 0u;
    if sobol != 0u {
        key = owen_sobol_pixel_key(seed, pixel);
    }
    return Rng(pcg, sobol, key, index, stream << 16u);
}

// Sobol draws go on from the start of `stream`; the PCG32 stream goes on.
fn rng_start_stream(rng: ptr<function, Rng>, stream: u32) {
    (*rng).dimension = stream << 16u;
}

// (The PCG32 state is copied out and back: naga's SPIR-V writer fails on a pointer to a struct
// member passed to a function.)
fn rng_next_f32(rng: ptr<function, Rng>) -> f32 {
    if (*rng).sobol == 0u {
        var pcg = (*rng).pcg;
        let u = pcg32_next_f32(&pcg);
        (*rng).pcg = pcg;
        return u;
    }
    let u = owen_sobol_draw1((*rng).key, (*rng).dimension, (*rng).index);
    (*rng).dimension += 1u;
    return u;
}

fn rng_next_vec2(rng: ptr<function, Rng>) -> vec2<f32> {
    if (*rng).sobol == 0u {
        var pcg = (*rng).pcg;
        let u = pcg32_next_vec2(&pcg);
        (*rng).pcg = pcg;
        return u;
    }
    let u = owen_sobol_draw2((*rng).key, (*rng).dimension, (*rng).index);
    (*rng).dimension += 1u;
    return u;
}

// A choice (x) and the two numbers of the chosen one's warp (yz), one draw: with PCG32 the
// next number, then the next two.
fn rng_next_choice_vec2(rng: ptr<function, Rng>) -> vec3<f32> {
    if (*rng).sobol == 0u {
        var pcg = (*rng).pcg;
        let choice = pcg32_next_f32(&pcg);
        let u = pcg32_next_vec2(&pcg);
        (*rng).pcg = pcg;
        return vec3<f32>(choice, u);
    }
    let u = owen_sobol_draw3((*rng).key, (*rng).dimension, (*rng).index);
    (*rng).dimension += 1u;
    return u;
}
