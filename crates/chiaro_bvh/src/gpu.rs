//! Flat buffers of a [`SceneBvh`] for a GPU traversal, in the same records the CPU traverses
//! (obvhs's [`CwBvhNode`], [`TlasNode`], [`BvhTriangle`]) plus one [`GpuInstance`] per instance.
//!
//! Layout of [`GpuBvhBuffers`] (each field one storage buffer):
//!
//! - `blas_nodes`: every BLAS's CWBVH nodes (80 bytes each, Ylitie et al. 2017, in obvhs's
//!   field order: `p: vec3<f32>`, `e: 3 x u8`, `imask: u8`, `child_base_idx: u32`,
//!   `primitive_base_idx: u32`, then `child_meta`, `child_min_x`, `child_max_x`, `child_min_y`,
//!   `child_max_y`, `child_min_z`, `child_max_z` as 8 x u8 each), concatenated, with
//!   `child_base_idx` and `primitive_base_idx` made global: inner children index `blas_nodes`,
//!   leaf triangles index `triangles`. In WGSL read a node as 20 `u32` words; `p` is not
//!   16-byte aligned, so it cannot be a `vec3<f32>` member of a WGSL struct.
//! - `triangles`: every BLAS's triangles, concatenated, object-space vertices, with the mesh
//!   triangle index in `triangle`.
//! - `tlas_nodes`: the TLAS, root at 0 (empty when there are no instances). An inner node's
//!   children are `tlas_nodes[child]` and `tlas_nodes[child + 1]`; a leaf
//!   (`child & TLAS_LEAF_BIT != 0`) names instance `child & !TLAS_LEAF_BIT`.
//! - `instances`: indexed like [`SceneBvh::instances`], so a GPU hit's instance index means
//!   the same as a CPU [`crate::Hit::instance`].
//!
//! A traversal that wants the CPU's guarantees (no hit the watertight test would report is
//! culled) pads its box tests as [`crate::slab`] documents: TLAS boxes by
//! `64 * 2^-23 * kappa * max|world origin|`, BLAS boxes by
//! `16 * 2^-23 * (max|object origin| + mesh_magnitude)`.
//!
//! ```wgsl
//! struct Instance {
//!     world_to_object: array<vec4<f32>, 3>, // rows of the 3x4 matrix: p' = (dot(r0, p1), ...)
//!     object_to_world: array<vec4<f32>, 3>,
//!     blas_root: u32, mesh: u32, material: u32, mesh_magnitude: f32,
//! }                                         // 112 bytes
//! ```

use bytemuck::{Pod, Zeroable};
use glam::Affine3A;

use obvhs::cwbvh::node::CwBvhNode;

use crate::layout::{BvhTriangle, TlasNode};
use crate::scene_bvh::SceneBvh;

/// One instance as the GPU reads it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuInstance {
    /// Rows of the world-to-object 3x4 matrix (translation in `w`).
    pub world_to_object: [[f32; 4]; 3],
    /// Rows of the object-to-world 3x4 matrix (translation in `w`).
    pub object_to_world: [[f32; 4]; 3],
    /// Index of the root of the instance's BLAS in [`GpuBvhBuffers::blas_nodes`].
    pub blas_root: u32,
    /// Mesh id.
    pub mesh: u32,
    /// Material id.
    pub material: u32,
    /// Largest absolute object-space coordinate of the mesh (for the BLAS pad).
    pub mesh_magnitude: f32,
}

/// Rows of a 3x4 affine matrix.
fn rows(m: &Affine3A) -> [[f32; 4]; 3] {
    let c = m.to_cols_array_2d();
    [0, 1, 2].map(|r| [c[0][r], c[1][r], c[2][r], c[3][r]])
}

/// The scene's BVHs as flat buffers (see the module documentation for the layout).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuBvhBuffers {
    /// All BLAS nodes, global indices.
    pub blas_nodes: Vec<CwBvhNode>,
    /// All BLAS triangles.
    pub triangles: Vec<BvhTriangle>,
    /// The TLAS nodes.
    pub tlas_nodes: Vec<TlasNode>,
    /// The instances.
    pub instances: Vec<GpuInstance>,
}

impl GpuBvhBuffers {
    /// Flattens `bvh`. Only BLASes of meshes that some instance uses are included.
    pub fn from_scene(bvh: &SceneBvh) -> Self {
        Self::flatten(bvh, true)
    }

    /// The BLASes [`GpuBvhBuffers::from_scene`] lays out, in order: each one's mesh and
    /// fingerprint. While it stays the same (instances only moved), so do the BLAS nodes and
    /// triangles, and [`GpuBvhBuffers::without_blases`] gives the rest.
    pub fn blas_placement(bvh: &SceneBvh) -> Vec<(u32, u64)> {
        let mut placed = vec![false; bvh.blases.len()];
        let mut order = Vec::new();
        for record in bvh.instances() {
            let mesh = record.mesh.0 as usize;
            if let (false, Some(blas)) = (placed[mesh], bvh.blas(record.mesh)) {
                placed[mesh] = true;
                order.push((record.mesh.0, blas.fingerprint()));
            }
        }
        order
    }

    /// [`GpuBvhBuffers::from_scene`] with the BLAS nodes and triangles left empty (the
    /// instances point where they would be): for a scene whose instances only moved.
    pub fn without_blases(bvh: &SceneBvh) -> Self {
        Self::flatten(bvh, false)
    }

    fn flatten(bvh: &SceneBvh, with_blases: bool) -> Self {
        let mut out = Self::default();
        let mut root_of = vec![u32::MAX; bvh.blases.len()];
        let (mut node_count, mut triangle_count) = (0u32, 0u32);
        for record in bvh.instances() {
            let mesh = record.mesh.0 as usize;
            if root_of[mesh] != u32::MAX {
                continue;
            }
            let Some(blas) = bvh.blas(record.mesh) else {
                continue;
            };
            let (node_base, triangle_base) = (node_count, triangle_count);
            root_of[mesh] = node_base;
            node_count += blas.nodes().len() as u32;
            triangle_count += blas.triangles().len() as u32;
            if with_blases {
                out.blas_nodes
                    .extend(blas.nodes().iter().map(|n| CwBvhNode {
                        child_base_idx: n.child_base_idx + node_base,
                        primitive_base_idx: n.primitive_base_idx + triangle_base,
                        ..*n
                    }));
                out.triangles.extend_from_slice(blas.triangles());
            }
        }
        out.tlas_nodes = bvh.tlas.nodes.clone();
        out.instances = bvh
            .instances()
            .iter()
            .map(|r| GpuInstance {
                world_to_object: rows(&r.inverse),
                object_to_world: rows(&r.world),
                blas_root: root_of[r.mesh.0 as usize],
                mesh: r.mesh.0,
                material: r.material.0,
                mesh_magnitude: bvh.blas(r.mesh).map_or(0.0, |b| b.magnitude),
            })
            .collect();
        out
    }

    /// Total bytes of the four buffers.
    pub fn byte_size(&self) -> usize {
        std::mem::size_of_val(self.blas_nodes.as_slice())
            + std::mem::size_of_val(self.triangles.as_slice())
            + std::mem::size_of_val(self.tlas_nodes.as_slice())
            + std::mem::size_of_val(self.instances.as_slice())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy_ecs::world::World;
    use glam::Vec3;
    use std::mem::{offset_of, size_of};

    #[test]
    fn instance_layout_is_as_documented() {
        assert_eq!(size_of::<GpuInstance>(), 112);
        assert_eq!(offset_of!(GpuInstance, object_to_world), 48);
        assert_eq!(offset_of!(GpuInstance, blas_root), 96);
        assert_eq!(offset_of!(GpuInstance, mesh_magnitude), 108);
        let m = Affine3A::from_translation(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(rows(&m)[1], [0.0, 1.0, 0.0, 2.0]);
    }

    #[test]
    fn flattened_indices_point_into_the_global_buffers() {
        let mut world = World::new();
        chiaro_scene::load_scene(&mut world, "builtin:hard-cases").unwrap();
        let bvh = SceneBvh::build(&mut world);
        let gpu = GpuBvhBuffers::from_scene(&bvh);
        assert_eq!(gpu.instances.len(), bvh.instances().len());
        assert_eq!(gpu.tlas_nodes.len(), 2 * gpu.instances.len() - 1);
        let bytes: &[u8] = bytemuck::cast_slice(&gpu.blas_nodes);
        assert_eq!(bytes.len(), 80 * gpu.blas_nodes.len());
        for inst in &gpu.instances {
            // Walk the instance's BLAS and check every triangle matches the CPU's.
            let blas = bvh.blas(chiaro_scene::MeshId(inst.mesh)).unwrap();
            let mut seen = 0;
            let mut stack = vec![inst.blas_root as usize];
            while let Some(i) = stack.pop() {
                let n = gpu.blas_nodes[i];
                for child in (0..8).filter(|&c| !n.is_child_empty(c)) {
                    if n.is_leaf(child) {
                        let (first, count) = n.child_primitives(child);
                        for t in &gpu.triangles[first as usize..][..count as usize] {
                            assert_eq!(Some(t.vertices()), blas.triangle(t.triangle));
                            seen += 1;
                        }
                    } else {
                        stack.push(n.child_node_index(child) as usize);
                    }
                }
            }
            assert_eq!(seen, blas.triangle_count());
        }
    }
}
