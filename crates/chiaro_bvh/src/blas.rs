//! Bottom-level BVHs: one per mesh, in object space, shared by every instance of the mesh.
//!
//! Built with obvhs: its PLOC builder (Meister and Bittner, "Parallel Locally-Ordered
//! Clustering for Bounding Volume Hierarchy Construction", IEEE TVCG 2018) and reinsertion
//! optimisation make a binary BVH, which obvhs turns into a compressed wide BVH (CWBVH, eight
//! children per 80-byte node, at most three triangles per leaf). The triangles are copied in the
//! CWBVH's leaf order. Traversal is chiaro's ([`crate::wide`]): obvhs's CWBVH child ordering with
//! a conservative box test and the watertight triangle test ([`crate::watertight`]).
//!
//! PLOC turns quadratic when many primitives share a centroid (measured: 20,000 identical boxes
//! take 14.7 s at the medium preset, 4x per doubling); a mesh where more than [`CROWD_LIMIT`]
//! triangles fall in one cell of PLOC's 21-bit Morton grid gets its binary BVH from
//! [`crate::binned`] instead. obvhs's CWBVH conversion recurses once per level, so a binary BVH
//! deeper than [`MAX_BINARY_DEPTH`] (never seen in practice) is also rebuilt that way.

use chiaro_scene::{Aabb, Mesh};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb as ObvhsAabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::node::Bvh2Node;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};
use obvhs::triangle::Triangle;

use crate::binned;
use crate::layout::BvhTriangle;
use crate::object_ray::ObjectRay;
use crate::watertight::TriangleHit;
use crate::wide::{self, NodeRay};

/// Largest coordinate a triangle may have to enter a BLAS (as in chiaro_scene's validation);
/// obvhs panics on boxes whose area overflows `f32` (measured: from about 2e19).
pub const MAX_BLAS_COORDINATE: f32 = 1.0e18;
/// Triangles sharing one Morton cell above which obvhs's PLOC is not used.
pub const CROWD_LIMIT: usize = 256;
/// Deepest binary BVH handed to obvhs's (recursive) CWBVH conversion; also bounds the CWBVH's
/// depth, and so the traversal stack ([`crate::wide`]).
pub const MAX_BINARY_DEPTH: usize = wide::STACK_SIZE;
/// Most triangles per CWBVH leaf (the format's limit).
const MAX_LEAF: u32 = 3;
/// PLOC preset: obvhs's "medium" (search distance 14 below the top 3 levels, 5% reinsertion).
const SEARCH_DEPTH_THRESHOLD: usize = 3;
const REINSERTION_RATIO: f32 = 0.05;

/// Which builder made a BLAS's binary BVH.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlasBuilder {
    /// obvhs PLOC + reinsertion.
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

/// The BVH of one mesh: a CWBVH over its triangles.
#[derive(Clone, Debug)]
pub struct Blas {
    pub(crate) nodes: Vec<CwBvhNode>,
    pub(crate) triangles: Vec<BvhTriangle>,
    /// For each mesh triangle, its slot in `triangles` (`u32::MAX` if it was left out).
    pub(crate) slot_of: Vec<u32>,
    pub(crate) bounds: Aabb,
    /// Largest absolute coordinate of the mesh, for the box pad.
    pub(crate) magnitude: f32,
    pub(crate) depth: u32,
    pub(crate) builder: BlasBuilder,
    pub(crate) fingerprint: u64,
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
        let mut blas = Self::from_triangles(&tris, mesh.triangle_count());
        blas.fingerprint = Self::fingerprint_of(mesh);
        blas
    }

    /// A cheap fingerprint of a mesh (FNV-1a over its name, vertex and index counts, and 64
    /// positions and 64 indices sampled evenly): what [`crate::update_scene_bvh`] compares to
    /// notice a mesh replaced under an id that already has a BLAS. Edits that keep all of these
    /// go unnoticed; add an edited mesh as a new one.
    pub fn fingerprint_of(mesh: &Mesh) -> u64 {
        let mut hash = 0xcbf2_9ce4_8422_2325u64;
        let mut eat = |word: u32| {
            for byte in word.to_le_bytes() {
                hash = (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
            }
        };
        for chunk in mesh.name().as_bytes().chunks(4) {
            let mut word = [0u8; 4];
            word[..chunk.len()].copy_from_slice(chunk);
            eat(u32::from_le_bytes(word));
        }
        let (positions, indices) = (mesh.positions(), mesh.indices());
        eat(positions.len() as u32);
        eat(indices.len() as u32);
        for k in 0..64 {
            if let Some(p) = positions.get(k * positions.len() / 64) {
                for c in p.to_array() {
                    eat(c.to_bits());
                }
            }
            if let Some(&i) = indices.get(k * indices.len() / 64) {
                eat(i);
            }
        }
        hash
    }

    /// The fingerprint of the mesh this BLAS was built from (see [`Blas::fingerprint_of`]).
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
    }

    /// Builds over `tris` (already checked), `mesh_triangles` being the mesh's triangle count.
    pub(crate) fn from_triangles(tris: &[BvhTriangle], mesh_triangles: usize) -> Self {
        let mut builder = BlasBuilder::Obvhs;
        let mut binary = None;
        if max_cell_population(tris) <= CROWD_LIMIT {
            let bvh = ploc(tris);
            let depth = binary_depth(&bvh);
            if depth <= MAX_BINARY_DEPTH {
                binary = Some(bvh);
            } else {
                log::warn!(
                    "BVH of {} triangles is {depth} levels deep: rebuilt with the binned builder",
                    tris.len()
                );
            }
        }
        let binary = binary.unwrap_or_else(|| {
            builder = BlasBuilder::Binned;
            binned_bvh2(tris)
        });
        let cwbvh = bvh2_to_cwbvh(&binary, MAX_LEAF, true, false);
        let triangles: Vec<BvhTriangle> = cwbvh
            .primitive_indices
            .iter()
            .map(|&p| tris[p as usize])
            .collect();
        let mut slot_of = vec![u32::MAX; mesh_triangles];
        for (slot, t) in triangles.iter().enumerate() {
            slot_of[t.triangle as usize] = slot as u32;
        }
        let bounds = triangles.iter().fold(Aabb::EMPTY, |b, t| {
            t.vertices().into_iter().fold(b, Aabb::including)
        });
        let magnitude = if bounds.is_empty() {
            0.0
        } else {
            bounds.min.abs().max(bounds.max.abs()).max_element()
        };
        let depth = wide::depth(&cwbvh.nodes) as u32;
        Self {
            nodes: cwbvh.nodes,
            triangles,
            slot_of,
            bounds,
            magnitude,
            depth,
            builder,
            fingerprint: 0,
        }
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

    /// Levels of the CWBVH, root included.
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// Which builder made its binary BVH.
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

    /// CWBVH nodes, root first (obvhs's [`CwBvhNode`] layout: `primitive_base_idx` indexes
    /// [`Blas::triangles`]).
    pub fn nodes(&self) -> &[CwBvhNode] {
        &self.nodes
    }

    /// Triangles in leaf order.
    pub fn triangles(&self) -> &[BvhTriangle] {
        &self.triangles
    }

    /// Visits every triangle the ray hits in `(t_min, *t_max)`, shrinking `*t_max` on each
    /// accepted candidate. Returns true when `on_hit` stopped the traversal.
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
        let node_ray = NodeRay::new(ray.origin, ray.direction, ray.pad(self.magnitude));
        wide::traverse(
            &self.nodes,
            &self.triangles,
            &node_ray,
            &ray.watertight,
            t_min,
            t_max,
            on_hit,
        )
    }
}

/// obvhs's binary BVH over `tris`: PLOC (medium search) and reinsertion.
fn ploc(tris: &[BvhTriangle]) -> Bvh2 {
    let input: Vec<Triangle> = tris
        .iter()
        .map(|t| {
            let [v0, v1, v2] = t.vertices().map(Vec3A::from);
            Triangle { v0, v1, v2 }
        })
        .collect();
    let mut bvh = PlocBuilder::with_capacity(input.len()).build(
        PlocSearchDistance::Medium,
        &input,
        (0..input.len() as u32).collect(),
        SortPrecision::U64,
        SEARCH_DEPTH_THRESHOLD,
    );
    ReinsertionOptimizer::default().run(&mut bvh, REINSERTION_RATIO, None);
    bvh
}

/// chiaro's binned SAH tree over `tris`, in obvhs's binary BVH type (one triangle per leaf).
fn binned_bvh2(tris: &[BvhTriangle]) -> Bvh2 {
    let boxes: Vec<Aabb> = tris
        .iter()
        .map(|t| Aabb::from_points(t.vertices()))
        .collect();
    let tree = binned::build(&boxes, 1);
    debug_assert!(tree.depth as usize <= MAX_BINARY_DEPTH, "{}", tree.depth);
    Bvh2 {
        nodes: tree
            .nodes
            .iter()
            .map(|n| {
                let aabb = ObvhsAabb::new(n.bounds.min.into(), n.bounds.max.into());
                Bvh2Node::new(aabb, n.count, n.first)
            })
            .collect(),
        primitive_indices: tree.order,
        ..Bvh2::default()
    }
}

/// Levels of a binary BVH, walked iteratively.
fn binary_depth(bvh: &Bvh2) -> usize {
    let mut deepest = 0;
    let mut stack = Vec::new();
    if !bvh.nodes.is_empty() {
        stack.push((0usize, 1usize));
    }
    while let Some((i, level)) = stack.pop() {
        deepest = deepest.max(level);
        let node = &bvh.nodes[i];
        if !node.is_leaf() {
            stack.push((node.first_index as usize, level + 1));
            stack.push((node.first_index as usize + 1, level + 1));
        }
    }
    deepest
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

    /// Every triangle is in exactly one leaf, inside that leaf's (dequantised) box.
    fn check_boxes(blas: &Blas) {
        let mut seen = vec![0; blas.triangles.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let n = &blas.nodes[i];
            for child in 0..8 {
                if n.is_child_empty(child) {
                    continue;
                }
                if !n.is_leaf(child) {
                    stack.push(n.child_node_index(child) as usize);
                    continue;
                }
                let b = n.child_aabb(child);
                let slack = 1e-6 * blas.magnitude.max(1.0);
                let (first, count) = n.child_primitives(child);
                for slot in first..first + count {
                    seen[slot as usize] += 1;
                    for v in blas.triangles[slot as usize].vertices() {
                        let v = Vec3A::from(v);
                        assert!(v.cmpge(b.min - slack).all() && v.cmple(b.max + slack).all());
                    }
                }
            }
        }
        assert!(seen.into_iter().all(|s| s == 1));
    }

    #[test]
    fn single_triangle_and_grid_meshes_build() {
        let one = mesh(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![0, 1, 2]);
        let blas = Blas::build(&one);
        assert_eq!((blas.node_count(), blas.triangle_count()), (1, 1));
        assert_eq!(blas.triangle(0), Some([Vec3::ZERO, Vec3::X, Vec3::Y]));
        assert_eq!(blas.builder(), BlasBuilder::Obvhs);
        check_boxes(&blas);

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
        // 2,000 copies of one triangle: obvhs's PLOC would take quadratic time.
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let indices = (0..2000).flat_map(|_| [0, 1, 2]).collect();
        let blas = Blas::build(&mesh(positions, indices));
        assert_eq!(blas.builder(), BlasBuilder::Binned);
        assert_eq!(blas.triangle_count(), 2000);
        check_boxes(&blas);
    }
}
