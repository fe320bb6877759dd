//! The top-level BVH: a binary tree over instances, one instance per leaf, built with chiaro's
//! binned SAH builder ([`crate::binned`]) rather than obvhs, whose PLOC builder is quadratic on
//! coincident boxes (measured: 20,000 identical boxes, 14.7 s; 40,000 would be about a minute).
//!
//! Updates refit: a moved instance's leaf gets its new box and every ancestor is recomputed up
//! to the first one that does not change (`O(depth)`); many moved instances refit the whole tree
//! bottom-up in one `O(n)` pass instead. Refitting keeps the topology, so a tree whose boxes have
//! grown too much (the sum of inner-node areas above [`REBUILD_RATIO`] times its value at the
//! last build) asks for a full rebuild.

use chiaro_scene::Aabb;
use glam::Vec3;

use crate::binned;
use crate::instance::InstanceBounds;
use crate::layout::{TLAS_LEAF_BIT, TlasNode};
use crate::ray::Ray;
use crate::slab::{BoxRay, TLAS_PAD_ULPS};

/// Growth of the summed inner-node area past which a refitted TLAS is rebuilt.
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
    built_area: f64,
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
            built_area: 0.0,
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
        tlas.built_area = tlas.area;
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

    /// Refits every node from `bounds` (children have larger indices than their parents).
    pub fn refit_all(&mut self, bounds: &[InstanceBounds]) {
        for i in (0..self.nodes.len()).rev() {
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
        self.area = self
            .nodes
            .iter()
            .filter(|n| n.instance().is_none())
            .map(half_area)
            .sum();
    }

    /// Refits after instance `instance`'s bounds changed to `b`.
    pub fn refit_instance(&mut self, instance: u32, b: &InstanceBounds) {
        let leaf = self.leaf_of[instance as usize] as usize;
        self.set_leaf(leaf, b);
        let mut node = self.parents[leaf];
        while node != NO_PARENT && self.refit_inner(node as usize) {
            node = self.parents[node as usize];
        }
    }

    /// True when refits have grown the tree's boxes enough that a rebuild pays.
    pub fn degraded(&self) -> bool {
        self.area > REBUILD_RATIO * self.built_area.max(f64::MIN_POSITIVE)
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
        let mut stack = [(0u32, 0f32); STACK_SIZE];
        let mut top = 0usize;
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
                            stack[top] = (far as u32, t_far);
                            top += 1;
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
                if top == 0 {
                    return false;
                }
                top -= 1;
                let (index, t_entry) = stack[top];
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
        bounds[7] = at(Vec3::new(0.0, 1000.0, 0.0));
        tlas.refit_instance(7, &bounds[7]);
        assert!(tlas.degraded());
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
}
