// Tonemapping linear HDR radiance to linear display values in [0, 1]. Mirrors
// chiaro_shading::tonemap::Tonemapper::apply; the curves' numbers come from the generated
// module (chiaro_shading::tonemap::CURVE_CONSTANTS).
//
// - ACES fitted: Stephen Hill, 2016, "ACES.hlsl" (BakingLab), a fit of the Academy Color
//   Encoding System's reference rendering and sRGB output transforms.
// - PBR Neutral: Khronos 3D Commerce working group, 2024, "Khronos PBR Neutral Tone Mapper".
// - Clamp: no curve.
//
// Inputs are sanitised as in the Rust: an exposure that is not finite and positive counts as
// 0; each channel of linear * exposure is clamped to [0, MAX_TONEMAP_INPUT], NaN reading as 0.

#import lib/generated.wgsl
#import lib/float.wgsl

fn tonemap_sanitize_channel(x: f32) -> f32 {
    return select(0.0, min(x, MAX_TONEMAP_INPUT), x > 0.0);
}

// linear * exposure, sanitised.
fn tonemap_input(linear: vec3<f32>, exposure_in: f32) -> vec3<f32> {
    let exposure = select(0.0, exposure_in, f32_is_finite(exposure_in) && exposure_in > 0.0);
    let c = linear * exposure;
    return vec3<f32>(tonemap_sanitize_channel(c.x), tonemap_sanitize_channel(c.y), tonemap_sanitize_channel(c.z));
}

// A 3x3 matrix given by rows times c, summed in glam's order.
fn tonemap_rows(r0: vec3<f32>, r1: vec3<f32>, r2: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        (r0.x * c.x + r0.y * c.y) + r0.z * c.z,
        (r1.x * c.x + r1.y * c.y) + r1.z * c.z,
        (r2.x * c.x + r2.y * c.y) + r2.z * c.z,
    );
}

// Hill's fit, on a sanitised colour.
fn aces_fitted(c: vec3<f32>) -> vec3<f32> {
    let v = tonemap_rows(
        vec3<f32>(ACES_INPUT_00, ACES_INPUT_01, ACES_INPUT_02),
        vec3<f32>(ACES_INPUT_10, ACES_INPUT_11, ACES_INPUT_12),
        vec3<f32>(ACES_INPUT_20, ACES_INPUT_21, ACES_INPUT_22),
        c,
    );
    let a = v * (v + ACES_FIT_A) - ACES_FIT_B;
    let b = v * (ACES_FIT_C * v + ACES_FIT_D) + ACES_FIT_E;
    return tonemap_rows(
        vec3<f32>(ACES_OUTPUT_00, ACES_OUTPUT_01, ACES_OUTPUT_02),
        vec3<f32>(ACES_OUTPUT_10, ACES_OUTPUT_11, ACES_OUTPUT_12),
        vec3<f32>(ACES_OUTPUT_20, ACES_OUTPUT_21, ACES_OUTPUT_22),
        a / b,
    );
}

// Khronos PBR Neutral, on a sanitised colour.
fn pbr_neutral(color_in: vec3<f32>) -> vec3<f32> {
    var color = color_in;
    let x = min(min(color.x, color.y), color.z);
    var offset = PBR_NEUTRAL_OFFSET;
    if x < PBR_NEUTRAL_TOE_END {
        offset = x - PBR_NEUTRAL_TOE_SCALE * x * x;
    }
    color -= vec3<f32>(offset);
    let peak = max(max(color.x, color.y), color.z);
    if peak < PBR_NEUTRAL_START_COMPRESSION {
        return color;
    }
    let d = 1.0 - PBR_NEUTRAL_START_COMPRESSION;
    let new_peak = 1.0 - d * d / (peak + d - PBR_NEUTRAL_START_COMPRESSION);
    color *= new_peak / peak;
    let g = 1.0 - 1.0 / (PBR_NEUTRAL_DESATURATION * (peak - new_peak) + 1.0);
    return color + (vec3<f32>(new_peak) - color) * g;
}

// Tonemapper::AcesFitted.apply(linear, exposure).
fn tonemap_aces_fitted(linear: vec3<f32>, exposure: f32) -> vec3<f32> {
    return clamp(aces_fitted(tonemap_input(linear, exposure)), vec3<f32>(0.0), vec3<f32>(1.0));
}

// Tonemapper::PbrNeutral.apply(linear, exposure).
fn tonemap_pbr_neutral(linear: vec3<f32>, exposure: f32) -> vec3<f32> {
    return clamp(pbr_neutral(tonemap_input(linear, exposure)), vec3<f32>(0.0), vec3<f32>(1.0));
}

// Tonemapper::Clamp.apply(linear, exposure).
fn tonemap_clamp(linear: vec3<f32>, exposure: f32) -> vec3<f32> {
    return clamp(tonemap_input(linear, exposure), vec3<f32>(0.0), vec3<f32>(1.0));
}
