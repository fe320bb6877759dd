use bevy_ecs::world::World;

use crate::animation::pose_at;
use crate::info::SceneInfo;
use crate::material::AlphaMode;
use crate::mesh::Meshes;
use crate::scene_builder::SpawnedScene;
use crate::transform::GlobalTransform;
use crate::{ActiveCamera, Materials, load_scene};

use super::*;

fn load(spec: &str) -> (World, SpawnedScene) {
    let mut world = World::new();
    let spawned = load_scene(&mut world, spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
    (world, spawned)
}

#[test]
fn the_default_street_has_a_million_unique_triangles_and_everything_the_level_needs() {
    let (mut world, spawned) = load("builtin:walkthrough");
    assert!(spawned.repairs.is_empty(), "{:?}", spawned.repairs);
    let info = SceneInfo::gather(&mut world);
    assert!(
        info.mesh_triangles >= 1_000_000,
        "{} unique triangles",
        info.mesh_triangles
    );
    // Instancing: more triangles traced than stored.
    assert!(info.triangles > info.mesh_triangles);
    assert!(info.instances > info.meshes);
    let punctual = info.lights["point"] + info.lights["spot"];
    assert!(punctual >= 64, "{punctual} point and spot lights");
    assert!(info.lights["spot"] >= 8);
    assert_eq!(info.lights["directional"], 1, "the sun");
    assert!(
        info.environment.contains("walkthrough sky"),
        "{}",
        info.environment
    );
    assert!(info.emissive_triangles > 0, "emissive signs");
    // Textures: base colour, normal and metallic-roughness maps, and masked foliage.
    let slots: Vec<&str> = info
        .materials
        .iter()
        .flat_map(|m| m.texture_slots.clone())
        .collect();
    for slot in ["base colour", "normal", "metallic-roughness"] {
        assert!(
            slots.iter().any(|s| s.contains(slot)),
            "no {slot} texture in {slots:?}"
        );
    }
    let materials = world.resource::<Materials>();
    let masked = materials
        .iter()
        .any(|(_, m)| matches!(m.alpha_mode, AlphaMode::Mask { .. }));
    let metal = materials.iter().any(|(_, m)| m.metallic == 1.0);
    let glass = materials.iter().any(|(_, m)| m.transmission > 0.0);
    assert!(masked && metal && glass);
    // Motion: the camera path, doors, a fan and two balls.
    let clips: Vec<&str> = info
        .animations
        .iter()
        .map(|(name, _, _)| name.as_str())
        .collect();
    for clip in ["camera path", "doors", "fan", "ball"] {
        assert!(clips.contains(&clip), "no {clip} clip in {clips:?}");
    }
    assert_eq!(
        info.animations[clips.iter().position(|&c| c == "camera path").unwrap()].2 as f64,
        path_seconds(DEFAULT_BAYS)
    );
}

#[test]
fn the_same_seed_builds_the_same_street_and_another_seed_another() {
    let meshes = |spec: &str| -> Vec<Vec<glam::Vec3>> {
        let (world, _) = load(spec);
        let meshes = world.resource::<Meshes>();
        meshes.iter().map(|(_, m)| m.positions().to_vec()).collect()
    };
    let a = meshes("builtin:walkthrough?size=2&detail=1&seed=9");
    assert!(a == meshes("builtin:walkthrough?size=2&detail=1&seed=9"));
    assert!(a != meshes("builtin:walkthrough?size=2&detail=1&seed=10"));
}

#[test]
fn triangles_grow_with_bays_and_with_the_square_of_detail() {
    let triangles = |spec: &str| SceneInfo::gather(&mut load(spec).0).mesh_triangles as f64;
    let one = triangles("builtin:walkthrough?size=1&detail=1");
    let two = triangles("builtin:walkthrough?size=2&detail=1");
    let fine = triangles("builtin:walkthrough?size=1&detail=2");
    // The end of the street is a small fixed part; the rest is per bay.
    assert!((1.8..2.0).contains(&(two / one)), "{two} against {one}");
    assert!((3.5..4.1).contains(&(fine / one)), "{fine} against {one}");
    let e = crate::builtin::build("builtin:walkthrough?size=0")
        .unwrap_err()
        .to_string();
    assert!(e.contains("size and detail must be at least 1"), "{e}");
}

#[test]
fn posed_later_the_camera_has_walked_and_the_doors_have_opened() {
    let (mut world, spawned) = load("builtin:walkthrough?size=2&detail=1");
    let camera = world.resource::<ActiveCamera>().0;
    let door = spawned.entities[spawned
        .entities
        .iter()
        .position(|&e| {
            world
                .get::<bevy_ecs::name::Name>(e)
                .is_some_and(|n| n.as_str() == "door 0")
        })
        .unwrap()];
    pose_at(&mut world, 0.0);
    let start = world.get::<GlobalTransform>(camera).unwrap().0.translation;
    let shut = world.get::<GlobalTransform>(door).unwrap().0;
    pose_at(&mut world, f64::from(SECONDS_PER_BAY));
    let later = world.get::<GlobalTransform>(camera).unwrap().0.translation;
    assert!(
        (start.z - later.z - BAY).abs() < 1e-3,
        "{start} then {later}"
    );
    pose_at(&mut world, 2.0);
    let open = world.get::<GlobalTransform>(door).unwrap().0;
    // The leaf's far edge swung back from the wall, away from the street.
    let edge = |m: glam::Affine3A| m.transform_point3a(glam::Vec3A::new(1.2, 0.0, 0.0)).z;
    assert!(
        edge(open) < edge(shut) - 1.0,
        "{} against {}",
        edge(open),
        edge(shut)
    );
}
