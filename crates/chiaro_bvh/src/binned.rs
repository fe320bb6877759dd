//! A top-down binned SAH builder over boxes (Wald, "On fast Construction of SAH-based Bounding
//! Volume Hierarchies", IEEE Symposium on Interactive Ray Tracing 2007), used for the TLAS and as
//! the BLAS fallback for meshes that obvhs's PLOC builder would build in quadratic time.
//!
//! It stays `O(n log n)` whatever the input:
//! - a range whose centroids all coincide (40,000 instances spawned at the origin) is split in
//!   half by count, without sorting;
//! - below [`SAH_DEPTH_LIMIT`] levels it switches to median splits (`select_nth_unstable`), so
//!   pathological distributions (exponentially spaced centroids) cannot make the tree `O(n)`
//!   deep; the depth is at most `SAH_DEPTH_LIMIT + log2(n) + 1`, well inside the traversal stack.
//!
//! Costs are accumulated in `f64`: box areas of scenes with coordinates near 1e18 times a million
//! primitives overflow `f32`.

use chiaro_scene::Aabb;
use glam::Vec3;

/// Bins per axis.
const BINS: usize = 16;
/// Levels of SAH splitting before median splits take over.
pub const SAH_DEPTH_LIMIT: u32 = 48;
/// SAH cost of visiting a node, relative to testing one primitive.
const TRAVERSAL_COST: f64 = 1.0;

/// A node of a built tree: an inner node (`count == 0`) has children `first` and `first + 1`;
/// a leaf covers `order[first..first + count]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BuildNode {
    pub bounds: Aabb,
    pub first: u32,
    pub count: u32,
}

/// The result of [`build`].
#[derive(Clone, Debug, Default)]
pub(crate) struct BuiltTree {
    /// Nodes; the root is node 0 and every child has a larger index than its parent.
    pub nodes: Vec<BuildNode>,
    /// Primitive indices in leaf order.
    pub order: Vec<u32>,
    /// Levels, counting the root as 1 (0 for an empty tree).
    pub depth: u32,
}

fn half_area(b: &Aabb) -> f64 {
    let d = b.size().as_dvec3();
    d.x * d.y + d.y * d.z + d.z * d.x
}

/// Builds a binary tree over `boxes` (finite, non-empty boxes), with at most `max_leaf`
/// primitives per leaf (1 gives one leaf per primitive).
pub(crate) fn build(boxes: &[Aabb], max_leaf: usize) -> BuiltTree {
    let n = boxes.len();
    let max_leaf = max_leaf.max(1);
    let mut order: Vec<u32> = (0..n as u32).collect();
    if n == 0 {
        return BuiltTree::default();
    }
    let centroids: Vec<Vec3> = boxes.iter().map(Aabb::center).collect();
    let mut nodes = Vec::with_capacity(2 * n);
    nodes.push(BuildNode {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    });
    let mut depth = 0;
    // (node, start, end, depth)
    let mut tasks = vec![(0usize, 0usize, n, 1u32)];
    while let Some((node, start, end, level)) = tasks.pop() {
        depth = depth.max(level);
        let ids = &mut order[start..end];
        let (bounds, centroid_bounds) =
            ids.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), &i| {
                (
                    b.union(boxes[i as usize]),
                    c.including(centroids[i as usize]),
                )
            });
        nodes[node].bounds = bounds;
        let split = choose_split(
            ids,
            boxes,
            &centroids,
            &bounds,
            &centroid_bounds,
            level,
            max_leaf,
        );
        match split {
            None => {
                nodes[node].first = start as u32;
                nodes[node].count = ids.len() as u32;
            }
            Some(mid) => {
                let left = nodes.len();
                let placeholder = BuildNode {
                    bounds: Aabb::EMPTY,
                    first: 0,
                    count: 0,
                };
                nodes.push(placeholder);
                nodes.push(placeholder);
                nodes[node].first = left as u32;
                nodes[node].count = 0;
                tasks.push((left + 1, start + mid, end, level + 1));
                tasks.push((left, start, start + mid, level + 1));
            }
        }
    }
    BuiltTree {
        nodes,
        order,
        depth,
    }
}

/// Where to split `ids` (reordering it), as the size of the left part; `None` for a leaf.
fn choose_split(
    ids: &mut [u32],
    boxes: &[Aabb],
    centroids: &[Vec3],
    bounds: &Aabb,
    centroid_bounds: &Aabb,
    level: u32,
    max_leaf: usize,
) -> Option<usize> {
    let count = ids.len();
    if count <= 1 {
        return None;
    }
    let extent = centroid_bounds.size();
    if extent.max_element() <= 0.0 {
        // Every centroid coincides: no plane separates them, so split by count.
        return (count > max_leaf).then_some(count / 2);
    }
    if level > SAH_DEPTH_LIMIT {
        let axis = extent.max_position();
        let mid = count / 2;
        ids.select_nth_unstable_by(mid, |&a, &b| {
            centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
        });
        return (count > max_leaf).then_some(mid);
    }

    let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, last bin of the left side)
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let lo = centroid_bounds.min[axis];
        let scale = BINS as f32 * (1.0 - 1e-6) / extent[axis];
        let bin_of = |c: f32| (((c - lo) * scale) as usize).min(BINS - 1);
        let mut bin_bounds = [Aabb::EMPTY; BINS];
        let mut bin_counts = [0usize; BINS];
        for &i in ids.iter() {
            let b = bin_of(centroids[i as usize][axis]);
            bin_counts[b] += 1;
            bin_bounds[b] = bin_bounds[b].union(boxes[i as usize]);
        }
        // Right-to-left sweep: area x count of everything right of each plane.
        let mut right_cost = [0.0f64; BINS];
        let (mut acc, mut acc_count) = (Aabb::EMPTY, 0usize);
        for b in (1..BINS).rev() {
            acc = acc.union(bin_bounds[b]);
            acc_count += bin_counts[b];
            right_cost[b] = if acc_count > 0 {
                half_area(&acc) * acc_count as f64
            } else {
                0.0
            };
        }
        let (mut acc, mut acc_count) = (Aabb::EMPTY, 0usize);
        for b in 0..BINS - 1 {
            acc = acc.union(bin_bounds[b]);
            acc_count += bin_counts[b];
            if acc_count == 0 || acc_count == count {
                continue;
            }
            let cost = half_area(&acc) * acc_count as f64 + right_cost[b + 1];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, b));
            }
        }
    }
    // The minimum and maximum centroids on an axis with extent land in its first and last bin,
    // so some plane always has primitives on both sides.
    let (cost, axis, last_left) = best?;
    let area = half_area(bounds);
    if count <= max_leaf && area > 0.0 && TRAVERSAL_COST + cost / area >= count as f64 {
        return None;
    }
    let lo = centroid_bounds.min[axis];
    let scale = BINS as f32 * (1.0 - 1e-6) / extent[axis];
    let goes_left =
        |i: u32| (((centroids[i as usize][axis] - lo) * scale) as usize).min(BINS - 1) <= last_left;
    let mut mid = 0;
    for k in 0..count {
        if goes_left(ids[k]) {
            ids.swap(k, mid);
            mid += 1;
        }
    }
    debug_assert!(mid > 0 && mid < count);
    Some(mid)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(at: Vec3) -> Aabb {
        Aabb::from_points([at - 0.5, at + 0.5])
    }

    /// Checks structure: every primitive in exactly one leaf, boxes contain their children,
    /// children after parents.
    fn check(tree: &BuiltTree, boxes: &[Aabb], max_leaf: usize) {
        let mut seen = vec![0u32; boxes.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let node = tree.nodes[i];
            if node.count > 0 {
                assert!(node.count as usize <= max_leaf.max(1));
                for &p in &tree.order[node.first as usize..][..node.count as usize] {
                    seen[p as usize] += 1;
                    assert_eq!(node.bounds.union(boxes[p as usize]), node.bounds);
                }
            } else {
                for c in [node.first as usize, node.first as usize + 1] {
                    assert!(c > i);
                    assert_eq!(node.bounds.union(tree.nodes[c].bounds), node.bounds);
                    stack.push(c);
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
    }

    #[test]
    fn builds_valid_trees() {
        assert!(build(&[], 1).nodes.is_empty());
        let one = [unit_box(Vec3::ZERO)];
        let tree = build(&one, 1);
        assert_eq!(tree.nodes.len(), 1);
        assert_eq!(tree.depth, 1);
        let grid: Vec<Aabb> = (0..1000)
            .map(|i| {
                unit_box(Vec3::new((i % 10) as f32, (i / 10 % 10) as f32, (i / 100) as f32) * 2.0)
            })
            .collect();
        for max_leaf in [1, 4] {
            let tree = build(&grid, max_leaf);
            check(&tree, &grid, max_leaf);
            assert!(tree.depth <= 20, "{}", tree.depth);
        }
    }

    #[test]
    fn coincident_and_pathological_inputs_stay_shallow() {
        let same = vec![unit_box(Vec3::ZERO); 5000];
        let tree = build(&same, 1);
        check(&tree, &same, 1);
        assert_eq!(tree.depth, 14, "log2(5000) rounded up, plus the root");
        // Exponentially spaced centroids: each SAH split peels off one box.
        let exp: Vec<Aabb> = (0..2000)
            .map(|i| unit_box(Vec3::new(1.02f32.powi(i) * 1e3, 0.0, 0.0)))
            .collect();
        let tree = build(&exp, 1);
        check(&tree, &exp, 1);
        assert!(tree.depth <= SAH_DEPTH_LIMIT + 13, "{}", tree.depth);
    }
}
