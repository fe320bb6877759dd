// The scene part of group(0) beyond the BVH (bindings 8..20), mirroring the records of
// chiaro_gpu::gpu_scene::layout field for field (a test compares the layouts through naga).
// Also the accessors environment.wgsl asks its importer for.

#import lib/generated.wgsl
#import lib/bvh_bindings.wgsl

// chiaro_gpu::GpuVertex: object-space vertex; `color` is RGBA as four unorm16 (base_color.wgsl).
struct GpuVertex {
    position: vec3<f32>,
    u0: f32,
    normal: vec3<f32>,
    v0: f32,
    tangent: vec4<f32>,
    uv1: vec2<f32>,
    color: vec2<u32>,
}

// chiaro_gpu::GpuMesh: triangle t of the mesh uses scene_index(index_base + 3 t + k),
// which are global vertex indices.
struct GpuMesh {
    index_base: u32,
    vertex_base: u32,
    triangle_count: u32,
    flags: u32,
}

// chiaro_gpu::GpuTextureSlot: texture NO_INDEX when empty; sampler bits: wrap U (bits 0..2),
// wrap V (bits 2..4), SAMPLER_NEAREST.
struct GpuTextureSlot {
    texture: u32,
    uv_set: u32,
    sampler: u32,
    pad: u32,
    transform_m: vec4<f32>,
    transform_t: vec4<f32>,
}

// chiaro_gpu::GpuMaterial.
struct GpuMaterial {
    base_color: vec4<f32>,
    emission: vec3<f32>,
    alpha_cutoff: f32,
    metallic: f32,
    roughness: f32,
    f0_dielectric: f32,
    absorption: f32,
    normal_scale: f32,
    flags: u32,
    specular: f32,
    clearcoat: f32,
    specular_color: vec3<f32>,
    clearcoat_roughness: f32,
    sheen_color: vec3<f32>,
    sheen_roughness: f32,
    transmission: f32,
    ior: f32,
    clearcoat_normal_scale: f32,
    pad1: u32,
    attenuation: vec3<f32>,
    pad2: u32,
    base_color_texture: GpuTextureSlot,
    metallic_roughness_texture: GpuTextureSlot,
    normal_texture: GpuTextureSlot,
    emissive_texture: GpuTextureSlot,
    specular_texture: GpuTextureSlot,
    specular_color_texture: GpuTextureSlot,
    clearcoat_texture: GpuTextureSlot,
    clearcoat_roughness_texture: GpuTextureSlot,
    transmission_texture: GpuTextureSlot,
    sheen_color_texture: GpuTextureSlot,
    sheen_roughness_texture: GpuTextureSlot,
    clearcoat_normal_texture: GpuTextureSlot,
}

// chiaro_gpu::GpuTextureInfo: texel (x, y) is scene_texels[offset + y * width + x], RGBA8.
struct GpuTextureInfo {
    offset: u32,
    width: u32,
    height: u32,
    srgb: u32,
}

// chiaro_gpu::GpuLight: a punctual light. range +infinity: unlimited.
struct GpuLight {
    position: vec3<f32>,
    kind: u32,
    direction: vec3<f32>,
    range: f32,
    intensity: vec3<f32>,
    cdf: f32,
    inner: f32,
    outer: f32,
    pmf: f32,
    directional_cdf: f32,
}

// chiaro_gpu::GpuAreaLight: an emissive triangle, or the environment (instance NO_INDEX).
struct GpuAreaLight {
    instance: u32,
    triangle: u32,
    cdf: f32,
    pmf: f32,
}

// chiaro_gpu::GpuInstanceExtra.
struct GpuInstanceExtra {
    previous_object_to_world: array<vec4<f32>, 3>,
    area_first: u32,
    mirrored: u32,
    pad0: u32,
    pad1: u32,
}

// chiaro_gpu::GpuSceneInfo.
struct GpuSceneInfo {
    env_radiance: vec3<f32>,
    env_kind: u32,
    env_width: u32,
    env_height: u32,
    env_cos_rotation: f32,
    env_sin_rotation: f32,
    light_count: u32,
    area_count: u32,
    env_pmf: f32,
    instance_count: u32,
    area_tree: u32,
    punctual_tree: u32,
    directional_share: f32,
    area_leaves: u32,
}

// chiaro_gpu::GpuLightTreeNode: a node of a light tree (both trees share binding 20; an inner
// node's `first` and `second` are its children, a leaf's `first` its light's table index).
// Area-table entry i's leaf is node scene_info.area_leaves + i.
struct GpuLightTreeNode {
    min: vec3<f32>,
    power: f32,
    max: vec3<f32>,
    theta_o: f32,
    axis: vec3<f32>,
    theta_e: f32,
    first: u32,
    second: u32,
    parent: u32,
    leaf: u32,
}

@group(0) @binding(8) var scene_vertex_texels: texture_2d<u32>;
@group(0) @binding(9) var scene_index_texels: texture_2d<u32>;
@group(0) @binding(10) var<storage, read> scene_meshes: array<GpuMesh>;
@group(0) @binding(11) var scene_material_texels: texture_2d<u32>;
@group(0) @binding(12) var<storage, read> scene_texels: array<u32>;
@group(0) @binding(13) var<storage, read> scene_textures: array<GpuTextureInfo>;
@group(0) @binding(14) var scene_light_texels: texture_2d<u32>;
@group(0) @binding(15) var scene_area_light_texels: texture_2d<u32>;
@group(0) @binding(16) var<storage, read> scene_instance_extras: array<GpuInstanceExtra>;
@group(0) @binding(17) var scene_env_texels: texture_2d<u32>;
@group(0) @binding(18) var scene_env_table_texels: texture_2d<u32>;
@group(0) @binding(19) var<storage, read> scene_info: GpuSceneInfo;
@group(0) @binding(20) var scene_light_tree_texels: texture_2d<u32>;

// Vertex i (4 texels). The vertices, the indices and the materials are texel arrays: every
// hit a path shades reads them at its own address, and lavapipe loads a storage word lane by
// lane.
fn scene_vertex(i: u32) -> GpuVertex {
    let a = bitcast<vec4<f32>>(texel_array_load(scene_vertex_texels, 4u * i));
    let b = bitcast<vec4<f32>>(texel_array_load(scene_vertex_texels, 4u * i + 1u));
    let c = bitcast<vec4<f32>>(texel_array_load(scene_vertex_texels, 4u * i + 2u));
    let d = bitcast<vec4<f32>>(texel_array_load(scene_vertex_texels, 4u * i + 3u));
    return GpuVertex(a.xyz, a.w, b.xyz, b.w, c, d.xy, bitcast<vec2<u32>>(d.zw));
}

// Global vertex index i (four to a texel).
fn scene_index(i: u32) -> u32 {
    return texel_array_load(scene_index_texels, i >> 2u)[i & 3u];
}

// Material i (44 texels: 8 of factors, then 3 for each of the 12 texture slots). The shaders
// read a few fields of it; the fetches of the others are dead code.
fn scene_material(i: u32) -> GpuMaterial {
    let first = 44u * i;
    let base_color = bitcast<vec4<f32>>(texel_array_load(scene_material_texels, first));
    let emission = texel_array_load(scene_material_texels, first + 1u);
    let factors = bitcast<vec4<f32>>(texel_array_load(scene_material_texels, first + 2u));
    let tail = texel_array_load(scene_material_texels, first + 3u);
    let specular_color = texel_array_load(scene_material_texels, first + 4u);
    let sheen = bitcast<vec4<f32>>(texel_array_load(scene_material_texels, first + 5u));
    let layers = texel_array_load(scene_material_texels, first + 6u);
    let volume = texel_array_load(scene_material_texels, first + 7u);
    return GpuMaterial(base_color, bitcast<vec3<f32>>(emission.xyz), bitcast<f32>(emission.w),
        factors.x, factors.y, factors.z, factors.w, bitcast<f32>(tail.x), tail.y,
        bitcast<f32>(tail.z), bitcast<f32>(tail.w), bitcast<vec3<f32>>(specular_color.xyz),
        bitcast<f32>(specular_color.w), sheen.xyz, sheen.w, bitcast<f32>(layers.x),
        bitcast<f32>(layers.y), bitcast<f32>(layers.z), layers.w,
        bitcast<vec3<f32>>(volume.xyz), volume.w,
        scene_texture_slot(first + 8u), scene_texture_slot(first + 11u),
        scene_texture_slot(first + 14u), scene_texture_slot(first + 17u),
        scene_texture_slot(first + 20u), scene_texture_slot(first + 23u),
        scene_texture_slot(first + 26u), scene_texture_slot(first + 29u),
        scene_texture_slot(first + 32u), scene_texture_slot(first + 35u),
        scene_texture_slot(first + 38u), scene_texture_slot(first + 41u));
}

// The texture slot at material texel `first` (3 texels).
fn scene_texture_slot(first: u32) -> GpuTextureSlot {
    let a = texel_array_load(scene_material_texels, first);
    let m = bitcast<vec4<f32>>(texel_array_load(scene_material_texels, first + 1u));
    let t = bitcast<vec4<f32>>(texel_array_load(scene_material_texels, first + 2u));
    return GpuTextureSlot(a.x, a.y, a.z, a.w, m, t);
}

// Punctual light i (4 texels).
fn scene_light(i: u32) -> GpuLight {
    let a = texel_array_load(scene_light_texels, 4u * i);
    let b = texel_array_load(scene_light_texels, 4u * i + 1u);
    let c = texel_array_load(scene_light_texels, 4u * i + 2u);
    let d = bitcast<vec4<f32>>(texel_array_load(scene_light_texels, 4u * i + 3u));
    return GpuLight(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), bitcast<f32>(b.w),
        bitcast<vec3<f32>>(c.xyz), bitcast<f32>(c.w), d.x, d.y, d.z, d.w);
}

// Area-light table entry i (1 texel).
fn scene_area_light(i: u32) -> GpuAreaLight {
    let a = texel_array_load(scene_area_light_texels, i);
    return GpuAreaLight(a.x, a.y, bitcast<f32>(a.z), bitcast<f32>(a.w));
}

// The hook lib/light_tree.wgsl reads its nodes through (4 texels a node).
fn light_tree_node(i: u32) -> GpuLightTreeNode {
    let a = texel_array_load(scene_light_tree_texels, 4u * i);
    let b = texel_array_load(scene_light_tree_texels, 4u * i + 1u);
    let c = texel_array_load(scene_light_tree_texels, 4u * i + 2u);
    let d = texel_array_load(scene_light_tree_texels, 4u * i + 3u);
    return GpuLightTreeNode(bitcast<vec3<f32>>(a.xyz), bitcast<f32>(a.w), bitcast<vec3<f32>>(b.xyz),
        bitcast<f32>(b.w), bitcast<vec3<f32>>(c.xyz), bitcast<f32>(c.w), d.x, d.y, d.z, d.w);
}

// The environment image's importance table (chiaro_gpu::gpu_scene::gather::environment):
// marginal CDF at 0 (height + 1), marginal masses at height + 1, conditional CDFs at
// 2 height + 1 (width + 1 per row), conditional masses after them (width per row); entry i
// is component i % 4 of texel i / 4. Both are texel arrays: every environment sample walks
// the table, and lavapipe loads a storage word lane by lane.
fn env_texel(column: u32, row: u32) -> vec3<f32> {
    return bitcast<vec3<f32>>(texel_array_load(scene_env_texels, row * scene_info.env_width + column).xyz);
}

fn scene_env_table(i: u32) -> f32 {
    return bitcast<f32>(texel_array_load(scene_env_table_texels, i >> 2u)[i & 3u]);
}

fn env_marginal_cdf(i: u32) -> f32 {
    return scene_env_table(i);
}

fn env_marginal_pmf(row: u32) -> f32 {
    return scene_env_table(scene_info.env_height + 1u + row);
}

fn env_conditional_cdf(row: u32, i: u32) -> f32 {
    return scene_env_table(2u * scene_info.env_height + 1u + row * (scene_info.env_width + 1u) + i);
}

fn env_conditional_pmf(row: u32, column: u32) -> f32 {
    let h = scene_info.env_height;
    let w = scene_info.env_width;
    return scene_env_table(2u * h + 1u + h * (w + 1u) + row * w + column);
}

// The three global vertex indices of triangle `triangle` of mesh `mesh`.
fn scene_triangle_indices(mesh: u32, triangle: u32) -> vec3<u32> {
    let base = scene_meshes[mesh].index_base + 3u * triangle;
    return vec3<u32>(scene_index(base), scene_index(base + 1u), scene_index(base + 2u));
}

// The UVs (set 0 in xy, set 1 in zw) at barycentrics b (of vertices 1 and 2) of a triangle.
fn scene_uvs(indices: vec3<u32>, b: vec2<f32>) -> vec4<f32> {
    let v0 = scene_vertex(indices.x);
    let v1 = scene_vertex(indices.y);
    let v2 = scene_vertex(indices.z);
    let w = vec3<f32>(1.0 - b.x - b.y, b.x, b.y);
    let uv0 = vec2<f32>(v0.u0, v0.v0) * w.x + vec2<f32>(v1.u0, v1.v0) * w.y
        + vec2<f32>(v2.u0, v2.v0) * w.z;
    let uv1 = v0.uv1 * w.x + v1.uv1 * w.y + v2.uv1 * w.z;
    return vec4<f32>(uv0, uv1);
}
