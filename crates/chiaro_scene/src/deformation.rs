//! Meshes that deform with the scene: skinned meshes following their joints
//! ([`crate::skinning`]) and morphed meshes following their node's weights ([`crate::morph`]).
//!
//! The importer poses every such mesh once at load. An instance that can deform carries a
//! [`DeformedMesh`]: the mesh's data before deformation (its bind pose, morph targets and skin
//! weights), its skin's joints and the node whose [`MorphWeights`] it follows.
//! [`deform_meshes`] re-poses the mesh whenever the instance or a joint moved or the weights
//! changed (an animation, an edit): morphed first, then skinned, as glTF orders them, rebuilt
//! through [`Mesh::new`]'s checks, replacing the old one in [`Meshes`] (a mesh of the
//! instance's own). The BVH system then rebuilds that one BLAS and the GPU scene uploads it,
//! and nothing else.

use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::Mat4;

use crate::components::MeshInstance;
use crate::mesh::{Mesh, Meshes};
use crate::mesh_repair::MeshData;
use crate::morph::{MorphTarget, MorphWeights, morph_mesh_data};
use crate::skinning::{Influences, skin_mesh_data};
use crate::transform::GlobalTransform;

/// A deformable mesh as the file stores it.
#[derive(Clone, Debug, PartialEq)]
pub struct BindPose {
    /// The mesh's name.
    pub name: String,
    /// The data before morphing and skinning.
    pub data: MeshData,
    /// Its morph targets (none: not morphed).
    pub targets: Vec<MorphTarget>,
    /// One entry per vertex of `data` when skinned.
    pub influences: Option<Influences>,
}

/// A skin's joints (node indices of a [`crate::SceneBuilder`] before spawning, entities after)
/// and their inverse bind matrices.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinJoints<T> {
    /// The joints, in the skin's order.
    pub joints: Vec<T>,
    /// Each joint's inverse bind matrix.
    pub inverse_binds: Arc<[Mat4]>,
}

/// What a deformable instance follows (targets are builder node indices before spawning,
/// entities after).
#[derive(Component, Clone, Debug, PartialEq)]
pub struct DeformedMesh<T: Send + Sync + 'static = Entity> {
    /// The mesh before deformation.
    pub bind_pose: Arc<BindPose>,
    /// Its skin, when skinned and every joint is in the scene.
    pub skin: Option<SkinJoints<T>>,
    /// The node whose [`MorphWeights`] it follows, when morphed.
    pub weights_from: Option<T>,
}

impl<T: Send + Sync + 'static> DeformedMesh<T> {
    /// The same with its nodes mapped by `f`.
    pub fn map_nodes<U: Send + Sync + 'static>(
        &self,
        mut f: impl FnMut(&T) -> U,
    ) -> DeformedMesh<U> {
        DeformedMesh {
            bind_pose: self.bind_pose.clone(),
            skin: self.skin.as_ref().map(|s| SkinJoints {
                joints: s.joints.iter().map(&mut f).collect(),
                inverse_binds: s.inverse_binds.clone(),
            }),
            weights_from: self.weights_from.as_ref().map(f),
        }
    }
}

/// Poses `bind_pose` with morph `weights` and skin joint `matrices`: the data to build a mesh
/// from.
pub fn posed_data(
    bind_pose: &BindPose,
    weights: Option<&[f32]>,
    matrices: Option<&[Mat4]>,
) -> Result<MeshData, String> {
    let mut data = bind_pose.data.clone();
    if let Some(weights) = weights {
        morph_mesh_data(&mut data, &bind_pose.targets, weights);
    }
    if let (Some(influences), Some(matrices)) = (&bind_pose.influences, matrices) {
        skin_mesh_data(&mut data, influences, matrices)?;
    }
    Ok(data)
}

/// The joint matrices of a skin for an instance whose world matrix is `instance_world`:
/// `inverse(instance_world) * world(joint) * inverseBindMatrix`; None when one is not finite.
fn joint_matrices(
    skin: &SkinJoints<Entity>,
    instance_world: Mat4,
    globals: &Query<Ref<GlobalTransform>>,
) -> Option<Vec<Mat4>> {
    let to_mesh = instance_world.inverse();
    skin.joints
        .iter()
        .zip(skin.inverse_binds.iter())
        .map(|(joint, inverse_bind)| {
            let world = globals.get(*joint).ok()?.matrix();
            let m = to_mesh * world * *inverse_bind;
            m.is_finite().then_some(m)
        })
        .collect()
}

/// Re-poses the mesh of every [`DeformedMesh`] whose instance or joints moved, or whose
/// weights changed, since the system last ran (see the module documentation). Run it after
/// [`crate::propagate_transforms`] and before the BVH system. A pose that cannot be computed (a
/// joint's world not finite, or a mesh the checks refuse) leaves the mesh as it was, with a
/// warning.
pub fn deform_meshes(
    deformed: Query<(Entity, &DeformedMesh, &MeshInstance)>,
    globals: Query<Ref<GlobalTransform>>,
    weights: Query<Ref<MorphWeights>>,
    meshes: Option<ResMut<Meshes>>,
) {
    let Some(mut meshes) = meshes else {
        return;
    };
    for (entity, deformation, instance) in &deformed {
        let Ok(world) = globals.get(entity) else {
            continue;
        };
        let morph = deformation
            .weights_from
            .and_then(|node| weights.get(node).ok());
        let moved = |e: &Entity| globals.get(*e).is_ok_and(|g| g.is_changed());
        let changed = morph.as_ref().is_some_and(|w| w.is_changed())
            || deformation
                .skin
                .as_ref()
                .is_some_and(|s| world.is_changed() || s.joints.iter().any(moved));
        if !changed {
            continue;
        }
        let name = &deformation.bind_pose.name;
        let matrices = match &deformation.skin {
            Some(skin) => match joint_matrices(skin, world.matrix(), &globals) {
                Some(m) => Some(m),
                None => {
                    log::warn!(
                        "{name}: a joint's world transform is not finite: the mesh keeps its last pose"
                    );
                    continue;
                }
            },
            None => None,
        };
        let posed = posed_data(
            &deformation.bind_pose,
            morph.as_ref().map(|w| w.0.as_slice()),
            matrices.as_deref(),
        )
        .and_then(|data| Mesh::new(name.clone(), data).map_err(|e| e.to_string()));
        match posed {
            Ok((mesh, _)) => {
                if let Some(slot) = meshes.get_mut(instance.mesh) {
                    *slot = mesh;
                }
            }
            Err(why) => log::warn!("{name}: cannot pose the mesh ({why}): it keeps its last pose"),
        }
    }
}
