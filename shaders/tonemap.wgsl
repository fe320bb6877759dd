// Tonemap: the linear HDR image times the exposure through the chosen operator (ACES fitted,
// Khronos PBR Neutral or clamp; see lib/tonemap.wgsl), then the sRGB transfer function, into
// the 8-bit image, as chiaro_reference's PNG output does.

#import lib/color.wgsl
#import lib/tonemap.wgsl

// chiaro_gpu::passes::tonemap::TonemapParams.
struct TonemapParams {
    // 0 ACES fitted, 1 PBR Neutral, 2 clamp.
    tonemapper: u32,
    exposure: f32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var hdr: texture_2d<f32>;
@group(0) @binding(1) var<storage, read> params: TonemapParams;
@group(0) @binding(2) var ldr_out: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ldr_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let linear = textureLoad(hdr, vec2<i32>(id.xy), 0).xyz;
    var mapped: vec3<f32>;
    if params.tonemapper == 0u {
        mapped = tonemap_aces_fitted(linear, params.exposure);
    } else if params.tonemapper == 1u {
        mapped = tonemap_pbr_neutral(linear, params.exposure);
    } else {
        mapped = tonemap_clamp(linear, params.exposure);
    }
    let encoded = vec3<f32>(linear_to_srgb(mapped.x), linear_to_srgb(mapped.y), linear_to_srgb(mapped.z));
    textureStore(ldr_out, vec2<i32>(id.xy), vec4<f32>(encoded, 1.0));
}
