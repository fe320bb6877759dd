// What the denoiser's passes (temporal, variance, atrous) share: their parameters, the per-pixel
// edge data the temporal pass writes for the filters, and SVGF's edge-stopping weights
// (Schied et al., "Spatiotemporal Variance-Guided Filtering", HPG 2017, section 4.4).

#import lib/gbuffer_packing.wgsl
#import lib/color.wgsl

// chiaro_gpu::denoiser::DenoiseParams: one copy per a-trous iteration (the temporal and
// variance passes read the first).
struct DenoiseParams {
    // Least weight of the new frame in the temporal moving average this frame.
    temporal_floor: f32,
    // 1: drop all history this frame.
    reset: u32,
    // This a-trous iteration's step between taps in pixels (1, 2, 4, ...).
    step: u32,
    // A-trous iterations in the frame.
    iterations: u32,
    // SVGF's sigma_z, sigma_n and sigma_l.
    sigma_depth: f32,
    sigma_normal: f32,
    sigma_luminance: f32,
    // The variance of a long history's average relative to one frame's sample.
    history_variance: f32,
}

// log2(e): exp(x) = exp2(x log2(e)).
const DENOISE_LOG2_E: f32 = 1.4426950408889634;
// Least cosine between normals in the edge-stopping weight (log2(0) is -infinity): 1e-30^sigma_n
// is 0 in f32 for any sigma_n of 2 or more.
const DENOISE_MIN_COSINE: f32 = 1.0e-30;

// Frames of history below which the variance pass estimates variance spatially.
const DENOISE_SHORT_HISTORY: f32 = 4.0;

// The edge texel (rgba32float) of a pixel the temporal pass writes: view depth (negative where
// the pixel is not a covered, shading surface: its lighting passes through unfiltered), the
// depth gradient per pixel in x and y, and the shading normal (denoise_normal_encode).
struct DenoiseEdge {
    depth: f32,
    gradient: vec2<f32>,
    normal: vec3<f32>,
}

// A unit normal as one float: octahedral coordinates (as the G-buffer's) quantized to 12 bits
// each, held as an integer below 2^24, so it is exact in f32 (raw bits could be a denormal,
// which a device may flush to zero).
fn denoise_normal_encode(n: vec3<f32>) -> f32 {
    let f = unpack2x16snorm(octahedral_encode(n));
    let u = vec2<u32>(round((f * 0.5 + 0.5) * 4095.0));
    return f32(u.x + u.y * 4096u);
}

fn denoise_normal_decode(x: f32) -> vec3<f32> {
    let u = u32(x);
    let f = vec2<f32>(vec2<u32>(u & 4095u, u >> 12u)) / 4095.0 * 2.0 - 1.0;
    return octahedral_unfold(f);
}

fn denoise_edge_decode(t: vec4<f32>) -> DenoiseEdge {
    return DenoiseEdge(t.x, t.yz, denoise_normal_decode(t.w));
}

// Whether the pixel's lighting is filtered (a covered surface that shades).
fn denoise_edge_filtered(e: DenoiseEdge) -> bool {
    return e.depth >= 0.0;
}

// SVGF's edge-stopping weight between the centre pixel `p` and a tap `q` at pixel offset
// `offset` (equation 3 to 5): depth against the centre's gradient along the offset, normals
// raised to sigma_n, luminance in units of the centre's standard deviation `sigma_l_scaled`
// (sigma_l x the prefiltered standard deviation). The luminance term is the exponent, so the
// weight is exp(-depth term - luminance term) x normal term, computed as one power of 2:
// exp2(sigma_n log2(n_p . n_q) - (depth term + luminance term) log2(e)), the cosine floored at
// DENOISE_MIN_COSINE (where the normal term is 0 to f32 anyway).
fn denoise_weight(p: DenoiseEdge, q: DenoiseEdge, offset: vec2<f32>, l_p: f32, l_q: f32,
    sigma_l_scaled: f32, params: DenoiseParams) -> f32 {
    if !denoise_edge_filtered(q) {
        return 0.0;
    }
    let w_z = abs(p.depth - q.depth) / (params.sigma_depth * abs(dot(p.gradient, offset)) + 1.0e-3 * p.depth + 1.0e-8);
    let cosine = max(dot(p.normal, q.normal), DENOISE_MIN_COSINE);
    let w_l = abs(l_p - l_q) / (sigma_l_scaled + 1.0e-10);
    return exp2(params.sigma_normal * log2(cosine) - (w_z + w_l) * DENOISE_LOG2_E);
}
