// One iteration of the denoiser's edge-avoiding a-trous wavelet filter, after SVGF (Schied et
// al., "Spatiotemporal Variance-Guided Filtering", HPG 2017, section 4.3; the a-trous scheme of
// Dammertz et al., "Edge-Avoiding A-Trous Wavelet Transform for fast Global Illumination
// Filtering", HPG 2010): a 3 x 3 kernel, the linear B-spline (1/4, 1/2, 1/4) on each axis,
// whose taps lie `step` pixels apart, each weighted by SVGF's edge-stopping on depth (against
// the depth gradient), normal and luminance (in standard deviations of the 3 x 3
// Gaussian-prefiltered variance). The colour is the demodulated lighting; the variance in alpha
// is filtered with the squared weights, as the variance of a weighted mean.
//
// Both papers use the 5 x 5 B3-spline (1/16, 1/4, 3/8, 1/4, 1/16). The 3 x 3 kernel reads 8
// taps instead of 24 and, over the same steps, reaches half as far. Measured with `chiaro
// bench` on its nine scenes at 256x256 (realtime, lavapipe), four 3 x 3 iterations against five
// 5 x 5 ones: the pass took half the time, and the error after 64 frames was lower on every
// scene (relMSE 8% to 31% lower, FLIP too: with the temporal history the wider kernel blurs
// more than it removes noise); after one frame it was within 10% either way
// (docs/experiments/atrous-kernel.md).
//
// Pixels that are not a covered, shading surface pass through. On smooth metals the taps around
// the centre weigh less, down to none on a mirror: their lighting is the reflected image, which
// the filter would blur, and the spatial blur of a specular signal is scaled by the width of its
// lobe (as REBLUR does: Zhdan, "ReBLUR: A Hierarchical Recurrent Denoiser", Ray Tracing Gems II,
// 2021, chapter 49); the temporal accumulation alone denoises them.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/denoise.wgsl

@group(0) @binding(0) var<storage, read> params: DenoiseParams;
@group(0) @binding(1) var input: texture_2d<f32>;
@group(0) @binding(2) var edges: texture_2d<f32>;
@group(0) @binding(3) var output: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var gbuffer_position: texture_2d<u32>;
@group(0) @binding(5) var gbuffer_surface: texture_2d<u32>;

// Roughness at and above which a metal is filtered fully.
const SPECULAR_FULL_FILTER_ROUGHNESS: f32 = 0.5;

// The weight of the taps around pixel p relative to SVGF's: 1 for dielectrics (mostly diffuse
// light) and rough metals, (roughness / SPECULAR_FULL_FILTER_ROUGHNESS)^2 below it on metals
// (the GGX lobe's width is roughness^2), mixed by metallic.
fn filter_spread(p: vec2<i32>) -> f32 {
    let roughness = bitcast<f32>(textureLoad(gbuffer_position, p, 0).w);
    let metallic = unpack2x16unorm(textureLoad(gbuffer_surface, p, 0).w).y;
    let r = clamp(roughness / SPECULAR_FULL_FILTER_ROUGHNESS, 0.0, 1.0);
    return mix(1.0, r * r, metallic);
}

// Linear B-spline weight of the tap `i` taps from the centre (0 or 1).
fn kernel(i: i32) -> f32 {
    return select(0.25, 0.5, i == 0);
}

// The centre's variance blurred by a 3 x 3 Gaussian (1/4 centre, 1/8 sides, 1/16 corners) over
// the pixels that shade.
fn prefiltered_variance(p: vec2<i32>, size: vec2<i32>) -> f32 {
    var sum = 0.0;
    var sum_w = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let q = p + vec2<i32>(x, y);
            if any(q < vec2<i32>(0)) || any(q >= size) {
                continue;
            }
            if !denoise_edge_filtered(denoise_edge_decode(textureLoad(edges, q, 0))) {
                continue;
            }
            let w = 0.25 / f32(1 << u32(abs(x) + abs(y)));
            sum += w * textureLoad(input, q, 0).w;
            sum_w += w;
        }
    }
    return sum / sum_w;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(output));
    let p = vec2<i32>(id.xy);
    if any(p >= size) {
        return;
    }
    let centre = textureLoad(input, p, 0);
    let e_p = denoise_edge_decode(textureLoad(edges, p, 0));
    if !denoise_edge_filtered(e_p) {
        textureStore(output, p, centre);
        return;
    }
    let l_p = luminance(centre.xyz);
    let sigma = params.sigma_luminance * sqrt(max(prefiltered_variance(p, size), 0.0));
    let step = i32(params.step);
    let spread = filter_spread(p);
    let w_centre = kernel(0) * kernel(0);
    var sum_w = w_centre;
    var sum_c = w_centre * centre.xyz;
    var sum_v = w_centre * w_centre * centre.w;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            if x == 0 && y == 0 {
                continue;
            }
            let offset = vec2<i32>(x, y) * step;
            let q = p + offset;
            if any(q < vec2<i32>(0)) || any(q >= size) {
                continue;
            }
            let c_q = textureLoad(input, q, 0);
            let e_q = denoise_edge_decode(textureLoad(edges, q, 0));
            let w = spread * kernel(abs(x)) * kernel(abs(y))
                * denoise_weight(e_p, e_q, vec2<f32>(offset), l_p, luminance(c_q.xyz), sigma, params);
            sum_w += w;
            sum_c += w * c_q.xyz;
            sum_v += w * w * c_q.w;
        }
    }
    var out = vec4<f32>(sum_c / sum_w, sum_v / (sum_w * sum_w));
    if !(vec3_is_finite(out.xyz) && f32_is_finite(out.w)) {
        out = centre;
    }
    textureStore(output, p, out);
}
