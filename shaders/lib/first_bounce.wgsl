// The BRDF ray that the direct pass traces from the primary surface x0, handed to the indirect
// pass, whose first path continues along it instead of tracing a ray of its own: one closest
// hit per pixel less. The direct pass counts the emission that ray reaches (MIS-weighted); the
// path counts what lies beyond, so the two together are one path tracer's BRDF-sampled step
// from x0, as chiaro_reference takes it.
//
// Both passes draw the sample's three random numbers (lobe, then the 2D direction) from one
// PCG32 generator of their own, or as one Sobol draw of its own stream (lib/rng_source.wgsl), so each computes the same brdf_sample from the same G-buffer;
// only the hit travels, in one rgba32uint texel per pixel:
// instance (FIRST_BOUNCE_NOT_TRACED where the direct pass traced no ray, BVH_NO_HIT for a
// miss), triangle, and the barycentrics' f32 bits.

#import lib/generated.wgsl
#import lib/rng_source.wgsl
#import lib/bvh.wgsl

// XORed into the frame's seed (the 64-bit golden ratio of SplitMix64, as (low, high)). The
// generator is on the direct pass's stream (pixel index, frame), at another seed: a state that
// far along the same sequence. A stream of its own would not do: PCG32 generators whose
// increments differ only in high bits have states that differ only in those bits, so their
// outputs are near copies, and the first path's direction would be correlated with the numbers
// of its later vertices.
const FIRST_BOUNCE_SEED: vec2<u32> = vec2<u32>(0x7f4a7c15u, 0x9e3779b9u);
// No ray was traced: the reader traces its own.
const FIRST_BOUNCE_NOT_TRACED: u32 = 0xfffffffeu;

// The random numbers of the BRDF sample at x0 in pixel `index` of `frame` (with `sobol` 1, the
// pixel's sample index): lobe choice in x, the direction's 2D sample in yz.
fn first_bounce_numbers(seed: vec2<u32>, index: u32, frame: u32, sobol: u32) -> vec3<f32> {
    var rng = rng_new(pcg32_new(seed ^ FIRST_BOUNCE_SEED, vec2<u32>(index, frame)), sobol, seed,
        index, frame, RNG_STREAM_FIRST_BOUNCE);
    return rng_next_choice_vec2(&rng);
}

fn first_bounce_encode(hit: Hit) -> vec4<u32> {
    return vec4<u32>(hit.instance, hit.triangle, bitcast<vec2<u32>>(hit.barycentrics));
}

fn first_bounce_not_traced() -> vec4<u32> {
    return vec4<u32>(FIRST_BOUNCE_NOT_TRACED, 0u, 0u, 0u);
}

fn first_bounce_traced(texel: vec4<u32>) -> bool {
    return texel.x != FIRST_BOUNCE_NOT_TRACED;
}

// The hit of a traced texel (its distance is not kept: 0).
fn first_bounce_decode(texel: vec4<u32>) -> Hit {
    var hit: Hit;
    hit.t = 0.0;
    hit.instance = texel.x;
    hit.triangle = texel.y;
    hit.barycentrics = bitcast<vec2<f32>>(texel.zw);
    return hit;
}
