// Texture lookups in the scene's texel buffer, mirroring chiaro_reference's texture_sampling:
// the slot's UV set and KHR_texture_transform, the sampler's wrap modes, bilinear filtering
// (or nearest) of texels decoded to linear before filtering, no mip-maps.

#import lib/generated.wgsl
#import lib/color.wgsl
#import lib/scene_bindings.wgsl
#import lib/features.wgsl

// Wraps texel coordinate i into 0..n (mode 0 repeat, 1 mirrored repeat, 2 clamp).
fn texture_wrap(i: i32, n: i32, mode: u32) -> i32 {
    if mode == 2u {
        return clamp(i, 0, n - 1);
    }
    if mode == 1u {
        let period = ((i % (2 * n)) + 2 * n) % (2 * n);
        return select(2 * n - 1 - period, period, period < n);
    }
    return ((i % n) + n) % n;
}

// Linear RGBA of texel (x, y) of texture `info`.
fn texture_texel(info: GpuTextureInfo, x: i32, y: i32) -> vec4<f32> {
    let raw = unpack4x8unorm(scene_texels[info.offset + u32(y) * info.width + u32(x)]);
    if info.srgb == 0u {
        return raw;
    }
    return vec4<f32>(srgb_to_linear(raw.x), srgb_to_linear(raw.y), srgb_to_linear(raw.z), raw.w);
}

// The linear RGBA value of `slot` at the UVs `uvs` (set 0 in xy, set 1 in zw) of a mesh with
// flags `mesh_flags`, or `fallback` when the slot is empty or its UV set is missing.
fn texture_sample_slot(slot: GpuTextureSlot, uvs: vec4<f32>, mesh_flags: u32, fallback: vec4<f32>) -> vec4<f32> {
    if slot.texture == NO_INDEX {
        return fallback;
    }
    let has_set = select(mesh_flags & MESH_HAS_UV0, mesh_flags & MESH_HAS_UV1, slot.uv_set == 1u);
    if has_set == 0u || slot.uv_set > 1u {
        return fallback;
    }
    let raw_uv = select(uvs.xy, uvs.zw, slot.uv_set == 1u);
    let m = slot.transform_m;
    let uv = vec2<f32>(m.x * raw_uv.x + m.z * raw_uv.y, m.y * raw_uv.x + m.w * raw_uv.y)
        + slot.transform_t.xy;
    let info = scene_textures[slot.texture];
    if info.width == 0u || info.height == 0u || !(abs(uv.x) < 3.0e38) || !(abs(uv.y) < 3.0e38) {
        return fallback;
    }
    let w = i32(info.width);
    let h = i32(info.height);
    let wrap_u = slot.sampler & 3u;
    let wrap_v = (slot.sampler >> 2u) & 3u;
    let x = uv.x * f32(info.width) - 0.5;
    let y = uv.y * f32(info.height) - 0.5;
    if (slot.sampler & SAMPLER_NEAREST) != 0u {
        let xi = texture_wrap(i32(floor(x + 0.5)), w, wrap_u);
        let yi = texture_wrap(i32(floor(y + 0.5)), h, wrap_v);
        return texture_texel(info, xi, yi);
    }
    let x0 = floor(x);
    let y0 = floor(y);
    let f = vec2<f32>(x - x0, y - y0);
    let xa = texture_wrap(i32(x0), w, wrap_u);
    let xb = texture_wrap(i32(x0) + 1, w, wrap_u);
    let ya = texture_wrap(i32(y0), h, wrap_v);
    let yb = texture_wrap(i32(y0) + 1, h, wrap_v);
    let top = mix(texture_texel(info, xa, ya), texture_texel(info, xb, ya), f.x);
    let bottom = mix(texture_texel(info, xa, yb), texture_texel(info, xb, yb), f.x);
    return mix(top, bottom, f.y);
}

// texture_sample_slot where the pipeline has this kind of texture (`feature`, one of the
// FEATURE_*_TEXTURES flags), else the fallback without reading the slot.
fn texture_sample_feature(feature: bool, slot: GpuTextureSlot, uvs: vec4<f32>, mesh_flags: u32, fallback: vec4<f32>) -> vec4<f32> {
    if !feature {
        return fallback;
    }
    return texture_sample_slot(slot, uvs, mesh_flags, fallback);
}
