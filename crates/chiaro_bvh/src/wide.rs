//! Robust traversal of obvhs's compressed wide BVH (CWBVH: Ylitie, Karras and Laine, "Efficient
//! Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", High Performance Graphics
//! 2017): eight children per 80-byte [`CwBvhNode`], child boxes quantised to 8 bits on a
//! power-of-two grid anchored at the node's `p`.
//!
//! The traversal order (octant-sorted child slots, groups of children and of triangles kept as
//! bit masks on a stack) follows the paper and obvhs. The child box test is chiaro's own, because
//! obvhs's `CwBvhNode::intersect_ray` is not conservative: it clamps `1/d` to `1/f32::EPSILON`
//! and every entry distance to `t >= 1e-4` (measured: 80% of axis-parallel rays from 1e5 units
//! away lose their hit). Here each plane distance is `(e * q - (o - p)) / d`:
//!
//! - `e * q` is exact (a power of two times an integer up to 255) and `o - p` is rounded once,
//!   so the distance is off by a few ulps of `|o| + |p| + node extent`, which the box pad of
//!   [`crate::slab`] (16 ulps of `|o| + largest mesh coordinate`) covers, as it covers
//!   obvhs's quantisation (boxes rounded outwards, up to an ulp of the node's extent);
//! - the exit distance gets Ize's `1 + 2 gamma(3)` factor;
//! - a zero direction component gives an infinite reciprocal, and NaN only where the padded
//!   origin lies exactly on a plane; such NaNs are replaced by the value that keeps the ray in
//!   the slab.

use arrayvec::ArrayVec;
use glam::{UVec2, Vec3, Vec3A, Vec4, uvec2};
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};

use crate::blas::Candidate;
use crate::layout::BvhTriangle;
use crate::watertight::{TriangleHit, WatertightRay};

/// `2 gamma(3)`, as in [`crate::slab`].
const TWO_GAMMA3: f32 = 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Traversal stack entries: at most one per level, and BLASes deeper than this are rebuilt.
pub(crate) const STACK_SIZE: usize = 128;

/// A ray prepared for the child-box tests of one BLAS.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NodeRay {
    /// Origin moved by +pad (for the lower planes) and -pad (for the upper planes).
    origin_lo: Vec3A,
    origin_hi: Vec3A,
    inv_direction: Vec3A,
    zero_component: bool,
    /// Octant of the direction, for the child ordering.
    oct_inv4: u32,
}

impl NodeRay {
    /// Prepares `origin + t * direction` (finite, non-zero direction) with box pad `pad`.
    pub fn new(origin: Vec3, direction: Vec3, pad: f32) -> Self {
        let d = Vec3A::from(direction) + Vec3A::ZERO; // -0 becomes +0: its reciprocal is +inf
        let o = Vec3A::from(origin);
        let oct_inv4 = (if d.x < 0.0 { 0 } else { 0x0404_0404 })
            | (if d.y < 0.0 { 0 } else { 0x0202_0202 })
            | (if d.z < 0.0 { 0 } else { 0x0101_0101 });
        Self {
            origin_lo: o + Vec3A::splat(pad),
            origin_hi: o - Vec3A::splat(pad),
            inv_direction: Vec3A::ONE / d,
            zero_component: d.cmpeq(Vec3A::ZERO).any(),
            oct_inv4,
        }
    }
}

#[inline(always)]
fn quads(q: &[u8; 8]) -> [Vec4; 2] {
    [
        Vec4::new(
            f32::from(q[0]),
            f32::from(q[1]),
            f32::from(q[2]),
            f32::from(q[3]),
        ),
        Vec4::new(
            f32::from(q[4]),
            f32::from(q[5]),
            f32::from(q[6]),
            f32::from(q[7]),
        ),
    ]
}

/// The hit mask of `node`'s children for `ray` over `[t_min, t_max]`, in the bit layout of
/// obvhs's `CwBvhNode::intersect_ray` (inner children in the top byte by traversal priority,
/// leaf triangles in the low 24 bits).
#[inline(always)]
pub(crate) fn intersect_node(node: &CwBvhNode, ray: &NodeRay, t_min: f32, t_max: f32) -> u32 {
    let e = node.compute_extent();
    let p = Vec3A::from(node.p);
    // Plane distance: (p + e q - o) / d = (e q - (o - p)) * inv.
    let c_lo = ray.origin_lo - p;
    let c_hi = ray.origin_hi - p;
    let (q_lo, q_hi) = (
        [
            quads(&node.child_min_x),
            quads(&node.child_min_y),
            quads(&node.child_min_z),
        ],
        [
            quads(&node.child_max_x),
            quads(&node.child_max_y),
            quads(&node.child_max_z),
        ],
    );
    let mut hit = 0u32;
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(ray.oct_inv4);
    for half in 0..2 {
        let mut near = Vec4::splat(t_min);
        let mut far = Vec4::INFINITY;
        for axis in 0..3 {
            let inv = Vec4::splat(ray.inv_direction[axis]);
            let ea = Vec4::splat(e[axis]);
            let mut t_lo = (q_lo[axis][half] * ea - Vec4::splat(c_lo[axis])) * inv;
            let mut t_hi = (q_hi[axis][half] * ea - Vec4::splat(c_hi[axis])) * inv;
            if ray.zero_component {
                t_lo = Vec4::select(t_lo.is_nan_mask(), Vec4::NEG_INFINITY, t_lo);
                t_hi = Vec4::select(t_hi.is_nan_mask(), Vec4::INFINITY, t_hi);
            }
            near = near.max(t_lo.min(t_hi));
            far = far.min(t_lo.max(t_hi));
        }
        let far =
            (far * (Vec4::ONE + Vec4::splat(TWO_GAMMA3).copysign(far))).min(Vec4::splat(t_max));
        let mask = near.cmple(far).bitmask();
        for j in 0..4 {
            if mask & (1 << j) != 0 {
                let child = half * 4 + j;
                hit |= extract_byte64(child_bits8, child) << extract_byte64(bit_index8, child);
            }
        }
    }
    hit
}

/// Visits every triangle of a CWBVH the ray hits in `(t_min, *t_max)`, shrinking `*t_max` on
/// each accepted candidate; returns true when `on_hit` stopped it. `triangles` are in the
/// CWBVH's primitive order.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn traverse<F>(
    nodes: &[CwBvhNode],
    triangles: &[BvhTriangle],
    node_ray: &NodeRay,
    watertight: &WatertightRay,
    t_min: f32,
    t_max: &mut f32,
    on_hit: &mut F,
) -> bool
where
    F: FnMut(u32, TriangleHit) -> Candidate,
{
    if nodes.is_empty() {
        return false;
    }
    // Not zero-filled per ray, unlike an array: this runs once per instance a ray visits.
    let mut stack = ArrayVec::<UVec2, STACK_SIZE>::new();
    // The root, as the only inner child of a virtual parent.
    let mut group = uvec2(0, 0x8000_0000);
    let mut triangle_group = UVec2::ZERO;
    loop {
        while triangle_group.y != 0 {
            let local = 31 - triangle_group.y.leading_zeros();
            triangle_group.y &= !(1 << local);
            let tri = &triangles[(triangle_group.x + local) as usize];
            let [v0, v1, v2] = tri.vertices();
            if let Some(hit) = watertight.intersect(v0, v1, v2, t_min, *t_max) {
                match on_hit(tri.triangle, hit) {
                    Candidate::Reject => {}
                    Candidate::Accept => *t_max = hit.t,
                    Candidate::Stop => return true,
                }
            }
        }
        if group.y & 0xff00_0000 != 0 {
            let hits = group.y;
            let slot_bit = 31 - hits.leading_zeros();
            group.y &= !(1 << slot_bit);
            if group.y & 0xff00_0000 != 0 {
                stack.push(group);
            }
            // Child slot from its priority bit, then its rank among the inner children.
            let slot = (slot_bit - 24) ^ (node_ray.oct_inv4 & 0xff);
            let rank = (hits & !(u32::MAX << slot)).count_ones();
            let node = &nodes[(group.x + rank) as usize];
            let mask = intersect_node(node, node_ray, t_min, *t_max);
            group = uvec2(
                node.child_base_idx,
                (mask & 0xff00_0000) | u32::from(node.imask),
            );
            triangle_group = uvec2(node.primitive_base_idx, mask & 0x00ff_ffff);
        } else {
            group = UVec2::ZERO;
        }
        if triangle_group.y == 0 && group.y & 0xff00_0000 == 0 {
            let Some(next) = stack.pop() else {
                return false;
            };
            group = next;
        }
    }
}

/// Levels of a CWBVH (0 when empty).
pub(crate) fn depth(nodes: &[CwBvhNode]) -> usize {
    if nodes.is_empty() {
        return 0;
    }
    let mut deepest = 0;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((i, level)) = stack.pop() {
        deepest = deepest.max(level);
        let node = &nodes[i];
        for child in 0..8 {
            if node.imask & (1 << child) != 0 {
                stack.push((node.child_node_index(child) as usize, level + 1));
            }
        }
    }
    deepest
}
