// Resampled direct light, first pass (ReSTIR DI: Bitterli et al., "Spatiotemporal Reservoir
// Resampling for Real-Time Ray Tracing with Dynamic Direct Lighting", SIGGRAPH 2020,
// algorithm 5's first half): per pixel of the G-buffer, `candidates` area-light samples drawn
// as the direct pass draws its one (lib/next_event.wgsl), resampled into a reservoir by the
// target f cos L before any shadow ray (lib/reservoir.wgsl), then merged with last frame's at
// the point the motion vector gives, if that surface is similar (view depth within 10%,
// normals within 25 degrees), its M capped at history_cap. The merge is normalised by M: last
// frame's surface is this one reprojected, so the two targets' supports (the hemisphere, the
// emitters' front faces) differ only by the sub-pixel jitter and by what moved (the similarity
// test bounds it). A disoccluded pixel, or one whose history is dissimilar, starts again from
// its candidates.
//
// No visibility reuse (Bitterli et al.'s zeroing of an occluded sample's weight): measured on
// the Cornell box in the direct mode, a history zeroed at last frame's jittered point darkened
// contact shadows 15-fold under 1/M, since the history's count outweighs the new candidates
// 20 to 1. The reservoirs resample the unshadowed light; the direct pass's one shadow ray
// decides visibility.
//
// The reservoirs go to reservoirs_out for the spatial pass (restir_spatial.wgsl).

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
// Last frame's final reservoirs (the spatial pass's) and their surfaces (read-only storage:
// the scene and the G-buffer leave one sampled texture), and the motion vectors.
@group(1) @binding(6) var previous_reservoirs: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(7) var previous_surfaces: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(8) var gbuffer_motion: texture_2d<u32>;

// Keeps this pass's numbers apart from the direct pass's and the spatial pass's.
const RESTIR_TEMPORAL_SEED: vec2<u32> = vec2<u32>(0x2545f491u, 0x4f6cdd1du);

// lib/next_event.wgsl's hook.
fn light_tree_sampling() -> bool {
    return params.light_sampling == LIGHT_SAMPLING_TREE;
}

// One candidate's light: an area-table entry or a punctual light, and the probability of the
// pick (0: none).
struct CandidatePick {
    entry: u32,
    pmf: f32,
}

// A candidate's pick with the number u_pick: a punctual light (by punctual_pick) or an
// area-table entry (area_light_pick), its probability scaled by the share of the candidates
// of its kind: the candidates are a fixed mixture of the two, whose lights are disjoint, so
// that share times the pick's probability is the mixture's density (the balance heuristic's
// weight of each candidate).
fn candidate_pick(s: Shading, punctual: bool, share: f32, u_pick: f32) -> CandidatePick {
    if punctual {
        let pick = punctual_pick(s, u_pick);
        return CandidatePick(RESERVOIR_PUNCTUAL + pick.light, share * pick.pmf);
    }
    let pick = area_light_pick(s, u_pick);
    return CandidatePick(pick.entry, share * pick.pmf);
}

// The reservoir of `candidates` light samples at s: area-light samples, the first half of them
// punctual lights where the reservoirs hold those (restir_punctual; all of them where there is
// no area light). The kind follows the candidate's number, the same in every lane, so a lane
// never runs the other kind's walk masked. `kept_target` gets the target of the sample kept.
fn initial_reservoir(s: Shading, rng: ptr<function, Pcg32>, kept_target: ptr<function, f32>) -> Reservoir {
    var r = reservoir_empty();
    let n = params.candidates;
    var n_punctual = 0u;
    if restir_punctual() {
        n_punctual = select(max(n / 2u, 1u), n, scene_info.area_count == 0u);
    }
    for (var i = 0u; i < n; i++) {
        let punctual = i < n_punctual;
        let kind_count = select(n - n_punctual, n_punctual, punctual);
        let share = f32(kind_count) / f32(n);
        let pick = candidate_pick(s, punctual, share, pcg32_next_f32(rng));
        let u = reservoir_quantise(pcg32_next_vec2(rng));
        let rand = pcg32_next_f32(rng);
        if pick.pmf == 0.0 {
            r.count += 1u;
            continue;
        }
        let ls = restir_light_at(s, pick.entry, u);
        let target_value = restir_target(s, ls);
        let source_pdf = pick.pmf * ls.pdf * restir_measure(ls);
        let weight = select(0.0, target_value / source_pdf, source_pdf > 0.0);
        if reservoir_stream(&r, pick.entry, u, weight, 1u, rand) {
            *kept_target = target_value;
        }
    }
    reservoir_finish(&r, *kept_target, r.count);
    return r;
}

// Last frame's reservoir at the point `pixel` moved from, where its surface is similar; an
// empty one (M 0) where not.
fn history_reservoir(pixel: vec2<i32>, depth: f32, normal: vec3<f32>, size: vec2<u32>) -> Reservoir {
    let motion = motion_unpack(textureLoad(gbuffer_motion, pixel, 0).x);
    if params.temporal == 0u || !all(abs(motion) < vec2<f32>(1.0e6)) {
        return reservoir_empty();
    }
    let previous = vec2<i32>(floor(vec2<f32>(pixel) + 0.5 + motion));
    if any(previous < vec2<i32>(0)) || any(previous >= vec2<i32>(size)) {
        return reservoir_empty();
    }
    if !reservoir_surface_similar(textureLoad(previous_surfaces, previous), depth, normal) {
        return reservoir_empty();
    }
    var r = reservoir_unpack(textureLoad(previous_reservoirs, previous));
    if r.entry != RESERVOIR_NO_SAMPLE && !restir_entry_valid(r.entry) {
        // Not a light of this scene (an edit removed it): nothing to reuse.
        return reservoir_empty();
    }
    reservoir_cap(&r, params.history_cap);
    return r;
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
    let g = gbuffer_unpack(texels);
    if !gbuffer_covered(texels) || !g.shades {
        textureStore(reservoirs_out, pixel, reservoir_pack(reservoir_empty()));
        return;
    }
    let s = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
    let index = id.y * size.x + id.x;
    let seed = vec2<u32>(params.seed_lo, params.seed_hi) ^ RESTIR_TEMPORAL_SEED;
    var rng = pcg32_new(seed, vec2<u32>(index, params.frame));
    var initial_target = 0.0;
    let initial = initial_reservoir(s, &rng, &initial_target);
    let history = history_reservoir(pixel, reservoir_depth(camera, g.position), g.shading_normal, size);
    var history_target = 0.0;
    if history.entry != RESERVOIR_NO_SAMPLE {
        history_target = restir_target(s, restir_light_at(s, history.entry, history.u));
    }
    // Both enter by target here times W times M.
    var r = reservoir_empty();
    var kept_target = 0.0;
    if reservoir_merge(&r, initial, initial_target, pcg32_next_f32(&rng)) {
        kept_target = initial_target;
    }
    if reservoir_merge(&r, history, history_target, pcg32_next_f32(&rng)) {
        kept_target = history_target;
    }
    reservoir_finish(&r, kept_target, r.count);
    textureStore(reservoirs_out, pixel, reservoir_pack(r));
}
