//! What a scene uses, derived from its ECS data and kept current on change, so that a renderer
//! compiles and pays for only the features in use: a scene without textures, spot lights or
//! emissive meshes pays nothing for them.
//!
//! Only what instances really reach counts: a material no instance uses, or a light of zero
//! intensity, turns nothing on.

use std::collections::HashSet;

use bevy_ecs::prelude::*;

use crate::components::{Light, LightKind, MeshInstance};
use crate::environment::{Environment, EnvironmentSource};
use crate::material::{AlphaMode, Material, Materials};
use crate::mesh::Meshes;

/// Where light from outside the scene comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum EnvironmentFeature {
    /// No environment, or one of zero radiance.
    #[default]
    Black,
    /// The same radiance from every direction.
    Constant,
    /// An equirectangular image, importance-sampled.
    Map,
}

/// The features a scene uses. Kept in the World by [`update_scene_features`], which rewrites it
/// only when its value changes: `Res<SceneFeatures>::is_changed` tells a renderer exactly when
/// to re-specialise its pipelines.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SceneFeatures {
    /// Some used material has a base colour texture.
    pub base_color_textures: bool,
    /// Some used material has a metallic-roughness texture.
    pub metallic_roughness_textures: bool,
    /// Some used material has a normal map.
    pub normal_maps: bool,
    /// Some used material has an emissive texture.
    pub emissive_textures: bool,
    /// Some used material has a texture of a material extension ([`crate::LayerTextures`]).
    pub layer_textures: bool,
    /// Some used texture slot reads the second UV set.
    pub second_uv_set: bool,
    /// Some used material is alpha-masked.
    pub alpha_masks: bool,
    /// Some used material is alpha-blended: stochastic coverage (`chiaro_shading::coverage`).
    pub alpha_blend: bool,
    /// Some used mesh has vertex colours (glTF's COLOR_0).
    pub vertex_colors: bool,
    /// Some used material has a clear coat (KHR_materials_clearcoat).
    pub clearcoat: bool,
    /// Some used material transmits light (KHR_materials_transmission).
    pub transmission: bool,
    /// Some used material has a sheen (KHR_materials_sheen).
    pub sheen: bool,
    /// Some used material bounds a medium (KHR_materials_volume): refraction and attenuation.
    pub volumes: bool,
    /// Some used material is double-sided.
    pub double_sided: bool,
    /// The scene has a point light of non-zero intensity.
    pub point_lights: bool,
    /// The scene has a spot light of non-zero intensity.
    pub spot_lights: bool,
    /// The scene has a directional light of non-zero illuminance.
    pub directional_lights: bool,
    /// Some instance's material emits: its triangles are area lights.
    pub emissive_triangles: bool,
    /// The environment.
    pub environment: EnvironmentFeature,
    /// Some mesh is used by more than one instance.
    pub instancing: bool,
}

impl SceneFeatures {
    /// The features of a scene with these instances, lights, materials, meshes and environment.
    pub fn gather<'a>(
        instances: impl IntoIterator<Item = &'a MeshInstance>,
        lights: impl IntoIterator<Item = &'a Light>,
        materials: &Materials,
        meshes: &Meshes,
        environment: Option<&Environment>,
    ) -> Self {
        let mut features = Self::default();
        let mut meshes_seen = HashSet::new();
        let mut materials_seen = HashSet::new();
        for instance in instances {
            if !meshes_seen.insert(instance.mesh) {
                features.instancing = true;
            } else if let Some(mesh) = meshes.get(instance.mesh) {
                features.vertex_colors |= mesh.colors().is_some();
            }
            if materials_seen.insert(instance.material)
                && let Some(material) = materials.get(instance.material)
            {
                features.add_material(material);
            }
        }
        for light in lights {
            if light.radiant_intensity().max_element() <= 0.0 {
                continue;
            }
            match light.kind {
                LightKind::Point => features.point_lights = true,
                LightKind::Spot { .. } => features.spot_lights = true,
                LightKind::Directional => features.directional_lights = true,
            }
        }
        features.environment = match environment {
            Some(env) if env.strength > 0.0 => match &env.source {
                EnvironmentSource::Constant(c) if c.max_element() > 0.0 => {
                    EnvironmentFeature::Constant
                }
                EnvironmentSource::Constant(_) => EnvironmentFeature::Black,
                EnvironmentSource::Equirect(_) => EnvironmentFeature::Map,
            },
            _ => EnvironmentFeature::Black,
        };
        features
    }

    fn add_material(&mut self, m: &Material) {
        self.base_color_textures |= m.base_color_texture.is_some();
        self.metallic_roughness_textures |= m.metallic_roughness_texture.is_some();
        self.normal_maps |= m.normal_texture.is_some() || m.clearcoat_normal_texture.is_some();
        self.emissive_textures |= m.emissive_texture.is_some() && m.is_emissive();
        self.layer_textures |= m.layer_textures.any();
        self.second_uv_set |= m.texture_slots().any(|(_, t)| t.uv_set == 1);
        self.alpha_masks |= matches!(m.alpha_mode, AlphaMode::Mask { .. });
        self.alpha_blend |= m.alpha_mode == AlphaMode::Blend;
        self.clearcoat |= m.clearcoat > 0.0;
        self.transmission |= m.transmission > 0.0;
        self.sheen |= m.sheen_color.max_element() > 0.0;
        self.volumes |= m.volume.is_some() && m.transmission > 0.0;
        self.double_sided |= m.double_sided;
        self.emissive_triangles |= m.is_emissive();
    }

    /// The names of the features in use, in declaration order (`chiaro info` prints them).
    pub fn in_use(&self) -> Vec<&'static str> {
        let environment = match self.environment {
            EnvironmentFeature::Black => None,
            EnvironmentFeature::Constant => Some("constant environment"),
            EnvironmentFeature::Map => Some("environment map"),
        };
        [
            (self.base_color_textures, "base colour textures"),
            (
                self.metallic_roughness_textures,
                "metallic-roughness textures",
            ),
            (self.normal_maps, "normal maps"),
            (self.emissive_textures, "emissive textures"),
            (self.layer_textures, "material extension textures"),
            (self.second_uv_set, "second UV set"),
            (self.alpha_masks, "alpha masks"),
            (self.alpha_blend, "alpha blend (stochastic coverage)"),
            (self.vertex_colors, "vertex colours"),
            (self.clearcoat, "clear coats"),
            (self.transmission, "transmission"),
            (self.sheen, "sheen"),
            (self.volumes, "volumes"),
            (self.double_sided, "double-sided materials"),
            (self.point_lights, "point lights"),
            (self.spot_lights, "spot lights"),
            (self.directional_lights, "directional lights"),
            (self.emissive_triangles, "emissive triangles"),
            (self.instancing, "instancing"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .chain(environment)
        .collect()
    }
}

/// How often [`update_scene_features`] has recomputed the features (tests read it).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneFeatureStats {
    /// Runs that found a change and recomputed.
    pub recomputes: u64,
    /// Recomputes whose result differed from the stored features.
    pub changes: u64,
}

/// Recomputes [`SceneFeatures`] when instances, lights, materials, meshes or the environment changed
/// (added, edited or removed), and stores it only when it differs. Creates the resources on
/// its first run.
#[allow(clippy::too_many_arguments)]
pub fn update_scene_features(
    mut commands: Commands,
    instances: Query<&MeshInstance>,
    lights: Query<&Light>,
    changed_instances: Query<(), Changed<MeshInstance>>,
    changed_lights: Query<(), Changed<Light>>,
    mut removed_instances: RemovedComponents<MeshInstance>,
    mut removed_lights: RemovedComponents<Light>,
    materials: Option<Res<Materials>>,
    meshes: Option<Res<Meshes>>,
    environment: Option<Res<Environment>>,
    features: Option<ResMut<SceneFeatures>>,
    stats: Option<ResMut<SceneFeatureStats>>,
) {
    let removed = removed_instances.read().count() + removed_lights.read().count() > 0;
    let changed = removed
        || !changed_instances.is_empty()
        || !changed_lights.is_empty()
        || materials.as_ref().is_some_and(|m| m.is_changed())
        || meshes.as_ref().is_some_and(|m| m.is_changed())
        || environment.as_ref().is_some_and(|e| e.is_changed());
    if features.is_some() && !changed {
        return;
    }
    let (no_materials, no_meshes) = (Materials::default(), Meshes::default());
    let fresh = SceneFeatures::gather(
        instances,
        lights,
        materials.as_deref().unwrap_or(&no_materials),
        meshes.as_deref().unwrap_or(&no_meshes),
        environment.as_deref(),
    );
    let differs = match features {
        // Only a different value marks the resource changed.
        Some(mut stored) => stored.set_if_neq(fresh),
        None => {
            commands.insert_resource(fresh);
            true
        }
    };
    match stats {
        Some(mut s) => {
            s.recomputes += 1;
            s.changes += u64::from(differs);
        }
        None => commands.insert_resource(SceneFeatureStats {
            recomputes: 1,
            changes: u64::from(differs),
        }),
    }
}

#[cfg(test)]
mod tests {
    use bevy_ecs::system::RunSystemOnce;
    use glam::Vec3;

    use super::*;
    use crate::load::load_scene;

    fn loaded(spec: &str) -> World {
        let mut world = World::new();
        load_scene(&mut world, spec).unwrap();
        world.run_system_once(update_scene_features).unwrap();
        world
    }

    fn features(world: &World) -> SceneFeatures {
        *world.resource::<SceneFeatures>()
    }

    fn stats(world: &World) -> SceneFeatureStats {
        *world.resource::<SceneFeatureStats>()
    }

    #[test]
    fn builtin_scenes_use_what_they_hold() {
        assert_eq!(
            features(&loaded("builtin:cornell")).in_use(),
            ["emissive triangles"]
        );
        let instances = features(&loaded("builtin:instances?n=16"));
        assert!(instances.instancing && !instances.emissive_triangles);
        let many = features(&loaded("builtin:many-lights?quads=4&lights=4"));
        assert!(many.point_lights && many.spot_lights && many.emissive_triangles);
        assert!(!many.directional_lights && !many.base_color_textures && !many.normal_maps);
        assert_eq!(
            features(&loaded("builtin:furnace")).environment,
            EnvironmentFeature::Black
        );
    }

    #[test]
    fn no_change_means_no_work_and_edits_follow() {
        let mut world = World::new();
        load_scene(&mut world, "builtin:cornell").unwrap();
        let mut schedule = Schedule::default();
        schedule.add_systems(update_scene_features);
        schedule.run(&mut world);
        schedule.run(&mut world);
        assert_eq!(
            stats(&world).recomputes,
            1,
            "nothing changed after the first run"
        );

        // A spot light turns its feature on.
        let light = world
            .spawn(Light {
                kind: LightKind::Spot {
                    inner_cone_angle: 0.1,
                    outer_cone_angle: 0.5,
                },
                color: Vec3::ONE,
                intensity: 10.0,
                range: None,
            })
            .id();
        schedule.run(&mut world);
        assert!(features(&world).spot_lights);
        assert_eq!(
            stats(&world),
            SceneFeatureStats {
                recomputes: 2,
                changes: 2
            }
        );

        // Masking a used material turns alpha masks on; removing the light turns spots off.
        let used = world
            .query::<&MeshInstance>()
            .iter(&world)
            .next()
            .unwrap()
            .material;
        world
            .resource_mut::<Materials>()
            .get_mut(used)
            .unwrap()
            .alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
        world.despawn(light);
        schedule.run(&mut world);
        let now = features(&world);
        assert!(now.alpha_masks && !now.spot_lights);

        // An environment of zero strength stays black; a lit one is constant.
        let mut environment = Environment::constant(Vec3::ONE);
        environment.strength = 0.0;
        world.insert_resource(environment);
        schedule.run(&mut world);
        assert_eq!(features(&world).environment, EnvironmentFeature::Black);
        world.resource_mut::<Environment>().strength = 2.0;
        schedule.run(&mut world);
        assert_eq!(features(&world).environment, EnvironmentFeature::Constant);
    }

    #[test]
    fn unused_materials_and_dark_lights_turn_nothing_on() {
        let mut materials = Materials::default();
        let mut masked = Material::diffuse("masked", Vec3::ONE, 1.0);
        masked.alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
        materials.add(masked);
        let dark = Light {
            kind: LightKind::Directional,
            color: Vec3::ONE,
            intensity: 0.0,
            range: None,
        };
        let mut meshes = Meshes::default();
        let mut colored = crate::builtin::shapes::floor(1.0);
        colored.colors = Some(vec![glam::Vec4::ONE; colored.positions.len()]);
        meshes.add(crate::mesh::Mesh::new("coloured", colored).unwrap().0);
        let f = SceneFeatures::gather([], [&dark], &materials, &meshes, None);
        assert_eq!(f, SceneFeatures::default());
        let used = MeshInstance {
            mesh: crate::mesh::MeshId(0),
            material: crate::material::MaterialId(0),
        };
        let f = SceneFeatures::gather([&used], [], &materials, &meshes, None);
        assert!(f.vertex_colors && f.alpha_masks && !f.alpha_blend);
        materials.get_mut(used.material).unwrap().alpha_mode = AlphaMode::Blend;
        let f = SceneFeatures::gather([&used], [], &materials, &meshes, None);
        assert!(f.alpha_blend && !f.alpha_masks);
    }
}
