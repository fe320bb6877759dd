//! Tangent generation with MikkTSpace (the bevy_mikktspace port), the tangent space normal maps
//! are baked in. MikkTSpace works per triangle corner, so the mesh is unwelded, given tangents,
//! and welded again where every attribute of two corners is bit-identical.
//!
//! glTF's normal textures are "+X right, +Y up" in the image, and glTF's V runs down the image:
//! the bitangent points toward decreasing V. MikkTSpace's points toward increasing V, so it is
//! given V negated; an upright texture on an unmirrored surface then has W = +1, as in the
//! tangents Blender writes and as the Khronos sample viewer derives them
//! (bitangent = cross(normal, tangent)).

use std::collections::HashMap;

use glam::{Vec2, Vec3, Vec4};

use crate::mesh::Mesh;

struct Corners<'a> {
    mesh: &'a Mesh,
    uv_set: usize,
    tangents: Vec<Vec4>,
}

impl bevy_mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.triangle_count()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.vertex(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.vertex(face, vert)].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uvs()[self.vertex(face, vert)];
        [uv.x, -uv.y]
    }

    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(space) = tangent_space {
            self.tangents[face * 3 + vert] = Vec4::from_array(space.tangent_encoded());
        }
    }
}

impl Corners<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.mesh.indices[face * 3 + vert] as usize
    }

    fn uvs(&self) -> &[Vec2] {
        self.mesh.uvs[self.uv_set].as_deref().unwrap_or_default()
    }
}

/// A unit tangent perpendicular to `normal`, for corners MikkTSpace leaves without one.
fn any_tangent(normal: Vec3) -> Vec4 {
    normal.any_orthonormal_vector().extend(1.0)
}

/// Replaces the mesh's tangents with MikkTSpace tangents for UV set `uv_set`, which must exist.
pub(crate) fn generate_tangents(mesh: &mut Mesh, uv_set: usize) {
    let mut corners = Corners {
        mesh,
        uv_set,
        tangents: vec![Vec4::ZERO; mesh.indices.len()],
    };
    // The error type has no variants: generation cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut corners);
    let corner_tangents = corners.tangents;

    let old_indices = std::mem::take(&mut mesh.indices);
    let mut welded: HashMap<(u32, [u32; 4]), u32> = HashMap::new();
    let mut remap_source = Vec::new();
    let mut tangents = Vec::new();
    for (corner, &vertex) in old_indices.iter().enumerate() {
        let mut tangent = corner_tangents[corner];
        if !tangent.is_finite() || tangent.truncate().length_squared() < 1e-24 {
            tangent = any_tangent(mesh.normals[vertex as usize]);
        }
        let key = (vertex, tangent.to_array().map(f32::to_bits));
        let index = *welded.entry(key).or_insert_with(|| {
            remap_source.push(vertex as usize);
            tangents.push(tangent);
            tangents.len() as u32 - 1
        });
        mesh.indices.push(index);
    }
    let gather3 = |v: &[Vec3]| remap_source.iter().map(|&i| v[i]).collect::<Vec<_>>();
    let gather2 = |v: &[Vec2]| remap_source.iter().map(|&i| v[i]).collect::<Vec<_>>();
    mesh.positions = gather3(&mesh.positions);
    mesh.normals = gather3(&mesh.normals);
    mesh.uvs = [
        mesh.uvs[0].as_deref().map(gather2),
        mesh.uvs[1].as_deref().map(gather2),
    ];
    mesh.tangents = Some(tangents);
}

#[cfg(test)]
mod tests {
    use crate::mesh::Mesh;
    use crate::mesh_repair::MeshData;
    use glam::{Vec2, Vec3};

    /// A unit quad in the XY plane facing +Z with the texture upright (glTF's V down, so V
    /// grows toward -Y): tangent +X, bitangent cross(Z, X) = +Y, the image's up.
    #[test]
    fn upright_texture_gets_tangents_along_u_and_bitangents_up_the_image() {
        let data = MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            normals: Some(vec![Vec3::Z; 4]),
            uvs: [Some(vec![Vec2::Y, Vec2::ONE, Vec2::X, Vec2::ZERO]), None],
            indices: Some(vec![0, 1, 2, 0, 2, 3]),
            tangent_uv_set: Some(0),
            ..Default::default()
        };
        let (mesh, repairs) = Mesh::new("quad", data).unwrap();
        assert!(repairs.is_empty());
        // Shared corners with equal tangents weld back: still four vertices.
        assert_eq!(mesh.positions().len(), 4);
        for t in mesh.tangents().unwrap() {
            assert!(t.truncate().abs_diff_eq(Vec3::X, 1e-5), "{t}");
            assert_eq!(t.w, 1.0);
        }
    }

    /// V growing toward +Y shows the image upside down: the bitangent (toward decreasing V) is
    /// -Y, so W = -1.
    #[test]
    fn a_vertically_mirrored_texture_flips_the_bitangent_sign() {
        let data = MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: Some(vec![Vec3::Z; 3]),
            uvs: [Some(vec![Vec2::ZERO, Vec2::X, Vec2::Y]), None],
            tangent_uv_set: Some(0),
            ..Default::default()
        };
        let (mesh, _) = Mesh::new("tri", data).unwrap();
        assert!(mesh.tangents().unwrap().iter().all(|t| t.w == -1.0));
    }
}
