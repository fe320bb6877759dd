// Resampled indirect light, first pass (ReSTIR GI: Ouyang et al., "ReSTIR GI: Path Resampling
// for Real-Time Path Tracing", HPG 2021, section 4): each pixel traces one path as the
// indirect pass does (lib/path.wgsl; the first bounce along the direct pass's BRDF ray) and
// keeps it as a sample (lib/gi_sample.wgsl): the point y its first bounce reached, the light
// y reflects back along it (next-event estimation at y and what lies beyond, with its own
// throughput from y, so Russian roulette there weighs the path after y alone), and the
// sample's area-measure weight. With temporal reuse (gi_history_cap > 0), last frame's
// reservoir at the point the motion vector gives, where its surface is similar (lib/
// reservoir.wgsl's test), is merged with it (Ouyang et al., algorithm 3): both enter by the
// target here times W times M, the history's M capped at gi_history_cap, and the result is
// normalised by the sum of the counts (1/M). Last frame's sample is not tested for visibility
// here (as in the paper: the spatial pass tests what it reuses from elsewhere); its light is
// what y reflected toward last frame's point, the same diffuse assumption as spatial reuse.
// The reservoir goes to reservoirs_out; restir_gi_spatial.wgsl resamples it with the
// neighbours' and writes the indirect light, and the frame keeps a copy as the next frame's
// history.
//
// A path whose first direction is a delta lobe's (a mirror, smooth glass) has no density to
// reuse: it is kept as its own contribution. Test hook: with `poison` nonzero, the pixel at the
// image's centre and the one to its right write NaN and infinite samples (where the Cornell
// box's neighbours reuse them), which the spatial pass must not spread.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/rng_source.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_inputs.wgsl
#import lib/surface.wgsl
#import lib/color.wgsl
#import lib/first_bounce.wgsl
#import lib/path.wgsl
#import lib/gi_sample.wgsl
#import lib/reservoir.wgsl
#import lib/lane_tiles.wgsl

// lib/next_event.wgsl's hook.
fn light_tree_sampling() -> bool {
    return params.light_sampling == LIGHT_SAMPLING_TREE;
}

@group(1) @binding(4) var<storage, read> params: IndirectParams;
@group(1) @binding(5) var reservoirs_out: texture_storage_2d<rgba32uint, write>;
// Last frame's reservoirs, and the direct pass's BRDF-ray hits (read-only storage: the scene
// and the G-buffer leave one sampled texture, the motion vectors').
@group(1) @binding(6) var history: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(7) var first_bounce: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(8) var gbuffer_motion: texture_2d<u32>;

// Keeps the temporal merge's numbers apart from the path's.
const RESTIR_GI_TEMPORAL_SEED: vec2<u32> = vec2<u32>(0xd1b54a32u, 0xd192ed03u);

// The sample of one path from x0 whose first direction is `first`'s.
fn gi_path(x0: Shading, rng: ptr<function, Rng>, first: FirstBounce) -> GiSample {
    let step = brdf_scatter(x0, first.numbers);
    if !step.valid || !vec3_is_finite(step.weight) || all(step.weight == vec3<f32>(0.0)) {
        return gi_sample_none();
    }
    var hit: Hit;
    if first_bounce_traced(first.texel) {
        hit = first_bounce_decode(first.texel);
    } else {
        hit = trace_closest(leaving_ray(x0, step.wi), f32_infinity());
    }
    if hit.instance == BVH_NO_HIT || params.bounces == 0u {
        return gi_sample_none();
    }
    var transmittance = vec3<f32>(1.0);
    if FEATURE_VOLUMES {
        transmittance = medium_transmittance(x0.position, step.wi, hit);
    }
    let y = surface_at_hit(step.wi, hit);
    if !y.shades {
        return gi_sample_none();
    }
    var path = Path(y.shading, vec3<f32>(1.0), vec3<f32>(0.0), 1u);
    loop {
        if !path_step(&path, rng, false, first) {
            break;
        }
    }
    let radiance = path.total * transmittance;
    if !vec3_is_finite(radiance) {
        return gi_sample_none();
    }
    if step.delta {
        return gi_sample_own(clamp_luminance(step.weight * radiance, params.firefly_clamp));
    }
    let weight = gi_area_weight(x0.position, y.shading.position, y.shading.geometric_normal,
        step.pdf);
    return GiSample(y.shading.position, y.shading.geometric_normal, radiance, weight);
}

fn store_reservoir(pixel: vec2<i32>, r: GiReservoir) {
    textureStore(reservoirs_out, gi_reservoir_texel(pixel, 0), gi_sample_pack_point(r.sample));
    textureStore(reservoirs_out, gi_reservoir_texel(pixel, 1), gi_sample_pack_radiance(r.sample));
    textureStore(reservoirs_out, gi_reservoir_texel(pixel, 2), gi_reservoir_pack_count(r));
}

// Last frame's reservoir at the point `pixel` moved from, where its surface is similar to
// (depth, normal) and its sample reusable, its count capped; a count of 0 where not.
fn history_reservoir(pixel: vec2<i32>, depth: f32, normal: vec3<f32>, size: vec2<u32>) -> GiReservoir {
    let none = GiReservoir(gi_sample_none(), 0u, reservoir_no_surface());
    let motion = motion_unpack(textureLoad(gbuffer_motion, pixel, 0).x);
    if !all(abs(motion) < vec2<f32>(1.0e6)) {
        return none;
    }
    let previous = vec2<i32>(floor(vec2<f32>(pixel) + 0.5 + motion));
    if any(previous < vec2<i32>(0)) || any(previous >= vec2<i32>(size)) {
        return none;
    }
    var r = gi_reservoir_unpack(textureLoad(history, gi_reservoir_texel(previous, 0)),
        textureLoad(history, gi_reservoir_texel(previous, 1)),
        textureLoad(history, gi_reservoir_texel(previous, 2)));
    if !gi_sample_reusable(r.sample) || !reservoir_surface_similar(r.surface, depth, normal) {
        return none;
    }
    r.count = min(r.count, params.gi_history_cap);
    return r;
}

// The pixel's sample merged with `history` at x0 (Ouyang et al., algorithm 3).
fn merged(x0: Shading, own: GiSample, history: GiReservoir, rand: f32) -> GiReservoir {
    var r = gi_resampling_start(own, luminance(gi_value(x0, own)), 1u);
    if history.count > 0u {
        let here = luminance(gi_value(x0, history.sample));
        gi_resampling_add(&r, history.sample, here, history.count, rand);
    }
    var kept = r.kept;
    kept.weight = gi_resampling_weight(r);
    return GiReservoir(kept, r.count, vec4<u32>(0u));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(workgroup_id) workgroup: vec3<u32>, @builtin(local_invocation_index) local_index: u32) {
    let id = lane_tile_pixel(workgroup, local_index);
    let size = textureDimensions(first_bounce);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let texels = gbuffer_load(pixel);
    var r = GiReservoir(gi_sample_none(), 1u, reservoir_no_surface());
    if gbuffer_covered(texels) {
        let g = gbuffer_unpack(texels);
        if g.shades {
            let x0 = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
            let index = id.y * size.x + id.x;
            let start = path_start(index, textureLoad(first_bounce, pixel));
            var rng = start.rng;
            r.sample = gi_path(x0, &rng, start.first);
            let depth = reservoir_depth(camera, g.position);
            if params.gi_history_cap > 0u && gi_sample_reusable(r.sample) {
                let history = history_reservoir(pixel, depth, g.shading_normal, size);
                let seed = vec2<u32>(params.seed_lo, params.seed_hi) ^ RESTIR_GI_TEMPORAL_SEED;
                var merge_rng = pcg32_new(seed, vec2<u32>(index, params.frame));
                r = merged(x0, r.sample, history, pcg32_next_f32(&merge_rng));
            }
            r.surface = reservoir_surface_pack(depth, g.shading_normal);
        }
    }
    let centre = size / 2u;
    if params.poison != 0u && id.y == centre.y && (id.x == centre.x || id.x == centre.x + 1u) {
        let poison = select(bitcast<f32>(0x7fc00000u), f32_infinity(), id.x != centre.x);
        r.sample = GiSample(vec3<f32>(poison), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(poison), poison);
    }
    store_reservoir(pixel, r);
}
