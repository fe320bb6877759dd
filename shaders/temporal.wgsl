// Temporal accumulation of the denoiser, after SVGF (Schied et al., "Spatiotemporal
// Variance-Guided Filtering", HPG 2017, section 4.1): this frame's lighting, demodulated by
// the surface albedo, is blended into the history reprojected through the G-buffer's motion
// vectors (camera and object motion), with the moments of its luminance. The lighting is the
// direct and indirect light less the punctual lights' part when it is exact (direct_punctual:
// every light evaluated, no sampling noise), which the composite adds back unfiltered: filtered
// with the rest, a sun's sharp shadow would be blurred by the variance of the sampled light
// (SVGF filters its direct and indirect light apart for the same reason).
//
// - Reprojection: the previous frame's 2 x 2 texels around the point the motion vector gives,
//   each accepted only if the previous G-buffer saw the same instance there, with a normal
//   within 25 degrees of this one and a position within 1% of the view depth of this pixel's
//   tangent plane (plane distance: slope-aware, a slanted surface's texels pass however much
//   their depth differs). The accepted texels are blended bilinearly, renormalized; where
//   none is, the accepted texels of the 3 x 3 around the point, equally (as SVGF).
// - Moving average: weight max(1 / history length, temporal_floor) for the new frame (the floor
//   falls frame by frame on a still view: chiaro_gpu::still_view); the history length
//   restarts at 1 where no texel is accepted (disocclusion) or on reset.
// - Non-finite guard: a sample with a NaN or an infinity (found by exponent bits: WGSL has no
//   isNan) is replaced by the history, or by 0 where there is none, so it never enters history.
//   No firefly clamp.
//
// Pixels that are not a covered, shading surface pass their light through unfiltered.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/demodulate.wgsl
#import lib/denoise.wgsl

@group(0) @binding(0) var<storage, read> camera: GpuCamera;
@group(0) @binding(1) var<storage, read> params: DenoiseParams;
@group(0) @binding(2) var direct_light: texture_2d<f32>;
@group(0) @binding(3) var indirect_light: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_position: texture_2d<u32>;
@group(0) @binding(5) var gbuffer_surface: texture_2d<u32>;
@group(0) @binding(6) var gbuffer_emission: texture_2d<u32>;
@group(0) @binding(7) var gbuffer_motion: texture_2d<u32>;
@group(0) @binding(8) var previous_position: texture_2d<u32>;
@group(0) @binding(9) var previous_surface: texture_2d<u32>;
@group(0) @binding(10) var previous_emission: texture_2d<u32>;
// Last frame's temporal average (rgb; chiaro_gpu::Denoiser::record_atrous says why not SVGF's
// first a-trous iteration).
@group(0) @binding(11) var color_history: texture_2d<f32>;
// Last frame's moments: luminance, luminance squared, history length.
@group(0) @binding(12) var moments_history: texture_2d<f32>;
@group(0) @binding(13) var integrated_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(14) var moments_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(15) var edges_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(16) var lighting_out: texture_storage_2d<rgba32float, write>;
// The part of direct_light from punctual lights that has no sampling noise: left out here.
@group(0) @binding(17) var direct_punctual: texture_2d<f32>;

// Longest history counted (the weight stops falling at the floor long before).
const MAX_HISTORY: f32 = 1024.0;
// Least cosine between this normal and a history texel's.
const NORMAL_COS: f32 = 0.9;
// Largest distance of a history texel from this pixel's tangent plane, over the view depth.
const PLANE_DISTANCE: f32 = 0.01;
// Least total bilinear weight of accepted texels for the history to count.
const MIN_WEIGHT: f32 = 1.0e-3;

fn current_texels(p: vec2<i32>) -> GbufferTexels {
    return GbufferTexels(textureLoad(gbuffer_position, p, 0), textureLoad(gbuffer_surface, p, 0),
        textureLoad(gbuffer_emission, p, 0));
}

fn previous_texels(p: vec2<i32>) -> GbufferTexels {
    return GbufferTexels(textureLoad(previous_position, p, 0), textureLoad(previous_surface, p, 0),
        textureLoad(previous_emission, p, 0));
}

fn shades(t: GbufferTexels) -> bool {
    return gbuffer_covered(t) && (t.emission.w & GBUFFER_SHADES) != 0u;
}

fn view_depth(position: vec3<f32>) -> f32 {
    return dot(position - camera.origin, camera.forward);
}

// The depth change per pixel towards +axis: the smaller one-sided difference among the
// neighbours that shade (0 with none), so that a depth edge beside the pixel does not count.
fn depth_slope(p: vec2<i32>, axis: vec2<i32>, depth: f32, size: vec2<i32>) -> f32 {
    var best = 0.0;
    var found = false;
    for (var side = -1; side <= 1; side += 2) {
        let q = p + axis * side;
        if any(q < vec2<i32>(0)) || any(q >= size) {
            continue;
        }
        let t = current_texels(q);
        if !shades(t) {
            continue;
        }
        let d = (view_depth(gbuffer_unpack(t).position) - depth) * f32(side);
        if !found || abs(d) < abs(best) {
            best = d;
            found = true;
        }
    }
    return best;
}

fn finite4(v: vec4<f32>) -> bool {
    return vec3_is_finite(v.xyz) && f32_is_finite(v.w);
}

// A usable lighting sample: finite, and small enough that its luminance squared (the second
// moment) stays finite.
fn usable(c: vec3<f32>) -> bool {
    return vec3_is_finite(c) && abs(luminance(c)) < 1.0e18;
}

struct HistoryTap {
    color: vec3<f32>,
    moments: vec3<f32>,
    // 1 if accepted, else 0 (and the rest 0).
    weight: f32,
}

// The previous frame's texel `q` if it passes the disocclusion tests against the surface `s`
// at view depth `depth`: inside the image, a shading surface of the same instance, normals
// within NORMAL_COS, within PLANE_DISTANCE x depth of the surface's tangent plane, finite.
fn history_tap(q: vec2<i32>, s: GbufferSurface, depth: f32, size: vec2<i32>) -> HistoryTap {
    var none: HistoryTap;
    if any(q < vec2<i32>(0)) || any(q >= size) {
        return none;
    }
    let t = previous_texels(q);
    if !shades(t) {
        return none;
    }
    let h = gbuffer_unpack(t);
    let plane = abs(dot(h.position - s.position, s.geometric_normal));
    if h.instance != s.instance || dot(h.geometric_normal, s.geometric_normal) < NORMAL_COS
        || !(plane <= PLANE_DISTANCE * depth) {
        return none;
    }
    let c = textureLoad(color_history, q, 0);
    let m = textureLoad(moments_history, q, 0);
    if !finite4(c) || !finite4(m) {
        return none;
    }
    return HistoryTap(c.xyz, m.xyz, 1.0);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(integrated_out));
    let p = vec2<i32>(id.xy);
    if any(p >= size) {
        return;
    }
    let light = textureLoad(direct_light, p, 0).xyz - textureLoad(direct_punctual, p, 0).xyz
        + textureLoad(indirect_light, p, 0).xyz;
    let texels = current_texels(p);
    if !shades(texels) {
        let through = select(vec3<f32>(0.0), light, usable(light));
        textureStore(integrated_out, p, vec4<f32>(through, 0.0));
        textureStore(moments_out, p, vec4<f32>(0.0));
        textureStore(edges_out, p, vec4<f32>(-1.0, 0.0, 0.0, 0.0));
        textureStore(lighting_out, p, vec4<f32>(light, 0.0));
        return;
    }
    let s = gbuffer_unpack(texels);
    let depth = view_depth(s.position);
    let slope = vec2<f32>(depth_slope(p, vec2<i32>(1, 0), depth, size),
        depth_slope(p, vec2<i32>(0, 1), depth, size));
    textureStore(edges_out, p, vec4<f32>(depth, slope, denoise_normal_encode(s.shading_normal)));
    let lighting = light / demodulation_albedo(s.base_color);
    textureStore(lighting_out, p, vec4<f32>(lighting, 0.0));

    // Bilinear history over the accepted texels.
    let motion = motion_unpack(textureLoad(gbuffer_motion, p, 0).x);
    // Texel centres sit at +0.5: the taps around the point p + 0.5 + motion start at floor(p + motion).
    let previous = vec2<f32>(p) + motion;
    var color = vec3<f32>(0.0);
    var moments = vec3<f32>(0.0);
    var weight = 0.0;
    let reprojects = params.reset == 0u && all(abs(motion) < vec2<f32>(1.0e6));
    if reprojects {
        let base = vec2<i32>(floor(previous));
        let f = previous - floor(previous);
        for (var k = 0; k < 4; k++) {
            let o = vec2<i32>(k & 1, k >> 1u);
            let b = select(1.0 - f, f, vec2<bool>(o == vec2<i32>(1)));
            let tap = history_tap(base + o, s, depth, size);
            color += b.x * b.y * tap.color;
            moments += b.x * b.y * tap.moments;
            weight += b.x * b.y * tap.weight;
        }
    }
    if reprojects && weight < MIN_WEIGHT {
        // As SVGF: where no bilinear tap is accepted (sub-pixel edges move with the jitter),
        // the accepted texels of the 3 x 3 around the point, equally weighted.
        let centre = vec2<i32>(floor(previous + 0.5));
        for (var k = 0; k < 9; k++) {
            let tap = history_tap(centre + vec2<i32>(k % 3 - 1, k / 3 - 1), s, depth, size);
            color += tap.color;
            moments += tap.moments;
            weight += tap.weight;
        }
    }
    let has_history = weight >= MIN_WEIGHT;
    var history_color = vec3<f32>(0.0);
    var history_moments = vec3<f32>(0.0);
    if has_history {
        history_color = color / weight;
        history_moments = moments / weight;
    }
    var x = lighting;
    if !usable(x) {
        x = history_color;
    }
    let l = luminance(x);
    let frames = min(history_moments.z + 1.0, MAX_HISTORY);
    let alpha = select(1.0, max(1.0 / frames, params.temporal_floor), has_history);
    var integrated = mix(history_color, x, alpha);
    var m = mix(history_moments.xy, vec2<f32>(l, l * l), alpha);
    if !vec3_is_finite(integrated) || !f32_is_finite(m.x) || !f32_is_finite(m.y) {
        integrated = x;
        m = vec2<f32>(l, l * l);
    }
    textureStore(integrated_out, p, vec4<f32>(integrated, 0.0));
    textureStore(moments_out, p, vec4<f32>(m, select(1.0, frames, has_history), 0.0));
}
