//! A summary of what a World's scene holds, as `chiaro info` prints it.

use std::collections::BTreeMap;
use std::fmt;

use bevy_ecs::name::Name;
use bevy_ecs::prelude::*;
use bevy_ecs::system::RunSystemOnce;
use glam::Vec3;

use crate::bounds::Aabb;
use crate::components::{
    ActiveCamera, Camera, Light, LightKind, MeshInstance, Projection, Skinned,
};
use crate::environment::{Environment, EnvironmentSource};
use crate::error::{ImportReport, Repair};
use crate::features::SceneFeatures;
use crate::material::Materials;
use crate::mesh::Meshes;
use crate::scene_builder::AutoCamera;
use crate::texture::Textures;
use crate::transform::{GlobalTransform, Transform, propagate_transforms};

/// One material, summarised.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialSummary {
    /// Its name.
    pub name: String,
    /// The texture slots it uses.
    pub texture_slots: Vec<&'static str>,
    /// Whether it emits.
    pub emissive: bool,
}

/// The active camera, summarised.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraSummary {
    /// Its name.
    pub name: String,
    /// World position.
    pub position: Vec3,
    /// World viewing direction (unit).
    pub forward: Vec3,
    /// Its projection.
    pub projection: Projection,
    /// True when chiaro placed it because the scene had none.
    pub automatic: bool,
}

/// What a scene holds.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneInfo {
    /// Meshes stored (each once, however many instances use it).
    pub meshes: usize,
    /// Triangles stored in those meshes.
    pub mesh_triangles: usize,
    /// Mesh instances (entities with a [`MeshInstance`]).
    pub instances: usize,
    /// Triangles over all instances: what a renderer traces.
    pub triangles: usize,
    /// Entities with a [`Transform`] (nodes of the hierarchy).
    pub nodes: usize,
    /// Every material.
    pub materials: Vec<MaterialSummary>,
    /// Decoded textures.
    pub textures: usize,
    /// Punctual lights by kind: point, spot, directional.
    pub lights: BTreeMap<&'static str, usize>,
    /// Mesh instances posed by a skin at load ([`Skinned`]).
    pub skinned_instances: usize,
    /// The skins posing them: each one's joint count, by skin index.
    pub skins: BTreeMap<u32, u32>,
    /// The animation clips: each one's name, channel count and duration in seconds.
    pub animations: Vec<(String, usize, f32)>,
    /// Triangles over all instances whose material emits.
    pub emissive_triangles: usize,
    /// The active camera.
    pub camera: Option<CameraSummary>,
    /// The environment, described.
    pub environment: String,
    /// World bounds of every instance.
    pub bounds: Aabb,
    /// The features the scene uses (what a renderer specialises for).
    pub features: SceneFeatures,
    /// What loading repaired, with the source of each repair.
    pub repairs: Vec<(String, Repair)>,
}

impl SceneInfo {
    /// Propagates transforms and summarises the world's scene.
    pub fn gather(world: &mut World) -> Self {
        // Only fails if the system's parameters are missing, which they cannot be.
        let _ = world.run_system_once(propagate_transforms);
        let meshes = world.get_resource_or_init::<Meshes>();
        let mesh_stats: Vec<(usize, Aabb)> = meshes
            .iter()
            .map(|(_, m)| (m.triangle_count(), m.bounds()))
            .collect();
        let materials = world.get_resource_or_init::<Materials>();
        let emissive: Vec<bool> = materials.iter().map(|(_, m)| m.is_emissive()).collect();
        let material_summaries = materials
            .iter()
            .map(|(_, m)| MaterialSummary {
                name: m.name.clone(),
                texture_slots: m.texture_slots().map(|(slot, _)| slot).collect(),
                emissive: m.is_emissive(),
            })
            .collect();
        let textures = world.get_resource_or_init::<Textures>().len();

        let mut instances = 0;
        let mut triangles = 0;
        let mut emissive_triangles = 0;
        let mut bounds = Aabb::EMPTY;
        let mut query = world.query::<(&MeshInstance, &GlobalTransform)>();
        for (instance, global) in query.iter(world) {
            let Some(&(count, mesh_bounds)) = mesh_stats.get(instance.mesh.0 as usize) else {
                continue;
            };
            instances += 1;
            triangles += count;
            if emissive
                .get(instance.material.0 as usize)
                .copied()
                .unwrap_or(false)
            {
                emissive_triangles += count;
            }
            bounds = bounds.union(mesh_bounds.transformed(&global.0));
        }
        let mut lights = BTreeMap::from([("point", 0), ("spot", 0), ("directional", 0)]);
        for light in world.query::<&Light>().iter(world) {
            let kind = match light.kind {
                LightKind::Point => "point",
                LightKind::Spot { .. } => "spot",
                LightKind::Directional => "directional",
            };
            *lights.entry(kind).or_default() += 1;
        }
        let mut skinned_instances = 0;
        let mut skins = BTreeMap::new();
        for skinned in world
            .query_filtered::<&Skinned, With<MeshInstance>>()
            .iter(world)
        {
            skinned_instances += 1;
            skins.insert(skinned.skin, skinned.joints);
        }
        let animations = world
            .get_resource::<crate::animation::Animations>()
            .map(|a| {
                a.clips
                    .iter()
                    .map(|c| (c.name.clone(), c.channels.len(), c.duration()))
                    .collect()
            })
            .unwrap_or_default();
        let nodes = world.query::<&Transform>().iter(world).count();
        let camera = world.get_resource::<ActiveCamera>().and_then(|active| {
            let e = world.get_entity(active.0).ok()?;
            let global = e.get::<GlobalTransform>()?;
            Some(CameraSummary {
                name: e
                    .get::<Name>()
                    .map_or_else(|| format!("{}", active.0), |n| n.to_string()),
                position: global.translation(),
                forward: global.transform_vector(Vec3::NEG_Z).normalize_or_zero(),
                projection: e.get::<Camera>()?.projection,
                automatic: e.contains::<AutoCamera>(),
            })
        });
        let environment = match world.get_resource::<Environment>() {
            None => "none (black)".to_owned(),
            Some(env) => {
                let what = match &env.source {
                    EnvironmentSource::Constant(c) => {
                        format!("constant ({:.3}, {:.3}, {:.3})", c.x, c.y, c.z)
                    }
                    EnvironmentSource::Equirect(img) => {
                        format!("{} ({}x{})", img.path, img.width, img.height)
                    }
                };
                format!(
                    "{what}, strength {}, rotation {} rad",
                    env.strength, env.rotation
                )
            }
        };
        let features = {
            let instances: Vec<MeshInstance> = world
                .query::<&MeshInstance>()
                .iter(world)
                .copied()
                .collect();
            let lights: Vec<Light> = world.query::<&Light>().iter(world).copied().collect();
            SceneFeatures::gather(
                &instances,
                &lights,
                world.resource::<Materials>(),
                world.resource::<Meshes>(),
                world.get_resource::<Environment>(),
            )
        };
        let repairs = world
            .get_resource::<ImportReport>()
            .map(|r| {
                r.repairs()
                    .map(|(s, r)| (s.to_owned(), r.clone()))
                    .collect()
            })
            .unwrap_or_default();
        Self {
            meshes: mesh_stats.len(),
            mesh_triangles: mesh_stats.iter().map(|(t, _)| t).sum(),
            instances,
            triangles,
            nodes,
            materials: material_summaries,
            textures,
            lights,
            skinned_instances,
            skins,
            animations,
            emissive_triangles,
            camera,
            environment,
            bounds,
            features,
            repairs,
        }
    }
}

impl fmt::Display for SceneInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "meshes: {} ({} triangles stored)",
            self.meshes, self.mesh_triangles
        )?;
        writeln!(
            f,
            "instances: {} ({} triangles traced)",
            self.instances, self.triangles
        )?;
        writeln!(f, "nodes: {}", self.nodes)?;
        writeln!(f, "materials: {}", self.materials.len())?;
        for m in &self.materials {
            let slots = if m.texture_slots.is_empty() {
                "no textures".to_owned()
            } else {
                m.texture_slots.join(", ")
            };
            let emissive = if m.emissive { ", emissive" } else { "" };
            writeln!(f, "  {}: {slots}{emissive}", m.name)?;
        }
        writeln!(f, "textures: {}", self.textures)?;
        let lights: Vec<String> = self
            .lights
            .iter()
            .map(|(k, n)| format!("{n} {k}"))
            .collect();
        writeln!(f, "lights: {}", lights.join(", "))?;
        if self.skinned_instances == 0 {
            writeln!(f, "skinned: none")?;
        } else {
            let joints: Vec<String> = self.skins.values().map(u32::to_string).collect();
            let plural = |n: usize, what: &str| match n {
                1 => format!("1 {what}"),
                n => format!("{n} {what}s"),
            };
            writeln!(
                f,
                "skinned: {} posed at load by {} (joints: {})",
                plural(self.skinned_instances, "instance"),
                plural(self.skins.len(), "skin"),
                joints.join(", ")
            )?;
        }
        if self.animations.is_empty() {
            writeln!(f, "animations: none")?;
        } else {
            let clips: Vec<String> = self
                .animations
                .iter()
                .map(|(name, channels, seconds)| {
                    format!("{name} ({channels} channels, {seconds:.2} s)")
                })
                .collect();
            writeln!(f, "animations: {}", clips.join(", "))?;
        }
        writeln!(f, "emissive triangles: {}", self.emissive_triangles)?;
        match &self.camera {
            Some(c) => {
                let projection = match c.projection {
                    Projection::Perspective { yfov, .. } => {
                        format!("perspective, yfov {:.2} deg", yfov.to_degrees())
                    }
                    Projection::Orthographic { xmag, ymag, .. } => {
                        format!("orthographic, {xmag} x {ymag}")
                    }
                };
                let auto = if c.automatic { " (automatic)" } else { "" };
                writeln!(
                    f,
                    "camera: {}{auto}: at ({:.4}, {:.4}, {:.4}) looking ({:.3}, {:.3}, {:.3}), {projection}",
                    c.name,
                    c.position.x,
                    c.position.y,
                    c.position.z,
                    c.forward.x,
                    c.forward.y,
                    c.forward.z
                )?;
            }
            None => writeln!(f, "camera: none")?,
        }
        writeln!(f, "environment: {}", self.environment)?;
        if self.bounds.is_empty() {
            writeln!(f, "bounds: empty")?;
        } else {
            let (lo, hi) = (self.bounds.min, self.bounds.max);
            writeln!(
                f,
                "bounds: ({}, {}, {}) to ({}, {}, {})",
                lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
            )?;
        }
        let features = self.features.in_use();
        if features.is_empty() {
            writeln!(f, "features: none")?;
        } else {
            writeln!(f, "features: {}", features.join(", "))?;
        }
        writeln!(f, "repairs: {}", self.repairs.len())?;
        for (source, r) in &self.repairs {
            writeln!(f, "  {source}: {r}")?;
        }
        Ok(())
    }
}
