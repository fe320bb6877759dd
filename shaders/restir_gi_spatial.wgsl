// Resampled indirect light, second pass (ReSTIR GI: Ouyang et al., HPG 2021, algorithm 4):
// each pixel resamples its own reservoir (restir_gi_initial.wgsl: its path's sample, merged
// with last frame's where temporal reuse is on) and those of `indirect_spatial_samples`
// neighbours drawn uniformly in a disc of `spatial_radius` pixels whose surfaces are similar
// (lib/reservoir.wgsl's test), each by the target f cos L cos_y / d^2 in the area measure at
// the samples' points (lib/gi_sample.wgsl) times its W times its weight. It shades the
// survivor and writes the frame's indirect light. The weights follow RestirSettings::bias:
//
// - Biased (`unbiased` = 0, the default): each reservoir by its count M, normalised by the
//   summed counts (1/M), the target without visibility. A neighbour's survivor is tested by
//   one visibility ray; where the pixel cannot see it, the pixel shades its own reservoir's
//   sample instead. 1/M counts neighbours that could not have drawn the survivor, and the
//   fallback is chosen more often where the own sample is dark: on the Cornell box at 32 x 32
//   (4 neighbours within 4 pixels, 128 frames) the mean indirect light is 1.3% dark.
// - Unbiased (`unbiased` = 1): pairwise MIS (Bitterli 2022, "Correlations and Reuse for Fast
//   and Accurate Physically Based Light Transport", PhD thesis; Lin et al. 2022, "Generalized
//   Resampled Importance Sampling"). The own reservoir is the canonical technique, and each
//   neighbour forms a pair with it, each sample weighted by the balance heuristic of the two
//   surfaces' targets times their counts (the canonical's count split over the pairs). The
//   targets include visibility: a neighbour's sample is weighed by a ray from this pixel, the
//   own sample's weight in a pair by one from the neighbour. Every sample's weights sum to
//   one, so the estimate is unbiased where the reused points are diffuse: on the same box over
//   1024 frames the mean is the paths' within 0.75 standard errors, where the counts' is 1.7%
//   dark, 6 of them (tests/restir_gi.rs). Two rays and one G-buffer decode a neighbour,
//   against one ray a pixel.
//
// Both: a neighbour's sample assumes its point reflects the same light toward this pixel (a
// diffuse point). A neighbour's sample whose distance and angle differ so much that its weight
// here is over GI_JACOBIAN_MAX times (or under 1 / GI_JACOBIAN_MAX of) its weight there is
// left out, as Ouyang et al. reject large Jacobians.
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

// The target of `sample` at the surface s, paired with the surface at `other`: 0 where the
// Jacobian bound leaves it out between the two, or, with `test_visibility`, where s cannot see
// the sample's point (a pixel sees its own path's point untested).
fn gi_target_at(s: Shading, other: vec3<f32>, sample: GiSample, test_visibility: bool) -> f32 {
    if !gi_jacobian_bounded(s, other, sample) {
        return 0.0;
    }
    let value = luminance(gi_value(s, sample));
    if !(value > 0.0) || !test_visibility {
        return max(value, 0.0);
    }
    return select(0.0, value, gi_sees(s, sample));
}

// Whether nothing blocks the way from s to the sample's point.
fn gi_sees(s: Shading, sample: GiSample) -> bool {
    let to_point = sample.point - s.position;
    let distance = length(to_point);
    return unoccluded(s, to_point / distance, distance);
}

// The balance heuristic's weight of the technique whose weighted density is `a` against one of
// weighted density `b`: a / (a + b), 0 where both are 0.
fn gi_pair_weight(a: f32, b: f32) -> f32 {
    let w = a / (a + b);
    return select(0.0, w, a > 0.0 && f32_is_finite(w));
}

// The pixel's indirect light resampled by counts (RestirBias::Biased): each reservoir by
// target here times W times M, normalised by the summed counts (1/M); the survivor, if it is a
// neighbour's, is tested by one visibility ray, and where the pixel cannot see it the pixel
// shades its own reservoir's sample instead.
fn resample_by_counts(pixel: vec2<i32>, size: vec2<u32>, s: Shading, depth: f32, normal: vec3<f32>, own_reservoir: GiReservoir, rng: ptr<function, Pcg32>) -> vec3<f32> {
    let own = own_reservoir.sample;
    var r = gi_resampling_start(own, luminance(gi_value(s, own)), max(own_reservoir.count, 1u));
    var kept_own = true;
    for (var i = 0u; i < min(params.indirect_spatial_samples, GI_MAX_NEIGHBOURS); i++) {
        let n = reservoir_neighbour(pixel, size, pcg32_next_vec2(rng), params.spatial_radius,
            depth, normal);
        let rand = pcg32_next_f32(rng);
        if !n.found {
            continue;
        }
        let neighbour = reservoir_at(n.pixel);
        let other = neighbour.sample;
        if !gi_sample_reusable(other) || !gi_jacobian_bounded(s, n.position, other) {
            continue;
        }
        if gi_resampling_add(&r, other, luminance(gi_value(s, other)), neighbour.count, rand) {
            kept_own = false;
        }
    }
    let contribution_weight = gi_resampling_weight(r);
    if !(contribution_weight > 0.0) {
        return vec3<f32>(0.0);
    }
    let kept = r.kept;
    if !kept_own && !gi_sees(s, kept) {
        return gi_value(s, own) * own.weight;
    }
    return gi_value(s, kept) * contribution_weight;
}

// The pixel's indirect light resampled by pairwise MIS with visibility (RestirBias::Unbiased;
// see the top of this file).
fn resample_pairwise(pixel: vec2<i32>, size: vec2<u32>, s: Shading, depth: f32, normal: vec3<f32>, own_reservoir: GiReservoir, rng: ptr<function, Pcg32>) -> vec3<f32> {
    // The pixel's own reservoir is the canonical technique: its confidence, its target.
    let own = own_reservoir.sample;
    let own_count = f32(max(own_reservoir.count, 1u));
    let own_here = luminance(gi_value(s, own));
    // The own reservoir stands for 1/k of its count in each of the k = indirect_spatial_samples
    // pairs.
    let own_share = own_count / f32(max(params.indirect_spatial_samples, 1u));
    var r = GiResampling(gi_sample_none(), 0.0, 0.0, 0u);
    // The canonical sample's MIS weight, summed over the pairs.
    var own_weight = 0.0;
    var pairs = 0u;
    for (var i = 0u; i < min(params.indirect_spatial_samples, GI_MAX_NEIGHBOURS); i++) {
        let n = reservoir_neighbour(pixel, size, pcg32_next_vec2(rng), params.spatial_radius,
            depth, normal);
        let rand = pcg32_next_f32(rng);
        if !n.found {
            continue;
        }
        pairs += 1u;
        let neighbour = reservoir_at(n.pixel);
        let other = neighbour.sample;
        let sn = gbuffer_shading(gbuffer_unpack(gbuffer_load(n.pixel)),
            gbuffer_triangle_at(n.pixel), camera);
        let count = f32(max(neighbour.count, 1u));
        // Each sample of the pair by the balance heuristic of the two targets times counts.
        let there_own = count * gi_target_at(sn, s.position, own, true);
        own_weight += gi_pair_weight(own_share * own_here, there_own);
        if gi_sample_reusable(other) {
            let there = count * gi_target_at(sn, s.position, other, false);
            let here = gi_target_at(s, n.position, other, true);
            gi_resampling_add_weighted(&r, other, here, gi_pair_weight(there, own_share * here),
                rand);
        }
    }
    if pairs == 0u {
        own_weight = 1.0;
        pairs = 1u;
    }
    gi_resampling_add_weighted(&r, own, own_here, own_weight, pcg32_next_f32(rng));
    // A pair's two weights of a sample sum to 1, so the pairs' sum to their number: W divides
    // by it.
    r.count = pairs;
    let contribution_weight = gi_resampling_weight(r);
    if !(contribution_weight > 0.0) {
        return vec3<f32>(0.0);
    }
    return gi_value(s, r.kept) * contribution_weight;
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
    var radiance = vec3<f32>(0.0);
    if !gbuffer_covered(texels) || !g.shades {
        // Nothing to shade.
    } else if !gi_sample_reusable(own_reservoir.sample) {
        radiance = own_reservoir.sample.radiance;
    } else {
        let s = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
        let depth = reservoir_depth(camera, g.position);
        let index = id.y * size.x + id.x;
        let seed = vec2<u32>(params.seed_lo, params.seed_hi) ^ RESTIR_GI_SEED;
        var rng = pcg32_new(seed, vec2<u32>(index, params.frame));
        if params.unbiased != 0u {
            radiance = resample_pairwise(pixel, size, s, depth, g.shading_normal, own_reservoir,
                &rng);
        } else {
            radiance = resample_by_counts(pixel, size, s, depth, g.shading_normal, own_reservoir,
                &rng);
        }
        radiance = clamp_luminance(radiance, params.firefly_clamp);
    }
    if !vec3_is_finite(radiance) {
        radiance = vec3<f32>(0.0);
    }
    textureStore(indirect_out, pixel, vec4<f32>(radiance, 1.0));
}
