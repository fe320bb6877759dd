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
// colour is averaged over frames along the motion vectors (where the camera sees the
// environment, which the G-buffer gives none, along the camera's rotation), its history
// clamped to the 3 x 3 neighbourhood of this frame's colours so that what moved leaves no
// ghost (temporal anti-aliasing: Karis, "High Quality Temporal Supersampling", SIGGRAPH 2014
// course); on a still view the clamp fades out as the running mean grows
// (chiaro_gpu::still_view), so that a feature thinner than a pixel, which the jitter misses in
// some frames, keeps the mean of the frames that saw it. Under motion the history is resampled
// with Catmull-Rom, clipped to the neighbourhood's mean and standard deviation, kept shorter,
// and weighed against this frame by inverse luminance; the history of another surface much
// brighter or darker is left out, so that a bright emitter's does not smear onto its dark
// surroundings, and where no history is left the pixel starts from a tent filter of this
// frame. Non-finite radiance never enters the sum or the history (DESIGN.md: tested by
// exponent bits).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/demodulate.wgsl
#import lib/color.wgsl
#import lib/camera.wgsl

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
    // How much of the clamp to this frame's neighbourhood the history gets on a still view.
    resolve_clamp: f32,
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
@group(0) @binding(10) var resolve_previous: texture_2d<f32>;
@group(0) @binding(11) var resolve_next: texture_storage_2d<rgba32float, write>;
@group(0) @binding(12) var resolve_previous_surface: texture_2d<u32>;
@group(0) @binding(13) var resolve_next_surface: texture_storage_2d<r32uint, write>;
// The punctual lights' exact part of direct_light, which the denoiser leaves out of its lighting.
@group(0) @binding(14) var direct_punctual: texture_2d<f32>;
@group(0) @binding(15) var<storage, read> camera: GpuCamera;

// The surface a pixel sees: its instance + 1, or 0 where it sees none.
fn resolve_surface(pixel: vec2<i32>) -> u32 {
    return textureLoad(gbuffer_emission, pixel, 0).w & ~GBUFFER_FLAGS;
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

// The workgroup's side in pixels.
const GROUP_SIDE: u32 = 8u;

// This frame's finite radiance over the workgroup's pixels and a border of one pixel
// (NEIGHBOURHOOD_SIDE squared, row by row, coordinates clamped to the image): the resolve's
// 3 x 3 neighbourhoods read it, so each pixel's radiance is composed once, not nine times.
const NEIGHBOURHOOD_SIDE: u32 = GROUP_SIDE + 2u;
var<workgroup> neighbourhood: array<vec3<f32>, NEIGHBOURHOOD_SIDE * NEIGHBOURHOOD_SIDE>;

// Fills `neighbourhood` for the workgroup whose first pixel is `origin`; `local` is the
// invocation's index in the workgroup.
fn fill_neighbourhood(origin: vec2<i32>, local: u32, size: vec2<i32>) {
    for (var k = local; k < NEIGHBOURHOOD_SIDE * NEIGHBOURHOOD_SIDE; k += GROUP_SIDE * GROUP_SIDE) {
        let offset = vec2<i32>(i32(k % NEIGHBOURHOOD_SIDE), i32(k / NEIGHBOURHOOD_SIDE)) - 1;
        neighbourhood[k] = finite_radiance(clamp(origin + offset, vec2<i32>(0), size - 1));
    }
}

// This frame's finite radiance at `pixel` + `offset` (each in -1..1), clamped to the image;
// `local` is the pixel's position in its workgroup.
fn neighbour(local: vec2<u32>, offset: vec2<i32>) -> vec3<f32> {
    let at = vec2<u32>(vec2<i32>(local) + 1 + offset);
    return neighbourhood[at.y * NEIGHBOURHOOD_SIDE + at.x];
}

// Motion, in pixels per frame, from which the resolve treats the view as moving: the history
// of other surfaces of a different brightness is left out, the history is clipped to
// RESOLVE_CLIP_SIGMAS standard deviations, this frame weighs at least RESOLVE_MOVING_FLOOR and
// colours weigh by resolve_tone_weight. Between 0 and this, it blends from the still view's
// rules to those.
const RESOLVE_MOVING_FROM: f32 = 0.1;

// Standard deviations of this frame's 3 x 3 neighbourhood the history may lie from its mean
// under motion.
const RESOLVE_CLIP_SIGMAS: f32 = 1.0;

// Least weight of this frame in the resolve under motion (still: the denoiser's temporal
// floor, 0.05 by default, falling while nothing changes: chiaro_gpu::still_view). Every moving
// frame resamples the history between pixels; a shorter memory blurs a thin shadow less.
const RESOLVE_MOVING_FLOOR: f32 = 0.3;

// Luminance ratio from which the history of another surface is left out under motion.
const RESOLVE_OTHER_SURFACE_CONTRAST: f32 = 8.0;

// Whether history texel `q` (colour `history`) may stand for a pixel that sees `surface` with
// luminance `lum`: it saw the same surface, or one of a luminance within
// RESOLVE_OTHER_SURFACE_CONTRAST of it.
fn resolve_compatible(q: vec2<i32>, history: vec4<f32>, surface: u32, lum: f32) -> bool {
    let h = max(luminance(history.xyz), 0.0) + 1e-3;
    let l = max(lum, 0.0) + 1e-3;
    return textureLoad(resolve_previous_surface, q, 0).x == surface
        || max(h, l) < RESOLVE_OTHER_SURFACE_CONTRAST * min(h, l);
}

// Under motion (`moving` 1), a colour's weight in the resolve's averages falls as 1 / (1 +
// luminance), so that one jittered sample of a small bright emitter or highlight does not
// outweigh the rest (Karis 2014); a still view (`moving` 0) weighs colours alike, so that its
// history converges to the unbiased mean. Never below 1e-30, so that no sum of weights is 0.
fn resolve_tone_weight(c: vec3<f32>, moving: f32) -> f32 {
    return max(mix(1.0, 1.0 / (1.0 + max(luminance(c), 0.0)), moving), 1e-30);
}

// Catmull-Rom weights of the four taps at -1, 0, 1 and 2 around a position t in [0, 1) past
// tap 0.
fn catmull_rom_weights(t: f32) -> vec4<f32> {
    let t2 = t * t;
    let t3 = t2 * t;
    return vec4<f32>(-0.5 * t + t2 - 0.5 * t3, 1.0 - 2.5 * t2 + 1.5 * t3,
        0.5 * t + 2.0 * t2 - 1.5 * t3, -0.5 * t2 + 0.5 * t3);
}

// The resolve's history at the previous frame's position `at` (pixel units, texel centres at
// integer + 0.5), resampled with a Catmull-Rom filter over its 4 x 4 taps: a bilinear fetch
// would blur the history a little more at every frame the view moves, and the resolve keeps
// most of it frame after frame (Karis 2014 resamples TAA's history so, for the same reason).
// Where a tap is outside the image or is not resolve_compatible with this pixel's `surface` and
// luminance `lum`, bilinear over the 2 x 2 taps inside the image, renormalised, instead. There
// the incompatible taps weigh `other`: 1 on a still view, where the jitter moves a pixel's
// sample across silhouettes and the history averages them; down to 0 as the view moves, so
// that a bright emitter's history does not bleed into the dark ceiling around it. Taps of
// other surfaces of a like brightness (a sphere's edge on the floor under it) stay: they are
// the anti-aliased edge. w = -1 if no tap is left.
fn resolve_history(at: vec2<f32>, size: vec2<i32>, surface: u32, lum: f32, other: f32)
    -> vec4<f32> {
    let f = at - 0.5;
    let base = vec2<i32>(floor(f));
    let t = f - floor(f);
    if all(base - 1 >= vec2<i32>(0)) && all(base + 2 < size) {
        let wx = catmull_rom_weights(t.x);
        let wy = catmull_rom_weights(t.y);
        var sum = vec4<f32>(0.0);
        var same = true;
        for (var k = 0; k < 16; k++) {
            let o = vec2<i32>(k & 3, k >> 2u);
            let q = base - 1 + o;
            let h = textureLoad(resolve_previous, q, 0);
            same = same && resolve_compatible(q, h, surface, lum);
            sum += wx[o.x] * wy[o.y] * h;
        }
        if same {
            return sum;
        }
    }
    var sum = vec4<f32>(0.0);
    var total = 0.0;
    for (var k = 0; k < 4; k++) {
        let o = vec2<i32>(k & 1, k >> 1u);
        let q = base + o;
        let w = select(1.0 - t.x, t.x, o.x == 1) * select(1.0 - t.y, t.y, o.y == 1);
        if all(q >= vec2<i32>(0)) && all(q < size) && w > 0.0 {
            let h = textureLoad(resolve_previous, q, 0);
            let w_surface = w * select(other, 1.0, resolve_compatible(q, h, surface, lum));
            sum += w_surface * h;
            total += w_surface;
        }
    }
    if total <= 0.0 {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    return sum / total;
}

// The motion of the environment seen at `pixel` (where the G-buffer drew nothing and left no
// motion vector), in pixels from where it is now to where it was in the previous frame: a
// direction at infinity moves with the camera's rotation alone. Zero for an orthographic camera
// (every pixel sees the environment along the same direction); infinite (the history restarts)
// where the previous camera did not look that way.
fn environment_motion(pixel: vec2<i32>) -> vec2<f32> {
    if camera.orthographic != 0u {
        return vec2<f32>(0.0);
    }
    let d = camera_ray(camera, vec2<f32>(pixel) + 0.5).direction;
    let now = camera.unjittered_view_proj * vec4<f32>(d, 0.0);
    let before = camera.previous_view_proj * vec4<f32>(d, 0.0);
    if now.w <= 0.0 || before.w <= 0.0 {
        return vec2<f32>(f32_infinity());
    }
    let to_pixel = vec2<f32>(0.5, -0.5) * vec2<f32>(camera.width, camera.height);
    return (before.xy / before.w - now.xy / now.w) * to_pixel;
}

// The resolved colour: this frame's `x` averaged with the history found along the motion
// vector (resolve_history), the history clamped to the range of this frame's 3 x 3
// neighbourhood. Where the history's position is outside the image or no tap is left, the
// history restarts: from `x` on a still view, from the 3 x 3 tent filter of this frame (weighed
// by resolve_tone_weight) under motion, whose one jittered sample at a silhouette would
// otherwise show for a frame with full weight.
fn resolve(pixel: vec2<i32>, local: vec2<u32>, size: vec2<i32>, x: vec3<f32>) -> vec4<f32> {
    var motion = motion_unpack(textureLoad(gbuffer_motion, pixel, 0).x);
    if resolve_surface(pixel) == 0u {
        motion = environment_motion(pixel);
    }
    let valid = f32_is_finite(motion.x) && f32_is_finite(motion.y);
    if (params.flags & COMPOSITE_RESET) != 0u || !valid {
        return vec4<f32>(x, 1.0);
    }
    let other = clamp(1.0 - length(motion) / RESOLVE_MOVING_FROM, 0.0, 1.0);
    let moving = 1.0 - other;
    var lo = x;
    var hi = x;
    var sum = vec3<f32>(0.0);
    var sum2 = vec3<f32>(0.0);
    var tent = vec3<f32>(0.0);
    var tent_weight = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let c = neighbour(local, vec2<i32>(dx, dy));
            lo = min(lo, c);
            hi = max(hi, c);
            sum += c;
            sum2 += c * c;
            let w = f32((2 - abs(dx)) * (2 - abs(dy))) * resolve_tone_weight(c, moving);
            tent += w * c;
            tent_weight += w;
        }
    }
    let at = vec2<f32>(pixel) + 0.5 + motion;
    let history = resolve_history(at, size, resolve_surface(pixel), luminance(x), other);
    if history.w < 0.0 || any(at < vec2<f32>(0.0)) || any(at >= vec2<f32>(size)) {
        return vec4<f32>(mix(x, tent / tent_weight, moving), 1.0);
    }
    // Under motion, the range narrows to RESOLVE_CLIP_SIGMAS standard deviations about the
    // neighbourhood's mean (variance clipping: Salvi, "An Excursion in Temporal Supersampling",
    // GDC 2016): a moving view fetches its history between pixels, blending a thin shadow or
    // highlight with its surroundings, and the full 3 x 3 range, which holds both, would keep the
    // blend frame after frame. A still view keeps the full range, and applies only the share
    // params.resolve_clamp of it, so that the history converges.
    let mean = sum / 9.0;
    let sigma = sqrt(max(sum2 / 9.0 - mean * mean, vec3<f32>(0.0)));
    lo = max(lo, mix(lo, mean - RESOLVE_CLIP_SIGMAS * sigma, moving));
    hi = min(hi, mix(hi, mean + RESOLVE_CLIP_SIGMAS * sigma, moving));
    let length = history.w + 1.0;
    let weight = max(1.0 / length, mix(params.resolve_floor, RESOLVE_MOVING_FLOOR, moving));
    let clamp_share = mix(params.resolve_clamp, 1.0, moving);
    let clamped = mix(history.xyz, clamp(history.xyz, lo, hi), clamp_share);
    let w_x = weight * resolve_tone_weight(x, moving);
    let w_history = (1.0 - weight) * resolve_tone_weight(clamped, moving);
    return vec4<f32>((w_x * x + w_history * clamped) / (w_x + w_history), length);
}

@compute @workgroup_size(GROUP_SIDE, GROUP_SIDE)
fn main(@builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
    @builtin(workgroup_id) group: vec3<u32>) {
    let size = textureDimensions(hdr_out);
    let resolving = (params.flags & COMPOSITE_RESOLVE) != 0u;
    if resolving {
        fill_neighbourhood(vec2<i32>(group.xy * GROUP_SIDE), local_index, vec2<i32>(size));
    }
    workgroupBarrier();
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let index = id.y * size.x + id.x;
    if resolving {
        let x = neighbour(local.xy, vec2<i32>(0));
        let resolved = resolve(vec2<i32>(id.xy), local.xy, vec2<i32>(size), x);
        textureStore(resolve_next, vec2<i32>(id.xy), resolved);
        textureStore(resolve_next_surface, vec2<i32>(id.xy),
            vec4<u32>(resolve_surface(vec2<i32>(id.xy)), 0u, 0u, 0u));
        textureStore(hdr_out, vec2<i32>(id.xy), vec4<f32>(resolved.xyz, 1.0));
        return;
    }
    var sum = vec4<f32>(finite_radiance(vec2<i32>(id.xy)), 1.0);
    if params.frames > 1u {
        sum += accumulation[index];
    }
    accumulation[index] = sum;
    textureStore(hdr_out, vec2<i32>(id.xy), vec4<f32>(sum.xyz / f32(params.frames), 1.0));
}
