// Indirect light per pixel of the G-buffer: the mean over `spp` paths of the light that the
// surface the camera sees reflects and that the direct pass does not count, by path tracing
// (Kajiya, "The Rendering Equation", SIGGRAPH 1986), written as is (not demodulated).
//
// Default (realtime and reference modes): the path leaves the primary surface x0 by BRDF
// importance sampling (GGX visible normals: Heitz, "Sampling the GGX Distribution of Visible
// Normals", JCGT 7(4), 2018, through brdf_sample); at each further vertex x1 .. x_bounces it
// adds next-event estimation (one light: a punctual light or an area-light or environment
// sample, lib/next_event.wgsl's next_event) and the emission or environment that the next
// BRDF-sampled ray reaches, the two combined by multiple importance sampling with the power
// heuristic (Veach, "Robust Monte Carlo Methods for Light Transport Simulation", PhD thesis,
// Stanford, 1997, chapter 9). The emission the
// primary vertex's own BRDF ray reaches, and the light sampled at x0, are the direct pass's.
// So direct + indirect with `bounces` = b is chiaro_reference's path tracer with max_depth
// b + 1 (scattering at x0 .. x_b, emission reached up to x_(b+1)).
//
// Naive (`naive` = 1, the path tracing notes' baseline): every vertex from x0 on continues in a
// direction uniform over the hemisphere of its shading normal (pdf 1 / (2 pi), weight
// f cos / pdf); emission and environment count with weight 1 wherever a ray reaches them; no
// light sampling at all. Its output is all the light x0 reflects (the direct pass then writes
// none). Perfect mirrors (a delta lobe) reflect nothing to it: uniform directions never find
// the mirror direction.
//
// Both: Russian roulette as chiaro_reference's integrator (after the BRDF sample at vertex
// x_d for d + 1 >= RUSSIAN_ROULETTE_FROM, survival max(throughput) clamped to
// [RUSSIAN_ROULETTE_MIN, 1], survivors divided by it), so the estimate stays unbiased.
//
// The first path (not in naive mode) leaves x0 along the direct pass's BRDF ray and takes its
// hit from first_bounce (lib/first_bounce.wgsl) instead of tracing it again; the other paths
// draw and trace their own.
//
// Random numbers: one PCG32 per pixel and frame, on the direct pass's stream (pixel index,
// frame) at the seed XOR INDIRECT_SEED, for the reason lib/first_bounce.wgsl gives for its
// own; the first path's first direction as lib/first_bounce.wgsl draws it.
//
// Firefly clamp (`firefly_clamp` > 0, realtime mode only): a path whose contribution has a
// luminance above the clamp is scaled down to it, its colour kept. This trades the rare very
// bright paths (noise the denoiser spreads into blotches) for a loss of energy (bias).
//
// Test hook: with `poison` nonzero, pixel (0, 0) writes NaN and pixel (1, 0) writes +infinity
// (what the denoiser's non-finite guard must keep out of its history).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/rng_source.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_inputs.wgsl
#import lib/surface.wgsl
#import lib/color.wgsl
#import lib/first_bounce.wgsl
#import lib/path.wgsl
#import lib/lane_tiles.wgsl

// lib/next_event.wgsl's hook.
fn light_tree_sampling() -> bool {
    return params.light_sampling == LIGHT_SAMPLING_TREE;
}

@group(1) @binding(4) var<storage, read> params: IndirectParams;
@group(1) @binding(5) var indirect_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(6) var first_bounce: texture_2d<u32>;

// The sum over `spp` paths from x0 of the light each counts, each scaled down to the firefly
// clamp. One loop steps whichever path each invocation is on and starts the next where one
// ends (path regeneration: Novak, Havran and Dachsbacher, "Path Regeneration for Interactive
// Path Tracing", Eurographics 2010 short papers): the invocations that run as one SIMD vector
// (or subgroup) take as many steps as the longest of their sums of path lengths, not the sum
// of their longest paths. Each invocation draws its numbers in the same order as path after
// path, so the estimate is the same.
fn trace_paths(x0: Shading, rng: ptr<function, Rng>, first: FirstBounce, spp: u32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    var path = path_from(x0);
    var done = 0u;
    loop {
        if !path_step(&path, rng, done == 0u, first) {
            sum += clamp_luminance(path.total, params.firefly_clamp);
            done += 1u;
            if done == spp {
                break;
            }
            path = path_from(x0);
            rng_start_stream(rng, RNG_STREAM_PATHS + done);
        }
    }
    return sum;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(workgroup_id) workgroup: vec3<u32>, @builtin(local_invocation_index) local_index: u32) {
    let id = lane_tile_pixel(workgroup, local_index);
    let size = textureDimensions(indirect_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    if params.poison != 0u && id.y == 0u && id.x < 2u {
        let poison = select(bitcast<f32>(0x7fc00000u), f32_infinity(), id.x == 1u);
        textureStore(indirect_out, pixel, vec4<f32>(vec3<f32>(poison), 1.0));
        return;
    }
    let texels = gbuffer_load(pixel);
    var radiance = vec3<f32>(0.0);
    if gbuffer_covered(texels) {
        let g = gbuffer_unpack(texels);
        if g.shades && params.spp > 0u {
            let x0 = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
            let start = path_start(id.y * size.x + id.x, textureLoad(first_bounce, pixel, 0));
            var rng = start.rng;
            // `spp` is loaded once, before the loop over paths, and passed in: a load inside a
            // loop that invocations leave at different iterations must not be read again
            // after it. llvmpipe's GL driver (Mesa 22.3) reused the loop's load of params.spp
            // after the loop, where it read 0 for the invocations that had left earlier:
            // radiance 0 / 0, a NaN the composite's guard turned black (docs/architecture.md,
            // "Portability").
            let spp = params.spp;
            radiance = trace_paths(x0, &rng, start.first, spp) / f32(spp);
        }
    }
    textureStore(indirect_out, pixel, vec4<f32>(radiance, 1.0));
}
