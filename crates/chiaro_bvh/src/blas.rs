//! Bottom-level BVHs: one binary BVH per mesh, in object space, shared by every instance of the
//! mesh.
//!
//! Built with obvhs's PLOC builder (Meister and Bittner, "Parallel Locally-Ordered Clustering for
//! Bounding Volume Hierarchy Construction", IEEE TVCG 2018) followed by its reinsertion
//! optimisation and SAH leaf collapsing, then copied into chiaro's own flat [`BvhNode`] /
//! [`BvhTriangle`] layout with the boxes recomputed exactly from the vertices. Traversal is
//! chiaro's: a robust padded slab test ([`crate::slab`]) and the watertight triangle test
//! ([`crate::watertight`]).
//!
//! PLOC turns quadratic when many primitives share a centroid (measured: 20,000 identical boxes
//! take 14.7 s at the medium preset, 4x per doubling); a mesh where more than
//! [`CROWD_LIMIT`] triangles fall in one cell of PLOC's 21-bit Morton grid is built with
//! [`crate::binned`] instead. A tree deeper than the traversal stack (never seen in practice)
//! is rebuilt the same way.

use std::time::Duration;

use chiaro_scene::{Aabb, Mesh};
use glam::{Vec3, Vec3A};
use obvhs::{BvhBuildParams, bvh2::builder::build_bvh2_from_tris, triangle::Triangle};

use crate::binned;
use crate::layout::{BvhNode, BvhTriangle};
use crate::object_ray::ObjectRay;
use crate::watertight::TriangleHit;

/// Largest coordinate a triangle may have to enter a BLAS (as in chiaro_scene's validation);
/// obvhs panics on boxes whose area overflows `f32` (measured: from about 2e19).
pub const MAX_BLAS_COORDINATE: f32 = 1.0e18;
/// Triangles sharing one Morton cell above which obvhs's PLOC is not used.
pub const CROWD_LIMIT: usize = 256;
/// Traversal stack entries; trees deeper than this are rebuilt with the binned builder.
pub(crate) const STACK_SIZE: usize = 128;
/// Most triangles per leaf.
const MAX_LEAF: u32 = 4;

/// Which builder made a BLAS.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlasBuilder {
    /// obvhs PLOC + reinsertion + leaf collapsing.
    Obvhs,
    /// chiaro's binned SAH builder (crowded meshes).
    Binned,
}

/// What a traversal callback decides about a candidate hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Candidate {
    /// Ignore it (an alpha-masked hole) and go on.
    Reject,
    /// Keep it: later hits must be nearer.
    Accept,
    /// End the traversal (any-hit found).
    Stop,
}

/// The BVH of one mesh.
#[derive(Clone, Debug)]
pub struct Blas {
    pub(crate) nodes: Vec<BvhNode>,
    pub(crate) triangles: Vec<BvhTriangle>,
    /// For each mesh triangle, its slot in `triangles` (`u32::MAX` if it was left out).
    pub(crate) slot_of: Vec<u32>,
    pub(crate) bounds: Aabb,
    /// Largest absolute coordinate of the mesh, for the box pad.
    pub(crate) magnitude: f32,
    pub(crate) depth: u32,
    pub(crate) builder: BlasBuilder,
}

impl Blas {
    /// Builds the BVH of `mesh`. Triangles with a non-finite coordinate or one beyond
    /// [`MAX_BLAS_COORDINATE`] (which a validated [`Mesh`] does not have) are left out.
    pub fn build(mesh: &Mesh) -> Self {
        let positions = mesh.positions();
        let mut tris = Vec::with_capacity(mesh.triangle_count());
        let mut left_out = 0usize;
        for (index, idx) in mesh.indices().chunks_exact(3).enumerate() {
            let v = [0, 1, 2].map(|k| positions.get(idx[k] as usize).copied().unwrap_or(Vec3::NAN));
            if v.iter()
                .all(|p| p.is_finite() && p.abs().max_element() <= MAX_BLAS_COORDINATE)
            {
                tris.push(BvhTriangle::new(v, index as u32));
            } else {
                left_out += 1;
            }
        }
        if left_out > 0 {
            log::warn!(
                "mesh {:?}: {left_out} triangles with non-finite or huge coordinates left out of its BVH",
                mesh.name()
            );
        }
        Self::from_triangles(tris, mesh.triangle_count())
    }

    /// Builds over `tris` (already checked), `mesh_triangles` being the mesh's triangle count.
    pub(crate) fn from_triangles(tris: Vec<BvhTriangle>, mesh_triangles: usize) -> Self {
        let crowded = max_cell_population(&tris) > CROWD_LIMIT;
        let mut blas = if crowded {
            Self::with_binned(&tris)
        } else {
            Self::with_obvhs(&tris)
        };
        if blas.depth as usize > STACK_SIZE {
            log::warn!(
                "BLAS of {} triangles is {} levels deep: rebuilt with the binned builder",
                tris.len(),
                blas.depth
            );
            blas = Self::with_binned(&tris);
        }
        blas.slot_of = vec![u32::MAX; mesh_triangles];
        for (slot, t) in blas.triangles.iter().enumerate() {
            blas.slot_of[t.triangle as usize] = slot as u32;
        }
        blas.refit();
        blas
    }

    fn empty(builder: BlasBuilder) -> Self {
        Self {
            nodes: Vec::new(),
            triangles: Vec::new(),
            slot_of: Vec::new(),
            bounds: Aabb::EMPTY,
            magnitude: 0.0,
            depth: 0,
            builder,
        }
    }

    fn with_obvhs(tris: &[BvhTriangle]) -> Self {
        let mut blas = Self::empty(BlasBuilder::Obvhs);
        if tris.is_empty() {
            return blas;
        }
        let input: Vec<Triangle> = tris
            .iter()
            .map(|t| {
                let [v0, v1, v2] = t.vertices().map(Vec3A::from);
                Triangle { v0, v1, v2 }
            })
            .collect();
        let params = BvhBuildParams {
            max_prims_per_leaf: MAX_LEAF,
            ..BvhBuildParams::medium_build()
        };
        let mut build_time = Duration::ZERO;
        let bvh = build_bvh2_from_tris(&input, params, &mut build_time);
        // Copy the reachable tree depth first; children of a node stay adjacent.
        blas.nodes.push(BvhNode::default());
        let mut stack = vec![(0usize, 0usize, 1u32)];
        while let Some((old, new, level)) = stack.pop() {
            blas.depth = blas.depth.max(level);
            let node = &bvh.nodes[old];
            if node.is_leaf() {
                let first = blas.triangles.len() as u32;
                let prims =
                    &bvh.primitive_indices[node.first_index as usize..][..node.prim_count as usize];
                blas.triangles
                    .extend(prims.iter().map(|&p| tris[p as usize]));
                blas.nodes[new] = BvhNode {
                    first,
                    count: node.prim_count,
                    ..BvhNode::default()
                };
            } else {
                let child = blas.nodes.len();
                blas.nodes.push(BvhNode::default());
                blas.nodes.push(BvhNode::default());
                blas.nodes[new].first = child as u32;
                stack.push((node.first_index as usize + 1, child + 1, level + 1));
                stack.push((node.first_index as usize, child, level + 1));
            }
        }
        blas
    }

    fn with_binned(tris: &[BvhTriangle]) -> Self {
        let mut blas = Self::empty(BlasBuilder::Binned);
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| Aabb::from_points(t.vertices()))
            .collect();
        let tree = binned::build(&boxes, MAX_LEAF as usize);
        blas.triangles = tree.order.iter().map(|&i| tris[i as usize]).collect();
        blas.nodes = tree
            .nodes
            .iter()
            .map(|n| BvhNode {
                first: n.first,
                count: n.count,
                ..BvhNode::default()
            })
            .collect();
        blas.depth = tree.depth;
        blas
    }

    /// Recomputes every box exactly from the vertices (children have larger indices than their
    /// parents in both builders' output), and the bounds and magnitude.
    fn refit(&mut self) {
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let b = if node.is_leaf() {
                self.triangles[node.first as usize..][..node.count as usize]
                    .iter()
                    .fold(Aabb::EMPTY, |b, t| {
                        t.vertices().into_iter().fold(b, Aabb::including)
                    })
            } else {
                let f = node.first as usize;
                debug_assert!(f > i);
                let (l, r) = (&self.nodes[f], &self.nodes[f + 1]);
                Aabb {
                    min: Vec3::from_array(l.min).min(Vec3::from_array(r.min)),
                    max: Vec3::from_array(l.max).max(Vec3::from_array(r.max)),
                }
            };
            self.nodes[i].min = b.min.to_array();
            self.nodes[i].max = b.max.to_array();
        }
        self.bounds = self.nodes.first().map_or(Aabb::EMPTY, |n| Aabb {
            min: Vec3::from_array(n.min),
            max: Vec3::from_array(n.max),
        });
        self.magnitude = if self.bounds.is_empty() {
            0.0
        } else {
            self.bounds
                .min
                .abs()
                .max(self.bounds.max.abs())
                .max_element()
        };
    }

    /// Object-space bounds (empty for a BLAS without triangles).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Levels of the tree, root included.
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// Which builder made it.
    pub fn builder(&self) -> BlasBuilder {
        self.builder
    }

    /// Bytes of the traversal data (nodes, triangles and the triangle-to-slot map).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice())
            + std::mem::size_of_val(self.triangles.as_slice())
            + std::mem::size_of_val(self.slot_of.as_slice())
    }

    /// The object-space vertices of mesh triangle `triangle`, if it is in this BLAS.
    pub fn triangle(&self, triangle: u32) -> Option<[Vec3; 3]> {
        let slot = *self.slot_of.get(triangle as usize)?;
        self.triangles.get(slot as usize).map(BvhTriangle::vertices)
    }

    /// Nodes, root first.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// Triangles in leaf order.
    pub fn triangles(&self) -> &[BvhTriangle] {
        &self.triangles
    }

    /// Visits every triangle the ray hits in `(t_min, *t_max)`, nearest boxes first, shrinking
    /// `*t_max` on each accepted candidate. Returns true when `on_hit` stopped the traversal.
    #[inline]
    pub(crate) fn traverse<F>(
        &self,
        ray: &ObjectRay,
        t_min: f32,
        t_max: &mut f32,
        on_hit: &mut F,
    ) -> bool
    where
        F: FnMut(u32, TriangleHit) -> Candidate,
    {
        let Some(root) = self.nodes.first() else {
            return false;
        };
        let boxes = &ray.boxes;
        let origins = boxes.padded_origins(ray.pad(self.magnitude));
        if boxes
            .entry(root.lo(), root.hi(), origins, t_min, *t_max)
            .is_infinite()
        {
            return false;
        }
        let mut stack = [(0u32, 0f32); STACK_SIZE];
        let mut top = 0usize;
        let mut node = root;
        loop {
            if node.is_leaf() {
                for tri in &self.triangles[node.first as usize..][..node.count as usize] {
                    let [v0, v1, v2] = tri.vertices();
                    if let Some(hit) = ray.watertight.intersect(v0, v1, v2, t_min, *t_max) {
                        match on_hit(tri.triangle, hit) {
                            Candidate::Reject => {}
                            Candidate::Accept => *t_max = hit.t,
                            Candidate::Stop => return true,
                        }
                    }
                }
            } else {
                let first = node.first as usize;
                let (left, right) = (&self.nodes[first], &self.nodes[first + 1]);
                let t_left = boxes.entry(left.lo(), left.hi(), origins, t_min, *t_max);
                let t_right = boxes.entry(right.lo(), right.hi(), origins, t_min, *t_max);
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
            // Pop the next subtree still in reach.
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

/// The most triangles whose centroids share one cell of a 2^21-per-axis grid over the
/// centroids' bounds (the Morton resolution obvhs's PLOC sorts with).
fn max_cell_population(tris: &[BvhTriangle]) -> usize {
    if tris.len() <= CROWD_LIMIT {
        return tris.len().min(1);
    }
    let centroid = |t: &BvhTriangle| {
        let [a, b, c] = t.vertices();
        (a + b + c) / 3.0
    };
    let bounds = Aabb::from_points(tris.iter().map(centroid));
    let size = bounds.size().as_dvec3();
    let cells = f64::from(1u32 << 21);
    let mut keys: Vec<u64> = tris
        .iter()
        .map(|t| {
            let p = (centroid(t) - bounds.min).as_dvec3();
            let q = |axis: usize| {
                if size[axis] > 0.0 {
                    ((p[axis] / size[axis] * cells) as u64).min((1 << 21) - 1)
                } else {
                    0
                }
            };
            (q(0) << 42) | (q(1) << 21) | q(2)
        })
        .collect();
    keys.sort_unstable();
    keys.chunk_by(|a, b| a == b)
        .map(<[u64]>::len)
        .max()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::MeshData;

    fn mesh(positions: Vec<Vec3>, indices: Vec<u32>) -> Mesh {
        Mesh::new(
            "test",
            MeshData {
                positions,
                indices: Some(indices),
                ..MeshData::default()
            },
        )
        .unwrap()
        .0
    }

    fn check_boxes(blas: &Blas) {
        let mut seen = vec![false; blas.triangles.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let n = blas.nodes[i];
            let b = Aabb {
                min: Vec3::from_array(n.min),
                max: Vec3::from_array(n.max),
            };
            if n.is_leaf() {
                for (k, t) in blas.triangles[n.first as usize..][..n.count as usize]
                    .iter()
                    .enumerate()
                {
                    seen[n.first as usize + k] = true;
                    for v in t.vertices() {
                        assert_eq!(b.including(v), b);
                    }
                }
            } else {
                stack.extend([n.first as usize, n.first as usize + 1]);
            }
        }
        assert!(seen.into_iter().all(|s| s));
    }

    #[test]
    fn single_triangle_and_grid_meshes_build() {
        let one = mesh(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![0, 1, 2]);
        let blas = Blas::build(&one);
        assert_eq!((blas.node_count(), blas.triangle_count()), (1, 1));
        assert_eq!(blas.triangle(0), Some([Vec3::ZERO, Vec3::X, Vec3::Y]));
        assert_eq!(blas.builder(), BlasBuilder::Obvhs);

        let n = 40u32;
        let positions = (0..=n)
            .flat_map(|y| {
                (0..=n).map(move |x| Vec3::new(x as f32, y as f32, ((x * y) % 7) as f32 * 0.1))
            })
            .collect();
        let indices = (0..n)
            .flat_map(|y| {
                (0..n).flat_map(move |x| {
                    let i = y * (n + 1) + x;
                    [i, i + 1, i + n + 2, i, i + n + 2, i + n + 1]
                })
            })
            .collect();
        let blas = Blas::build(&mesh(positions, indices));
        assert_eq!(blas.triangle_count(), (2 * n * n) as usize);
        check_boxes(&blas);
    }

    #[test]
    fn crowded_meshes_use_the_binned_builder() {
        // 2,000 copies of one triangle: obvhs would take quadratic time.
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let indices = (0..2000).flat_map(|_| [0, 1, 2]).collect();
        let blas = Blas::build(&mesh(positions, indices));
        assert_eq!(blas.builder(), BlasBuilder::Binned);
        assert_eq!(blas.triangle_count(), 2000);
        check_boxes(&blas);
    }
}
