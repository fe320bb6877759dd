//! Morph targets (glTF 2.0, section 3.7.2.2, "Morph Targets"): a mesh's vertices displaced by
//! the weighted sum of its targets' displacements. A node's weights live in its
//! [`MorphWeights`] component, which animations drive; [`crate::deformation`] re-poses the mesh
//! when they change.

use bevy_ecs::prelude::*;
use glam::{Vec3, Vec4};

use crate::mesh_repair::MeshData;

/// One morph target: per-vertex displacements of positions, normals and tangents (xyz), each
/// optional, each one per vertex of the mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    /// Position displacements.
    pub positions: Option<Vec<Vec3>>,
    /// Normal displacements.
    pub normals: Option<Vec<Vec3>>,
    /// Tangent displacements (xyz; the bitangent sign is kept).
    pub tangents: Option<Vec<Vec3>>,
}

/// A node's morph target weights, one per target of its mesh.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct MorphWeights(pub Vec<f32>);

/// Displaces `data` in place by `targets` weighted by `weights` (a missing weight counts as 0):
/// positions, normals (renormalised) and tangents (renormalised, sign kept).
pub fn morph_mesh_data(data: &mut MeshData, targets: &[MorphTarget], weights: &[f32]) {
    let used = || {
        targets
            .iter()
            .zip(weights)
            .filter(|(_, w)| **w != 0.0 && w.is_finite())
    };
    for (target, &w) in used() {
        if let Some(d) = &target.positions {
            for (p, d) in data.positions.iter_mut().zip(d) {
                *p += *d * w;
            }
        }
        if let (Some(normals), Some(d)) = (&mut data.normals, &target.normals) {
            for (n, d) in normals.iter_mut().zip(d) {
                *n += *d * w;
            }
        }
        if let (Some(tangents), Some(d)) = (&mut data.tangents, &target.tangents) {
            for (t, d) in tangents.iter_mut().zip(d) {
                *t += Vec4::from((*d * w, 0.0));
            }
        }
    }
    if used().next().is_none() {
        return;
    }
    if let Some(normals) = &mut data.normals {
        for n in normals.iter_mut() {
            *n = n.normalize_or_zero();
        }
    }
    if let Some(tangents) = &mut data.tangents {
        for t in tangents.iter_mut() {
            *t = Vec4::from((t.truncate().normalize_or_zero(), t.w));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two targets on one vertex: position (0, 0, 0) + 0.5 (2, 0, 0) + 0.25 (0, 4, 0) = (1, 1, 0);
    /// the normal (0, 0, 1) + 0.5 (1, 0, -1) = (0.5, 0, 0.5), renormalised.
    #[test]
    fn displacements_add_by_weight() {
        let mut data = MeshData {
            positions: vec![Vec3::ZERO],
            normals: Some(vec![Vec3::Z]),
            ..MeshData::default()
        };
        let targets = [
            MorphTarget {
                positions: Some(vec![Vec3::new(2.0, 0.0, 0.0)]),
                normals: Some(vec![Vec3::new(1.0, 0.0, -1.0)]),
                tangents: None,
            },
            MorphTarget {
                positions: Some(vec![Vec3::new(0.0, 4.0, 0.0)]),
                ..MorphTarget::default()
            },
        ];
        morph_mesh_data(&mut data, &targets, &[0.5, 0.25]);
        assert_eq!(data.positions[0], Vec3::new(1.0, 1.0, 0.0));
        let n = data.normals.as_ref().unwrap()[0];
        assert!(
            n.abs_diff_eq(Vec3::new(1.0, 0.0, 1.0).normalize(), 1e-6),
            "{n}"
        );
        // Zero weights change nothing, not even the normals' length.
        let mut unchanged = MeshData {
            positions: vec![Vec3::ONE],
            normals: Some(vec![Vec3::new(0.0, 0.0, 2.0)]),
            ..MeshData::default()
        };
        morph_mesh_data(&mut unchanged, &targets, &[0.0]);
        assert_eq!(unchanged.normals.unwrap()[0], Vec3::new(0.0, 0.0, 2.0));
    }
}
