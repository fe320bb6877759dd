// Resampled indirect light, second pass (ReSTIR GI: Ouyang et al., HPG 2021, algorithm 4):
// each pixel resamples its own reservoir (restir_gi_initial.wgsl: its path's sample, merged
// with last frame's where temporal reuse is on) and those of `indirect_spatial_samples`
// neighbours drawn uniformly in a disc of `spatial_radius` pixels whose surfaces are similar
// (lib/reservoir.wgsl's test), each by the target f cos L cos_y / d^2 in the area measure at
// the samples' points (lib/gi_sample.wgsl) times its W times its M, normalised by the sum of
// the counts (1/M). It shades the survivor and writes the frame's indirect light.
// A neighbour's survivor is tested by one visibility ray; where the pixel cannot see it, the
// pixel shades its own reservoir's sample instead.
//
// Bias: a neighbour's sample assumes its point reflects the same light toward this pixel (a
// diffuse point); the target has no visibility, so the weight of a sample the pixel cannot
// see goes to its own path; 1/M counts neighbours that could not have drawn this pixel's
// samples. A neighbour's sample whose distance and angle differ so much that its weight here
// is over GI_JACOBIAN_MAX times (or under 1 / GI_JACOBIAN_MAX of) its weight there is left
// out, as Ouyang et al. reject large Jacobians. On the Cornell box at 32 x 32 (4 neighbours
// within 4 pixels, 128 frames) the image's mean indirect light is 1.3% dark (2.7% when an
// occluded survivor shades nothing, 4.6% when rejected samples count in M; tests/restir_gi.rs).
// Where the frame converges (a still view's running mean), no neighbour is drawn: each pixel
// shades its own path, the path tracer's estimate, so the mean converges to the reference
// (chiaro_gpu::passes::restir).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/rng.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/gbuffer_inputs.wgsl
#import lib/surface.wgsl
#import lib/next_event.wgsl
#import lib/color.wgsl
#import lib/reservoir.wgsl
#import lib/reservoir_neighbours.wgsl
#import lib/gi_sample.wgsl
#import lib/lane_tiles.wgsl

@group(1) @binding(4) var<storage, read> params: RestirParams;
@group(1) @binding(5) var indirect_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(6) var reservoirs: texture_storage_2d<rgba32uint, read>;

// Most neighbours (FrameSettings validation keeps indirect_spatial_samples within it).
const GI_MAX_NEIGHBOURS: u32 = 8u;
// Most ratio of a reused sample's area-to-solid-angle factor here and at its pixel.
const GI_JACOBIAN_MAX: f32 = 10.0;
// Keeps this pass's numbers apart from the other passes'.
const RESTIR_GI_SEED: vec2<u32> = vec2<u32>(0x94d049bbu, 0x133111ebu);

// lib/next_event.wgsl's hook.
fn light_tree_sampling() -> bool {
    return params.light_sampling == LIGHT_SAMPLING_TREE;
}

fn reservoir_at(pixel: vec2<i32>) -> GiReservoir {
    return gi_reservoir_unpack(textureLoad(reservoirs, gi_reservoir_texel(pixel, 0)),
        textureLoad(reservoirs, gi_reservoir_texel(pixel, 1)),
        textureLoad(reservoirs, gi_reservoir_texel(pixel, 2)));
}

// Whether a sample drawn at the point `there` may be reused at s: the ratio of the
// area-to-solid-angle factors is within GI_JACOBIAN_MAX (a sample of weight 0 always may).
fn gi_jacobian_bounded(s: Shading, there: vec3<f32>, sample: GiSample) -> bool {
    if sample.weight == 0.0 {
        return true;
    }
    let here_factor = gi_geometry(s.position, sample);
    let there_factor = gi_geometry(there, sample);
    return here_factor <= GI_JACOBIAN_MAX * there_factor
        && there_factor <= GI_JACOBIAN_MAX * here_factor;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(workgroup_id) workgroup: vec3<u32>, @builtin(local_invocation_index) local_index: u32) {
    let id = lane_tile_pixel(workgroup, local_index);
    let size = textureDimensions(indirect_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let texels = gbuffer_load(pixel);
    let g = gbuffer_unpack(texels);
    let own_reservoir = reservoir_at(pixel);
    let own = own_reservoir.sample;
    var radiance = vec3<f32>(0.0);
    if !gbuffer_covered(texels) || !g.shades {
        // Nothing to shade.
    } else if !gi_sample_reusable(own) {
        radiance = own.radiance;
    } else {
        let s = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
        let depth = reservoir_depth(camera, g.position);
        let index = id.y * size.x + id.x;
        let seed = vec2<u32>(params.seed_lo, params.seed_hi) ^ RESTIR_GI_SEED;
        var rng = pcg32_new(seed, vec2<u32>(index, params.frame));
        var r = gi_resampling_start(own, luminance(gi_value(s, own)),
            max(own_reservoir.count, 1u));
        var kept_own = true;
        for (var i = 0u; i < min(params.indirect_spatial_samples, GI_MAX_NEIGHBOURS); i++) {
            let n = reservoir_neighbour(pixel, size, pcg32_next_vec2(&rng), params.spatial_radius,
                depth, g.shading_normal);
            let rand = pcg32_next_f32(&rng);
            if !n.found {
                continue;
            }
            let neighbour = reservoir_at(n.pixel);
            let other = neighbour.sample;
            if !gi_sample_reusable(other) {
                continue;
            }
            if !gi_jacobian_bounded(s, n.position, other) {
                continue;
            }
            let here = luminance(gi_value(s, other));
            if gi_resampling_add(&r, other, here, neighbour.count, rand) {
                kept_own = false;
            }
        }
        let contribution_weight = gi_resampling_weight(r);
        if contribution_weight > 0.0 {
            let kept = r.kept;
            radiance = gi_value(s, kept) * contribution_weight;
            if !kept_own {
                let to_point = kept.point - s.position;
                let distance = length(to_point);
                if !unoccluded(s, to_point / distance, distance) {
                    radiance = gi_value(s, own) * own.weight;
                }
            }
            radiance = clamp_luminance(radiance, params.firefly_clamp);
        }
    }
    if !vec3_is_finite(radiance) {
        radiance = vec3<f32>(0.0);
    }
    textureStore(indirect_out, pixel, vec4<f32>(radiance, 1.0));
}
