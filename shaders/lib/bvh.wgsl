// Two-level ray traversal mirroring chiaro_bvh::SceneBvh: a binary TLAS over instances, the ray
// carried into each instance's object space, and the instance's compressed wide BLAS.
//
// - BLAS: Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal on GPUs Through
//   Compressed Wide BVHs", High Performance Graphics 2017 (octant-ordered child slots, node and
//   triangle groups as bit masks on the stack), with chiaro_bvh::wide's conservative child-box
//   test.
// - Box tests: the slab test with the exit bound of Ize, "Robust BVH Ray Traversal", JCGT 2(2),
//   2013, padded as chiaro_bvh::slab documents so that no hit of the watertight test is culled.
// - Triangles: watertight.wgsl (Woop, Benthin and Wald, 2013).
//
// API: trace_closest(ray, t_max) -> Hit (the nearest accepted hit in (ray.t_min, t_max);
// hit.instance == BVH_NO_HIT when there is none) and trace_any(ray, t_max) -> bool (true at
// the first accepted hit found, nearest or not). Rays that chiaro_bvh::Ray::is_valid refuses
// hit nothing. The importing module must define
//     fn hit_accepted(ray: Ray, instance: u32, triangle: u32, barycentrics: vec2<f32>) -> bool
// which decides whether a candidate hit of the (world) ray counts (false: a hole, e.g. an
// alpha mask, or a blended surface the ray passes); both
// queries call it for candidates only, the closest-hit query only for candidates nearer than
// the best accepted so far.
//
// Shape of the loops: lavapipe runs 8 invocations as the lanes of one SIMD vector and runs every
// `if` block whatever the lanes decide (masked: its stores and loads skip the lanes that do not
// take it; Mesa's gallivm has no branches for them), and every loop until all its lanes are
// done. So a loop costs its whole body per iteration, and a loop nested in an `if` runs at
// least once per iteration of the loop around it. The traversal is laid out for that: the TLAS
// descent (one loop, visit or pop per iteration) ends at the next instance, then that instance's
// BLAS is traversed, then the descent goes on. With the BLAS loop nested in the TLAS loop's leaf
// branch, every TLAS step also paid a BLAS step and a triangle test: measured with
// chiaro_gpu's traversal_bench on lavapipe, this layout traces 1.2x to 2.2x more rays per
// second. A hardware GPU skips a block that no lane of a subgroup takes; the layout has not been
// measured on one.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/bvh_bindings.wgsl
#import lib/watertight.wgsl

// Hit::instance of a miss.
const BVH_NO_HIT: u32 = 0xffffffffu;

// The traversal stacks: TLAS entries (a node's child word, entry distance bits) and BLAS
// entries (node or triangle base, hit mask), BVH_STACK_SIZE each (chiaro_bvh's bound). WGSL
// zero-fills every variable where it is declared; at module scope that happens once per
// invocation, however many rays the invocation traces (declared per BLAS visit, it cost 3x on
// lavapipe).
var<private> bvh_tlas_stack: array<vec2<u32>, BVH_STACK_SIZE>;
var<private> bvh_blas_stack: array<vec2<u32>, BVH_STACK_SIZE>;

// Traversal steps of this invocation's rays so far: one per TLAS node whose two children are
// tested, BLAS node visited and triangle tested (the viewer's traversal heatmap resets it, traces a ray and
// reads it). A shader that never reads it pays nothing: its increments are stores to a private
// variable nobody loads, which the driver's compiler removes.
var<private> bvh_steps: u32;

// The points origin + t direction for t in (t_min, t_max); the direction need not be unit.
struct Ray {
    origin: vec3<f32>,
    t_min: f32,
    direction: vec3<f32>,
}

// A hit: t in units of the ray's direction, the instance (index into bvh_instances), the
// triangle's index in its mesh, and the barycentrics of its vertices 1 and 2.
struct Hit {
    t: f32,
    instance: u32,
    triangle: u32,
    barycentrics: vec2<f32>,
}

fn bvh_max_element(v: vec3<f32>) -> f32 {
    return max(max(v.x, v.y), v.z);
}

// Whether chiaro_bvh would trace the ray over (ray.t_min, t_max) (Ray::is_valid).
fn bvh_ray_is_valid(ray: Ray, t_max: f32) -> bool {
    let largest = bvh_max_element(abs(ray.direction));
    return vec3_is_finite(ray.origin) && bvh_max_element(abs(ray.origin)) <= MAX_RAY_COORDINATE
        && vec3_is_finite(ray.direction) && largest >= MIN_RAY_DIRECTION
        && largest <= MAX_RAY_COORDINATE && !f32_is_nan(ray.t_min) && !f32_is_nan(t_max);
}

// 1 / d with -0 read as +0 (every zero component gets +infinity).
fn bvh_inverse_direction(d: vec3<f32>) -> vec3<f32> {
    let positive_zero = select(d, vec3<f32>(0.0), d == vec3<f32>(0.0));
    return vec3<f32>(1.0) / positive_zero;
}

fn bvh_has_zero(d: vec3<f32>) -> bool {
    return any(d == vec3<f32>(0.0));
}

// x * (1 + copysign(TWO_GAMMA3, x)): |x| grown by Ize's bound, infinities kept.
fn bvh_grow_exit(x: f32) -> f32 {
    let g = bitcast<f32>(bitcast<u32>(TWO_GAMMA3) | (bitcast<u32>(x) & 0x80000000u));
    return x * (1.0 + g);
}

fn bvh_grow_exit4(x: vec4<f32>) -> vec4<f32> {
    let g = bitcast<vec4<f32>>(vec4<u32>(bitcast<u32>(TWO_GAMMA3)) | (bitcast<vec4<u32>>(x) & vec4<u32>(0x80000000u)));
    return x * (vec4<f32>(1.0) + g);
}

fn bvh_is_nan3(v: vec3<f32>) -> vec3<bool> {
    return (bitcast<vec3<u32>>(v) & vec3<u32>(F32_ABS_MASK)) > vec3<u32>(F32_EXPONENT_MASK);
}

fn bvh_is_nan4(v: vec4<f32>) -> vec4<bool> {
    return (bitcast<vec4<u32>>(v) & vec4<u32>(F32_ABS_MASK)) > vec4<u32>(F32_EXPONENT_MASK);
}

// A world ray prepared for TLAS box tests (chiaro_bvh::slab::BoxRay).
struct BvhBoxRay {
    origin: vec3<f32>,
    inv_direction: vec3<f32>,
    zero_component: bool,
}

// Entry distance into [lo, hi] grown by `pad`, clipped to [t_min, t_max]; +infinity on a miss.
fn bvh_box_entry(r: BvhBoxRay, lo: vec3<f32>, hi: vec3<f32>, pad: f32, t_min: f32, t_max: f32) -> f32 {
    var t_lo = (lo - (r.origin + vec3<f32>(pad))) * r.inv_direction;
    var t_hi = (hi - (r.origin - vec3<f32>(pad))) * r.inv_direction;
    if r.zero_component {
        let inf = f32_infinity();
        t_lo = select(t_lo, vec3<f32>(-inf), bvh_is_nan3(t_lo));
        t_hi = select(t_hi, vec3<f32>(inf), bvh_is_nan3(t_hi));
    }
    let near = max(bvh_max_element(min(t_lo, t_hi)), t_min);
    let m = max(t_lo, t_hi);
    let far = min(bvh_grow_exit(min(min(m.x, m.y), m.z)), t_max);
    return select(f32_infinity(), near, near <= far);
}

// An object-space ray prepared for one BLAS's child-box tests (chiaro_bvh::wide::NodeRay).
struct BvhNodeRay {
    // Origin moved by +pad (lower planes) and -pad (upper planes).
    origin_lo: vec3<f32>,
    origin_hi: vec3<f32>,
    inv_direction: vec3<f32>,
    zero_component: bool,
    // Octant of the direction, one copy per byte, for the child ordering.
    oct_inv4: u32,
}

// The four bytes of a word as floats.
fn bvh_bytes(w: u32) -> vec4<f32> {
    return vec4<f32>((vec4<u32>(w) >> vec4<u32>(0u, 8u, 16u, 24u)) & vec4<u32>(0xffu));
}

// Slab distances of four children on one axis: (e q - (o - p)) / d.
fn bvh_child_planes(q: u32, e: f32, c: f32, inv: f32, zero_component: bool, miss: f32) -> vec4<f32> {
    var t = (bvh_bytes(q) * e - vec4<f32>(c)) * inv;
    if zero_component {
        t = select(t, vec4<f32>(miss), bvh_is_nan4(t));
    }
    return t;
}

// Hit mask of a node's children over [t_min, t_max] in obvhs's layout: inner children in the
// top byte by traversal priority, leaf triangles in the low 24 bits.
fn bvh_intersect_node(node: CwBvhNode, r: BvhNodeRay, t_min: f32, t_max: f32) -> u32 {
    let e = bitcast<vec3<f32>>(((vec3<u32>(node.e_imask) >> vec3<u32>(0u, 8u, 16u)) & vec3<u32>(0xffu)) << vec3<u32>(23u));
    let p = vec3<f32>(node.p[0], node.p[1], node.p[2]);
    let c_lo = r.origin_lo - p;
    let c_hi = r.origin_hi - p;
    let inf = f32_infinity();
    var hit = 0u;
    for (var h4 = 0u; h4 < 2u; h4++) {
        let child_meta = node.child_meta[h4];
        if child_meta == 0u {
            continue;
        }
        // obvhs's CwBvhNode::get_child_and_index_bits, four slots at a time.
        let is_inner = (child_meta & (child_meta << 1u)) & 0x10101010u;
        let inner_mask = (is_inner >> 4u) * 0xffu;
        let bit_index = (child_meta ^ (r.oct_inv4 & inner_mask)) & 0x1f1f1f1fu;
        let child_bits = (child_meta >> 5u) & 0x07070707u;

        let x_lo = bvh_child_planes(node.child_min_x[h4], e.x, c_lo.x, r.inv_direction.x, r.zero_component, -inf);
        let x_hi = bvh_child_planes(node.child_max_x[h4], e.x, c_hi.x, r.inv_direction.x, r.zero_component, inf);
        let y_lo = bvh_child_planes(node.child_min_y[h4], e.y, c_lo.y, r.inv_direction.y, r.zero_component, -inf);
        let y_hi = bvh_child_planes(node.child_max_y[h4], e.y, c_hi.y, r.inv_direction.y, r.zero_component, inf);
        let z_lo = bvh_child_planes(node.child_min_z[h4], e.z, c_lo.z, r.inv_direction.z, r.zero_component, -inf);
        let z_hi = bvh_child_planes(node.child_max_z[h4], e.z, c_hi.z, r.inv_direction.z, r.zero_component, inf);
        var near = max(vec4<f32>(t_min), min(x_lo, x_hi));
        near = max(near, min(y_lo, y_hi));
        near = max(near, min(z_lo, z_hi));
        var far = min(vec4<f32>(inf), max(x_lo, x_hi));
        far = min(far, max(y_lo, y_hi));
        far = min(far, max(z_lo, z_hi));
        far = min(bvh_grow_exit4(far), vec4<f32>(t_max));
        let inside = near <= far;
        for (var j = 0u; j < 4u; j++) {
            if inside[j] {
                let shift = 8u * j;
                hit |= ((child_bits >> shift) & 0xffu) << ((bit_index >> shift) & 0xffu);
            }
        }
    }
    return hit;
}

// The linear part of a 3x4 matrix (rows) applied to v, summed in glam's order.
fn bvh_transform_vector(m: array<vec4<f32>, 3>, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        (m[0].x * v.x + m[0].y * v.y) + m[0].z * v.z,
        (m[1].x * v.x + m[1].y * v.y) + m[1].z * v.z,
        (m[2].x * v.x + m[2].y * v.y) + m[2].z * v.z,
    );
}

// A 3x4 matrix (rows, translation in w) applied to the point p, as glam's transform_point3.
fn bvh_transform_point(m: array<vec4<f32>, 3>, p: vec3<f32>) -> vec3<f32> {
    return bvh_transform_vector(m, p) + vec3<f32>(m[0].w, m[1].w, m[2].w);
}

// Traverses one instance's BLAS (chiaro_bvh::wide::traverse), shrinking *t_max on accepted
// hits and recording them in *best; returns true when an any-hit query found its occluder.
fn bvh_trace_instance(
    ray: Ray,
    instance: u32,
    t_max: ptr<function, f32>,
    best: ptr<function, Hit>,
    any_hit: bool,
) -> bool {
    let record = bvh_load_instance(instance);
    let o = bvh_transform_point(record.world_to_object, ray.origin);
    let d = bvh_transform_vector(record.world_to_object, ray.direction);
    if !vec3_is_finite(o) || !vec3_is_finite(d) || bvh_max_element(abs(d)) == 0.0 {
        return false;
    }
    let watertight = watertight_ray_new(o, d);
    let pad = BLAS_PAD_ULPS * F32_EPSILON * (bvh_max_element(abs(o)) + record.mesh_magnitude);
    var node_ray: BvhNodeRay;
    node_ray.origin_lo = o + vec3<f32>(pad);
    node_ray.origin_hi = o - vec3<f32>(pad);
    node_ray.inv_direction = bvh_inverse_direction(d);
    node_ray.zero_component = bvh_has_zero(d);
    node_ray.oct_inv4 = select(0x04040404u, 0u, d.x < 0.0) | select(0x02020202u, 0u, d.y < 0.0)
        | select(0x01010101u, 0u, d.z < 0.0);
    let t_min = ray.t_min;

    var top = 0u;
    // The root, as the only inner child of a virtual parent.
    var group = vec2<u32>(record.blas_root, 0x80000000u);
    var triangle_group = vec2<u32>(0u, 0u);
    loop {
        while triangle_group.y != 0u {
            let offset = firstLeadingBit(triangle_group.y);
            triangle_group.y &= ~(1u << offset);
            let tri = bvh_load_triangle(triangle_group.x + offset);
            bvh_steps += 1u;
            let h = watertight_intersect(watertight, tri.v0, tri.v1, tri.v2, t_min, *t_max);
            if h.found && hit_accepted(ray, instance, tri.triangle, vec2<f32>(h.b1, h.b2)) {
                (*best).t = h.t;
                (*best).instance = instance;
                (*best).triangle = tri.triangle;
                (*best).barycentrics = vec2<f32>(h.b1, h.b2);
                if any_hit {
                    return true;
                }
                *t_max = h.t;
            }
        }
        if (group.y & 0xff000000u) != 0u {
            let hits = group.y;
            let slot_bit = firstLeadingBit(hits);
            group.y &= ~(1u << slot_bit);
            if (group.y & 0xff000000u) != 0u {
                bvh_blas_stack[top] = group;
                top += 1u;
            }
            // The child slot from its priority bit, then its rank among the inner children.
            let slot = (slot_bit - 24u) ^ (node_ray.oct_inv4 & 0xffu);
            let rank = countOneBits(hits & ~(0xffffffffu << slot));
            let node = bvh_load_blas_node(group.x + rank);
            bvh_steps += 1u;
            let mask = bvh_intersect_node(node, node_ray, t_min, *t_max);
            group = vec2<u32>(node.child_base_idx, (mask & 0xff000000u) | ((node.e_imask >> 24u) & 0xffu));
            triangle_group = vec2<u32>(node.primitive_base_idx, mask & 0x00ffffffu);
        } else {
            group = vec2<u32>(0u, 0u);
        }
        if triangle_group.y == 0u && (group.y & 0xff000000u) == 0u {
            if top == 0u {
                return false;
            }
            top -= 1u;
            group = bvh_blas_stack[top];
        }
    }
    return false;
}

// The TLAS traversal of chiaro_bvh::tlas::Tlas::traverse, visiting instances nearest box first:
// the same instances in the same order, so the same hits.
fn bvh_trace(ray: Ray, t_max_in: f32, any_hit: bool) -> Hit {
    var best: Hit;
    best.t = t_max_in;
    best.instance = BVH_NO_HIT;
    best.triangle = 0u;
    best.barycentrics = vec2<f32>(0.0);
    if !bvh_ray_is_valid(ray, t_max_in) || ray.t_min >= t_max_in {
        return best;
    }
    var t_max = t_max_in;
    var box_ray: BvhBoxRay;
    box_ray.origin = ray.origin;
    box_ray.inv_direction = bvh_inverse_direction(ray.direction);
    box_ray.zero_component = bvh_has_zero(ray.direction);
    let unit_pad = TLAS_PAD_ULPS * F32_EPSILON * bvh_max_element(abs(ray.origin));
    let t_min = ray.t_min;
    let root = bvh_load_tlas_node(0);
    if !f32_is_finite(bvh_box_entry(box_ray, root.min, root.max, root.kappa * unit_pad, t_min, t_max)) {
        return best;
    }
    var top = 0u;
    // The `child` word of the TLAS node to visit next (its first child, or its instance with
    // TLAS_LEAF_BIT), known from its parent's pair of records, so a visit loads only the
    // node's two children; `visit` false: pop one off the stack first.
    var next = root.child;
    var visit = true;
    loop {
        // Down the TLAS to the next instance whose box the ray enters.
        var instance = BVH_NO_HIT;
        loop {
            if visit {
                if (next & TLAS_LEAF_BIT) != 0u {
                    instance = next & ~TLAS_LEAF_BIT;
                    visit = false;
                    break;
                }
                let left = bvh_load_tlas_node(next);
                let right = bvh_load_tlas_node(next + 1u);
                bvh_steps += 1u;
                let t_left = bvh_box_entry(box_ray, left.min, left.max, left.kappa * unit_pad, t_min, t_max);
                let t_right = bvh_box_entry(box_ray, right.min, right.max, right.kappa * unit_pad, t_min, t_max);
                let hit_left = f32_is_finite(t_left);
                let hit_right = f32_is_finite(t_right);
                if hit_left && hit_right {
                    if t_left <= t_right {
                        bvh_tlas_stack[top] = vec2<u32>(right.child, bitcast<u32>(t_right));
                        next = left.child;
                    } else {
                        bvh_tlas_stack[top] = vec2<u32>(left.child, bitcast<u32>(t_left));
                        next = right.child;
                    }
                    top += 1u;
                } else if hit_left {
                    next = left.child;
                } else if hit_right {
                    next = right.child;
                } else {
                    visit = false;
                }
            } else {
                // Pop the nearest pending node that can still hold a nearer hit.
                if top == 0u {
                    break;
                }
                top -= 1u;
                if bitcast<f32>(bvh_tlas_stack[top].y) < t_max {
                    next = bvh_tlas_stack[top].x;
                    visit = true;
                }
            }
        }
        if instance == BVH_NO_HIT {
            return best;
        }
        if instance < arrayLength(&bvh_instances) && bvh_trace_instance(ray, instance, &t_max, &best, any_hit) {
            return best;
        }
        // Nothing left to pop (one instance, or the last): done now, not after another round,
        // whose masked BLAS step cost a one-instance scene a fifth of its rays per second.
        if top == 0u {
            return best;
        }
    }
    return best;
}

// The nearest accepted hit in (ray.t_min, t_max); instance BVH_NO_HIT when none.
fn trace_closest(ray: Ray, t_max: f32) -> Hit {
    return bvh_trace(ray, t_max, false);
}

// Whether any accepted hit lies in (ray.t_min, t_max); stops at the first one found.
fn trace_any(ray: Ray, t_max: f32) -> bool {
    return bvh_trace(ray, t_max, true).instance != BVH_NO_HIT;
}
