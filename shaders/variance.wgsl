// Variance estimation of the denoiser, after SVGF (Schied et al., "Spatiotemporal
// Variance-Guided Filtering", HPG 2017, section 4.2): the luminance variance per pixel from
// the temporal moments, E[l^2] - E[l]^2, divided by the moving average's effective sample
// count (SVGF does not divide: its filter then blurs a converged history as much as one
// frame's noise; on the Cornell box at 64 x 64 the division lowers relMSE after 64 frames,
// see tests/denoise.rs); where the history is shorter than 4 frames the
// moments are too few, so the variance (and the colour) comes from a 7 x 7 cross-bilateral
// neighbourhood instead (depth and normal edge-stopping as the a-trous filter, luminance with
// SVGF's fixed sigma of 10), boosted by 4 / history length as SVGF does (and divided by the
// history length, as the long history's).
//
// Writes the colour with the variance in alpha, the a-trous filter's input.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/denoise.wgsl

@group(0) @binding(0) var<storage, read> params: DenoiseParams;
@group(0) @binding(1) var integrated: texture_2d<f32>;
@group(0) @binding(2) var moments: texture_2d<f32>;
@group(0) @binding(3) var edges: texture_2d<f32>;
@group(0) @binding(4) var filtered_out: texture_storage_2d<rgba32float, write>;

// SVGF's luminance sigma of the spatial estimate (absolute: it only stops at large jumps).
const SPATIAL_SIGMA_LUMINANCE: f32 = 10.0;
const SPATIAL_RADIUS: i32 = 3;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(filtered_out));
    let p = vec2<i32>(id.xy);
    if any(p >= size) {
        return;
    }
    let c_p = textureLoad(integrated, p, 0).xyz;
    let e_p = denoise_edge_decode(textureLoad(edges, p, 0));
    let m_p = textureLoad(moments, p, 0);
    if !denoise_edge_filtered(e_p) {
        textureStore(filtered_out, p, vec4<f32>(c_p, 0.0));
        return;
    }
    if m_p.z >= DENOISE_SHORT_HISTORY {
        // The moments give the variance of one frame's sample, but the colour filtered is the
        // moving average, whose variance is smaller by its effective sample count: 1 / n for
        // the plain mean of n frames (weights 1 / n); for a long history, a / (2 - a) for an
        // exponential average of weight a in its steady state, less on a still view
        // (chiaro_gpu::still_view); the larger of the two in between.
        let v = max(m_p.y - m_p.x * m_p.x, 0.0) * max(1.0 / m_p.z, params.history_variance);
        textureStore(filtered_out, p, vec4<f32>(c_p, v));
        return;
    }
    let l_p = luminance(c_p);
    var sum_w = 0.0;
    var sum_c = vec3<f32>(0.0);
    var sum_m = vec2<f32>(0.0);
    for (var y = -SPATIAL_RADIUS; y <= SPATIAL_RADIUS; y++) {
        for (var x = -SPATIAL_RADIUS; x <= SPATIAL_RADIUS; x++) {
            let q = p + vec2<i32>(x, y);
            if any(q < vec2<i32>(0)) || any(q >= size) {
                continue;
            }
            let c_q = textureLoad(integrated, q, 0).xyz;
            let e_q = denoise_edge_decode(textureLoad(edges, q, 0));
            var w = 1.0;
            if x != 0 || y != 0 {
                w = denoise_weight(e_p, e_q, vec2<f32>(f32(x), f32(y)), l_p, luminance(c_q),
                    SPATIAL_SIGMA_LUMINANCE, params);
            }
            sum_w += w;
            sum_c += w * c_q;
            sum_m += w * textureLoad(moments, q, 0).xy;
        }
    }
    let c = sum_c / sum_w;
    let m = sum_m / sum_w;
    // SVGF's boost of 4 / h for a short history, over h as for the long one: the
    // neighbourhood's moments are single frames', the colour the mean of h. (Without the last
    // division frames 2 and 3 measured relMSE 1.47e-2 and 1.82e-2 on the 64 x 64 Cornell box,
    // with it 1.36e-2 and 1.63e-2; frame 1 is the same.)
    let h = max(m_p.z, 1.0);
    let v = max(m.y - m.x * m.x, 0.0) * DENOISE_SHORT_HISTORY / (h * h);
    var out = vec4<f32>(c, v);
    if !(vec3_is_finite(c) && f32_is_finite(v)) {
        out = vec4<f32>(c_p, 0.0);
    }
    textureStore(filtered_out, p, out);
}
