// The base colour and alpha of a material at a surface point, as chiaro_reference's
// base_color_at: factor x base colour texture x vertex colour (glTF 2.0: COLOR_0 multiplies the
// base colour and its alpha). A vertex's colour rides in its record's last two words as four
// unorm16 (chiaro_gpu::gpu_scene::gather::pack_color, white where the mesh has none); with
// FEATURE_VERTEX_COLORS off it is neither read nor applied.

#import lib/scene_bindings.wgsl
#import lib/textures.wgsl
#import lib/features.wgsl

// A vertex record's colour words as linear RGBA.
fn unpack_vertex_color(color: vec2<u32>) -> vec4<f32> {
    return vec4<f32>(unpack2x16unorm(color.x), unpack2x16unorm(color.y));
}

// The colour at weights w of the vertices v0, v1, v2 (white without the feature).
fn vertex_color_of(v0: GpuVertex, v1: GpuVertex, v2: GpuVertex, w: vec3<f32>) -> vec4<f32> {
    if !FEATURE_VERTEX_COLORS {
        return vec4<f32>(1.0);
    }
    return unpack_vertex_color(v0.color) * w.x + unpack_vertex_color(v1.color) * w.y
        + unpack_vertex_color(v2.color) * w.z;
}

// The colour at barycentrics b (of vertices 1 and 2) of the triangle with global vertex
// indices `indices` (white without the feature).
fn vertex_color(indices: vec3<u32>, b: vec2<f32>) -> vec4<f32> {
    if !FEATURE_VERTEX_COLORS {
        return vec4<f32>(1.0);
    }
    let w = vec3<f32>(1.0 - b.x - b.y, b.x, b.y);
    return vertex_color_of(scene_vertex(indices.x), scene_vertex(indices.y),
        scene_vertex(indices.z), w);
}

// Base colour (xyz) and alpha (w) of `material` at UVs `uvs` where the vertex colour is
// `color`: factor x texture x colour, multiplied in chiaro_reference's order.
fn material_base_color(material: GpuMaterial, mesh_flags: u32, uvs: vec4<f32>,
    color: vec4<f32>) -> vec4<f32> {
    let texel = texture_sample_feature(FEATURE_BASE_COLOR_TEXTURES, material.base_color_texture,
        uvs, mesh_flags, vec4<f32>(1.0));
    var c = material.base_color * texel;
    if FEATURE_VERTEX_COLORS {
        c *= color;
    }
    return c;
}
