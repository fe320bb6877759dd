// The BVH part of the scene bind group, group(0) bindings 0..4: chiaro_bvh::GpuBvhBuffers field
// for field (binding 5 is the G-buffer's raster vertices, in gbuffer.wgsl; 6 and 7 are
// reserved). The traversal's records are texel arrays
// (chiaro_gpu::gpu_scene::texel_mirror: rgba32uint textures, record i is texels
// i * (record size / 16) onwards in row-major order, 2^TEXEL_ROW_BITS texels to a row), read
// with bvh_load_*: a texel fetch gathers 16 bytes per lane, where lavapipe loads a storage
// buffer at per-lane addresses one lane and one word at a time. The instances are also a
// storage buffer (binding 3), which the shaders read only for its length (the empty scene's
// leaf below); the passes that shade read the texels (bvh_load_instance_whole).
//
// Compressed wide BVH nodes after Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal
// on GPUs Through Compressed Wide BVHs", High Performance Graphics 2017, in obvhs's record
// (CwBvhNode, 80 bytes); the TLAS node, triangle and instance records of chiaro_bvh::layout and
// chiaro_bvh::gpu.
//
// No array may be empty (a binding needs at least one element). A scene without instances is
// uploaded as one TLAS node that is a leaf naming an instance past the end of `bvh_instances`
// (for example TLAS_LEAF_BIT | 0x7fffffff): traversal skips such a leaf and finds nothing.

#import lib/generated.wgsl

// obvhs's CwBvhNode. `p` is not 16-byte aligned in the Rust record, so it is three floats.
// Byte k of a vec2<u32> field is child slot k (little-endian: word k / 4, bits 8 (k % 4)).
struct CwBvhNode {
    // Origin of the child-box grid.
    p: array<f32, 3>,
    // Bytes: exponents e[0], e[1], e[2] of the grid spacing per axis, then imask (bit k set
    // when child slot k is an inner node).
    e_imask: u32,
    // Index of the first inner child among the BLAS nodes (global).
    child_base_idx: u32,
    // Index of the first leaf triangle among the BLAS triangles (global).
    primitive_base_idx: u32,
    // Per child slot: 0 empty; inner: 0b001 in the top bits, slot + 24 in the low five; leaf:
    // unary triangle count in the top three bits, triangle offset in the low five.
    child_meta: vec2<u32>,
    // Quantised child boxes: plane = p + 2^(e - 127) q.
    child_min_x: vec2<u32>,
    child_max_x: vec2<u32>,
    child_min_y: vec2<u32>,
    child_max_y: vec2<u32>,
    child_min_z: vec2<u32>,
    child_max_z: vec2<u32>,
}

// chiaro_bvh::BvhTriangle: object-space vertices and the triangle's index in its mesh.
struct BvhTriangle {
    v0: vec3<f32>,
    triangle: u32,
    v1: vec3<f32>,
    pad0: u32,
    v2: vec3<f32>,
    pad1: u32,
}

// chiaro_bvh::TlasNode: an inner node's children are tlas[child] and tlas[child + 1]; a leaf
// (child & TLAS_LEAF_BIT) names instance child & ~TLAS_LEAF_BIT. kappa is the largest
// instance-matrix condition number below the node (it scales the box pad).
struct TlasNode {
    min: vec3<f32>,
    child: u32,
    max: vec3<f32>,
    kappa: f32,
}

// chiaro_bvh::GpuInstance: rows of 3x4 matrices, p' = (dot(r0, (p, 1)), ...).
struct GpuInstance {
    world_to_object: array<vec4<f32>, 3>,
    object_to_world: array<vec4<f32>, 3>,
    // Root of the instance's BLAS among the BLAS nodes.
    blas_root: u32,
    mesh: u32,
    material: u32,
    // Largest absolute object-space coordinate of the mesh (for the BLAS pad).
    mesh_magnitude: f32,
}

@group(0) @binding(0) var bvh_blas_node_texels: texture_2d<u32>;
@group(0) @binding(1) var bvh_triangle_texels: texture_2d<u32>;
@group(0) @binding(2) var bvh_tlas_node_texels: texture_2d<u32>;
@group(0) @binding(3) var<storage, read> bvh_instances: array<GpuInstance>;
@group(0) @binding(4) var bvh_instance_texels: texture_2d<u32>;

// Texel i of a texel array.
fn texel_array_load(texels: texture_2d<u32>, i: u32) -> vec4<u32> {
    let row_mask = (1u << TEXEL_ROW_BITS) - 1u;
    return textureLoad(texels, vec2<u32>(i & row_mask, i >> TEXEL_ROW_BITS), 0);
}

// BLAS node i (5 texels).
fn bvh_load_blas_node(i: u32) -> CwBvhNode {
    let a = texel_array_load(bvh_blas_node_texels, 5u * i);
    let b = texel_array_load(bvh_blas_node_texels, 5u * i + 1u);
    let c = texel_array_load(bvh_blas_node_texels, 5u * i + 2u);
    let d = texel_array_load(bvh_blas_node_texels, 5u * i + 3u);
    let e = texel_array_load(bvh_blas_node_texels, 5u * i + 4u);
    let p = bitcast<vec3<f32>>(a.xyz);
    return CwBvhNode(array<f32, 3>(p.x, p.y, p.z), a.w, b.x, b.y, b.zw, c.xy, c.zw, d.xy, d.zw,
        e.xy, e.zw);
}

// BLAS triangle i (3 texels).
fn bvh_load_triangle(i: u32) -> BvhTriangle {
    let a = texel_array_load(bvh_triangle_texels, 3u * i);
    let b = texel_array_load(bvh_triangle_texels, 3u * i + 1u);
    let c = texel_array_load(bvh_triangle_texels, 3u * i + 2u);
    return BvhTriangle(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), b.w,
        bitcast<vec3<f32>>(c.xyz), c.w);
}

// TLAS node i (2 texels).
fn bvh_load_tlas_node(i: u32) -> TlasNode {
    let a = texel_array_load(bvh_tlas_node_texels, 2u * i);
    let b = texel_array_load(bvh_tlas_node_texels, 2u * i + 1u);
    return TlasNode(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), bitcast<f32>(b.w));
}

// What the traversal reads of instance i: the world-to-object rows (its texels 0..2), the BLAS
// root and the mesh magnitude (texel 6).
struct BvhInstanceRecord {
    world_to_object: array<vec4<f32>, 3>,
    blas_root: u32,
    mesh_magnitude: f32,
}

fn bvh_load_instance(i: u32) -> BvhInstanceRecord {
    let first = 7u * i;
    let rows = array<vec4<f32>, 3>(bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first)),
        bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first + 1u)),
        bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first + 2u)));
    let tail = texel_array_load(bvh_instance_texels, first + 6u);
    return BvhInstanceRecord(rows, tail.x, bitcast<f32>(tail.w));
}

// Instance i, its whole record (7 texels), for the passes that shade: lavapipe fetches a texel
// for every lane at once, where it would load a storage record lane by lane.
fn bvh_load_instance_whole(i: u32) -> GpuInstance {
    let first = 7u * i;
    let w0 = bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first));
    let w1 = bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first + 1u));
    let w2 = bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first + 2u));
    let o0 = bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first + 3u));
    let o1 = bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first + 4u));
    let o2 = bitcast<vec4<f32>>(texel_array_load(bvh_instance_texels, first + 5u));
    let tail = texel_array_load(bvh_instance_texels, first + 6u);
    return GpuInstance(array<vec4<f32>, 3>(w0, w1, w2), array<vec4<f32>, 3>(o0, o1, o2), tail.x,
        tail.y, tail.z, bitcast<f32>(tail.w));
}
