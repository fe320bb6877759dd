// Resampled direct light, second pass (ReSTIR DI: Bitterli et al., "Spatiotemporal Reservoir
// Resampling for Real-Time Ray Tracing with Dynamic Direct Lighting", SIGGRAPH 2020,
// algorithms 3 and 4): each pixel's reservoir of the first pass (restir_temporal.wgsl) merged
// with those of `spatial_samples` neighbours drawn uniformly in a disc of `spatial_radius`
// pixels, each only where its surface is similar (view depth within 10%, normals within 25
// degrees).
//
// Bias: with unbiased = 0 each reservoir enters with weight target-here x W x M and the sum is
// normalised by the total M (1/M): biased where a neighbour cannot produce the sample kept (a
// sample below its horizon, or on an emitter's back as it sees it), which darkens creases. With
// unbiased = 1 each enters with the generalised balance heuristic's weight, M_i p_i(x_i) over
// the sum over the reservoirs j of M_j p_j(x_i), where p_j is reservoir j's surface's target
// (Lin et al., "Generalized Resampled Importance Sampling", SIGGRAPH 2022, section 5; the
// targets are unshadowed, so no visibility ray is needed): unbiased, and without the fireflies
// of Bitterli et al.'s 1/Z where few neighbours can produce a sample, at the cost of the
// square of the reservoirs' count in target evaluations. The frame uses it where it converges
// (the direct mode, a still view: chiaro_gpu::passes::restir).
//
// Writes the final reservoirs, which the direct pass shades (one shadow ray) and the next
// frame's first pass merges, and the surface each belongs to.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/rng.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/gbuffer_inputs.wgsl
#import lib/surface.wgsl
#import lib/next_event.wgsl
#import lib/reservoir.wgsl
#import lib/reservoir_neighbours.wgsl
#import lib/lane_tiles.wgsl

@group(1) @binding(4) var<storage, read> params: RestirParams;
@group(1) @binding(5) var reservoirs_out: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(6) var surfaces_out: texture_storage_2d<rgba32uint, write>;
// The first pass's reservoirs.
@group(1) @binding(7) var reservoirs_in: texture_2d<u32>;

// This pixel and the most neighbours merged (FrameSettings validation keeps spatial_samples
// within it).
const MAX_DOMAINS: u32 = 9u;
// Keeps this pass's numbers apart from the first pass's and the direct pass's.
const RESTIR_SPATIAL_SEED: vec2<u32> = vec2<u32>(0x68e31da4u, 0xb5297a4du);

// lib/next_event.wgsl's hook.
fn light_tree_sampling() -> bool {
    return params.light_sampling == LIGHT_SAMPLING_TREE;
}

// The target of the sample (entry, u) at the surface pixel q sees.
fn target_at(q: vec2<i32>, entry: u32, u: vec2<f32>) -> f32 {
    let at = gbuffer_shading(gbuffer_unpack(gbuffer_load(q)), gbuffer_triangle_at(q), camera);
    return restir_target(at, restir_light_at(at, entry, u));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(workgroup_id) workgroup: vec3<u32>, @builtin(local_invocation_index) local_index: u32) {
    let id = lane_tile_pixel(workgroup, local_index);
    let size = textureDimensions(reservoirs_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let texels = gbuffer_load(pixel);
    let own = reservoir_unpack(textureLoad(reservoirs_in, pixel, 0));
    let g = gbuffer_unpack(texels);
    if !gbuffer_covered(texels) || !g.shades {
        textureStore(reservoirs_out, pixel, reservoir_pack(reservoir_empty()));
        textureStore(surfaces_out, pixel, reservoir_no_surface());
        return;
    }
    let s = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
    let depth = reservoir_depth(camera, g.position);
    let index = id.y * size.x + id.x;
    let seed = vec2<u32>(params.seed_lo, params.seed_hi) ^ RESTIR_SPATIAL_SEED;
    var rng = pcg32_new(seed, vec2<u32>(index, params.frame));

    // Domain 0 is this pixel, then the similar neighbours found.
    var pixels: array<vec2<i32>, MAX_DOMAINS>;
    var found_reservoirs: array<Reservoir, MAX_DOMAINS>;
    pixels[0] = pixel;
    found_reservoirs[0] = own;
    var found = 1u;
    for (var i = 0u; i < min(params.spatial_samples, MAX_DOMAINS - 1u); i++) {
        let n = reservoir_neighbour(pixel, size, pcg32_next_vec2(&rng), params.spatial_radius,
            depth, g.shading_normal);
        if !n.found {
            continue;
        }
        let q = n.pixel;
        pixels[found] = q;
        found_reservoirs[found] = reservoir_unpack(textureLoad(reservoirs_in, q, 0));
        found += 1u;
    }

    var r = reservoir_empty();
    var kept_target = 0.0;
    for (var i = 0u; i < found; i++) {
        let other = found_reservoirs[i];
        let rand = pcg32_next_f32(&rng);
        if other.entry == RESERVOIR_NO_SAMPLE {
            r.count += other.count;
            continue;
        }
        let here = restir_target(s, restir_light_at(s, other.entry, other.u));
        var weight = here * other.contribution_weight;
        if params.unbiased != 0u {
            // The generalised balance heuristic: M_i p_i(x_i) over the sum of M_j p_j(x_i).
            var own_term = 0.0;
            var total = 0.0;
            for (var j = 0u; j < found; j++) {
                var t = here;
                if j > 0u {
                    t = target_at(pixels[j], other.entry, other.u);
                }
                let term = f32(found_reservoirs[j].count) * t;
                total += term;
                if j == i {
                    own_term = term;
                }
            }
            weight *= select(0.0, own_term / total, total > 0.0);
        } else {
            weight *= f32(other.count);
        }
        if reservoir_stream(&r, other.entry, other.u, weight, other.count, rand) {
            kept_target = here;
        }
    }
    // 1/M, or the balance heuristic's weights already sum to one.
    let normaliser = select(r.count, 1u, params.unbiased != 0u);
    reservoir_finish(&r, kept_target, normaliser);
    textureStore(reservoirs_out, pixel, reservoir_pack(r));
    textureStore(surfaces_out, pixel, reservoir_surface_pack(depth, g.shading_normal));
}
