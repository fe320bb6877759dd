//! The flat node and triangle records the BVHs are made of. They are `#[repr(C)]`, `Pod` and
//! free of implicit padding, and the CPU traverses exactly these records, so the GPU copy made by
//! [`crate::GpuBvhBuffers`] is the same bytes with indices offset, not a translation.
//!
//! BLAS nodes are obvhs's `CwBvhNode` (see [`crate::gpu`]). The two records here are 16-byte
//! aligned so that a WGSL struct of `vec3<f32>` + `u32` pairs mirrors them field for field:
//!
//! ```wgsl
//! struct TlasNode { min: vec3<f32>, child: u32, max: vec3<f32>, kappa: f32 }    // 32 bytes
//! struct Triangle { v0: vec3<f32>, triangle: u32, v1: vec3<f32>, pad0: u32,
//!                   v2: vec3<f32>, pad1: u32 }                                  // 48 bytes
//! ```

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A};

/// Set in [`TlasNode::child`] when the node is a leaf; the low bits are then the instance index.
pub const TLAS_LEAF_BIT: u32 = 1 << 31;

/// A node of the top-level BVH (a binary tree over instances, one instance per leaf).
///
/// `child` is either the index of the first of two adjacent child nodes (`child + 1` is the
/// second), or, with [`TLAS_LEAF_BIT`] set, the instance index. The box is the instance's world
/// box grown by its static pad (see [`crate::slab`]); `kappa` is the largest condition number
/// of an instance matrix below this node, which scales the per-ray pad
/// (`TLAS_PAD_ULPS * f32::EPSILON * kappa * largest |origin coordinate|`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct TlasNode {
    /// Box minimum corner.
    pub min: [f32; 3],
    /// First child node, or instance index with [`TLAS_LEAF_BIT`].
    pub child: u32,
    /// Box maximum corner.
    pub max: [f32; 3],
    /// Largest instance-matrix condition number below this node (>= 1).
    pub kappa: f32,
}

impl TlasNode {
    /// The instance of a leaf, `None` for an inner node.
    #[inline(always)]
    pub fn instance(&self) -> Option<u32> {
        (self.child & TLAS_LEAF_BIT != 0).then_some(self.child & !TLAS_LEAF_BIT)
    }

    #[inline(always)]
    pub(crate) fn lo(&self) -> Vec3A {
        Vec3A::from_array(self.min)
    }

    #[inline(always)]
    pub(crate) fn hi(&self) -> Vec3A {
        Vec3A::from_array(self.max)
    }
}

/// One triangle of a bottom-level BVH, stored in leaf order with its object-space vertices in
/// the mesh's order (so the winding, and the barycentrics, match the mesh).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct BvhTriangle {
    /// Vertex 0.
    pub v0: [f32; 3],
    /// Index of the triangle in its mesh's triangle list.
    pub triangle: u32,
    /// Vertex 1.
    pub v1: [f32; 3],
    /// Padding, zero.
    pub pad0: u32,
    /// Vertex 2.
    pub v2: [f32; 3],
    /// Padding, zero.
    pub pad1: u32,
}

impl BvhTriangle {
    /// A triangle record.
    pub fn new(vertices: [Vec3; 3], triangle: u32) -> Self {
        Self {
            v0: vertices[0].to_array(),
            triangle,
            v1: vertices[1].to_array(),
            pad0: 0,
            v2: vertices[2].to_array(),
            pad1: 0,
        }
    }

    /// The three vertices.
    #[inline(always)]
    pub fn vertices(&self) -> [Vec3; 3] {
        [
            Vec3::from_array(self.v0),
            Vec3::from_array(self.v1),
            Vec3::from_array(self.v2),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{align_of, offset_of, size_of};

    #[test]
    fn layouts_are_as_documented() {
        assert_eq!((size_of::<TlasNode>(), align_of::<TlasNode>()), (32, 16));
        assert_eq!(offset_of!(TlasNode, kappa), 28);
        assert_eq!(
            (size_of::<BvhTriangle>(), align_of::<BvhTriangle>()),
            (48, 16)
        );
        assert_eq!(offset_of!(BvhTriangle, v1), 16);
        assert_eq!(offset_of!(BvhTriangle, v2), 32);
    }

    #[test]
    fn tlas_leaf_bit_round_trips() {
        let leaf = TlasNode {
            child: 7 | TLAS_LEAF_BIT,
            ..TlasNode::default()
        };
        assert_eq!(leaf.instance(), Some(7));
        assert_eq!(TlasNode::default().instance(), None);
    }
}
