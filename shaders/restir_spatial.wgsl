// Resampled direct light, second pass (ReSTIR DI: Bitterli et al., "Spatiotemporal Reservoir
// Resampling for Real-Time Ray Tracing with Dynamic Direct Lighting", SIGGRAPH 2020,
// algorithms 3 and 4): each pixel's reservoir of the first pass (restir_temporal.wgsl) merged
// with those of `spatial_samples` neighbours drawn uniformly in a disc of `spatial_radius`
// pixels, each only where its surface is similar (view depth within 10%, normals within 25
// degrees). Each enters with weight target-here times W times M.
//
// Bias: normalising by the total M (unbiased = 0) is biased where a neighbour cannot produce
// the sample kept (a sample below its horizon, or on an emitter's back as it sees it): the
// image darkens at creases. With unbiased = 1 the sum is normalised by Z, the M of only those
// reservoirs (this pixel's and the neighbours') whose surface has a positive target for the
// sample kept (Bitterli et al., section 4.3; the targets are unshadowed, so no visibility ray
// is needed). The frame uses Z where it converges (the direct mode, a still view:
// chiaro_gpu::passes::restir).
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
#import lib/lane_tiles.wgsl

@group(1) @binding(4) var<storage, read> params: RestirParams;
@group(1) @binding(5) var reservoirs_out: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(6) var surfaces_out: texture_storage_2d<rgba32uint, write>;
// The first pass's reservoirs.
@group(1) @binding(7) var reservoirs_in: texture_2d<u32>;

// Most neighbours merged (FrameSettings validation keeps spatial_samples within it).
const MAX_NEIGHBOURS: u32 = 8u;
// Keeps this pass's numbers apart from the first pass's and the direct pass's.
const RESTIR_SPATIAL_SEED: vec2<u32> = vec2<u32>(0x68e31da4u, 0xb5297a4du);

// lib/next_event.wgsl's hook.
fn light_tree_sampling() -> bool {
    return params.light_sampling == LIGHT_SAMPLING_TREE;
}

// The shading point at a covered, shading pixel.
fn shading_at(pixel: vec2<i32>) -> Shading {
    return gbuffer_shading(gbuffer_unpack(gbuffer_load(pixel)), gbuffer_triangle_at(pixel), camera);
}

// Whether the sample (entry, u) has a positive target at the neighbour's surface: whether the
// neighbour's reservoir could have produced it.
fn could_produce(pixel: vec2<i32>, entry: u32, u: vec2<f32>) -> bool {
    let s = shading_at(pixel);
    return restir_target(s, restir_light_at(s, entry, u)) > 0.0;
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
    if !gbuffer_covered(texels) {
        textureStore(reservoirs_out, pixel, reservoir_pack(reservoir_empty()));
        textureStore(surfaces_out, pixel, reservoir_no_surface());
        return;
    }
    let g = gbuffer_unpack(texels);
    if !g.shades {
        textureStore(reservoirs_out, pixel, reservoir_pack(reservoir_empty()));
        textureStore(surfaces_out, pixel, reservoir_no_surface());
        return;
    }
    let s = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
    let depth = reservoir_depth(camera, g.position);
    let index = id.y * size.x + id.x;
    let seed = vec2<u32>(params.seed_lo, params.seed_hi) ^ RESTIR_SPATIAL_SEED;
    var rng = pcg32_new(seed, vec2<u32>(index, params.frame));

    var r = reservoir_empty();
    var kept_target = 0.0;
    if own.entry != RESERVOIR_NO_SAMPLE {
        kept_target = restir_target(s, restir_light_at(s, own.entry, own.u));
    }
    reservoir_merge(&r, own, kept_target, pcg32_next_f32(&rng));
    var neighbours: array<vec2<i32>, MAX_NEIGHBOURS>;
    var counts: array<u32, MAX_NEIGHBOURS>;
    var found = 0u;
    for (var i = 0u; i < min(params.spatial_samples, MAX_NEIGHBOURS); i++) {
        let disc = concentric_disk(pcg32_next_vec2(&rng)) * params.spatial_radius;
        let rand = pcg32_next_f32(&rng);
        let q = pixel + vec2<i32>(round(disc));
        if all(q == pixel) || any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size)) {
            continue;
        }
        let neighbour_texels = gbuffer_load(q);
        if !gbuffer_covered(neighbour_texels) {
            continue;
        }
        let n = gbuffer_unpack(neighbour_texels);
        let neighbour_surface = reservoir_surface_pack(reservoir_depth(camera, n.position), n.shading_normal);
        if !n.shades || !reservoir_surface_similar(neighbour_surface, depth, g.shading_normal) {
            continue;
        }
        let other = reservoir_unpack(textureLoad(reservoirs_in, q, 0));
        var target_value = 0.0;
        if other.entry != RESERVOIR_NO_SAMPLE {
            target_value = restir_target(s, restir_light_at(s, other.entry, other.u));
        }
        if reservoir_merge(&r, other, target_value, rand) {
            kept_target = target_value;
        }
        neighbours[found] = q;
        counts[found] = other.count;
        found += 1u;
    }
    var normaliser = r.count;
    if params.unbiased != 0u && r.entry != RESERVOIR_NO_SAMPLE {
        // Z: this pixel's M (its target for the sample is kept_target > 0) and the M of each
        // neighbour that could have produced the sample.
        normaliser = own.count;
        for (var i = 0u; i < found; i++) {
            if could_produce(neighbours[i], r.entry, r.u) {
                normaliser += counts[i];
            }
        }
    }
    reservoir_finish(&r, kept_target, normaliser);
    textureStore(reservoirs_out, pixel, reservoir_pack(r));
    textureStore(surfaces_out, pixel, reservoir_surface_pack(depth, g.shading_normal));
}
