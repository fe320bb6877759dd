//! The light trees on the GPU: chiaro_shading's [`LightTree`] over the area table's emissive
//! triangles (when there are more than [`super::layout::AREA_LIGHTS_BY_POWER_MAX`]) and one
//! over the point and spot lights (when there are more punctual lights than the direct pass
//! evaluates one by one), flattened into one node buffer, area tree first.
//!
//! Each tree is laid out with its `n - 1` inner nodes first (root at 0, in the CPU tree's
//! order) and then its `n` leaves in the order of its lights, so the leaf of light `k` is node
//! `n - 1 + k` and no leaf table is needed (the scene's group(0) is at the storage-buffer limit
//! of a stage); an inner node therefore names both children.
//!
//! The lights of infinite extent stay outside the trees, as in the CPU reference: the
//! environment keeps its power share of the area table (`env_pmf`), the directional lights
//! theirs of the punctual lights (`directional_share`).

use chiaro_shading::light_tree::{LightBounds, LightTree, NO_PARENT};

use super::layout::{GpuLightTreeNode, NO_INDEX};

/// One tree, flattened: node indices relative to its root.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlatTree {
    /// The inner nodes, root first, then one leaf per light; a leaf's `first` is its light's
    /// table index.
    pub nodes: Vec<GpuLightTreeNode>,
}

impl FlatTree {
    /// The tree over the table entries that have bounds (`bounds[i]` is entry `i`'s; the
    /// tree's lights are those entries in order); empty when none has.
    pub fn build(bounds: &[Option<LightBounds>]) -> Self {
        let (table_index, lights): (Vec<u32>, Vec<LightBounds>) = bounds
            .iter()
            .enumerate()
            .filter_map(|(i, b)| b.map(|b| (i as u32, b)))
            .unzip();
        let Some(tree) = LightTree::build(&lights) else {
            return Self::default();
        };
        let inner = lights.len() as u32 - 1;
        // New index of each CPU node: inner nodes by rank, leaves after them by light.
        let mut rank = 0;
        let moved: Vec<u32> = tree
            .nodes()
            .iter()
            .map(|n| {
                if n.leaf {
                    inner + n.first
                } else {
                    rank += 1;
                    rank - 1
                }
            })
            .collect();
        let mut nodes = vec![GpuLightTreeNode::default(); tree.nodes().len()];
        for (old, n) in tree.nodes().iter().enumerate() {
            let (first, second) = if n.leaf {
                (table_index[n.first as usize], NO_INDEX)
            } else {
                (moved[n.first as usize], moved[n.first as usize + 1])
            };
            nodes[moved[old] as usize] = GpuLightTreeNode {
                min: n.bounds.min.to_array(),
                power: n.bounds.power,
                max: n.bounds.max.to_array(),
                theta_o: n.bounds.theta_o,
                axis: n.bounds.axis.to_array(),
                theta_e: n.bounds.theta_e,
                first,
                second,
                parent: if n.parent == NO_PARENT {
                    NO_INDEX
                } else {
                    moved[n.parent as usize]
                },
                leaf: u32::from(n.leaf),
            };
        }
        Self { nodes }
    }

    /// The leaf of the tree's light `k` (relative to the root).
    pub fn leaf(&self, k: usize) -> u32 {
        (self.nodes.len() / 2 + k) as u32
    }
}

/// Both trees in the shared buffer: the nodes and the roots ([`NO_INDEX`] for an empty tree).
pub fn combine(area: &FlatTree, punctual: &FlatTree) -> (Vec<GpuLightTreeNode>, u32, u32) {
    let base = area.nodes.len() as u32;
    let shift = |i: u32| if i == NO_INDEX { NO_INDEX } else { i + base };
    let mut nodes = area.nodes.clone();
    nodes.extend(punctual.nodes.iter().map(|n| GpuLightTreeNode {
        first: if n.leaf != 0 { n.first } else { shift(n.first) },
        second: shift(n.second),
        parent: shift(n.parent),
        ..*n
    }));
    let root = |tree: &FlatTree, at: u32| if tree.nodes.is_empty() { NO_INDEX } else { at };
    (nodes, root(area, 0), root(punctual, base))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn combined_trees_keep_their_links_and_leaves_in_light_order() {
        let at = |x: f32| Some(LightBounds::point(Vec3::new(x, 0.0, 0.0), 1.0));
        let area = FlatTree::build(&[at(2.0), at(0.0), at(1.0)]);
        let punctual = FlatTree::build(&[None, at(5.0), at(6.0), at(4.0)]);
        assert_eq!(area.nodes.len(), 5);
        let (nodes, area_root, punctual_root) = combine(&area, &punctual);
        assert_eq!((area_root, punctual_root), (0, 5));
        assert_eq!(nodes.len(), 10);
        assert_eq!(nodes[5].parent, NO_INDEX);
        // Leaf k of each tree holds its k-th light, whose table index it names.
        for k in 0..3 {
            let leaf = &nodes[area.leaf(k) as usize];
            assert_eq!((leaf.leaf, leaf.first as usize), (1, k));
            let leaf = &nodes[5 + punctual.leaf(k) as usize];
            assert_eq!((leaf.leaf, leaf.first as usize), (1, k + 1));
        }
        for (i, n) in nodes.iter().enumerate().filter(|(_, n)| n.leaf == 0) {
            assert_eq!(nodes[n.first as usize].parent as usize, i);
            assert_eq!(nodes[n.second as usize].parent as usize, i);
        }
        assert_eq!(
            combine(&FlatTree::default(), &FlatTree::default()),
            (Vec::new(), NO_INDEX, NO_INDEX)
        );
    }
}
