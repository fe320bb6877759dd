// A light tree walked from a root to one light by the importance of each subtree to the
// shading point, and the probability of that walk re-computed from a light's leaf up to the
// root, after Conty Estevez and Kulla, "Importance Sampling of Many Lights with Adaptive Tree
// Splitting", HPG 2018 (sections 4.1 to 4.3: orientation cones, their union, the importance
// bound). Mirrors chiaro_shading::light_tree function for function (importance,
// first_child_probability, LightTree::pick, LightTree::pmf); chiaro_gpu's gather builds the
// nodes from that tree.
//
// The nodes live wherever the importing module keeps them; it defines
//     struct GpuLightTreeNode      // chiaro_gpu::GpuLightTreeNode
//     fn light_tree_node(i: u32) -> GpuLightTreeNode
// Several trees may share one array: a walk starts at a root, and a root's parent is NO_INDEX.
// Unlike the CPU tree, an inner node names both children (`first`, `second`): the GPU layout
// puts the leaves after the inner nodes in the order of their lights.

#import lib/generated.wgsl
#import lib/float.wgsl

// Deeper than any tree the gather builds (chiaro_shading's SAH_LEVELS heuristic cuts, then
// median ones: depth at most 56 for 2^32 lights);
// bounds the walks should the nodes be corrupt.
const LIGHT_TREE_MAX_DEPTH: u32 = 64u;

// A picked light (its index in its table, the leaf's `first`) and the probability of the walk.
struct LightTreePick {
    light: u32,
    pmf: f32,
}

// asin of x in [0, 1] through atan2: some drivers' asin is far less exact (lavapipe's errs by
// up to 4e-4, its atan2 by 3e-6), and the walk's probabilities should match the CPU's.
fn light_tree_asin(x: f32) -> f32 {
    return atan2(x, sqrt((1.0 - x) * (1.0 + x)));
}

// The angle between two unit vectors, robust near 0 and pi.
fn light_tree_angle_between(a: vec3<f32>, b: vec3<f32>) -> f32 {
    if dot(a, b) < 0.0 {
        return PI - 2.0 * light_tree_asin(min(length(a + b) * 0.5, 1.0));
    }
    return 2.0 * light_tree_asin(min(length(a - b) * 0.5, 1.0));
}

// An upper bound on what the lights under `b` send to p on a surface of normal n (a zero n
// drops the surface term): power cos(theta') cos(theta_i') / d^2 (see chiaro_shading).
fn light_tree_importance(b: GpuLightTreeNode, p: vec3<f32>, n: vec3<f32>) -> f32 {
    if b.power <= 0.0 {
        return 0.0;
    }
    let center = 0.5 * (b.min + b.max);
    let half_diagonal = 0.5 * length(b.max - b.min);
    let to_light = center - p;
    let distance2 = dot(to_light, to_light);
    let inside = all(p >= b.min) && all(p <= b.max);
    if inside || distance2 <= half_diagonal * half_diagonal {
        // Too close for the cone bounds to say anything: the power alone, at the box scale.
        let h = max(half_diagonal, 1e-6);
        return b.power / (h * h);
    }
    let distance = sqrt(distance2);
    let wi = to_light / distance;
    let theta_u = light_tree_asin(min(half_diagonal / distance, 1.0));
    let theta = light_tree_angle_between(b.axis, -wi);
    let theta_emit = max(theta - b.theta_o - theta_u, 0.0);
    if theta_emit >= b.theta_e && !(b.theta_e == 0.0 && theta_emit == 0.0) {
        return 0.0;
    }
    let cos_emit = max(cos(theta_emit), 0.0);
    var cos_receive = 1.0;
    if any(n != vec3<f32>(0.0)) {
        let reduced = max(light_tree_angle_between(n, wi) - theta_u, 0.0);
        if reduced >= FRAC_PI_2 {
            return 0.0;
        }
        cos_receive = cos(reduced);
    }
    return b.power * cos_emit * cos_receive / distance2;
}

// The probability of taking the first of two children with importances left and right, a
// LIGHT_TREE_UNIFORM_SHARE of it uniform.
fn light_tree_first_child_probability(left: f32, right: f32) -> f32 {
    let total = left + right;
    var proportional = 0.5;
    if total > 0.0 && f32_is_finite(total) {
        proportional = left / total;
    }
    return (1.0 - LIGHT_TREE_UNIFORM_SHARE) * proportional + LIGHT_TREE_UNIFORM_SHARE * 0.5;
}

// The probability of taking the first child of inner node `node` from p, n.
fn light_tree_first_of(node: GpuLightTreeNode, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let left = light_tree_importance(light_tree_node(node.first), p, n);
    let right = light_tree_importance(light_tree_node(node.second), p, n);
    return light_tree_first_child_probability(left, right);
}

// Walks the tree under `root` to one light for shading point p with normal n from the uniform
// number u in [0, 1), u rescaled at each step for the next.
fn light_tree_pick(root: u32, p: vec3<f32>, n: vec3<f32>, u_in: f32) -> LightTreePick {
    var node = light_tree_node(root);
    var u = u_in;
    var pmf = 1.0;
    for (var depth = 0u; depth < LIGHT_TREE_MAX_DEPTH && node.leaf == 0u; depth++) {
        let p_left = light_tree_first_of(node, p, n);
        var next = node.first;
        if u < p_left {
            u = min(u / p_left, ONE_MINUS_EPSILON);
            pmf *= p_left;
        } else {
            u = clamp((u - p_left) / (1.0 - p_left), 0.0, ONE_MINUS_EPSILON);
            pmf *= 1.0 - p_left;
            next = node.second;
        }
        node = light_tree_node(next);
    }
    return LightTreePick(node.first, pmf);
}

// The probability that light_tree_pick from p, n ends at node `leaf`: the walk re-traced from
// the leaf up to its root.
fn light_tree_pmf(leaf: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    var index = leaf;
    var parent = light_tree_node(leaf).parent;
    var pmf = 1.0;
    for (var depth = 0u; depth < LIGHT_TREE_MAX_DEPTH && parent != NO_INDEX; depth++) {
        let node = light_tree_node(parent);
        let p_left = light_tree_first_of(node, p, n);
        pmf *= select(1.0 - p_left, p_left, index == node.first);
        index = parent;
        parent = node.parent;
    }
    return pmf;
}
