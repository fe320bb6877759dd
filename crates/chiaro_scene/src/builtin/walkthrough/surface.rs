//! Parametric grid surfaces: the walkthrough's columns, sculptures, arches, floors and walls are
//! each one `p(u, v)` over the unit square, tessellated into a grid with normals and tangents
//! from the surface's own derivatives (so a normal map lines up without MikkTSpace), and
//! merged into one mesh per object.

use glam::{Vec2, Vec3, Vec4};

use crate::mesh_repair::MeshData;

/// Step of the central differences that give a surface's derivatives, in parameter units.
const DERIVATIVE_STEP: f32 = 1.0e-3;

/// A tessellation of a parametric surface.
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    /// Quads along u.
    pub nu: u32,
    /// Quads along v.
    pub nv: u32,
    /// Texture repeats over the surface along u and v.
    pub uv_scale: Vec2,
    /// False when the normal is dp/du x dp/dv, true when it is the opposite.
    pub flip: bool,
}

impl Grid {
    /// `nu` by `nv` quads, textured once over the surface, normal dp/du x dp/dv.
    pub fn new(nu: u32, nv: u32) -> Self {
        Self {
            nu,
            nv,
            uv_scale: Vec2::ONE,
            flip: false,
        }
    }

    /// The same grid with its texture repeated `scale` times along u and v.
    pub fn textured(mut self, scale: Vec2) -> Self {
        self.uv_scale = scale;
        self
    }

    /// The same grid with its normals (and winding) turned over.
    pub fn flipped(mut self) -> Self {
        self.flip = !self.flip;
        self
    }

    /// Appends the surface `p` (defined a little outside the unit square too, for the
    /// derivatives at its edges) to `data`: positions, normals, tangents, UVs and indices.
    pub fn append(&self, data: &mut MeshData, p: impl Fn(f32, f32) -> Vec3) {
        let base = data.positions.len() as u32;
        let sign = if self.flip { -1.0 } else { 1.0 };
        let (positions, normals, tangents, uvs) = parts(data);
        for j in 0..=self.nv {
            let v = j as f32 / self.nv as f32;
            for i in 0..=self.nu {
                let u = i as f32 / self.nu as f32;
                let h = DERIVATIVE_STEP;
                let du = p(u + h, v) - p(u - h, v);
                let dv = p(u, v + h) - p(u, v - h);
                let normal = (du.cross(dv) * sign).try_normalize().unwrap_or(Vec3::Y);
                let tangent = du.try_normalize().unwrap_or(Vec3::X);
                positions.push(p(u, v));
                normals.push(normal);
                tangents.push(tangent.extend(sign));
                uvs.push(Vec2::new(u, v) * self.uv_scale);
            }
        }
        let indices = data.indices.get_or_insert_with(Vec::new);
        let row = self.nu + 1;
        for j in 0..self.nv {
            for i in 0..self.nu {
                let a = base + j * row + i;
                let (b, c, d) = (a + 1, a + row + 1, a + row);
                if self.flip {
                    indices.extend([a, c, b, a, d, c]);
                } else {
                    indices.extend([a, b, c, a, c, d]);
                }
            }
        }
    }
}

/// The attribute vectors of `data` that a grid fills, created when missing.
fn parts(
    data: &mut MeshData,
) -> (
    &mut Vec<Vec3>,
    &mut Vec<Vec3>,
    &mut Vec<Vec4>,
    &mut Vec<Vec2>,
) {
    let [uv0, _] = &mut data.uvs;
    (
        &mut data.positions,
        data.normals.get_or_insert_with(Vec::new),
        data.tangents.get_or_insert_with(Vec::new),
        uv0.get_or_insert_with(Vec::new),
    )
}

/// Appends `other` to `data` (both with normals, tangents and UVs, or `data` empty): where
/// `other` lacks tangents any vector across its normals stands in (flat pieces, whose stone
/// texture is not directional).
pub fn merge(data: &mut MeshData, other: MeshData) {
    let base = data.positions.len() as u32;
    let count = other.positions.len();
    let indices: Vec<u32> = match other.indices {
        Some(i) => i,
        None => (0..count as u32).collect(),
    };
    let normals = other.normals.unwrap_or_else(|| vec![Vec3::Y; count]);
    let tangents = other.tangents.unwrap_or_else(|| {
        normals
            .iter()
            .map(|n| n.any_orthonormal_vector().extend(1.0))
            .collect()
    });
    let [uv0, _] = other.uvs;
    let uvs = uv0.unwrap_or_else(|| vec![Vec2::ZERO; count]);
    let (positions, all_normals, all_tangents, all_uvs) = parts(data);
    positions.extend(other.positions);
    all_normals.extend(normals);
    all_tangents.extend(tangents);
    all_uvs.extend(uvs);
    data.indices
        .get_or_insert_with(Vec::new)
        .extend(indices.into_iter().map(|i| base + i));
}

/// A smooth step from 0 at `edge0` to 1 at `edge1`.
pub fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Every triangle's geometric normal agrees with its vertices' normals.
    pub(in crate::builtin::walkthrough) fn normals_face_out(data: &MeshData) -> Result<(), String> {
        let normals = data.normals.as_ref().unwrap();
        for (k, tri) in data.indices.as_ref().unwrap().chunks(3).enumerate() {
            let p = [0, 1, 2].map(|k| data.positions[tri[k] as usize]);
            let face = (p[1] - p[0]).cross(p[2] - p[0]);
            for &i in tri {
                if face.dot(normals[i as usize]) <= 0.0 {
                    return Err(format!("triangle {k}: face {face} against vertex {i}"));
                }
            }
        }
        Ok(())
    }

    #[test]
    fn a_plane_gets_its_normal_tangent_and_winding() {
        let mut data = MeshData::default();
        let grid = Grid::new(3, 2).textured(Vec2::new(2.0, 1.0));
        grid.append(&mut data, |u, v| Vec3::new(u, 0.0, -v));
        assert_eq!(data.positions.len(), 12);
        assert_eq!(data.indices.as_ref().unwrap().len(), 3 * 2 * 3 * 2);
        for (n, t) in data
            .normals
            .as_ref()
            .unwrap()
            .iter()
            .zip(data.tangents.as_ref().unwrap())
        {
            assert!(n.distance(Vec3::Y) < 1e-5, "{n}");
            assert!(t.distance(Vec4::new(1.0, 0.0, 0.0, 1.0)) < 1e-5, "{t}");
        }
        assert_eq!(data.uvs[0].as_ref().unwrap()[11], Vec2::new(2.0, 1.0));
        normals_face_out(&data).unwrap();

        let mut under = MeshData::default();
        grid.flipped()
            .append(&mut under, |u, v| Vec3::new(u, 0.0, -v));
        assert!(under.normals.as_ref().unwrap()[0].distance(Vec3::NEG_Y) < 1e-5);
        assert_eq!(under.tangents.as_ref().unwrap()[0].w, -1.0);
        normals_face_out(&under).unwrap();
    }

    #[test]
    fn merging_offsets_indices_and_fills_missing_attributes() {
        let mut data = MeshData::default();
        Grid::new(1, 1).append(&mut data, |u, v| Vec3::new(u, 0.0, -v));
        merge(
            &mut data,
            crate::builtin::shapes::cuboid(Vec3::ZERO, Vec3::ONE),
        );
        let indices = data.indices.as_ref().unwrap();
        assert_eq!(indices.len(), 6 + 36);
        assert!(indices[6..].iter().all(|&i| (4..28).contains(&i)));
        assert_eq!(data.tangents.as_ref().unwrap().len(), data.positions.len());
        normals_face_out(&data).unwrap();
    }
}
