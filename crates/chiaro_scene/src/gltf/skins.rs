//! glTF skins, posed once at load (glTF 2.0, section 3.7.3 "Skins"). A mesh instance whose node
//! has a skin gets a mesh of its own: each vertex moved by the weighted sum of its joints'
//! matrices, `inverse(world of the mesh node) * world(joint) * inverseBindMatrix(joint)`, so
//! that, drawn under the mesh node's world transform, it lands where the joints put it: the
//! mesh node's own transform is thereby ignored, as the specification requires. The pose at
//! load is the one the nodes' transforms describe; the bind pose is kept, so that an instance
//! whose joints are all in the scene is re-posed as they move ([`crate::skinning`]). Every joint
//! index, weight, accessor count and matrix is checked; a fault is an error naming the skin or
//! the primitive.

use glam::{Mat4, Quat, Vec3};
use gltf::mesh::Semantic;

use crate::gltf::accessor::{AccessorReader, Formats};
use crate::mesh_repair::MeshData;
use crate::skinning::{Influences, MAX_INFLUENCES, skin_mesh_data};

/// JOINTS_n / WEIGHTS_n sets read: 0 and 1 (up to eight influences a vertex).
const INFLUENCE_SETS: u32 = 2;

/// How far a vertex's weights may sum from 1 before they are normalised with a repair line
/// (8-bit normalized weights alone can miss 1 by a few 1/255).
const WEIGHT_SUM_TOLERANCE: f64 = 0.02;

/// A node's local matrix as the importer reads it (a rotation normalised; one without a
/// direction is the identity).
fn local_matrix(node: &gltf::Node) -> Mat4 {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => Mat4::from_cols_array_2d(&matrix),
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let q = Quat::from_array(rotation);
            let q = if q.length() < 1e-6 {
                Quat::IDENTITY
            } else {
                q.normalize()
            };
            Mat4::from_scale_rotation_translation(Vec3::from(scale), q, Vec3::from(translation))
        }
    }
}

/// The world matrix of every node of the file, from its own transforms, whether or not the
/// chosen scene holds it (a joint may lie outside it). `parent` is each node's parent in a
/// forest. A non-finite transform gives a non-finite world, which a joint refuses.
pub(crate) fn node_worlds(document: &gltf::Document, parent: &[Option<usize>]) -> Vec<Mat4> {
    let locals: Vec<Mat4> = document.nodes().map(|n| local_matrix(&n)).collect();
    let mut world: Vec<Option<Mat4>> = vec![None; locals.len()];
    for start in 0..locals.len() {
        let mut chain = Vec::new();
        let mut at = Some(start);
        while let Some(n) = at {
            if world[n].is_some() {
                break;
            }
            chain.push(n);
            at = parent.get(n).copied().flatten();
        }
        let mut above = at.and_then(|n| world[n]).unwrap_or(Mat4::IDENTITY);
        for &n in chain.iter().rev() {
            above *= locals[n];
            world[n] = Some(above);
        }
    }
    world
        .into_iter()
        .map(|w| w.unwrap_or(Mat4::IDENTITY))
        .collect()
}

/// One skin's joint matrices for one mesh node.
pub(crate) struct Pose {
    /// The skin's index in the file.
    pub skin: usize,
    /// `inverse(mesh node world) * world(joint) * inverseBindMatrix`, one per joint.
    pub matrices: Vec<Mat4>,
    /// The joints' glTF node indices.
    pub joints: Vec<usize>,
    /// Each joint's inverse bind matrix.
    pub inverse_binds: Vec<Mat4>,
}

/// The joint matrices of `skin` for a mesh node whose world matrix is `mesh_world`; `worlds`
/// is every node's world matrix ([`node_worlds`]). Without `inverseBindMatrices` each is the
/// identity, as the specification says.
pub(crate) fn pose(
    reader: &AccessorReader,
    skin: &gltf::Skin,
    worlds: &[Mat4],
    mesh_world: Mat4,
) -> Result<Pose, String> {
    let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
    if joints.is_empty() {
        return Err("has no joints".into());
    }
    let inverse_binds: Vec<Mat4> = match skin.inverse_bind_matrices() {
        Some(accessor) => {
            let read = reader
                .read::<16>(&accessor, Formats::Float)
                .map_err(|why| format!("inverse bind matrices: {why}"))?;
            if read.len() < joints.len() {
                return Err(format!(
                    "has {} joints but its inverse bind matrices (accessor {}) hold {}",
                    joints.len(),
                    accessor.index(),
                    read.len()
                ));
            }
            let mut matrices = Vec::with_capacity(joints.len());
            for (j, m) in read.iter().take(joints.len()).enumerate() {
                let m = Mat4::from_cols_array(&m.map(|c| c as f32));
                if !m.is_finite() {
                    return Err(format!("inverse bind matrix {j} is not finite"));
                }
                matrices.push(m);
            }
            matrices
        }
        None => vec![Mat4::IDENTITY; joints.len()],
    };
    let to_mesh = mesh_world.inverse();
    if !to_mesh.is_finite() {
        return Err("the skinned mesh's node has a world transform with no inverse".into());
    }
    let mut matrices = Vec::with_capacity(joints.len());
    for (j, (&node, inverse_bind)) in joints.iter().zip(&inverse_binds).enumerate() {
        let world = worlds
            .get(node)
            .copied()
            .ok_or_else(|| format!("joint {j} names node {node}, which does not exist"))?;
        let matrix = to_mesh * world * *inverse_bind;
        if !matrix.is_finite() {
            return Err(format!(
                "joint {j} (node {node}) has a world transform that is not finite"
            ));
        }
        matrices.push(matrix);
    }
    Ok(Pose {
        skin: skin.index(),
        matrices,
        joints,
        inverse_binds,
    })
}

/// Each vertex's influences, read from JOINTS_n / WEIGHTS_n: (joint, weight) pairs.
fn influences(
    reader: &AccessorReader,
    primitive: &gltf::Primitive,
    vertices: usize,
) -> Result<Vec<Vec<(usize, f64)>>, String> {
    let mut out: Vec<Vec<(usize, f64)>> = vec![Vec::new(); vertices];
    for set in 0..INFLUENCE_SETS {
        let (joints, weights) = match (
            primitive.get(&Semantic::Joints(set)),
            primitive.get(&Semantic::Weights(set)),
        ) {
            (Some(j), Some(w)) => (j, w),
            (None, None) => break,
            (Some(_), None) => return Err(format!("has JOINTS_{set} without WEIGHTS_{set}")),
            (None, Some(_)) => return Err(format!("has WEIGHTS_{set} without JOINTS_{set}")),
        };
        let joints = reader
            .read::<4>(&joints, Formats::Joints)
            .map_err(|why| format!("JOINTS_{set}: {why}"))?;
        let weights = reader
            .read::<4>(&weights, Formats::FloatOrUnorm)
            .map_err(|why| format!("WEIGHTS_{set}: {why}"))?;
        for (name, len) in [("JOINTS", joints.len()), ("WEIGHTS", weights.len())] {
            if len != vertices {
                return Err(format!(
                    "{name}_{set} has {len} elements but there are {vertices} positions"
                ));
            }
        }
        for (v, (j, w)) in joints.iter().zip(&weights).enumerate() {
            for (&joint, &weight) in j.iter().zip(w) {
                if !weight.is_finite() || weight < 0.0 {
                    return Err(format!(
                        "WEIGHTS_{set} of vertex {v} holds {weight}, not a finite weight >= 0"
                    ));
                }
                out[v].push((joint as usize, weight));
            }
        }
    }
    Ok(out)
}

/// Poses `data` (read from `primitive`) by `pose`: positions, normals and tangents. Returns
/// the bind pose (the data before posing, with its normalised influences) and the repair lines:
/// a primitive without JOINTS_0 and WEIGHTS_0 is left as it is (no bind pose), and weights
/// that do not sum to 1 are normalised.
pub(crate) fn pose_primitive(
    reader: &AccessorReader,
    primitive: &gltf::Primitive,
    pose: &Pose,
    data: &mut MeshData,
) -> Result<(Option<Influences>, Vec<String>), String> {
    if primitive.get(&Semantic::Joints(0)).is_none()
        && primitive.get(&Semantic::Weights(0)).is_none()
    {
        return Ok((
            None,
            vec![format!(
                "has no JOINTS_0 and WEIGHTS_0 for skin {}: drawn as stored",
                pose.skin
            )],
        ));
    }
    let raw = influences(reader, primitive, data.positions.len())?;
    let mut renormalised = 0usize;
    let mut out = Influences::default();
    for (v, vertex) in raw.iter().enumerate() {
        let sum: f64 = vertex.iter().map(|(_, w)| w).sum();
        if sum <= 0.0 {
            return Err(format!(
                "the weights of vertex {v} sum to 0: it follows no joint"
            ));
        }
        if (sum - 1.0).abs() > WEIGHT_SUM_TOLERANCE {
            renormalised += 1;
        }
        let mut joints = [0u16; MAX_INFLUENCES];
        let mut weights = [0f32; MAX_INFLUENCES];
        for (k, &(joint, weight)) in vertex.iter().enumerate().take(MAX_INFLUENCES) {
            if weight == 0.0 {
                continue;
            }
            if joint >= pose.matrices.len() {
                return Err(format!(
                    "vertex {v} names joint {joint}, but skin {} has {} joints",
                    pose.skin,
                    pose.matrices.len()
                ));
            }
            joints[k] = joint as u16;
            weights[k] = (weight / sum) as f32;
        }
        out.joints.push(joints);
        out.weights.push(weights);
    }
    skin_mesh_data(data, &out, &pose.matrices)?;
    let repairs = if renormalised > 0 {
        vec![format!(
            "the weights of {renormalised} vertices did not sum to 1: normalised"
        )]
    } else {
        Vec::new()
    };
    Ok((Some(out), repairs))
}
