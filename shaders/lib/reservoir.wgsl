// Reservoirs of light samples for resampled direct light (ReSTIR DI: Bitterli et al.,
// "Spatiotemporal Reservoir Resampling for Real-Time Ray Tracing with Dynamic Direct
// Lighting", SIGGRAPH 2020), mirroring chiaro_shading::reservoir: streaming a candidate,
// merging another reservoir, the contribution weight W normalised by the count M (or by 1
// where the merge's weights already sum to one: restir_spatial.wgsl).
//
// A sample is an entry of the area-light table (an emissive triangle or the environment) and
// the two numbers that draw its point (area_light_at), quantised to 16 bits each so that a
// packed reservoir names exactly the sample it was weighed with; any shading point finds the
// sample again from them. Where there are more punctual lights than the direct pass evaluates
// one by one, a sample may also be one of them (RESERVOIR_PUNCTUAL on). The target function is
// the luminance of the sample's unshadowed reflected light, f cos L, over the emitter's area
// (restir_target, restir_measure).
//
// Packed in an rgba32uint texel: the entry (RESERVOIR_NO_SAMPLE: none), the numbers, W (f32
// bits) and M. The surface a reservoir belongs to is packed apart (reservoir_surface_pack):
// its view depth and normal, for the similarity test of reuse.

#import lib/float.wgsl
#import lib/features.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/color.wgsl
#import lib/next_event.wgsl

// chiaro_gpu::passes::restir::RestirParams: the resampling passes' parameters.
struct RestirParams {
    frame: u32,
    seed_lo: u32,
    seed_hi: u32,
    // LIGHT_SAMPLING_POWER or LIGHT_SAMPLING_TREE.
    light_sampling: u32,
    // Light candidates drawn per pixel.
    candidates: u32,
    // 1: merge last frame's reservoirs (0 on the first frame and after a reset).
    temporal: u32,
    // Most M a reservoir of last frame's brings.
    history_cap: u32,
    // Neighbours merged by the spatial pass.
    spatial_samples: u32,
    // Radius of the disc the neighbours are drawn in, in pixels.
    spatial_radius: f32,
    // 1: weigh neighbours by the generalised balance heuristic (unbiased); 0: normalise by M.
    unbiased: u32,
    // Neighbours whose indirect samples restir_gi_spatial.wgsl resamples (0 where the frame
    // converges).
    indirect_spatial_samples: u32,
    // Most luminance of a pixel's resampled indirect light; 0: off.
    firefly_clamp: f32,
}

const RESERVOIR_NO_SAMPLE: u32 = 0xffffffffu;
// Entries from this one on are punctual lights (the light's index added), resampled with the
// area light where the direct pass cannot evaluate every one (restir_punctual).
const RESERVOIR_PUNCTUAL: u32 = 0x80000000u;

struct Reservoir {
    entry: u32,
    u: vec2<f32>,
    weight_sum: f32,
    count: u32,
    contribution_weight: f32,
}

fn reservoir_empty() -> Reservoir {
    return Reservoir(RESERVOIR_NO_SAMPLE, vec2<f32>(0.0), 0.0, 0u, 0.0);
}

// u quantised to the 16-bit grid a packed reservoir keeps (cell centres, so never 0 or 1).
fn reservoir_quantise(u: vec2<f32>) -> vec2<f32> {
    let q = min(floor(clamp(u, vec2<f32>(0.0), vec2<f32>(1.0)) * 65536.0), vec2<f32>(65535.0));
    return (q + 0.5) / 65536.0;
}

// Streams `count` candidates' worth of the sample (entry, u) with resampling weight `weight`,
// kept with probability weight / weight_sum decided by `rand` in [0, 1). A weight that is not
// finite and positive is counted but never kept, so a NaN does not spread. Returns whether
// the sample was kept.
fn reservoir_stream(r: ptr<function, Reservoir>, entry: u32, u: vec2<f32>, weight: f32, count: u32, rand: f32) -> bool {
    (*r).count += count;
    if !(weight > 0.0) || !f32_is_finite(weight) {
        return false;
    }
    (*r).weight_sum += weight;
    if rand * (*r).weight_sum < weight {
        (*r).entry = entry;
        (*r).u = u;
        return true;
    }
    return false;
}

// Merges `other`, whose sample's target function here is `target_here`: weight
// target_here * W * M. Returns whether its sample was kept.
fn reservoir_merge(r: ptr<function, Reservoir>, other: Reservoir, target_here: f32, rand: f32) -> bool {
    if other.entry == RESERVOIR_NO_SAMPLE {
        (*r).count += other.count;
        return false;
    }
    let weight = target_here * other.contribution_weight * f32(other.count);
    return reservoir_stream(r, other.entry, other.u, weight, other.count, rand);
}

// W = weight_sum / (normaliser * target): normaliser M (1/M), or 1 where the weights already
// sum to one; 0 with no sample, a target that is not positive or a zero normaliser.
fn reservoir_finish(r: ptr<function, Reservoir>, target_value: f32, normaliser: u32) {
    var w = 0.0;
    if (*r).entry != RESERVOIR_NO_SAMPLE && target_value > 0.0 && normaliser > 0u {
        w = (*r).weight_sum / (f32(normaliser) * target_value);
    }
    (*r).contribution_weight = select(0.0, w, f32_is_finite(w));
}

// Caps M at `cap` (temporal reuse's history cap); W is unchanged.
fn reservoir_cap(r: ptr<function, Reservoir>, cap: u32) {
    (*r).count = min((*r).count, cap);
}

fn reservoir_pack(r: Reservoir) -> vec4<u32> {
    let q = vec2<u32>(r.u * 65536.0);
    return vec4<u32>(r.entry, q.x | (q.y << 16u), bitcast<u32>(r.contribution_weight), r.count);
}

// A packed reservoir (its weight sum is not kept: 0).
fn reservoir_unpack(texel: vec4<u32>) -> Reservoir {
    let q = vec2<u32>(texel.y & 0xffffu, texel.y >> 16u);
    let u = (vec2<f32>(q) + 0.5) / 65536.0;
    let w = bitcast<f32>(texel.z);
    return Reservoir(texel.x, u, 0.0, texel.w, select(0.0, w, f32_is_finite(w) && w > 0.0));
}

// The measure a sample's target and weights are in, relative to solid angle at the shading
// point: an emitter's point is the same point for every pixel that reuses it, so its integral is
// over the emitter's area, and the solid angle at one pixel is converted by cos_light / d^2 =
// 1 / (area pdf-to-solid-angle pdf), i.e. 1 / ls.pdf up to the triangle's area, which is the
// same wherever the sample is reused (and cancels between the source pdf and the target).
// Without it, a sample reused from a neighbour would carry the neighbour's solid-angle
// Jacobian: measured 2.5 times too bright where the light is seen at grazing angles.
// An environment direction is the same direction everywhere: solid angle, factor 1.
fn restir_measure(ls: LightSample) -> f32 {
    // A punctual light is one point, counted (its sample's pdf is 1 everywhere).
    if ls.delta || !f32_is_finite(ls.distance) {
        return 1.0;
    }
    return select(0.0, 1.0 / ls.pdf, ls.pdf > 0.0);
}

// Whether the reservoirs hold punctual lights too: there are more than the direct pass
// evaluates one by one, and the pipeline has a punctual kind.
fn restir_punctual() -> bool {
    return !punctual_lights_all_evaluated() && scene_info.light_count > 0u
        && (FEATURE_POINT_LIGHTS || FEATURE_SPOT_LIGHTS || FEATURE_DIRECTIONAL_LIGHTS);
}

// Whether `entry` names a light of this scene that the reservoirs may hold.
fn restir_entry_valid(entry: u32) -> bool {
    if entry >= RESERVOIR_PUNCTUAL {
        return restir_punctual() && entry - RESERVOIR_PUNCTUAL < scene_info.light_count;
    }
    return entry < scene_info.area_count;
}

// The light sample a reservoir entry names, seen from s.
fn restir_light_at(s: Shading, entry: u32, u: vec2<f32>) -> LightSample {
    if entry >= RESERVOIR_PUNCTUAL {
        return sample_punctual(scene_light(entry - RESERVOIR_PUNCTUAL), s.position);
    }
    return area_light_at(s, entry, u);
}

// The target function at s of a light sample: the luminance of f cos L before its shadow ray,
// in restir_measure's measure.
fn restir_target(s: Shading, ls: LightSample) -> f32 {
    let t = luminance(light_unoccluded_value(s, ls).xyz) * restir_measure(ls);
    return select(0.0, t, f32_is_finite(t));
}

// The surface a reservoir belongs to: view depth along the camera's forward axis and shading
// normal (depth -1: no surface, similar to none).
fn reservoir_surface_pack(depth: f32, normal: vec3<f32>) -> vec4<u32> {
    return vec4<u32>(bitcast<u32>(depth), octahedral_encode(normal), 0u, 0u);
}

fn reservoir_no_surface() -> vec4<u32> {
    return vec4<u32>(bitcast<u32>(-1.0), 0u, 0u, 0u);
}

// Least cosine between the normals of surfaces whose reservoirs are reused, and most relative
// difference of their view depths (RTXDI's defaults: 25 degrees, 10%).
const RESERVOIR_NORMAL_COS: f32 = 0.9;
const RESERVOIR_DEPTH: f32 = 0.1;

// Whether a surface of view depth other_depth and normal other_normal is close enough to
// (depth, normal) to reuse its reservoir.
fn reservoir_surfaces_similar(other_depth: f32, other_normal: vec3<f32>, depth: f32, normal: vec3<f32>) -> bool {
    if !(other_depth > 0.0) || !(depth > 0.0) {
        return false;
    }
    return abs(other_depth - depth) <= RESERVOIR_DEPTH * depth
        && dot(other_normal, normal) >= RESERVOIR_NORMAL_COS;
}

// reservoir_surfaces_similar for a packed surface (reservoir_surface_pack).
fn reservoir_surface_similar(packed: vec4<u32>, depth: f32, normal: vec3<f32>) -> bool {
    return reservoir_surfaces_similar(bitcast<f32>(packed.x), octahedral_decode(packed.y), depth, normal);
}

// The view depth of a world point for `camera`.
fn reservoir_depth(camera: GpuCamera, position: vec3<f32>) -> f32 {
    return dot(position - camera.origin, camera.forward);
}

// Whether the frame resamples its area light: the pipeline is specialised with the reservoirs'
// code and the frame asks for it (`enabled`: its parameters' flag).
fn restir_di_on(enabled: u32) -> bool {
    return FEATURE_RESTIR_DI && enabled != 0u;
}
