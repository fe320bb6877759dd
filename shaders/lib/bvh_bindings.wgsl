// The BVH part of the scene bind group, group(0) bindings 0..3 (4..7 are reserved for it):
// chiaro_bvh::GpuBvhBuffers field for field, one storage buffer each.
//
// Compressed wide BVH nodes after Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal
// on GPUs Through Compressed Wide BVHs", High Performance Graphics 2017, in obvhs's record
// (CwBvhNode, 80 bytes); the TLAS node, triangle and instance records of chiaro_bvh::layout and
// chiaro_bvh::gpu.
//
// No buffer may be empty (a binding needs at least one element). A scene without instances is
// uploaded as one TLAS node that is a leaf naming an instance past the end of `bvh_instances`
// (for example TLAS_LEAF_BIT | 0x7fffffff): traversal skips such a leaf and finds nothing.

// obvhs's CwBvhNode. `p` is not 16-byte aligned in the Rust record, so it is three floats.
// Byte k of a vec2<u32> field is child slot k (little-endian: word k / 4, bits 8 (k % 4)).
struct CwBvhNode {
    // Origin of the child-box grid.
    p: array<f32, 3>,
    // Bytes: exponents e[0], e[1], e[2] of the grid spacing per axis, then imask (bit k set
    // when child slot k is an inner node).
    e_imask: u32,
    // Index of the first inner child in bvh_blas_nodes (global).
    child_base_idx: u32,
    // Index of the first leaf triangle in bvh_triangles (global).
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
    // Root of the instance's BLAS in bvh_blas_nodes.
    blas_root: u32,
    mesh: u32,
    material: u32,
    // Largest absolute object-space coordinate of the mesh (for the BLAS pad).
    mesh_magnitude: f32,
}

@group(0) @binding(0) var<storage, read> bvh_blas_nodes: array<CwBvhNode>;
@group(0) @binding(1) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(0) @binding(2) var<storage, read> bvh_tlas_nodes: array<TlasNode>;
@group(0) @binding(3) var<storage, read> bvh_instances: array<GpuInstance>;
