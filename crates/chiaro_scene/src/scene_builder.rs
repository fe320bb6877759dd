//! A scene assembled and validated in memory before it touches a World, so that a load either
//! succeeds whole or leaves the World as it was. The glTF importer and the built-in scenes both
//! build one, then [`SceneBuilder::spawn`] puts it into a World.

use bevy_ecs::hierarchy::ChildOf;
use bevy_ecs::name::Name;
use bevy_ecs::prelude::*;
use glam::{Affine3A, Vec3};

use crate::animation::{AnimationClip, Animations};
use crate::bounds::Aabb;
use crate::components::{ActiveCamera, Camera, Light, MeshInstance, Projection, Skinned};
use crate::deformation::DeformedMesh;
use crate::environment::Environment;
use crate::error::{ImportReport, Repair, SceneError};
use crate::framing::frame_bounds;
use crate::material::{MaterialId, Materials};
use crate::mesh::{Mesh, MeshId, Meshes};
use crate::mesh_repair::{MeshData, MeshFault};
use crate::morph::MorphWeights;
use crate::texture::{TextureId, Textures};
use crate::transform::Transform;
use crate::{Material, Texture};

/// The index of the glTF node an entity was imported from.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct SourceNode(pub u32);

/// Marks the camera chiaro placed because the scene had none (see [`crate::framing`]).
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct AutoCamera;

/// Index of a node in a [`SceneBuilder`].
pub type NodeIndex = usize;

/// One entity to be: its place in the hierarchy and what it carries.
#[derive(Clone, Debug, Default)]
pub struct Node {
    /// Its name.
    pub name: Option<String>,
    /// Its parent, which must have been added before it.
    pub parent: Option<NodeIndex>,
    /// Transform relative to the parent.
    pub transform: Transform,
    /// A mesh with its material, ids local to the builder.
    pub instance: Option<MeshInstance>,
    /// A light.
    pub light: Option<Light>,
    /// A camera.
    pub camera: Option<Camera>,
    /// The glTF node it came from.
    pub source_node: Option<u32>,
    /// Set when its mesh instance was posed by a skin at load.
    pub skinned: Option<Skinned>,
    /// Its morph target weights (its mesh has morph targets): a [`MorphWeights`] component.
    pub morph_weights: Option<Vec<f32>>,
    /// What its deformable mesh instance follows: its skin's joints, its weights' node.
    pub deformation: Option<DeformedMesh<NodeIndex>>,
}

/// A validated scene waiting to be spawned.
#[derive(Debug)]
pub struct SceneBuilder {
    source: String,
    meshes: Vec<Mesh>,
    materials: Vec<Material>,
    textures: Vec<Texture>,
    nodes: Vec<Node>,
    environment: Option<Environment>,
    animations: Vec<AnimationClip<NodeIndex>>,
    repairs: Vec<Repair>,
}

/// What [`SceneBuilder::spawn`] created.
#[derive(Clone, Debug)]
pub struct SpawnedScene {
    /// The source name.
    pub source: String,
    /// One entity per node, in node order.
    pub entities: Vec<Entity>,
    /// The active camera (the scene's first, or the automatic one).
    pub camera: Entity,
    /// The repairs made while building it.
    pub repairs: Vec<Repair>,
}

impl SceneBuilder {
    /// An empty scene from `source` (a path or `builtin:` name, used in messages).
    pub fn new(source: impl Into<String>) -> Self {
        Self {
            source: source.into(),
            meshes: Vec::new(),
            materials: Vec::new(),
            textures: Vec::new(),
            nodes: Vec::new(),
            environment: None,
            animations: Vec::new(),
            repairs: Vec::new(),
        }
    }

    /// The source name.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Records a repair.
    pub fn repair(&mut self, element: impl Into<String>, action: impl Into<String>) {
        self.repairs.push(Repair {
            element: element.into(),
            action: action.into(),
        });
    }

    /// Records several repairs.
    pub fn extend_repairs(&mut self, repairs: impl IntoIterator<Item = Repair>) {
        self.repairs.extend(repairs);
    }

    /// Validates mesh data (see [`crate::mesh_repair`]) and adds the mesh. Repairs are recorded
    /// under `element`; data with no triangle left is dropped with a repair line (`Ok(None)`);
    /// other faults are errors naming `element`.
    pub fn add_mesh(
        &mut self,
        element: &str,
        name: &str,
        data: MeshData,
    ) -> Result<Option<MeshId>, SceneError> {
        match Mesh::new(name, data) {
            Ok((mesh, repairs)) => {
                for action in repairs {
                    self.repair(element, action);
                }
                self.meshes.push(mesh);
                Ok(Some(MeshId(self.meshes.len() as u32 - 1)))
            }
            Err(MeshFault::NoTriangles(why)) => {
                self.repair(element, format!("dropped: {why}"));
                Ok(None)
            }
            Err(fault) => Err(SceneError::at(self.source.clone(), element, fault)),
        }
    }

    /// Adds a material.
    pub fn add_material(&mut self, material: Material) -> MaterialId {
        self.materials.push(material);
        MaterialId(self.materials.len() as u32 - 1)
    }

    /// Adds a decoded texture.
    pub fn add_texture(&mut self, texture: Texture) -> TextureId {
        self.textures.push(texture);
        TextureId(self.textures.len() as u32 - 1)
    }

    /// Adds a perspective camera node named "camera" at `eye` looking at `target` (+Y up), with
    /// a vertical field of view of `yfov_degrees`, the image's aspect ratio and a near plane at
    /// 0.01.
    pub fn add_camera(&mut self, eye: Vec3, target: Vec3, yfov_degrees: f32) -> NodeIndex {
        self.add_node(Node {
            name: Some("camera".into()),
            transform: Transform::looking_at(eye, target, Vec3::Y),
            camera: Some(Camera {
                projection: Projection::Perspective {
                    yfov: yfov_degrees.to_radians(),
                    aspect_ratio: None,
                    znear: 0.01,
                    zfar: None,
                },
            }),
            ..Node::default()
        })
    }

    /// Adds a node. Its parent, if any, must already be in the builder.
    pub fn add_node(&mut self, node: Node) -> NodeIndex {
        assert!(
            node.parent.is_none_or(|p| p < self.nodes.len()),
            "parent added after child"
        );
        self.nodes.push(node);
        self.nodes.len() - 1
    }

    /// Adds a root node holding one mesh instance.
    pub fn add_instance(
        &mut self,
        name: &str,
        mesh: MeshId,
        material: MaterialId,
        transform: Transform,
    ) -> NodeIndex {
        self.add_node(Node {
            name: Some(name.to_owned()),
            transform,
            instance: Some(MeshInstance { mesh, material }),
            ..Node::default()
        })
    }

    /// Makes node `node`'s mesh instance follow `deformation`, whose nodes are this builder's.
    pub fn set_deformation(&mut self, node: NodeIndex, deformation: DeformedMesh<NodeIndex>) {
        let joints = deformation.skin.iter().flat_map(|s| s.joints.iter());
        assert!(
            joints
                .chain(&deformation.weights_from)
                .all(|&j| j < self.nodes.len()),
            "a deformation names a node not in the builder"
        );
        self.nodes[node].deformation = Some(deformation);
    }

    /// Adds an animation clip whose channels target nodes of this builder.
    pub fn add_animation(&mut self, clip: AnimationClip<NodeIndex>) {
        assert!(
            clip.channels.iter().all(|c| c.target < self.nodes.len()),
            "an animation channel targets a node not in the builder"
        );
        self.animations.push(clip);
    }

    /// The animation clips added so far.
    pub fn animations(&self) -> &[AnimationClip<NodeIndex>] {
        &self.animations
    }

    /// Sets the environment the scene comes with.
    pub fn set_environment(&mut self, environment: Environment) {
        self.environment = Some(environment);
    }

    /// The nodes added so far.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// World matrix of node `node`, through its parents.
    pub fn world_matrix(&self, node: NodeIndex) -> Affine3A {
        let mut world = Affine3A::IDENTITY;
        let mut at = Some(node);
        while let Some(n) = at {
            world = self.nodes[n].transform.to_affine() * world;
            at = self.nodes[n].parent;
        }
        world
    }

    /// World matrix of every node.
    pub fn world_matrices(&self) -> Vec<Affine3A> {
        let mut world: Vec<Affine3A> = Vec::with_capacity(self.nodes.len());
        for node in &self.nodes {
            let parent = node.parent.map_or(Affine3A::IDENTITY, |p| world[p]);
            world.push(parent * node.transform.to_affine());
        }
        world
    }

    /// World bounds of every mesh instance.
    pub fn bounds(&self) -> Aabb {
        let mesh_bounds: Vec<Aabb> = self.meshes.iter().map(Mesh::bounds).collect();
        self.world_matrices()
            .iter()
            .zip(&self.nodes)
            .filter_map(|(m, n)| {
                n.instance
                    .map(|i| mesh_bounds[i.mesh.0 as usize].transformed(m))
            })
            .fold(Aabb::EMPTY, Aabb::union)
    }

    /// Spawns the scene into `world`: assets appended to the [`Meshes`], [`Materials`] and
    /// [`Textures`] resources (created if missing), one entity per node with its hierarchy, the
    /// environment (black if neither the scene nor the world has one), and [`ActiveCamera`] set to
    /// the scene's first camera or to an automatic one. Repairs are logged as warnings and kept
    /// in [`ImportReport`].
    pub fn spawn(self, world: &mut World) -> SpawnedScene {
        let bounds = self.bounds();
        let texture_base = world.get_resource_or_init::<Textures>().len() as u32;
        let material_base = world.get_resource_or_init::<Materials>().len() as u32;
        let mesh_base = world.get_resource_or_init::<Meshes>().len() as u32;
        let remap = |t: &mut Option<crate::material::TextureRef>| {
            if let Some(t) = t {
                t.texture = TextureId(t.texture.0 + texture_base);
            }
        };
        {
            let mut textures = world.resource_mut::<Textures>();
            for t in self.textures {
                textures.add(t);
            }
        }
        {
            let mut materials = world.resource_mut::<Materials>();
            for mut m in self.materials {
                for slot in m.texture_slots_mut() {
                    remap(slot);
                }
                materials.add(m);
            }
        }
        {
            let mut meshes = world.resource_mut::<Meshes>();
            for m in self.meshes {
                meshes.add(m);
            }
        }

        let mut entities: Vec<Entity> = Vec::with_capacity(self.nodes.len());
        let mut camera = None;
        let mut deformations = Vec::new();
        for node in self.nodes {
            if let Some(deformation) = node.deformation {
                deformations.push((entities.len(), deformation));
            }
            let mut e = world.spawn(node.transform);
            if let Some(name) = node.name {
                e.insert(Name::new(name));
            }
            if let Some(parent) = node.parent {
                e.insert(ChildOf(entities[parent]));
            }
            if let Some(instance) = node.instance {
                e.insert(MeshInstance {
                    mesh: MeshId(instance.mesh.0 + mesh_base),
                    material: MaterialId(instance.material.0 + material_base),
                });
            }
            if let Some(light) = node.light {
                e.insert(light);
            }
            if let Some(c) = node.camera {
                e.insert(c);
                camera.get_or_insert(e.id());
            }
            if let Some(index) = node.source_node {
                e.insert(SourceNode(index));
            }
            if let Some(skinned) = node.skinned {
                e.insert(skinned);
            }
            if let Some(weights) = node.morph_weights {
                e.insert(MorphWeights(weights));
            }
            entities.push(e.id());
        }
        // Joints may come after the instance they pose: bound once every entity exists.
        for (node, deformation) in deformations {
            world
                .entity_mut(entities[node])
                .insert(deformation.map_nodes(|&j| entities[j]));
        }
        let camera = camera.unwrap_or_else(|| {
            let (transform, camera) = frame_bounds(&bounds);
            world
                .spawn((transform, camera, AutoCamera, Name::new("automatic camera")))
                .id()
        });
        world.insert_resource(ActiveCamera(camera));
        if !self.animations.is_empty() {
            let mut animations = world.get_resource_or_init::<Animations>();
            for clip in self.animations {
                animations
                    .clips
                    .push(clip.map_targets(|node| entities[node]));
            }
        }
        match self.environment {
            Some(env) => world.insert_resource(env),
            None => {
                world.get_resource_or_init::<Environment>();
            }
        }
        for r in &self.repairs {
            log::warn!("{}: {r}", self.source);
        }
        world
            .get_resource_or_init::<ImportReport>()
            .sources
            .push((self.source.clone(), self.repairs.clone()));
        SpawnedScene {
            source: self.source,
            entities,
            camera,
            repairs: self.repairs,
        }
    }
}

#[cfg(test)]
mod spawn_tests;
