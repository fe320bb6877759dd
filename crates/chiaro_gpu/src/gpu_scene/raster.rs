//! The G-buffer's vertex and index lists: indexed draws in which every triangle starts at a
//! vertex of its own.
//!
//! The G-buffer's fragments need their triangle's face (the geometric normal). A fragment takes
//! flat attributes from its triangle's first (provoking) vertex, so if no two triangles share a
//! first vertex, that vertex can carry its triangle's face. The lists here make it so: each
//! triangle's corners are rotated (which keeps its winding) so that it starts at a corner no
//! earlier triangle started at, and where all three are taken, at a copy of its first corner.
//! The other corners reuse any raster vertex of their scene vertex.
//!
//! A closed mesh has about twice as many triangles as vertices, so about one raster vertex per
//! triangle: a third of the vertex invocations of drawing three vertices per triangle, with no
//! need for the primitive index (an optional feature, and costly where the driver must then
//! assemble primitives one by one, as lavapipe's does), and no fragment reading its triangle's
//! corners.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::layout::{GpuMesh, GpuVertex};

/// A vertex of the G-buffer's vertex buffer (the draws' index list points here): its scene
/// vertex's attributes, and the face and number of the triangle that starts at it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct RasterVertex {
    /// The scene vertex's attributes.
    pub vertex: GpuVertex,
    /// The front side of the triangle that starts at this vertex, in object space and not unit:
    /// the cross product of its edges from its first corner, (p1 - p0) x (p2 - p0). Zero where
    /// no triangle starts.
    pub face: [f32; 3],
    /// The number, in its mesh, of the triangle that starts at this vertex (zero where none
    /// does): the G-buffer keeps it, so a pass can find the surface's UVs again.
    pub triangle: u32,
}

/// The raster lists for the scene's index list `indices` (global vertex indices, `vertex_count`
/// vertices) and mesh table `meshes`: the scene vertex of each raster vertex, and the raster
/// index list. The index list is parallel to `indices`: triangle t of mesh m is at
/// `meshes[m].index_base + 3 t`, its corners the same cycle of scene vertices, its first raster
/// vertex its own.
pub fn raster_lists(
    indices: &[u32],
    vertex_count: usize,
    meshes: &[GpuMesh],
) -> (Vec<u32>, Vec<u32>) {
    /// No raster vertex yet.
    const NONE: u32 = u32::MAX;
    let mut vertices: Vec<u32> = Vec::with_capacity(indices.len() / 3 + vertex_count);
    let mut raster_indices = vec![0; indices.len()];
    // Per scene vertex: its first raster vertex, and whether a triangle starts at it.
    let mut first = vec![NONE; vertex_count];
    let mut started = vec![false; vertex_count];
    for mesh in meshes {
        for t in 0..mesh.triangle_count {
            let at = (mesh.index_base + 3 * t) as usize;
            let corners = [indices[at], indices[at + 1], indices[at + 2]];
            let free = corners.iter().position(|&v| !started[v as usize]);
            let k = free.unwrap_or(0);
            for j in 0..3 {
                let v = corners[(k + j) % 3];
                let slot = v as usize;
                let starts = j == 0;
                raster_indices[at + j] = if starts && free.is_none() {
                    // Every corner starts a triangle already: a copy of this one.
                    push(&mut vertices, v)
                } else {
                    if first[slot] == NONE {
                        first[slot] = push(&mut vertices, v);
                    }
                    started[slot] |= starts;
                    first[slot]
                };
            }
        }
    }
    (vertices, raster_indices)
}

/// The G-buffer's vertex buffer for the raster lists `(raster, raster_indices)` of
/// [`raster_lists`] over `indices`, `meshes` and the scene vertices `vertices`.
pub fn raster_vertices(
    (raster, raster_indices): (&[u32], &[u32]),
    indices: &[u32],
    meshes: &[GpuMesh],
    vertices: &[GpuVertex],
) -> Vec<RasterVertex> {
    let mut out: Vec<RasterVertex> = raster
        .iter()
        .map(|&v| RasterVertex {
            vertex: vertices[v as usize],
            ..RasterVertex::default()
        })
        .collect();
    let position = |i: u32| Vec3::from(vertices[i as usize].position);
    for mesh in meshes {
        for t in 0..mesh.triangle_count {
            let at = (mesh.index_base + 3 * t) as usize;
            let [p0, p1, p2] = [at, at + 1, at + 2].map(|k| position(indices[k]));
            let first = &mut out[raster_indices[at] as usize];
            first.face = (p1 - p0).cross(p2 - p0).to_array();
            first.triangle = t;
        }
    }
    out
}

/// Appends a raster vertex of scene vertex `vertex`; returns its index.
fn push(vertices: &mut Vec<u32>, vertex: u32) -> u32 {
    vertices.push(vertex);
    (vertices.len() - 1) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks the lists' promise for `indices` and `meshes`; returns the raster vertex count.
    fn check(indices: &[u32], vertex_count: usize, meshes: &[GpuMesh]) -> usize {
        let (vertices, raster) = raster_lists(indices, vertex_count, meshes);
        assert_eq!(raster.len(), indices.len());
        let mut starts = vec![None; vertices.len()];
        for (m, mesh) in meshes.iter().enumerate() {
            for t in 0..mesh.triangle_count {
                let at = (mesh.index_base + 3 * t) as usize;
                let scene = [indices[at], indices[at + 1], indices[at + 2]];
                let drawn: Vec<u32> = raster[at..at + 3]
                    .iter()
                    .map(|&r| vertices[r as usize])
                    .collect();
                let rotation = (0..3).find(|&k| (0..3).all(|j| drawn[j] == scene[(k + j) % 3]));
                assert!(
                    rotation.is_some(),
                    "mesh {m} triangle {t}: {drawn:?} is not a rotation of {scene:?}"
                );
                let provoking = raster[at] as usize;
                assert_eq!(
                    starts[provoking], None,
                    "two triangles start at raster vertex {provoking}"
                );
                starts[provoking] = Some((m, t));
            }
        }
        vertices.len()
    }

    fn mesh(index_base: u32, triangle_count: u32) -> GpuMesh {
        GpuMesh {
            index_base,
            triangle_count,
            ..GpuMesh::default()
        }
    }

    #[test]
    fn a_closed_grid_starts_each_triangle_at_its_own_vertex() {
        // A torus of n x n quads: 2 n^2 triangles over n^2 vertices, every vertex in six.
        let n = 12u32;
        let at = |i: u32, j: u32| (i % n) * n + (j % n);
        let mut indices = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                indices.extend([a, b, c, a, c, d]);
            }
        }
        let triangles = 2 * n * n;
        let count = check(&indices, (n * n) as usize, &[mesh(0, triangles)]);
        // At least one per triangle; the greedy choice stays within a few copies of that.
        assert!(count >= triangles as usize);
        assert!(
            count <= triangles as usize + (n * n / 4) as usize,
            "{count} raster vertices"
        );
    }

    #[test]
    fn meshes_keep_their_own_triangle_numbers() {
        // Two meshes, the second's vertices after the first's; its last triangle's three
        // corners already start triangles, so it starts at a copy.
        let indices = [0, 1, 2, 2, 1, 3, 4, 5, 6, 5, 7, 6, 6, 5, 4, 4, 6, 5];
        let meshes = [mesh(0, 2), mesh(6, 4)];
        let count = check(&indices, 8, &meshes);
        assert_eq!(count, 8 + 1);
    }

    #[test]
    fn each_triangle_starts_at_a_vertex_carrying_its_face_and_number() {
        // A unit square in the plane z = 0 as two triangles sharing the diagonal, the first
        // facing +z, the second -z.
        let vertices = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ]
        .map(|position| GpuVertex {
            position,
            u0: position[0],
            ..GpuVertex::default()
        });
        let indices = [0, 1, 2, 0, 3, 2];
        let meshes = [mesh(0, 2)];
        let (scene, raster) = raster_lists(&indices, vertices.len(), &meshes);
        let drawn = raster_vertices((&scene, &raster), &indices, &meshes, &vertices);
        assert_eq!(drawn[raster[0] as usize].face, [0.0, 0.0, 1.0]);
        assert_eq!(drawn[raster[3] as usize].face, [0.0, 0.0, -1.0]);
        assert_eq!(drawn[raster[0] as usize].triangle, 0);
        assert_eq!(drawn[raster[3] as usize].triangle, 1);
        for (r, &v) in drawn.iter().zip(&scene) {
            assert_eq!(r.vertex, vertices[v as usize]);
        }
    }

    #[test]
    fn no_triangles_no_raster_vertices() {
        assert_eq!(
            raster_lists(&[], 3, &[mesh(0, 0)]),
            (Vec::new(), Vec::new())
        );
    }
}
