//! The glTF node graph: checked to be a forest, walked from the chosen scene's roots (parents
//! before children, with an explicit stack), each node turned into a builder [`Node`] with its
//! transform, mesh primitives, light and camera.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Mat4, Quat, Vec3};

use crate::components::{Camera, Light, LightKind, MeshInstance, Projection, Skinned};
use crate::deformation::BindPose;
use crate::error::{Fault, SceneError};
use crate::gltf::accessor::AccessorReader;
use crate::gltf::gpu_instancing::instance_transforms;
use crate::gltf::skins;
use crate::load::LightUnits;
use crate::material::{Material, MaterialId};
use crate::mesh::MeshId;
use crate::scene_builder::{Node, NodeIndex, SceneBuilder};
use crate::transform::{MAX_HIERARCHY_DEPTH, Transform};

mod meshes;

/// Smallest scale magnitude that is not treated as singular.
pub const MIN_SCALE: f32 = 1e-20;

/// `kind index ("name")`, the way every message names a glTF element.
pub(crate) fn element(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(name) => format!("{kind} {index} ({name:?})"),
        None => format!("{kind} {index}"),
    }
}

/// Each node's parent, refusing a node with two parents and any cycle.
fn parents(document: &gltf::Document) -> Result<Vec<Option<usize>>, (String, String)> {
    let count = document.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            let c = child.index();
            if c == node.index() {
                return Err((element("node", c, child.name()), "is its own child".into()));
            }
            if let Some(p) = parent[c] {
                return Err((
                    element("node", c, child.name()),
                    format!(
                        "is a child of both node {p} and node {}: the node graph is not a tree",
                        node.index()
                    ),
                ));
            }
            parent[c] = Some(node.index());
        }
    }
    // With one parent each, a cycle is a walk up the parents that comes back to itself.
    let mut state = vec![0u8; count]; // 0 unseen, 1 on the current walk, 2 known acyclic
    for start in 0..count {
        let mut walk = Vec::new();
        let mut at = Some(start);
        while let Some(n) = at {
            match state[n] {
                2 => break,
                1 => {
                    return Err((
                        format!("node {n}"),
                        "is its own ancestor: the node graph has a cycle".into(),
                    ));
                }
                _ => {
                    state[n] = 1;
                    walk.push(n);
                    at = parent[n];
                }
            }
        }
        for n in walk {
            state[n] = 2;
        }
    }
    Ok(parent)
}

/// A node's local transform: `Ok(None)` when it is singular (zero scale), an error when it is
/// not finite. A non-unit rotation is normalised; a matrix with shear is approximated by its
/// scale-rotation-translation part, with a repair line.
fn node_transform(
    node: &gltf::Node,
    repairs: &mut Vec<String>,
) -> Result<Option<Transform>, Fault> {
    let (translation, rotation, scale) = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            if !m.is_finite() {
                return Err(Fault::NonFiniteTransform(format!("matrix {matrix:?}")));
            }
            if m.determinant().abs() < MIN_SCALE.powi(3) {
                return Ok(None);
            }
            let (s, r, t) = m.to_scale_rotation_translation();
            let rebuilt = Mat4::from_scale_rotation_translation(s, r, t);
            if !rebuilt.abs_diff_eq(
                m,
                1e-4 * m
                    .abs()
                    .to_cols_array()
                    .iter()
                    .fold(1.0f32, |a, &b| a.max(b)),
            ) {
                repairs.push("matrix has shear or projection: approximated by scale, rotation and translation".into());
            }
            (t, r, s)
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let (t, q, s) = (
                Vec3::from(translation),
                Quat::from_array(rotation),
                Vec3::from(scale),
            );
            if !t.is_finite() || !q.is_finite() || !s.is_finite() {
                return Err(Fault::NonFiniteTransform(format!(
                    "translation {translation:?}, rotation {rotation:?}, scale {scale:?}"
                )));
            }
            let len = q.length();
            let q = if len < 1e-6 {
                repairs.push(format!(
                    "rotation {rotation:?} has no direction: identity used"
                ));
                Quat::IDENTITY
            } else {
                if (len - 1.0).abs() > 1e-3 {
                    repairs.push(format!(
                        "rotation {rotation:?} is not unit length: normalised"
                    ));
                }
                q / len
            };
            (t, q, s)
        }
    };
    if scale.abs().min_element() < MIN_SCALE {
        return Ok(None);
    }
    Ok(Some(Transform {
        translation,
        rotation,
        scale,
    }))
}

/// A KHR_lights_punctual light, its intensity read in `units`.
fn light(
    l: &gltf::khr_lights_punctual::Light,
    units: LightUnits,
    repairs: &mut Vec<String>,
) -> Result<Light, Fault> {
    let color = Vec3::from(l.color());
    let intensity = l.intensity();
    if !color.is_finite() || color.min_element() < 0.0 || !intensity.is_finite() || intensity < 0.0
    {
        return Err(Fault::Light(format!(
            "colour {color} and intensity {intensity} must be finite and non-negative"
        )));
    }
    let range = match l.range() {
        Some(r) if r.is_finite() && r > 0.0 => Some(r),
        Some(r) => {
            repairs.push(format!("range {r} is not positive: unlimited range used"));
            None
        }
        None => None,
    };
    let kind = match l.kind() {
        gltf::khr_lights_punctual::Kind::Point => LightKind::Point,
        gltf::khr_lights_punctual::Kind::Directional => LightKind::Directional,
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let half_pi = std::f32::consts::FRAC_PI_2;
            let outer = if outer_cone_angle.is_finite() {
                outer_cone_angle.clamp(1e-4, half_pi)
            } else {
                half_pi
            };
            let inner = if inner_cone_angle.is_finite() {
                inner_cone_angle.clamp(0.0, outer * 0.999)
            } else {
                0.0
            };
            if inner != inner_cone_angle || outer != outer_cone_angle {
                repairs.push(format!(
                    "spot cone ({inner_cone_angle}, {outer_cone_angle}) outside 0 <= inner < outer <= pi/2: \
                     ({inner}, {outer}) used"
                ));
            }
            LightKind::Spot {
                inner_cone_angle: inner,
                outer_cone_angle: outer,
            }
        }
    };
    Ok(Light {
        kind,
        color,
        intensity: units.radiometric(intensity),
        range,
    })
}

pub(crate) fn camera(c: &gltf::Camera) -> Result<Camera, Fault> {
    let bad = |why: String| Err(Fault::Camera(why));
    let projection = match c.projection() {
        gltf::camera::Projection::Perspective(p) => {
            let (yfov, znear, zfar, aspect) = (p.yfov(), p.znear(), p.zfar(), p.aspect_ratio());
            if !(yfov.is_finite() && yfov > 0.0 && yfov < std::f32::consts::PI) {
                return bad(format!("yfov {yfov} is outside (0, pi)"));
            }
            if !(znear.is_finite() && znear > 0.0) {
                return bad(format!("znear {znear} is not positive"));
            }
            if let Some(zfar) = zfar
                && zfar.partial_cmp(&znear) != Some(std::cmp::Ordering::Greater)
            {
                return bad(format!("zfar {zfar} is not greater than znear {znear}"));
            }
            if let Some(a) = aspect
                && !(a.is_finite() && a > 0.0)
            {
                return bad(format!("aspect ratio {a} is not positive"));
            }
            Projection::Perspective {
                yfov,
                aspect_ratio: aspect,
                znear,
                zfar: zfar.filter(|z| z.is_finite()),
            }
        }
        gltf::camera::Projection::Orthographic(o) => {
            let (xmag, ymag, znear, zfar) = (o.xmag(), o.ymag(), o.znear(), o.zfar());
            if !(xmag.is_finite() && ymag.is_finite() && xmag != 0.0 && ymag != 0.0) {
                return bad(format!(
                    "xmag {xmag} and ymag {ymag} must be finite and non-zero"
                ));
            }
            if !(znear.is_finite() && znear >= 0.0 && zfar.is_finite() && zfar > znear) {
                return bad(format!(
                    "znear {znear} and zfar {zfar} must satisfy 0 <= znear < zfar"
                ));
            }
            Projection::Orthographic {
                xmag: xmag.abs(),
                ymag: ymag.abs(),
                znear,
                zfar,
            }
        }
    };
    Ok(Camera { projection })
}

/// Walks the chosen scene into the builder.
pub(crate) struct NodeImporter<'a> {
    pub document: &'a gltf::Document,
    pub reader: AccessorReader<'a>,
    pub builder: &'a mut SceneBuilder,
    /// The file's materials, already in the builder with ids equal to their glTF index.
    pub materials: &'a [Material],
    /// How light intensities are read.
    pub light_units: LightUnits,
    meshes: HashMap<(usize, usize), Option<MeshId>>,
    default_material: Option<MaterialId>,
    /// Every glTF node's world matrix, for the joints of skins (empty without skins).
    worlds: Vec<Mat4>,
    /// Deformable instances waiting for their joints' nodes
    /// ([`NodeImporter::bind_deformations`]).
    pending: Vec<meshes::PendingDeformation>,
}

impl<'a> NodeImporter<'a> {
    pub fn new(
        document: &'a gltf::Document,
        reader: AccessorReader<'a>,
        builder: &'a mut SceneBuilder,
        materials: &'a [Material],
        light_units: LightUnits,
    ) -> Self {
        Self {
            document,
            reader,
            builder,
            materials,
            light_units,
            meshes: HashMap::new(),
            default_material: None,
            worlds: Vec::new(),
            pending: Vec::new(),
        }
    }

    fn error(&self, element: String, fault: Fault) -> SceneError {
        SceneError::at(self.builder.source().to_owned(), element, fault)
    }

    /// Imports the default scene, or the first, or (with no scenes) every root node.
    pub fn import(&mut self) -> Result<(), SceneError> {
        let parent =
            parents(self.document).map_err(|(e, why)| self.error(e, Fault::Hierarchy(why)))?;
        if self.document.skins().next().is_some() {
            self.worlds = skins::node_worlds(self.document, &parent);
        }
        let scene = self
            .document
            .default_scene()
            .or_else(|| self.document.scenes().next());
        let roots: Vec<usize> = match &scene {
            Some(scene) => scene.nodes().map(|n| n.index()).collect(),
            None => (0..parent.len()).filter(|&n| parent[n].is_none()).collect(),
        };
        let mut seen = vec![false; parent.len()];
        for &root in &roots {
            let scene_name = scene
                .as_ref()
                .map_or_else(String::new, |s| element("scene", s.index(), s.name()));
            if let Some(p) = parent[root] {
                return Err(self.error(
                    scene_name,
                    Fault::Hierarchy(format!(
                        "lists node {root} as a root, but it is a child of node {p}"
                    )),
                ));
            }
            if std::mem::replace(&mut seen[root], true) {
                return Err(self.error(
                    scene_name,
                    Fault::Hierarchy(format!("lists node {root} twice")),
                ));
            }
        }
        let nodes: Vec<gltf::Node> = self.document.nodes().collect();
        let mut stack: Vec<(usize, Option<NodeIndex>, usize)> =
            roots.into_iter().rev().map(|r| (r, None, 0)).collect();
        while let Some((index, parent_node, depth)) = stack.pop() {
            let Some(node) = nodes.get(index) else {
                continue;
            };
            if depth > MAX_HIERARCHY_DEPTH {
                return Err(self.error(
                    element("node", index, node.name()),
                    Fault::Hierarchy(format!(
                        "is {depth} levels below its scene's root, deeper than the \
                         {MAX_HIERARCHY_DEPTH} levels chiaro follows"
                    )),
                ));
            }
            if let Some(added) = self.node(node, parent_node)? {
                let children: Vec<usize> = node.children().map(|c| c.index()).collect();
                stack.extend(
                    children
                        .into_iter()
                        .rev()
                        .map(|c| (c, Some(added), depth + 1)),
                );
            }
        }
        self.bind_deformations();
        Ok(())
    }

    /// Adds one node; `None` when it is singular and its subtree is skipped.
    fn node(
        &mut self,
        node: &gltf::Node,
        parent: Option<NodeIndex>,
    ) -> Result<Option<NodeIndex>, SceneError> {
        let name = element("node", node.index(), node.name());
        let mut repairs = Vec::new();
        let transform =
            node_transform(node, &mut repairs).map_err(|f| self.error(name.clone(), f))?;
        let Some(transform) = transform else {
            let skipped = count_subtree(node);
            self.builder.repair(
                name,
                format!("has a singular (zero-scale) transform: it and its subtree ({skipped} nodes) are skipped"),
            );
            return Ok(None);
        };
        let light = match node.light() {
            Some(l) => Some(light(&l, self.light_units, &mut repairs).map_err(|f| {
                self.error(
                    format!("{name}, {}", element("light", l.index(), l.name())),
                    f,
                )
            })?),
            None => None,
        };
        let camera = match node.camera() {
            Some(c) => Some(camera(&c).map_err(|f| {
                self.error(
                    format!("{name}, {}", element("camera", c.index(), c.name())),
                    f,
                )
            })?),
            None => None,
        };
        for r in repairs {
            self.builder.repair(name.clone(), r);
        }
        let pose = match (node.mesh(), node.skin()) {
            (Some(_), Some(skin)) => {
                let above =
                    parent.map_or(glam::Affine3A::IDENTITY, |p| self.builder.world_matrix(p));
                let mesh_world = Mat4::from(above * transform.to_affine());
                let pose = skins::pose(&self.reader, &skin, &self.worlds, mesh_world);
                Some(pose.map_err(|why| {
                    let skin = element("skin", skin.index(), skin.name());
                    self.error(format!("{name}, {skin}"), Fault::Skin(why))
                })?)
            }
            _ => None,
        };
        let weights = node
            .mesh()
            .and_then(|mesh| self.morph_weights(node, &mesh, &name));
        let (instances, bind_poses): (Vec<MeshInstance>, Vec<Option<Arc<BindPose>>>) =
            match node.mesh() {
                Some(mesh) => self
                    .instances(&mesh, pose.as_ref(), weights.as_deref())?
                    .into_iter()
                    .unzip(),
                None => (Vec::new(), Vec::new()),
            };
        let skinned = pose.as_ref().map(|p| Skinned {
            skin: p.skin as u32,
            joints: p.matrices.len() as u32,
        });
        let gpu_instances = instance_transforms(&self.reader, self.document, node)
            .map_err(|why| self.error(name.clone(), Fault::Accessor(why)))?
            .filter(|_| !instances.is_empty());
        let added = self.builder.add_node(Node {
            name: Some(node.name().map_or_else(|| name.clone(), str::to_owned)),
            parent,
            transform,
            instance: (instances.len() == 1 && gpu_instances.is_none()).then(|| instances[0]),
            light,
            camera,
            source_node: Some(node.index() as u32),
            skinned,
            morph_weights: weights.clone(),
            deformation: None,
        });
        if let Some((transforms, dropped)) = gpu_instances {
            if dropped > 0 {
                self.builder.repair(
                    name.clone(),
                    format!(
                        "dropped {dropped} GPU instances with a non-finite or zero-scale transform"
                    ),
                );
            }
            for (k, transform) in transforms.into_iter().enumerate() {
                let holder = self.builder.add_node(Node {
                    name: Some(format!("{name} instance {k}")),
                    parent: Some(added),
                    transform,
                    instance: (instances.len() == 1).then(|| instances[0]),
                    skinned,
                    ..Node::default()
                });
                self.add_primitive_children(&name, holder, &instances, skinned);
            }
        } else {
            let carriers = self.add_primitive_children(&name, added, &instances, skinned);
            // (GPU instances share one mesh, which a deformation per instance cannot pose:
            // those keep their load pose.)
            for (carrier, bind_pose) in carriers.into_iter().zip(bind_poses) {
                if let Some(bind_pose) = bind_pose {
                    self.pending.push(meshes::PendingDeformation {
                        node: carrier,
                        skin: pose
                            .as_ref()
                            .map(|p| (p.skin, p.joints.clone(), p.inverse_binds.clone().into())),
                        weights_from: weights.as_ref().map(|_| added),
                        bind_pose,
                    });
                }
            }
        }
        Ok(Some(added))
    }

    /// With more than one primitive, each becomes a child of `holder` (one is carried by the
    /// holder itself).
    /// Returns the node carrying each instance.
    fn add_primitive_children(
        &mut self,
        name: &str,
        holder: NodeIndex,
        instances: &[MeshInstance],
        skinned: Option<Skinned>,
    ) -> Vec<NodeIndex> {
        let mut carriers = vec![holder; instances.len().min(1)];
        if instances.len() > 1 {
            carriers.clear();
            for (k, instance) in instances.iter().enumerate() {
                carriers.push(self.builder.add_node(Node {
                    name: Some(format!("{name} primitive {k}")),
                    parent: Some(holder),
                    instance: Some(*instance),
                    skinned,
                    ..Node::default()
                }));
            }
        }
        carriers
    }
}

fn count_subtree(node: &gltf::Node) -> usize {
    let mut count = 0;
    let mut stack = vec![node.clone()];
    while let Some(n) = stack.pop() {
        count += 1;
        stack.extend(n.children());
    }
    count
}
