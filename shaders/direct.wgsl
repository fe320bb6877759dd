// Direct light per pixel of the G-buffer, one frame's estimate of the light the surface seen
// reflects (its own emission is the composite's to add): every
// punctual light (or one picked when there are more than ALL_PUNCTUAL_LIGHTS_MAX),
// one area-light sample (an emissive triangle or the environment; picks by power or through
// the light trees, lib/next_event.wgsl) and one
// BRDF sample, the last two combined by multiple importance sampling with the power
// heuristic (Veach and Guibas, "Optimally Combining Sampling Techniques for Monte Carlo
// Rendering", SIGGRAPH 1995). Each light sample casts one shadow ray from an origin offset
// along the geometric normal (Wachter and Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems, 2019). Where the camera sees no surface, the
// environment along the camera ray. The same estimate as chiaro_reference with direct_only
// (in realtime mode, less what the firefly clamp takes off: the BRDF sample, and the punctual
// light picked when not all are evaluated, each scaled down to a luminance of
// params.firefly_clamp when above it).
//
// Apart, in direct_punctual_out: the punctual lights' part of the estimate where every one is
// evaluated (punctual_lights_all_evaluated: no light picked at random, so no sampling noise),
// else 0. The realtime denoiser leaves it out of the lighting it filters and adds it back.
//
// And in first_bounce_out, the BRDF ray's hit, for the indirect pass's first path to continue
// from (lib/first_bounce.wgsl).
//
// With resampled direct light (ReSTIR DI: restir_temporal.wgsl, restir_spatial.wgsl), the
// area-light sample (and the punctual light picked, where there are too many to evaluate) is
// the pixel's final reservoir's, shaded with one shadow ray and weighted by its W. The
// reservoirs then carry all the light the area-light table reaches, so the BRDF sample adds
// only what the table cannot (lib/next_event.wgsl's REACHED_UNSAMPLED: a constant environment,
// emitters outside the table).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/rng_source.wgsl
#import lib/frame.wgsl
#import lib/brdf.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/gbuffer_inputs.wgsl
#import lib/surface.wgsl
#import lib/next_event.wgsl
#import lib/color.wgsl
#import lib/first_bounce.wgsl
#import lib/reservoir.wgsl
#import lib/lane_tiles.wgsl

// chiaro_gpu::passes::direct::DirectParams.
struct DirectParams {
    frame: u32,
    seed_lo: u32,
    seed_hi: u32,
    // 1: light sampling as above; 0 (naive mode): covered pixels reflect nothing here.
    lights: u32,
    // LIGHT_SAMPLING_POWER or LIGHT_SAMPLING_TREE.
    light_sampling: u32,
    // Most luminance of the BRDF sample and of the punctual light picked at random; 0: off.
    firefly_clamp: f32,
    // 1: the area-light sample is the resampled reservoir's (when the pipeline has its code).
    restir: u32,
    // 1: Owen-scrambled Sobol draws, `frame` being the sample index; 0: PCG32.
    sampler: u32,
}

// lib/next_event.wgsl's hook.
fn light_tree_sampling() -> bool {
    return params.light_sampling == LIGHT_SAMPLING_TREE;
}

@group(1) @binding(4) var<storage, read> params: DirectParams;
@group(1) @binding(5) var direct_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(6) var direct_punctual_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(7) var first_bounce_out: texture_storage_2d<rgba32uint, write>;
// The final reservoirs of the resampling passes (read only with restir on).
@group(1) @binding(8) var reservoirs: texture_2d<u32>;

// One BRDF sample drawn with `numbers` (first_bounce_numbers): the emission or environment it
// reaches, weighed against light sampling as `weighing` says (lib/next_event.wgsl); `first`
// gets its hit when a ray is traced.
fn brdf_light(s: Shading, numbers: vec3<f32>, first: ptr<function, vec4<u32>>, weighing: u32) -> vec3<f32> {
    let bs = brdf_sample(s.params, s.wo, numbers.x, numbers.yz);
    if !bs.valid || !vec3_is_finite(bs.weight) || all(bs.weight == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let wi = frame_to_world(s.frame, bs.wi);
    if !on_its_side(s, wi, bs.wi.z) {
        return vec3<f32>(0.0);
    }
    let hit = trace_closest(leaving_ray(s, wi), f32_infinity());
    *first = first_bounce_encode(hit);
    return bs.weight * medium_transmittance(s.position, wi, hit)
        * emission_reached_weighing(s, wi, hit, bs.pdf, select(weighing, REACHED_UNWEIGHTED, bs.delta));
}

// The area light of the pixel's final reservoir: f cos L of its sample in the reservoirs'
// measure (lib/reservoir.wgsl), seen through one shadow ray, times its contribution weight W.
fn resampled_area_light(s: Shading, pixel: vec2<i32>) -> vec3<f32> {
    let r = reservoir_unpack(textureLoad(reservoirs, pixel, 0));
    if r.entry == RESERVOIR_NO_SAMPLE || r.contribution_weight == 0.0 {
        return vec3<f32>(0.0);
    }
    let ls = restir_light_at(s, r.entry, r.u);
    return light_contribution(s, ls).xyz * restir_measure(ls) * r.contribution_weight;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(workgroup_id) workgroup: vec3<u32>, @builtin(local_invocation_index) local_index: u32) {
    let id = lane_tile_pixel(workgroup, local_index);
    let size = textureDimensions(direct_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let texels = gbuffer_load(pixel);
    if !gbuffer_covered(texels) {
        let ray = camera_ray(camera, vec2<f32>(id.xy) + camera.jitter);
        textureStore(direct_out, pixel, vec4<f32>(environment_seen(ray.direction), 1.0));
        textureStore(direct_punctual_out, pixel, vec4<f32>(0.0));
        textureStore(first_bounce_out, pixel, first_bounce_not_traced());
        return;
    }
    let g = gbuffer_unpack(texels);
    var radiance = vec3<f32>(0.0);
    var punctual = vec3<f32>(0.0);
    var first = first_bounce_not_traced();
    if g.shades && params.lights != 0u {
        let s = gbuffer_shading(g, gbuffer_triangle_at(pixel), camera);
        let index = id.y * size.x + id.x;
        let seed = vec2<u32>(params.seed_lo, params.seed_hi);
        var rng = rng_new(pcg32_new(seed, vec2<u32>(index, params.frame)), params.sampler, seed,
            index, params.frame, RNG_STREAM_DIRECT);
        // Every punctual light (or one picked, unless the reservoirs hold them), then one
        // area-light sample.
        if !(restir_di_on(params.restir) && restir_punctual()) {
            punctual = punctual_light(s, &rng);
        }
        var area: vec3<f32>;
        var weighing = REACHED_MIS;
        if restir_di_on(params.restir) {
            area = resampled_area_light(s, pixel);
            weighing = REACHED_UNSAMPLED;
        } else {
            area = area_light(s, &rng);
        }
        let numbers = first_bounce_numbers(seed, index, params.frame, params.sampler);
        let brdf = brdf_light(s, numbers, &first, weighing);
        // The firefly clamp takes the samples whose value can be rare and huge: the BRDF
        // sample, and the punctual light picked at random; not the exact punctual part, nor
        // the area-light sample (light sampling: its value is about the light's true share).
        let clamp = params.firefly_clamp;
        var punctual_part = punctual;
        if !punctual_lights_all_evaluated() {
            punctual_part = clamp_luminance(punctual, clamp);
        }
        radiance = punctual_part + area + clamp_luminance(brdf, clamp);
    }
    textureStore(first_bounce_out, pixel, first);
    textureStore(direct_out, pixel, vec4<f32>(radiance, 1.0));
    let exact = select(vec3<f32>(0.0), punctual, punctual_lights_all_evaluated());
    textureStore(direct_punctual_out, pixel, vec4<f32>(exact, 1.0));
}
