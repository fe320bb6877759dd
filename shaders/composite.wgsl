// Composite: the frame's radiance from its parts, then the running mean over frames.
//
// Per pixel: where the camera sees no surface, the environment (which the direct pass wrote);
// where it sees one, its emission plus the light it reflects: the direct and indirect estimates
// as they are (modes direct, reference and naive, and realtime without the denoiser), or the
// denoiser's filtered lighting multiplied back by the demodulation albedo plus the punctual
// lights' exact part, which the denoiser leaves out (realtime). The
// running mean of independent frames is a progressive Monte Carlo estimate. The realtime mode
// with its denoiser resolves instead: the G-buffer takes one jittered point per pixel, so the
// emission, the environment and the albedo at silhouettes alias from frame to frame, and the
// colour is averaged over frames along the motion vectors, its history clamped to the 3 x 3
// neighbourhood of this frame's colours so that what moved leaves no ghost (temporal
// anti-aliasing: Karis, "High Quality Temporal Supersampling", SIGGRAPH 2014 course); under
// motion the history of other surfaces is left out, so that a bright emitter's does not smear
// onto its dark surroundings. Non-finite
// radiance never enters the sum or the history (DESIGN.md: tested by exponent bits).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/demodulate.wgsl

// chiaro_gpu::passes::composite::CompositeParams.
struct CompositeParams {
    // Frames in the sum after this one (1 on the first: the sum restarts).
    frames: u32,
    // COMPOSITE_DIRECT, COMPOSITE_PATHS or COMPOSITE_FILTERED.
    source: u32,
    // COMPOSITE_RESOLVE: average along the motion vectors; COMPOSITE_RESET: drop that history.
    flags: u32,
    // Least weight of this frame in the resolve's moving average.
    resolve_floor: f32,
}

@group(0) @binding(0) var direct_light: texture_2d<f32>;
@group(0) @binding(1) var indirect_light: texture_2d<f32>;
@group(0) @binding(2) var filtered_lighting: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_position: texture_2d<u32>;
@group(0) @binding(4) var gbuffer_surface: texture_2d<u32>;
@group(0) @binding(5) var gbuffer_emission: texture_2d<u32>;
@group(0) @binding(6) var<storage, read_write> accumulation: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read> params: CompositeParams;
@group(0) @binding(8) var hdr_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(9) var gbuffer_motion: texture_2d<u32>;
@group(0) @binding(10) var<storage, read> resolve_previous: array<vec4<f32>>;
@group(0) @binding(11) var<storage, read_write> resolve_next: array<vec4<f32>>;
@group(0) @binding(12) var<storage, read> resolve_previous_surface: array<u32>;
@group(0) @binding(13) var<storage, read_write> resolve_next_surface: array<u32>;
// The punctual lights' exact part of direct_light, which the denoiser leaves out of its lighting.
@group(0) @binding(14) var direct_punctual: texture_2d<f32>;

// The surface a pixel sees: its instance + 1, or 0 where it sees none.
fn resolve_surface(pixel: vec2<i32>) -> u32 {
    return textureLoad(gbuffer_emission, pixel, 0).w & ~GBUFFER_SHADES;
}

// This frame's radiance at a pixel.
fn frame_radiance(pixel: vec2<i32>) -> vec3<f32> {
    let direct = textureLoad(direct_light, pixel, 0).xyz;
    var texels: GbufferTexels;
    texels.position = textureLoad(gbuffer_position, pixel, 0);
    texels.surface = textureLoad(gbuffer_surface, pixel, 0);
    texels.emission = textureLoad(gbuffer_emission, pixel, 0);
    if !gbuffer_covered(texels) {
        return direct;
    }
    let g = gbuffer_unpack(texels);
    if params.source == COMPOSITE_DIRECT {
        return g.emission + direct;
    }
    if params.source == COMPOSITE_PATHS || !g.shades {
        return g.emission + direct + textureLoad(indirect_light, pixel, 0).xyz;
    }
    let lighting = textureLoad(filtered_lighting, pixel, 0).xyz;
    // A non-finite exact part is dropped alone (the temporal pass kept it out of history).
    let punctual = textureLoad(direct_punctual, pixel, 0).xyz;
    return g.emission + lighting * demodulation_albedo(g.base_color)
        + select(vec3<f32>(0.0), punctual, vec3_is_finite(punctual));
}

// This frame's radiance with non-finite values replaced by 0.
fn finite_radiance(pixel: vec2<i32>) -> vec3<f32> {
    let x = frame_radiance(pixel);
    return select(vec3<f32>(0.0), x, vec3_is_finite(x));
}

// Motion, in pixels per frame, from which the history of other surfaces is left out entirely.
const RESOLVE_OTHER_SURFACE_MOTION: f32 = 0.1;

// The resolve's history at the previous frame's position `at` (pixel units, texel centres at
// integer + 0.5): bilinear over the taps inside the image, renormalised; w = -1 if none is
// left. Taps that saw another surface than `surface` weigh `other` (1 on a still view, where
// the jitter moves a pixel's sample across silhouettes and the history averages them; down to 0
// as the view moves, so that one surface's history does not bleed into another's, as a bright
// emitter's would into the dark ceiling around it).
fn resolve_history(at: vec2<f32>, size: vec2<i32>, surface: u32, other: f32) -> vec4<f32> {
    let f = at - 0.5;
    let base = vec2<i32>(floor(f));
    let t = f - floor(f);
    var sum = vec4<f32>(0.0);
    var total = 0.0;
    for (var k = 0; k < 4; k++) {
        let o = vec2<i32>(k & 1, k >> 1u);
        let q = base + o;
        let w = select(1.0 - t.x, t.x, o.x == 1) * select(1.0 - t.y, t.y, o.y == 1);
        if all(q >= vec2<i32>(0)) && all(q < size) && w > 0.0 {
            let i = u32(q.y) * u32(size.x) + u32(q.x);
            let w_surface = w * select(other, 1.0, resolve_previous_surface[i] == surface);
            sum += w_surface * resolve_previous[i];
            total += w_surface;
        }
    }
    if total <= 0.0 {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    return sum / total;
}

// The resolved colour: this frame's `x` averaged with the history found along the motion
// vector (bilinear), the history clamped to the range of this frame's 3 x 3 neighbourhood.
fn resolve(pixel: vec2<i32>, size: vec2<i32>, x: vec3<f32>) -> vec4<f32> {
    let motion = bitcast<vec2<f32>>(textureLoad(gbuffer_motion, pixel, 0).xy);
    let valid = f32_is_finite(motion.x) && f32_is_finite(motion.y);
    if (params.flags & COMPOSITE_RESET) != 0u || !valid {
        return vec4<f32>(x, 1.0);
    }
    let other = clamp(1.0 - length(motion) / RESOLVE_OTHER_SURFACE_MOTION, 0.0, 1.0);
    let history = resolve_history(vec2<f32>(pixel) + 0.5 + motion, size, resolve_surface(pixel),
        other);
    if history.w < 0.0 {
        return vec4<f32>(x, 1.0);
    }
    var lo = x;
    var hi = x;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let q = clamp(pixel + vec2<i32>(dx, dy), vec2<i32>(0), size - 1);
            let c = finite_radiance(q);
            lo = min(lo, c);
            hi = max(hi, c);
        }
    }
    let length = history.w + 1.0;
    let weight = max(1.0 / length, params.resolve_floor);
    let clamped = clamp(history.xyz, lo, hi);
    return vec4<f32>(mix(clamped, x, weight), length);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(hdr_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let index = id.y * size.x + id.x;
    let x = finite_radiance(vec2<i32>(id.xy));
    if (params.flags & COMPOSITE_RESOLVE) != 0u {
        let resolved = resolve(vec2<i32>(id.xy), vec2<i32>(size), x);
        resolve_next[index] = resolved;
        resolve_next_surface[index] = resolve_surface(vec2<i32>(id.xy));
        textureStore(hdr_out, vec2<i32>(id.xy), vec4<f32>(resolved.xyz, 1.0));
        return;
    }
    var sum = vec4<f32>(x, 1.0);
    if params.frames > 1u {
        sum += accumulation[index];
    }
    accumulation[index] = sum;
    textureStore(hdr_out, vec2<i32>(id.xy), vec4<f32>(sum.xyz / f32(params.frames), 1.0));
}
