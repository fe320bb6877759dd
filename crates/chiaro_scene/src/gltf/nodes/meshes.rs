//! A node's mesh primitives turned into mesh instances: each primitive converted once and shared,
//! except a deformable one (skinned, or with morph targets), which is posed into a mesh of its
//! instance's own (morphed by the node's weights, then skinned) and keeps its bind pose, so
//! that it can follow its joints and weights later ([`crate::deformation`]).

use std::collections::HashMap;
use std::sync::Arc;

use glam::Mat4;

use super::{NodeImporter, element};
use crate::components::MeshInstance;
use crate::deformation::{BindPose, DeformedMesh, SkinJoints};
use crate::error::{Fault, SceneError};
use crate::gltf::primitives::{Converted, convert_primitive, morph_targets};
use crate::gltf::skins::{self, Pose};
use crate::material::{Material, MaterialId};
use crate::mesh::MeshId;
use crate::morph::morph_mesh_data;
use crate::scene_builder::NodeIndex;

/// A converted primitive's mesh, with its bind pose when it can deform.
type MeshWithBindPose = (MeshId, Option<Arc<BindPose>>);

/// A mesh instance, with its mesh's bind pose when it can deform.
pub(super) type InstanceWithBindPose = (MeshInstance, Option<Arc<BindPose>>);

/// A deformable instance's node and what it follows (its skin's joints as glTF node indices).
pub(super) struct PendingDeformation {
    /// The builder node carrying the instance.
    pub node: NodeIndex,
    /// The skin: its index, joints and inverse bind matrices.
    pub skin: Option<(usize, Vec<usize>, Arc<[Mat4]>)>,
    /// The builder node holding the morph weights.
    pub weights_from: Option<NodeIndex>,
    /// The mesh before deformation.
    pub bind_pose: Arc<BindPose>,
}

impl NodeImporter<'_> {
    /// The morph weights of `node`, whose mesh is `mesh`: the node's `weights`, else the
    /// mesh's, else zeros; None when the mesh has no morph targets. A count that differs from
    /// the targets' is repaired (cut or padded with zeros), with a line naming `name`.
    pub(super) fn morph_weights(
        &mut self,
        node: &gltf::Node,
        mesh: &gltf::Mesh,
        name: &str,
    ) -> Option<Vec<f32>> {
        let targets = mesh
            .primitives()
            .map(|p| p.morph_targets().count())
            .max()
            .unwrap_or(0);
        if targets == 0 {
            return None;
        }
        let mut weights = node
            .weights()
            .or_else(|| mesh.weights())
            .map_or_else(|| vec![0.0; targets], <[f32]>::to_vec);
        if weights.len() != targets || weights.iter().any(|w| !w.is_finite()) {
            self.builder.repair(
                name.to_owned(),
                format!(
                    "has {} morph weights for {targets} morph targets: the missing or non-finite ones are 0",
                    weights.len()
                ),
            );
            weights.resize(targets, 0.0);
            for w in &mut weights {
                if !w.is_finite() {
                    *w = 0.0;
                }
            }
        }
        Some(weights)
    }

    /// One instance per drawable primitive of the mesh, converting each primitive once; with
    /// a `pose` or morph `weights`, each is posed into a mesh of this instance's own, returned
    /// with its bind pose.
    pub(super) fn instances(
        &mut self,
        mesh: &gltf::Mesh,
        pose: Option<&Pose>,
        weights: Option<&[f32]>,
    ) -> Result<Vec<InstanceWithBindPose>, SceneError> {
        let mut out = Vec::new();
        let deformed = pose.is_some() || weights.is_some();
        for primitive in mesh.primitives() {
            let key = (mesh.index(), primitive.index());
            let material = self.material(&primitive);
            let converted = match (deformed, self.meshes.get(&key)) {
                (true, _) => self.convert(mesh, &primitive, material, pose, weights)?,
                (false, Some(id)) => id.map(|id| (id, None)),
                (false, None) => {
                    let converted = self.convert(mesh, &primitive, material, None, None)?;
                    self.meshes
                        .insert(key, converted.as_ref().map(|(id, _)| *id));
                    converted
                }
            };
            if let Some((mesh, bind_pose)) = converted {
                out.push((MeshInstance { mesh, material }, bind_pose));
            }
        }
        Ok(out)
    }

    fn material(&mut self, primitive: &gltf::Primitive) -> MaterialId {
        match primitive.material().index() {
            Some(i) => MaterialId(i as u32),
            None => *self
                .default_material
                .get_or_insert_with(|| self.builder.add_material(Material::default())),
        }
    }

    fn convert(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
        material: MaterialId,
        pose: Option<&Pose>,
        weights: Option<&[f32]>,
    ) -> Result<Option<MeshWithBindPose>, SceneError> {
        let element = format!(
            "{} primitive {}",
            element("mesh", mesh.index(), mesh.name()),
            primitive.index()
        );
        let tangent_uv_set = self
            .materials
            .get(material.0 as usize)
            .and_then(Material::tangent_uv_set)
            .map(|set| set as usize);
        let mut data = match convert_primitive(&self.reader, primitive, tangent_uv_set) {
            Ok(Converted::Triangles(data)) => data,
            Ok(Converted::Skipped(why)) => {
                self.builder.repair(element, format!("skipped: {why}"));
                return Ok(None);
            }
            Err(why) => return Err(self.error(element, Fault::Accessor(why))),
        };
        let name = mesh.name().map_or_else(|| element.clone(), str::to_owned);
        let targets = match weights {
            Some(_) => morph_targets(&self.reader, primitive, data.positions.len())
                .map_err(|why| self.error(element.clone(), Fault::Accessor(why)))?,
            None => Vec::new(),
        };
        let bind = (pose.is_some() || !targets.is_empty()).then(|| data.clone());
        if let Some(weights) = weights {
            morph_mesh_data(&mut data, &targets, weights);
        }
        let mut influences = None;
        if let Some(pose) = pose {
            let (read, repairs) = skins::pose_primitive(&self.reader, primitive, pose, &mut data)
                .map_err(|why| self.error(element.clone(), Fault::Skin(why)))?;
            for repair in repairs {
                self.builder.repair(element.clone(), repair);
            }
            influences = read;
        }
        let bind_pose = bind
            .filter(|_| influences.is_some() || !targets.is_empty())
            .map(|bind| {
                Arc::new(BindPose {
                    name: name.clone(),
                    data: bind,
                    targets,
                    influences,
                })
            });
        Ok(self
            .builder
            .add_mesh(&element, &name, data)?
            .map(|id| (id, bind_pose)))
    }

    /// Binds each deformable instance to its joints' nodes and its weights' node, so that it
    /// follows them; a skin with a joint outside the imported scene keeps its load pose, with
    /// a repair line.
    pub(super) fn bind_deformations(&mut self) {
        let mut node_of: HashMap<usize, NodeIndex> = HashMap::new();
        for (index, node) in self.builder.nodes().iter().enumerate() {
            if let Some(source) = node.source_node {
                node_of.entry(source as usize).or_insert(index);
            }
        }
        for pending in std::mem::take(&mut self.pending) {
            let skin = match pending.skin {
                Some((skin, joints, inverse_binds)) => {
                    let joints: Option<Vec<NodeIndex>> =
                        joints.iter().map(|j| node_of.get(j).copied()).collect();
                    let Some(joints) = joints else {
                        // Re-posed without its skin, the mesh would lose its pose.
                        self.builder.repair(
                            element("skin", skin, None),
                            "has a joint outside the imported scene: its meshes keep their load pose",
                        );
                        continue;
                    };
                    Some(SkinJoints {
                        joints,
                        inverse_binds,
                    })
                }
                None => None,
            };
            self.builder.set_deformation(
                pending.node,
                DeformedMesh {
                    bind_pose: pending.bind_pose,
                    skin,
                    weights_from: pending.weights_from,
                },
            );
        }
    }
}
