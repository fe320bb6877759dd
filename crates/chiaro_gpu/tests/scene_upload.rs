//! Change-driven upload: the first frame uploads the scene, a frame with no change uploads
//! nothing, moving one instance writes that instance and the TLAS nodes only (and, a frame
//! later, its previous-frame transform), a material edit writes that material only, a light
//! edit the light table only, a new sky the area-light table and the scene info only. Light
//! trees are built only past the bounds up to which lights are all evaluated or picked by power.

mod common;

use bevy_ecs::prelude::*;
use chiaro_gpu::{GpuScene, add_gpu_scene_systems};
use chiaro_scene::{Materials, MeshInstance, Transform, load_scene};
use glam::Vec3;

fn last(world: &World) -> chiaro_gpu::UploadStats {
    world.resource::<GpuScene>().last.clone()
}

#[test]
fn uploads_follow_changes_only() {
    let Some(gpu) = common::gpu() else { return };
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    world.insert_resource(GpuScene::new(&gpu));
    let mut schedule = Schedule::default();
    add_gpu_scene_systems(&mut schedule);

    schedule.run(&mut world);
    let first = last(&world);
    assert!(first.bytes > 5_000, "first frame uploaded {first:?}");
    for label in ["scene vertices", "scene blas nodes", "scene materials"] {
        assert!(first.bytes_of(label) > 0, "{label} not uploaded");
    }
    assert!(world.resource::<GpuScene>().bind_group().is_some());

    schedule.run(&mut world);
    assert_eq!(last(&world).bytes, 0, "{:?}", last(&world));

    // Move one instance that does not emit.
    let materials = world.resource::<Materials>();
    let dark: Vec<bool> = (0..materials.len() as u32)
        .map(|i| {
            !materials
                .get(chiaro_scene::MaterialId(i))
                .unwrap()
                .is_emissive()
        })
        .collect();
    let mut query = world.query::<(Entity, &MeshInstance)>();
    let (entity, _) = query
        .iter(&world)
        .find(|(_, mi)| dark[mi.material.0 as usize])
        .expect("the Cornell box has a non-emissive instance");
    world.get_mut::<Transform>(entity).unwrap().translation += Vec3::new(0.01, 0.0, 0.0);
    schedule.run(&mut world);
    let moved = last(&world);
    assert_eq!(
        moved.written(),
        [
            "scene instance texels",
            "scene instances",
            "scene tlas nodes"
        ],
        "{moved:?}"
    );
    // The instance's record, for the shading passes and for the traversal.
    for copy in ["scene instances", "scene instance texels"] {
        assert_eq!(
            moved.bytes_of(copy),
            size_of::<chiaro_bvh::GpuInstance>() as u64,
            "{copy}"
        );
    }
    let tlas = world.resource::<GpuScene>().instances().len() * 2 - 1;
    assert!(moved.bytes_of("scene tlas nodes") <= (tlas * 32) as u64);

    // The next frame records the moved instance's new transform as the previous one.
    schedule.run(&mut world);
    let after = last(&world);
    assert_eq!(after.written(), ["scene instance extras"], "{after:?}");
    assert_eq!(after.bytes, 64);

    schedule.run(&mut world);
    assert_eq!(last(&world).bytes, 0);

    // A material edit rewrites that material's record only.
    world
        .resource_mut::<Materials>()
        .get_mut(chiaro_scene::MaterialId(0))
        .unwrap()
        .roughness = 0.25;
    schedule.run(&mut world);
    let edited = last(&world);
    assert_eq!(edited.written(), ["scene materials"], "{edited:?}");
    assert_eq!(
        edited.bytes,
        size_of::<chiaro_gpu::gpu_scene::layout::GpuMaterial>() as u64
    );
}

#[test]
fn light_and_environment_edits_rewrite_their_tables_only() {
    let Some(gpu) = common::gpu() else { return };
    let mut world = World::new();
    load_scene(&mut world, "builtin:many-lights?quads=4&lights=12").unwrap();
    world.insert_resource(GpuScene::new(&gpu));
    let mut schedule = Schedule::default();
    add_gpu_scene_systems(&mut schedule);
    schedule.run(&mut world);
    assert_eq!(world.resource::<GpuScene>().info.light_count, 12);
    schedule.run(&mut world);
    assert_eq!(last(&world).bytes, 0);

    // One light brighter: the light table (its record, and the selection CDF after it) and,
    // with more than ALL_PUNCTUAL_LIGHTS_MAX lights, the punctual light tree's power bounds.
    let mut lights = world.query::<&mut chiaro_scene::Light>();
    lights.iter_mut(&mut world).next().unwrap().intensity *= 2.0;
    schedule.run(&mut world);
    let edited = last(&world);
    assert_eq!(
        edited.written(),
        ["scene light tree", "scene lights"],
        "{edited:?}"
    );
    let lights_bytes = edited.bytes_of("scene lights");
    assert!((64..=12 * 64).contains(&lights_bytes), "{edited:?}");
    // The path from the light's leaf to the root, at most: 23 nodes of 64 bytes.
    assert!(edited.bytes_of("scene light tree") <= 23 * 64, "{edited:?}");

    // A constant sky: the scene info alone; a constant environment is not light-sampled
    // (`Environment::light_sampling_radiance`), so the area-light table stays as it was.
    world.insert_resource(chiaro_scene::Environment::constant(Vec3::splat(0.5)));
    schedule.run(&mut world);
    let sky = last(&world);
    assert_eq!(sky.written(), ["scene info"], "{sky:?}");
    let scene = world.resource::<GpuScene>();
    assert_eq!(
        scene.info.env_kind,
        chiaro_gpu::gpu_scene::layout::ENV_CONSTANT
    );
    assert_eq!(scene.info.env_pmf, 0.0);

    // An environment image joins the area-light table, with a share of the picks.
    let image = chiaro_scene::EquirectImage {
        path: "sky.hdr".into(),
        width: 4,
        height: 2,
        texels: vec![Vec3::splat(0.5); 8],
    };
    world.insert_resource(chiaro_scene::Environment {
        source: chiaro_scene::EnvironmentSource::Equirect(image),
        strength: 1.0,
        rotation: 0.0,
    });
    schedule.run(&mut world);
    let sky = last(&world);
    assert!(sky.written().contains(&"scene area lights"), "{sky:?}");
    let env_pmf = world.resource::<GpuScene>().info.env_pmf;
    assert!(env_pmf > 0.0 && env_pmf < 1.0, "{env_pmf}");
}

/// The light trees exist only with more than `ALL_PUNCTUAL_LIGHTS_MAX` punctual lights or more
/// than `AREA_LIGHTS_BY_POWER_MAX` emissive triangles (two per quad of builtin:many-lights).
#[test]
fn light_trees_only_past_their_bounds() {
    use chiaro_gpu::gpu_scene::layout::{
        ALL_PUNCTUAL_LIGHTS_MAX, AREA_LIGHTS_BY_POWER_MAX, NO_INDEX,
    };
    let Some(gpu) = common::gpu() else { return };
    let trees = |quads: usize, lights: u32| {
        let mut world = World::new();
        load_scene(
            &mut world,
            &format!("builtin:many-lights?quads={quads}&lights={lights}"),
        )
        .unwrap();
        world.insert_resource(GpuScene::new(&gpu));
        let mut schedule = Schedule::default();
        add_gpu_scene_systems(&mut schedule);
        schedule.run(&mut world);
        let scene = world.resource::<GpuScene>();
        assert_eq!(scene.info.area_count as usize, 2 * quads);
        (
            scene.info.area_tree != NO_INDEX,
            scene.info.punctual_tree != NO_INDEX,
            scene.light_trees(),
        )
    };
    let few_quads = AREA_LIGHTS_BY_POWER_MAX / 2;
    let few_lights = ALL_PUNCTUAL_LIGHTS_MAX;
    assert_eq!(trees(few_quads, few_lights), (false, false, false));
    assert_eq!(trees(few_quads + 1, few_lights), (true, false, true));
    assert_eq!(trees(few_quads, few_lights + 1), (false, true, true));
}
