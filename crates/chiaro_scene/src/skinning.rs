//! Skinning's arithmetic (glTF 2.0, section 3.7.3, "Skins"): a vertex moved by the weighted sum
//! of its joints' matrices, `inverse(world of the mesh's node) * world(joint) *
//! inverseBindMatrix`. [`crate::deformation`] applies it whenever joints move.

use glam::{Mat3, Mat4, Vec4};

use crate::mesh_repair::MeshData;

/// Most joints one vertex follows (glTF's JOINTS_0/WEIGHTS_0 and JOINTS_1/WEIGHTS_1).
pub const MAX_INFLUENCES: usize = 8;

/// Each vertex's joints and weights: the weights normalised to sum to 1, unused slots weight 0.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Influences {
    /// Per vertex, the joints' indices in the skin.
    pub joints: Vec<[u16; MAX_INFLUENCES]>,
    /// Per vertex, the weights of those joints.
    pub weights: Vec<[f32; MAX_INFLUENCES]>,
}

/// The matrix that takes normals through `m`'s linear part: its cofactor matrix (the inverse
/// transpose times the determinant, finite even where `m` is singular), negated for a mirror
/// so that normals keep their side.
pub(crate) fn normal_matrix(m: &Mat3) -> Mat3 {
    let cofactor = Mat3::from_cols(
        m.y_axis.cross(m.z_axis),
        m.z_axis.cross(m.x_axis),
        m.x_axis.cross(m.y_axis),
    );
    if m.determinant() < 0.0 {
        -cofactor
    } else {
        cofactor
    }
}

/// Skins `data` in place by the joint `matrices`: positions, normals and tangents (a mirror
/// flips the tangent's bitangent sign). An error names a vertex whose joint the matrices lack.
pub fn skin_mesh_data(
    data: &mut MeshData,
    influences: &Influences,
    matrices: &[Mat4],
) -> Result<(), String> {
    for (v, (joints, weights)) in influences
        .joints
        .iter()
        .zip(&influences.weights)
        .enumerate()
    {
        let mut m = Mat4::ZERO;
        for (&joint, &weight) in joints.iter().zip(weights) {
            if weight == 0.0 {
                continue;
            }
            let matrix = matrices.get(usize::from(joint)).ok_or_else(|| {
                format!(
                    "vertex {v} names joint {joint}, but the skin has {} joints",
                    matrices.len()
                )
            })?;
            m += *matrix * weight;
        }
        let linear = Mat3::from_mat4(m);
        if let Some(p) = data.positions.get_mut(v) {
            *p = m.transform_point3(*p);
        }
        if let Some(normals) = &mut data.normals
            && let Some(n) = normals.get_mut(v)
        {
            *n = (normal_matrix(&linear) * *n).normalize_or_zero();
        }
        if let Some(tangents) = &mut data.tangents
            && let Some(t) = tangents.get_mut(v)
        {
            let xyz = (linear * t.truncate()).normalize_or_zero();
            let sign = if linear.determinant() < 0.0 {
                -t.w
            } else {
                t.w
            };
            *t = Vec4::from((xyz, sign));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    #[test]
    fn normals_keep_their_side_through_scales_and_mirrors() {
        let squash = Mat3::from_diagonal(Vec3::new(2.0, 1.0, 1.0));
        let n = (normal_matrix(&squash) * Vec3::new(1.0, 1.0, 0.0)).normalize();
        // The plane x + y = 0 stretched along x has the normal (1, 2, 0) / sqrt(5).
        assert!(
            n.abs_diff_eq(Vec3::new(1.0, 2.0, 0.0).normalize(), 1e-6),
            "{n}"
        );
        let mirror = Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
        assert_eq!(normal_matrix(&mirror) * Vec3::Z, Vec3::Z);
        assert!(normal_matrix(&Mat3::ZERO).is_finite());
    }
}
