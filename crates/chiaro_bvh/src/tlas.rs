//! The top-level BVH: a binary tree over instances, one instance per leaf, built with chiaro's
//! binned SAH builder ([`crate::binned`]) rather than obvhs, whose PLOC builder is quadratic on
//! coincident boxes (measured: 20,000 identical boxes, 14.7 s; 40,000 would be about a minute).
//!
//! Updates keep the tree and change what they must:
//! - a few moved instances are each taken out and inserted again where the SAH cost grows
//!   least, found by a greedy descent (the insertion of Catto's dynamic AABB tree in Box2D; see
//!   also Bittner, Hapala and Havran, "Fast Insertion-Based Optimization of Bounding Volume
//!   Hierarchies", Computer Graphics Forum 2013), and the boxes above both places are refitted:
//!   `O(depth)`, and a moved instance ends up next to its new neighbours rather than stretching
//!   its old ancestors across the scene;
//! - many moved instances (more than an eighth) refit the whole tree in one `O(n)` pass;
//! - a tree whose SAH cost (summed inner-node area over the root's area: the expected number
//!   of inner nodes a ray crossing the root visits) has grown above [`REBUILD_RATIO`] times its
//!   value at the last build asks for a full rebuild. Refits of instances scattered across the
//!   scene do that; an instance moved outside the scene does not (the root grows with it).

use arrayvec::ArrayVec;
use chiaro_scene::Aabb;
use glam::Vec3;

use crate::binned;
use crate::instance::InstanceBounds;
use crate::layout::{TLAS_LEAF_BIT, TlasNode};
use crate::ray::Ray;
use crate::slab::{BoxRay, TLAS_PAD_ULPS};

/// Growth of the SAH cost past which an updated TLAS is rebuilt.
pub const REBUILD_RATIO: f64 = 2.0;
/// Traversal stack entries; the binned builder's depth bound keeps the tree well inside.
const STACK_SIZE: usize = 128;
const NO_PARENT: u32 = u32::MAX;

fn half_area(n: &TlasNode) -> f64 {
    let d = (Vec3::from_array(n.max) - Vec3::from_array(n.min)).as_dvec3();
    d.x * d.y + d.y * d.z + d.z * d.x
}

/// The TLAS.
#[derive(Clone, Debug, Default)]
pub(crate) struct Tlas {
    pub nodes: Vec<TlasNode>,
    parents: Vec<u32>,
    /// Leaf node of each instance.
    leaf_of: Vec<u32>,
    /// SAH cost at the last build.
    built_cost: f64,
    /// Summed half-area of the inner nodes.
    area: f64,
}

impl Tlas {
    /// Builds over the instances' bounds (instance `i` has `bounds[i]`).
    pub fn build(bounds: &[InstanceBounds]) -> Self {
        let boxes: Vec<Aabb> = bounds.iter().map(|b| b.bounds).collect();
        let tree = binned::build(&boxes, 1);
        let mut tlas = Self {
            nodes: vec![TlasNode::default(); tree.nodes.len()],
            parents: vec![NO_PARENT; tree.nodes.len()],
            leaf_of: vec![0; bounds.len()],
            built_cost: 0.0,
            area: 0.0,
        };
        for (i, n) in tree.nodes.iter().enumerate() {
            if n.count > 0 {
                debug_assert_eq!(n.count, 1);
                let instance = tree.order[n.first as usize];
                tlas.nodes[i].child = instance | TLAS_LEAF_BIT;
                tlas.leaf_of[instance as usize] = i as u32;
            } else {
                tlas.nodes[i].child = n.first;
                tlas.parents[n.first as usize] = i as u32;
                tlas.parents[n.first as usize + 1] = i as u32;
            }
        }
        tlas.refit_all(bounds);
        tlas.built_cost = tlas.cost();
        tlas
    }

    fn set_leaf(&mut self, node: usize, b: &InstanceBounds) {
        let n = &mut self.nodes[node];
        n.min = b.bounds.min.to_array();
        n.max = b.bounds.max.to_array();
        n.kappa = b.kappa;
    }

    /// Recomputes inner node `i` from its children; returns whether it changed.
    fn refit_inner(&mut self, i: usize) -> bool {
        let first = self.nodes[i].child as usize;
        let (l, r) = (self.nodes[first], self.nodes[first + 1]);
        let updated = TlasNode {
            min: Vec3::from_array(l.min)
                .min(Vec3::from_array(r.min))
                .to_array(),
            child: self.nodes[i].child,
            max: Vec3::from_array(l.max)
                .max(Vec3::from_array(r.max))
                .to_array(),
            kappa: l.kappa.max(r.kappa),
        };
        if updated == self.nodes[i] {
            return false;
        }
        self.area += half_area(&updated) - half_area(&self.nodes[i]);
        self.nodes[i] = updated;
        true
    }

    /// Refits every node from `bounds`, children before parents.
    pub fn refit_all(&mut self, bounds: &[InstanceBounds]) {
        if self.nodes.is_empty() {
            self.area = 0.0;
            return;
        }
        // Pre-order (parents before children), then walked backwards.
        let mut order = Vec::with_capacity(self.nodes.len());
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            order.push(i);
            if self.nodes[i].instance().is_none() {
                let first = self.nodes[i].child as usize;
                stack.extend([first, first + 1]);
            }
        }
        for &i in order.iter().rev() {
            match self.nodes[i].instance() {
                Some(instance) => self.set_leaf(i, &bounds[instance as usize]),
                None => {
                    let first = self.nodes[i].child as usize;
                    let (l, r) = (self.nodes[first], self.nodes[first + 1]);
                    let n = &mut self.nodes[i];
                    n.min = Vec3::from_array(l.min)
                        .min(Vec3::from_array(r.min))
                        .to_array();
                    n.max = Vec3::from_array(l.max)
                        .max(Vec3::from_array(r.max))
                        .to_array();
                    n.kappa = l.kappa.max(r.kappa);
                }
            }
        }
        self.area = order
            .iter()
            .filter(|&&i| self.nodes[i].instance().is_none())
            .map(|&i| half_area(&self.nodes[i]))
            .sum();
    }

    /// Refits the ancestors of `node`, upwards until one does not change.
    fn refit_above(&mut self, node: usize) {
        let mut node = self.parents[node];
        while node != NO_PARENT && self.refit_inner(node as usize) {
            node = self.parents[node as usize];
        }
    }

    /// Copies node `from` into slot `to` and points its children (or its instance) there.
    fn move_node(&mut self, from: usize, to: usize) {
        let node = self.nodes[from];
        self.nodes[to] = node;
        match node.instance() {
            Some(instance) => self.leaf_of[instance as usize] = to as u32,
            None => {
                self.parents[node.child as usize] = to as u32;
                self.parents[node.child as usize + 1] = to as u32;
            }
        }
    }

    /// The node next to which a leaf with box `b` costs least, by greedy descent.
    fn find_sibling(&self, b: &Aabb) -> usize {
        let grown = |n: &TlasNode| {
            let mut g = *n;
            g.min = Vec3::from_array(n.min).min(b.min).to_array();
            g.max = Vec3::from_array(n.max).max(b.max).to_array();
            half_area(&g)
        };
        let mut index = 0;
        loop {
            let node = &self.nodes[index];
            if node.instance().is_some() {
                return index;
            }
            let combined = grown(node);
            // Cost of a new parent here, and what every deeper choice inherits.
            let here = 2.0 * combined;
            let inherited = 2.0 * (combined - half_area(node));
            let first = node.child as usize;
            let child_cost = |c: &TlasNode| {
                let enlarged = grown(c);
                inherited
                    + if c.instance().is_some() {
                        enlarged
                    } else {
                        enlarged - half_area(c)
                    }
            };
            let (left, right) = (
                child_cost(&self.nodes[first]),
                child_cost(&self.nodes[first + 1]),
            );
            if here <= left && here <= right {
                return index;
            }
            index = if left <= right { first } else { first + 1 };
        }
    }

    /// Moves instance `instance` to bounds `b`: takes its leaf out of the tree and inserts it
    /// again where the SAH cost grows least (see the module documentation).
    pub fn reinsert_instance(&mut self, instance: u32, b: &InstanceBounds) {
        if self.nodes.len() < 3 {
            // One instance: nothing to choose.
            self.refit_instance(instance, b);
            return;
        }
        // Take the leaf out: its sibling replaces their parent; the pair's slots become free.
        let leaf = self.leaf_of[instance as usize] as usize;
        let parent = self.parents[leaf] as usize;
        let pair = self.nodes[parent].child as usize;
        let sibling = if leaf == pair { pair + 1 } else { pair };
        self.area -= half_area(&self.nodes[parent]);
        self.move_node(sibling, parent);
        self.refit_above(parent);

        // Put it back next to the cheapest node, reusing the free pair of slots.
        let target = self.find_sibling(&b.bounds);
        self.move_node(target, pair);
        self.nodes[pair + 1] = TlasNode {
            child: instance | TLAS_LEAF_BIT,
            ..TlasNode::default()
        };
        self.set_leaf(pair + 1, b);
        self.leaf_of[instance as usize] = (pair + 1) as u32;
        self.parents[pair] = target as u32;
        self.parents[pair + 1] = target as u32;
        let (l, r) = (self.nodes[pair], self.nodes[pair + 1]);
        self.nodes[target] = TlasNode {
            min: Vec3::from_array(l.min)
                .min(Vec3::from_array(r.min))
                .to_array(),
            child: pair as u32,
            max: Vec3::from_array(l.max)
                .max(Vec3::from_array(r.max))
                .to_array(),
            kappa: l.kappa.max(r.kappa),
        };
        self.area += half_area(&self.nodes[target]);
        self.refit_above(target);
    }

    /// Refits after instance `instance`'s bounds changed to `b`.
    pub fn refit_instance(&mut self, instance: u32, b: &InstanceBounds) {
        let leaf = self.leaf_of[instance as usize] as usize;
        self.set_leaf(leaf, b);
        self.refit_above(leaf);
    }

    /// SAH cost: summed inner-node half-area over the root's (0 for an empty or flat root).
    pub fn cost(&self) -> f64 {
        let root = self.nodes.first().map_or(0.0, half_area);
        if root > 0.0 { self.area / root } else { 0.0 }
    }

    /// True when updates have made the tree enough worse than a rebuild would that one pays.
    pub fn degraded(&self) -> bool {
        self.cost() > REBUILD_RATIO * self.built_cost
    }

    /// Visits the instances whose boxes a valid `ray` enters in `(t_min, *t_max)`, nearest
    /// first. `visit(instance, t_max)` may shrink `*t_max` and returns true to stop; returns true
    /// when stopped.
    #[inline]
    pub fn traverse<F>(&self, ray: &Ray, t_max: &mut f32, visit: &mut F) -> bool
    where
        F: FnMut(u32, &mut f32) -> bool,
    {
        let Some(root) = self.nodes.first() else {
            return false;
        };
        let t_min = ray.t_min;
        let boxes = BoxRay::new(ray.origin, ray.direction);
        let unit_pad = TLAS_PAD_ULPS * f32::EPSILON * boxes.origin_magnitude();
        let entry = |n: &TlasNode, t_max: f32| {
            boxes.entry(
                n.lo(),
                n.hi(),
                boxes.padded_origins(n.kappa * unit_pad),
                t_min,
                t_max,
            )
        };
        if entry(root, *t_max).is_infinite() {
            return false;
        }
        let mut stack = ArrayVec::<(u32, f32), STACK_SIZE>::new();
        let mut node = root;
        loop {
            match node.instance() {
                Some(instance) => {
                    if visit(instance, t_max) {
                        return true;
                    }
                }
                None => {
                    let first = node.child as usize;
                    let (left, right) = (&self.nodes[first], &self.nodes[first + 1]);
                    let t_left = entry(left, *t_max);
                    let t_right = entry(right, *t_max);
                    match (t_left.is_finite(), t_right.is_finite()) {
                        (true, true) => {
                            let (near, far, t_far) = if t_left <= t_right {
                                (left, first + 1, t_right)
                            } else {
                                (right, first, t_left)
                            };
                            stack.push((far as u32, t_far));
                            node = near;
                            continue;
                        }
                        (true, false) => {
                            node = left;
                            continue;
                        }
                        (false, true) => {
                            node = right;
                            continue;
                        }
                        (false, false) => {}
                    }
                }
            }
            loop {
                let Some((index, t_entry)) = stack.pop() else {
                    return false;
                };
                if t_entry < *t_max {
                    node = &self.nodes[index as usize];
                    break;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(p: Vec3) -> InstanceBounds {
        InstanceBounds {
            bounds: Aabb::from_points([p - 0.5, p + 0.5]),
            kappa: 1.0,
        }
    }

    fn visited(tlas: &Tlas, ray: &Ray) -> Vec<u32> {
        let mut out = Vec::new();
        tlas.traverse(ray, &mut ray.t_max.clone(), &mut |i, _| {
            out.push(i);
            false
        });
        out.sort();
        out
    }

    #[test]
    fn refit_follows_a_moved_instance_and_rebuild_is_asked_for() {
        let mut bounds: Vec<_> = (0..100)
            .map(|i| at(Vec3::new(i as f32 * 2.0, 0.0, 0.0)))
            .collect();
        let mut tlas = Tlas::build(&bounds);
        let down = Ray::new(Vec3::new(10.0, 5.0, 0.0), Vec3::NEG_Y);
        assert_eq!(visited(&tlas, &down), vec![5]);
        bounds[42] = at(Vec3::new(10.0, 2.0, 0.0));
        tlas.refit_instance(42, &bounds[42]);
        assert_eq!(visited(&tlas, &down), vec![5, 42]);
        assert!(!tlas.degraded());
        // Scattering a third of them by refit stretches their ancestors over the scene.
        for i in (0..100).step_by(3) {
            bounds[i] = at(Vec3::new(((i * 37) % 100) as f32 * 2.0, 0.0, 0.0));
            tlas.refit_instance(i as u32, &bounds[i]);
        }
        assert!(tlas.degraded(), "{} vs {}", tlas.cost(), tlas.built_cost);
        let mut full = tlas.clone();
        full.refit_all(&bounds);
        assert_eq!(
            full.nodes, tlas.nodes,
            "incremental refit equals a full refit"
        );
    }

    #[test]
    fn empty_tlas_visits_nothing() {
        let tlas = Tlas::build(&[]);
        assert!(visited(&tlas, &Ray::new(Vec3::ZERO, Vec3::X)).is_empty());
    }

    /// Structure: every instance in exactly one leaf, `leaf_of` and `parents` consistent, boxes
    /// equal to a full refit's.
    fn check(tlas: &Tlas, bounds: &[InstanceBounds]) {
        let mut seen = vec![0; bounds.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            match tlas.nodes[i].instance() {
                Some(inst) => {
                    seen[inst as usize] += 1;
                    assert_eq!(tlas.leaf_of[inst as usize] as usize, i);
                }
                None => {
                    let c = tlas.nodes[i].child as usize;
                    assert_eq!(tlas.parents[c] as usize, i);
                    assert_eq!(tlas.parents[c + 1] as usize, i);
                    stack.extend([c, c + 1]);
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        let mut full = tlas.clone();
        full.refit_all(bounds);
        let reachable = |t: &Tlas| {
            let mut out = Vec::new();
            let mut stack = vec![0usize];
            while let Some(i) = stack.pop() {
                out.push((i, t.nodes[i]));
                if t.nodes[i].instance().is_none() {
                    stack.extend([t.nodes[i].child as usize, t.nodes[i].child as usize + 1]);
                }
            }
            out
        };
        assert_eq!(reachable(&full), reachable(tlas));
        assert!((full.area - tlas.area).abs() <= 1e-6 * full.area.max(1.0));
    }

    #[test]
    fn reinsertion_keeps_the_tree_valid_and_tight() {
        let mut state = 0x1234_5678u32;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        };
        for n in [1usize, 2, 3, 200] {
            let mut bounds: Vec<_> = (0..n)
                .map(|_| at(Vec3::new(next(), next(), next()) * 100.0))
                .collect();
            let mut tlas = Tlas::build(&bounds);
            for step in 0..500 {
                let i = (next() * n as f32) as usize % n;
                bounds[i] = at(Vec3::new(next(), next(), next()) * 100.0);
                if step % 3 == 0 {
                    tlas.refit_instance(i as u32, &bounds[i]);
                } else {
                    tlas.reinsert_instance(i as u32, &bounds[i]);
                }
                check(&tlas, &bounds);
            }
            // After reinsertion the instance is found where it went.
            let i = n / 2;
            bounds[i] = at(Vec3::new(500.0, 0.0, 0.0));
            tlas.reinsert_instance(i as u32, &bounds[i]);
            assert!(
                visited(&tlas, &Ray::new(Vec3::new(500.0, 10.0, 0.0), Vec3::NEG_Y))
                    .contains(&(i as u32))
            );
            // Reinsertion, unlike refit, keeps the tree from degrading under far moves.
            bounds[i] = at(Vec3::new(next(), next(), next()) * 100.0);
            let mut tlas = Tlas::build(&bounds);
            for _ in 0..1000 {
                let i = (next() * n as f32) as usize % n;
                bounds[i] = at(Vec3::new(next(), next(), next()) * 100.0);
                tlas.reinsert_instance(i as u32, &bounds[i]);
            }
            check(&tlas, &bounds);
            let ratio = tlas.cost() / tlas.built_cost.max(1e-9);
            assert!(n < 200 || ratio < 1.5, "SAH cost grew {ratio}x");
        }
    }
}
