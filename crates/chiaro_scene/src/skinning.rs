//! Skinning (glTF 2.0, section 3.7.3, "Skins"): a mesh deformed by the weighted sum of its
//! joints' matrices, `inverse(world of the mesh's node) * world(joint) * inverseBindMatrix`, so
//! that, drawn under its node's world transform, each vertex lands where its joints put it.
//!
//! The importer poses every skinned mesh once at load. A skinned instance whose joints are all
//! in the World also carries a [`SkinBinding`]: its bind-pose data and weights, and its joints'
//! entities. [`skin_meshes`] then re-poses its mesh whenever the instance or one of its joints
//! moved (an animation, an edit): the mesh is rebuilt from the bind pose through
//! [`Mesh::new`]'s checks and replaces the old one in [`Meshes`] (a mesh of the instance's own),
//! so the BVH system rebuilds that BLAS and the GPU scene uploads it, and nothing else.

use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::{Mat3, Mat4, Vec4};

use crate::components::MeshInstance;
use crate::mesh::{Mesh, Meshes};
use crate::mesh_repair::MeshData;
use crate::transform::GlobalTransform;

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

/// A skinned mesh's bind pose: the mesh data as the file stores it, and its influences.
#[derive(Clone, Debug, PartialEq)]
pub struct BindPose {
    /// The mesh's name.
    pub name: String,
    /// The data before skinning.
    pub data: MeshData,
    /// One entry per vertex of `data`.
    pub influences: Influences,
}

/// A skinned instance's link to its joints (targets are node indices of a
/// [`crate::SceneBuilder`] before spawning, entities after).
#[derive(Component, Clone, Debug, PartialEq)]
pub struct SkinBinding<T: Send + Sync + 'static = Entity> {
    /// The skin's joints, in the skin's order.
    pub joints: Vec<T>,
    /// Each joint's inverse bind matrix.
    pub inverse_binds: Arc<[Mat4]>,
    /// The mesh before skinning.
    pub bind_pose: Arc<BindPose>,
}

impl<T: Send + Sync + 'static> SkinBinding<T> {
    /// The same binding with its joints mapped by `f`.
    pub fn map_joints<U: Send + Sync + 'static>(&self, f: impl FnMut(&T) -> U) -> SkinBinding<U> {
        SkinBinding {
            joints: self.joints.iter().map(f).collect(),
            inverse_binds: self.inverse_binds.clone(),
            bind_pose: self.bind_pose.clone(),
        }
    }
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

/// The joint matrices of a binding for an instance whose world matrix is `instance_world`:
/// `inverse(instance_world) * world(joint) * inverseBindMatrix`; None when one is not finite.
fn joint_matrices(
    binding: &SkinBinding,
    instance_world: Mat4,
    globals: &Query<Ref<GlobalTransform>>,
) -> Option<Vec<Mat4>> {
    let to_mesh = instance_world.inverse();
    binding
        .joints
        .iter()
        .zip(binding.inverse_binds.iter())
        .map(|(joint, inverse_bind)| {
            let world = globals.get(*joint).ok()?.matrix();
            let m = to_mesh * world * *inverse_bind;
            m.is_finite().then_some(m)
        })
        .collect()
}

/// Re-poses the mesh of every [`SkinBinding`] whose instance or joints moved since the system
/// last ran (see the module documentation). Run it after [`crate::propagate_transforms`] and
/// before the BVH system. A pose that cannot be computed (a joint's world not finite, or a mesh
/// the checks refuse) leaves the mesh as it was, with a warning.
pub fn skin_meshes(
    skins: Query<(Entity, &SkinBinding, &MeshInstance)>,
    globals: Query<Ref<GlobalTransform>>,
    meshes: Option<ResMut<Meshes>>,
) {
    let Some(mut meshes) = meshes else {
        return;
    };
    for (entity, binding, instance) in &skins {
        let Ok(world) = globals.get(entity) else {
            continue;
        };
        let moved = world.is_changed()
            || binding
                .joints
                .iter()
                .any(|j| globals.get(*j).is_ok_and(|g| g.is_changed()));
        if !moved {
            continue;
        }
        let Some(matrices) = joint_matrices(binding, world.matrix(), &globals) else {
            log::warn!(
                "{}: a joint's world transform is not finite: the skin keeps its last pose",
                binding.bind_pose.name
            );
            continue;
        };
        let mut data = binding.bind_pose.data.clone();
        let posed = skin_mesh_data(&mut data, &binding.bind_pose.influences, &matrices)
            .map_err(|e| e.to_string())
            .and_then(|()| {
                Mesh::new(binding.bind_pose.name.clone(), data).map_err(|e| e.to_string())
            });
        match posed {
            Ok((mesh, _)) => {
                if let Some(slot) = meshes.get_mut(instance.mesh) {
                    *slot = mesh;
                }
            }
            Err(why) => log::warn!(
                "{}: cannot pose the skin ({why}): it keeps its last pose",
                binding.bind_pose.name
            ),
        }
    }
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
