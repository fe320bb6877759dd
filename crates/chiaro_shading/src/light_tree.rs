//! A light tree for many lights: a binary hierarchy over the lights of finite extent (emissive
//! triangles, point and spot lights), walked from the root to one light by the importance of each
//! subtree to the shading point, after Conty Estevez and Kulla 2018 ("Importance Sampling of Many
//! Lights with Adaptive Tree Splitting", sections 4.1 to 4.3: the orientation cone of a node's
//! emitters, its union, and the importance bound). One light is picked, with the exact
//! probability of the walk, so MIS against BRDF sampling stays exact ([`LightTree::pmf`]
//! re-walks the path of a given light).
//!
//! The importance of a node seen from point p with normal n is
//! `power * cos(theta') * cos(theta_i') / d^2`: `theta'` the angle between the node's emission cone
//! and the direction to p, reduced by the cone's spread and by the angle the node's box subtends
//! (zero past the emission falloff), `theta_i'` the angle between n and the direction to the
//! node, reduced the same way (zero below the horizon), and `d` the distance to the box centre,
//! kept at least half the box diagonal. It bounds what the node's lights can send to p. Each
//! step's child probability mixes in a uniform share of [`UNIFORM_SHARE`], so every light keeps a
//! non-zero probability whatever the bound says: the estimate stays unbiased even where the
//! bound, in floating point, would wrongly rule a light out.
//!
//! The tree is also readable flat ([`LightTree::nodes`], [`LightTree::leaves`]), for a GPU copy
//! that walks it the same way; [`LightSampling`] names the choice between it and power alone.

use std::f32::consts::PI;

use glam::Vec3;

/// Share of each child choice spread uniformly over the two children.
pub const UNIFORM_SHARE: f32 = 0.01;

/// A light as the tree sees it: where it is, how much it emits and towards where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// Lower corner of its world-space bounding box.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
    /// Emitted power (luminance), any consistent unit.
    pub power: f32,
    /// Unit axis of its emission cone.
    pub axis: Vec3,
    /// Half-angle of the cone of normals (0 for a flat one-sided emitter, pi for any direction).
    pub theta_o: f32,
    /// Spread of emission beyond the cone of normals (pi / 2 for cosine emitters, 0 for a spot's
    /// hard cut-off).
    pub theta_e: f32,
}

impl LightBounds {
    /// A one-sided emissive triangle (`two_sided`: both faces emit).
    pub fn triangle(v: [Vec3; 3], power: f32, two_sided: bool) -> Self {
        let normal = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or(Vec3::Z);
        Self {
            min: v[0].min(v[1]).min(v[2]),
            max: v[0].max(v[1]).max(v[2]),
            power,
            axis: normal,
            theta_o: if two_sided { PI } else { 0.0 },
            theta_e: PI / 2.0,
        }
    }

    /// A point light at `position`.
    pub fn point(position: Vec3, power: f32) -> Self {
        Self {
            min: position,
            max: position,
            power,
            axis: Vec3::Z,
            theta_o: PI,
            theta_e: 0.0,
        }
    }

    /// A spot light at `position` shining along `axis` up to `outer` radians from it.
    pub fn spot(position: Vec3, axis: Vec3, outer: f32, power: f32) -> Self {
        Self {
            min: position,
            max: position,
            power,
            axis,
            theta_o: outer.clamp(0.0, PI),
            theta_e: 0.0,
        }
    }

    fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
}

/// How next-event estimation picks a light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LightSampling {
    /// In proportion to each light's power, wherever the shading point is.
    Power,
    /// Through a light tree, by each light's importance to the shading point.
    #[default]
    Tree,
}

impl std::str::FromStr for LightSampling {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "power" => Ok(Self::Power),
            "tree" => Ok(Self::Tree),
            other => Err(format!(
                "unknown light sampling '{other}' (expected power or tree)"
            )),
        }
    }
}

/// One node of the flat tree ([`LightTree::nodes`]): a leaf holds one light, an inner node two
/// children, which always come after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightTreeNode {
    /// The bounds of the node's lights (a leaf: its light's).
    pub bounds: LightBounds,
    /// Inner: index of the first child (the second follows). Leaf: the light's index.
    pub first: u32,
    /// Whether the node is a leaf.
    pub leaf: bool,
    /// Index of the parent node, [`NO_PARENT`] for the root (node 0).
    pub parent: u32,
}

/// [`LightTreeNode::parent`] of the root.
pub const NO_PARENT: u32 = u32::MAX;

/// The hierarchy over a set of lights.
#[derive(Clone, Debug)]
pub struct LightTree {
    nodes: Vec<LightTreeNode>,
    /// The leaf of each light.
    leaf_of: Vec<u32>,
}

/// The angle between two unit vectors, robust near 0 and pi.
fn angle_between(a: Vec3, b: Vec3) -> f32 {
    let d = a.dot(b);
    if d < 0.0 {
        PI - 2.0 * ((a + b).length() * 0.5).min(1.0).asin()
    } else {
        2.0 * ((a - b).length() * 0.5).min(1.0).asin()
    }
}

/// The smallest cone (of normals, with emission spread) holding both (section 4.2).
fn union_cone(a: &LightBounds, b: &LightBounds) -> (Vec3, f32, f32) {
    let (a, b) = if a.theta_o >= b.theta_o {
        (a, b)
    } else {
        (b, a)
    };
    let theta_e = a.theta_e.max(b.theta_e);
    let theta_d = angle_between(a.axis, b.axis);
    if (theta_d + b.theta_o).min(PI) <= a.theta_o {
        return (a.axis, a.theta_o, theta_e);
    }
    let theta_o = 0.5 * (a.theta_o + theta_d + b.theta_o);
    if theta_o >= PI {
        return (a.axis, PI, theta_e);
    }
    let rotate_by = theta_o - a.theta_o;
    let pivot = a.axis.cross(b.axis);
    if pivot.length_squared() < 1e-12 {
        // Opposite axes: no plane to rotate in; any axis with the full sphere bounds them.
        return (a.axis, PI, theta_e);
    }
    let axis = glam::Quat::from_axis_angle(pivot.normalize(), rotate_by) * a.axis;
    (axis.normalize(), theta_o, theta_e)
}

fn union(a: &LightBounds, b: &LightBounds) -> LightBounds {
    let (axis, theta_o, theta_e) = union_cone(a, b);
    LightBounds {
        min: a.min.min(b.min),
        max: a.max.max(b.max),
        power: a.power + b.power,
        axis,
        theta_o,
        theta_e,
    }
}

/// An upper bound on what the lights in `b` send to `p` on a surface of normal `n` (a zero `n`
/// drops the surface term).
pub fn importance(b: &LightBounds, p: Vec3, n: Vec3) -> f32 {
    if b.power <= 0.0 {
        return 0.0;
    }
    let center = b.centroid();
    let half_diagonal = 0.5 * (b.max - b.min).length();
    let to_light = center - p;
    let distance2 = to_light.length_squared();
    let inside = p.cmpge(b.min).all() && p.cmple(b.max).all();
    if inside || distance2 <= half_diagonal * half_diagonal {
        // Too close for the cone bounds to say anything: the power alone, at the box scale.
        return b.power / half_diagonal.max(1e-6).powi(2);
    }
    let distance = distance2.sqrt();
    let wi = to_light / distance;
    let theta_u = (half_diagonal / distance).min(1.0).asin();
    let theta = angle_between(b.axis, -wi);
    let theta_emit = (theta - b.theta_o - theta_u).max(0.0);
    if theta_emit >= b.theta_e && !(b.theta_e == 0.0 && theta_emit == 0.0) {
        return 0.0;
    }
    let cos_emit = theta_emit.cos().max(0.0);
    let cos_receive = if n == Vec3::ZERO {
        1.0
    } else {
        let theta_i = angle_between(n, wi);
        let reduced = (theta_i - theta_u).max(0.0);
        if reduced >= PI / 2.0 {
            return 0.0;
        }
        reduced.cos()
    };
    b.power * cos_emit * cos_receive / distance2
}

/// Levels of the tree cut by `split`'s heuristic; below them, at the median. A heuristic cut
/// may peel one light off a node at every level, so this bounds the depth: at most
/// `SAH_LEVELS + ceil(log2 n)`, 56 for 2^32 lights, within the GPU walk's bound of 64
/// (`shaders/lib/light_tree.wgsl`).
pub const SAH_LEVELS: usize = 24;

/// The cost of a node holding `count` lights within a box of extent `size`: the count times the
/// square of the box's edge sum (its surface area up to a constant for a cube, and unlike the
/// area not zero for a flat or linear cluster of lights).
fn split_cost(count: usize, size: Vec3) -> f64 {
    count as f64 * f64::from(size.x + size.y + size.z).powi(2)
}

/// Orders `items` along the widest axis of their lights' centroids and returns where to cut them
/// in two: the cut that minimises the children's summed [`split_cost`], a surface area heuristic
/// (Conty Estevez and Kulla build with one, section 4.4, weighted by power and orientation).
/// Clusters of lights far apart land in different subtrees: a median cut put hard-cases' 1 cm
/// emitter and its copy 1e5 units away under one node whose box held every point near the
/// emitter, and so was weighed by its power alone, while its sibling was weighed by distance,
/// which starved the emitter of picks beside it. Not weighted by power: that grouped
/// many-lights' bright lights apart from the dim ones near them, whatever the distance, and the
/// CPU reference's noise there grew 27 times (docs/experiments/, the light tree cuts). Ties
/// (lights at one point) go to the cut nearest the middle. Without `sah`, the median cut.
fn split(lights: &[LightBounds], items: &mut [u32], sah: bool) -> usize {
    let centroid = |i: u32| lights[i as usize].centroid();
    let (lo, hi) = items
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(centroid(i)), hi.max(centroid(i)))
        });
    let axis = (hi - lo).max_position();
    let order = |a: &u32, b: &u32| centroid(*a)[axis].total_cmp(&centroid(*b)[axis]);
    let n = items.len();
    if !sah {
        items.select_nth_unstable_by(n / 2, order);
        return n / 2;
    }
    items.sort_unstable_by(order);
    // right[k]: the cost of items[k..] as one node.
    let mut right = vec![0.0; n];
    let (mut min, mut max) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for k in (1..n).rev() {
        let b = &lights[items[k] as usize];
        (min, max) = (min.min(b.min), max.max(b.max));
        right[k] = split_cost(n - k, max - min);
    }
    let (mut min, mut max) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let mut best = (f64::INFINITY, n / 2);
    for k in 1..n {
        let b = &lights[items[k - 1] as usize];
        (min, max) = (min.min(b.min), max.max(b.max));
        let cost = split_cost(k, max - min) + right[k];
        let nearer = k.abs_diff(n / 2) < best.1.abs_diff(n / 2);
        if cost < best.0 || (cost == best.0 && nearer) {
            best = (cost, k);
        }
    }
    best.1
}

/// The probability of taking the first of two children with importances `left` and `right`.
pub fn first_child_probability(left: f32, right: f32) -> f32 {
    let total = left + right;
    let proportional = if total > 0.0 && total.is_finite() {
        left / total
    } else {
        0.5
    };
    (1.0 - UNIFORM_SHARE) * proportional + UNIFORM_SHARE * 0.5
}

impl LightTree {
    /// Builds the tree over `lights` (their indices are what [`LightTree::pick`] returns);
    /// `None` when there are none.
    pub fn build(lights: &[LightBounds]) -> Option<Self> {
        if lights.is_empty() {
            return None;
        }
        let mut tree = Self {
            nodes: Vec::with_capacity(2 * lights.len()),
            leaf_of: vec![0; lights.len()],
        };
        let mut order: Vec<u32> = (0..lights.len() as u32).collect();
        tree.nodes.push(LightTreeNode {
            bounds: lights[0],
            first: 0,
            leaf: true,
            parent: NO_PARENT,
        });
        // Explicit stack: (node, range of `order`, depth).
        let mut stack = vec![(0usize, 0usize, lights.len(), 0usize)];
        while let Some((node, start, end, depth)) = stack.pop() {
            let items = &mut order[start..end];
            if items.len() == 1 {
                let light = items[0] as usize;
                tree.nodes[node] = LightTreeNode {
                    bounds: lights[light],
                    first: light as u32,
                    leaf: true,
                    parent: tree.nodes[node].parent,
                };
                tree.leaf_of[light] = node as u32;
                continue;
            }
            let mid = split(lights, items, depth < SAH_LEVELS);
            let first = tree.nodes.len();
            for _ in 0..2 {
                tree.nodes.push(LightTreeNode {
                    bounds: lights[0],
                    first: 0,
                    leaf: true,
                    parent: node as u32,
                });
            }
            tree.nodes[node].first = first as u32;
            tree.nodes[node].leaf = false;
            stack.push((first, start, start + mid, depth + 1));
            stack.push((first + 1, start + mid, end, depth + 1));
        }
        // Inner bounds bottom-up: children always come after their parent.
        for node in (0..tree.nodes.len()).rev() {
            if !tree.nodes[node].leaf {
                let first = tree.nodes[node].first as usize;
                tree.nodes[node].bounds =
                    union(&tree.nodes[first].bounds, &tree.nodes[first + 1].bounds);
            }
        }
        Some(tree)
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        self.leaf_of.len()
    }

    /// True when the tree holds no light (never: [`LightTree::build`] refuses that).
    pub fn is_empty(&self) -> bool {
        self.leaf_of.is_empty()
    }

    /// The nodes, root first, each inner node's children after it: what a walk reads.
    pub fn nodes(&self) -> &[LightTreeNode] {
        &self.nodes
    }

    /// The leaf node of each light (indexed as the lights passed to [`LightTree::build`]).
    pub fn leaves(&self) -> &[u32] {
        &self.leaf_of
    }

    /// Total power of the lights.
    pub fn power(&self) -> f32 {
        self.nodes[0].bounds.power
    }

    /// Picks a light for shading point `p` with normal `n` (zero: no surface term) from the
    /// uniform number `u`: its index and the probability it was picked.
    pub fn pick(&self, p: Vec3, n: Vec3, mut u: f32) -> (usize, f32) {
        let mut node = 0usize;
        let mut pmf = 1.0f32;
        while !self.nodes[node].leaf {
            let first = self.nodes[node].first as usize;
            let left = importance(&self.nodes[first].bounds, p, n);
            let right = importance(&self.nodes[first + 1].bounds, p, n);
            let p_left = first_child_probability(left, right);
            if u < p_left {
                u = (u / p_left).min(1.0 - f32::EPSILON / 2.0);
                pmf *= p_left;
                node = first;
            } else {
                u = ((u - p_left) / (1.0 - p_left)).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
                pmf *= 1.0 - p_left;
                node = first + 1;
            }
        }
        (self.nodes[node].first as usize, pmf)
    }

    /// The probability that [`LightTree::pick`] at `p`, `n` returns `light`.
    pub fn pmf(&self, light: usize, p: Vec3, n: Vec3) -> f32 {
        let Some(&leaf) = self.leaf_of.get(light) else {
            return 0.0;
        };
        let mut node = leaf as usize;
        let mut pmf = 1.0f32;
        while self.nodes[node].parent != NO_PARENT {
            let parent = self.nodes[node].parent as usize;
            let first = self.nodes[parent].first as usize;
            let left = importance(&self.nodes[first].bounds, p, n);
            let right = importance(&self.nodes[first + 1].bounds, p, n);
            let p_left = first_child_probability(left, right);
            pmf *= if node == first { p_left } else { 1.0 - p_left };
            node = parent;
        }
        pmf
    }
}

#[cfg(test)]
mod tests;
