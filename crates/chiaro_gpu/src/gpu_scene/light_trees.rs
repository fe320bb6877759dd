//! The light trees on the GPU: chiaro_shading's [`LightTree`] over the area table's emissive
//! triangles and one over the point and spot lights (when there are more punctual lights than
//! the direct pass evaluates one by one), flattened into one node buffer (area tree first) and
//! one leaf-per-light buffer (area-table entries, then punctual lights).
//!
//! The lights of infinite extent stay outside the trees, as in the CPU reference: the
//! environment keeps its power share of the area table (`env_pmf`), the directional lights
//! theirs of the punctual lights (`directional_share`).

use chiaro_shading::light_tree::{LightBounds, LightTree, NO_PARENT};

use super::layout::{GpuLightTreeNode, NO_INDEX};

/// One tree, flattened: node indices relative to its first node, and the leaf of each entry
/// of its light table ([`NO_INDEX`] for the entries it does not hold).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlatTree {
    /// The nodes, root first; a leaf's `first` is its light's table index.
    pub nodes: Vec<GpuLightTreeNode>,
    /// The leaf node of each table entry.
    pub leaves: Vec<u32>,
}

impl FlatTree {
    /// The tree over the table entries that have bounds (`bounds[i]` is entry `i`'s); empty
    /// when none has.
    pub fn build(bounds: &[Option<LightBounds>]) -> Self {
        let (table_index, lights): (Vec<u32>, Vec<LightBounds>) = bounds
            .iter()
            .enumerate()
            .filter_map(|(i, b)| b.map(|b| (i as u32, b)))
            .unzip();
        let Some(tree) = LightTree::build(&lights) else {
            return Self::default();
        };
        let nodes = tree
            .nodes()
            .iter()
            .map(|n| GpuLightTreeNode {
                min: n.bounds.min.to_array(),
                power: n.bounds.power,
                max: n.bounds.max.to_array(),
                theta_o: n.bounds.theta_o,
                axis: n.bounds.axis.to_array(),
                theta_e: n.bounds.theta_e,
                first: if n.leaf {
                    table_index[n.first as usize]
                } else {
                    n.first
                },
                parent: if n.parent == NO_PARENT {
                    NO_INDEX
                } else {
                    n.parent
                },
                leaf: u32::from(n.leaf),
                pad: 0,
            })
            .collect();
        let mut leaves = vec![NO_INDEX; bounds.len()];
        for (light, &leaf) in tree.leaves().iter().enumerate() {
            leaves[table_index[light] as usize] = leaf;
        }
        Self { nodes, leaves }
    }
}

/// Both trees in the shared buffers: the nodes, the leaves (the area table's `area_count`
/// entries, then the punctual lights'), and the roots ([`NO_INDEX`] for an empty tree).
pub fn combine(
    area: &FlatTree,
    punctual: &FlatTree,
    area_count: usize,
) -> (Vec<GpuLightTreeNode>, Vec<u32>, u32, u32) {
    let base = area.nodes.len() as u32;
    let mut nodes = area.nodes.clone();
    nodes.extend(punctual.nodes.iter().map(|n| GpuLightTreeNode {
        first: if n.leaf != 0 { n.first } else { n.first + base },
        parent: if n.parent == NO_INDEX {
            NO_INDEX
        } else {
            n.parent + base
        },
        ..*n
    }));
    let mut leaves = area.leaves.clone();
    leaves.resize(area_count, NO_INDEX);
    leaves.extend(
        punctual
            .leaves
            .iter()
            .map(|&l| if l == NO_INDEX { NO_INDEX } else { l + base }),
    );
    let root = |tree: &FlatTree, at: u32| if tree.nodes.is_empty() { NO_INDEX } else { at };
    (nodes, leaves, root(area, 0), root(punctual, base))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn combined_trees_keep_their_links_and_tables() {
        let at = |x: f32| Some(LightBounds::point(Vec3::new(x, 0.0, 0.0), 1.0));
        let area = FlatTree::build(&[at(0.0), at(1.0), at(2.0), None]);
        let punctual = FlatTree::build(&[None, at(5.0), at(6.0)]);
        assert_eq!(area.nodes.len(), 5);
        assert_eq!(area.leaves[3], NO_INDEX);
        let (nodes, leaves, area_root, punctual_root) = combine(&area, &punctual, 4);
        assert_eq!((area_root, punctual_root), (0, 5));
        assert_eq!(nodes.len(), 8);
        assert_eq!(leaves.len(), 7);
        assert_eq!(nodes[5].parent, NO_INDEX);
        // Each light's leaf names it back, and each child its parent.
        for (i, &leaf) in leaves.iter().enumerate() {
            let table = if i < 4 { i } else { i - 4 };
            if leaf != NO_INDEX {
                assert_eq!(nodes[leaf as usize].leaf, 1);
                assert_eq!(nodes[leaf as usize].first as usize, table);
            }
        }
        assert_eq!(leaves[4], NO_INDEX);
        for (i, n) in nodes.iter().enumerate().filter(|(_, n)| n.leaf == 0) {
            assert_eq!(nodes[n.first as usize].parent as usize, i);
            assert_eq!(nodes[n.first as usize + 1].parent as usize, i);
        }
        let empty = combine(&FlatTree::default(), &FlatTree::default(), 1);
        assert_eq!(empty, (Vec::new(), vec![NO_INDEX], NO_INDEX, NO_INDEX));
    }
}
