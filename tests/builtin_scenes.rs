//! The built-in scenes build, and their `info` figures are the intended ones.

use bevy_ecs::world::World;
use chiaro::scene::builtin::{BUILTIN_SCENES, CASES_ALONE, HARD_CASES};
use chiaro::scene::{SceneInfo, SpawnedScene, load_scene};
use glam::Vec3;

fn info(spec: &str) -> (SceneInfo, SpawnedScene) {
    let mut world = World::new();
    let spawned = load_scene(&mut world, spec).unwrap_or_else(|e| panic!("{e}"));
    (SceneInfo::gather(&mut world), spawned)
}

fn lights(i: &SceneInfo) -> [usize; 3] {
    [i.lights["point"], i.lights["spot"], i.lights["directional"]]
}

#[test]
fn every_builtin_builds_with_its_own_camera_and_no_surprise_repairs() {
    for name in BUILTIN_SCENES {
        let (i, spawned) = info(&format!("builtin:{name}"));
        let camera = i.camera.as_ref().unwrap();
        assert!(!camera.automatic, "{name} should bring its camera");
        assert!(i.triangles > 0 && !i.bounds.is_empty(), "{name}");
        if name != "hard-cases" {
            assert!(spawned.repairs.is_empty(), "{name}: {:?}", spawned.repairs);
        }
    }
}

#[test]
fn cornell_box_matches_the_published_layout() {
    let (i, _) = info("builtin:cornell");
    assert_eq!(
        (i.meshes, i.mesh_triangles, i.instances, i.triangles),
        (8, 32, 8, 32)
    );
    assert_eq!(i.materials.len(), 4);
    assert_eq!(i.emissive_triangles, 2);
    assert_eq!(lights(&i), [0, 0, 0]);
    let camera = i.camera.unwrap();
    assert!(
        camera
            .position
            .abs_diff_eq(Vec3::new(0.278, 0.273, -0.8), 1e-6)
    );
    assert!(camera.forward.abs_diff_eq(Vec3::Z, 1e-6));
    assert!(
        (i.bounds.max - Vec3::new(0.556, 0.5488, 0.5592))
            .abs()
            .max_element()
            < 1e-6
    );
}

#[test]
fn cornell_box_is_pure_lambertian() {
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    let materials = world.resource::<chiaro::scene::Materials>();
    let mut count = 0;
    for (_, m) in materials.iter() {
        assert_eq!(m.specular, 0.0, "{}: specular layer", m.name);
        assert_eq!((m.metallic, m.roughness), (0.0, 1.0), "{}", m.name);
        count += 1;
    }
    assert_eq!(count, 4);
}

#[test]
fn furnace_is_a_closed_emitting_sphere_around_the_camera() {
    let (i, _) = info("builtin:furnace");
    assert_eq!(
        (i.meshes, i.triangles, i.emissive_triangles),
        (1, 5120, 5120)
    );
    let camera = i.camera.unwrap();
    assert!(camera.position.length() < 0.5 * i.bounds.size().min_element());
}

#[test]
fn hard_cases_drop_exactly_the_degenerate_triangles() {
    let (i, spawned) = info("builtin:hard-cases?case=degenerate");
    let actions: Vec<&str> = spawned.repairs.iter().map(|r| r.action.as_str()).collect();
    assert_eq!(
        actions,
        [
            "dropped 1 triangles with a repeated index (degenerate)",
            "dropped 3 triangles with zero area (collinear or coincident corners)"
        ]
    );
    assert!(
        spawned
            .repairs
            .iter()
            .all(|r| r.element == "mesh \"degenerate mesh\"")
    );
    // Floor quad and the two good triangles of the degenerate mesh.
    assert_eq!(i.triangles, 4);
}

#[test]
fn hard_cases_each_build_alone_and_together() {
    let mut total = 0;
    for case in HARD_CASES {
        let (i, _) = info(&format!("builtin:hard-cases?case={case}"));
        assert_eq!(lights(&i)[2], 1, "{case}: the shared sun");
        assert!(i.camera.unwrap().name.starts_with(case), "{case}");
        if !CASES_ALONE.contains(&case) {
            total += i.triangles;
        }
    }
    let (all, _) = info("builtin:hard-cases");
    assert_eq!(all.triangles, total);
}

#[test]
fn far_copy_is_the_lit_group_moved_1e5_along_x() {
    let (near, _) = info("builtin:hard-cases?case=lit-group");
    let (far, _) = info("builtin:hard-cases?case=far-copy");
    assert_eq!(near.triangles, far.triangles);
    assert_eq!(near.emissive_triangles, far.emissive_triangles);
    let offset = Vec3::new(1.0e5, 0.0, 0.0);
    assert!(
        (far.bounds.min - near.bounds.min - offset)
            .abs()
            .max_element()
            < 0.02
    );
    let (nc, fc) = (near.camera.unwrap(), far.camera.unwrap());
    assert!((fc.position - nc.position - offset).abs().max_element() < 0.02);
    assert!(fc.forward.abs_diff_eq(nc.forward, 1e-6));
}

#[test]
fn scale_case_spans_eight_orders_of_magnitude() {
    let (i, _) = info("builtin:hard-cases?case=scale");
    // The cube's 12, and the box's: 56 grid lines a side (the edges, and 27 on each side of the
    // cube from 5e-4 out by doubling), 55 x 55 cells on the top and on the bottom, 55 a side.
    assert_eq!(i.triangles, 12 + 2 * 2 * 55 * 55 + 4 * 2 * 55);
    assert!(i.bounds.size().x >= 1.0e5);
    // At the origin, where f32 resolves the cube to about 1e-10.
    let cube = Vec3::splat(5.0e-4);
    assert!(i.bounds.min.cmple(cube).all() && i.bounds.max.cmpge(cube).all());
    assert!(i.bounds.max.max_element() <= 5.0e4);
}

#[test]
fn instances_scale_with_n_and_share_one_mesh() {
    let (i, _) = info("builtin:instances?n=10000");
    assert_eq!((i.meshes, i.mesh_triangles), (2, 82));
    assert_eq!((i.instances, i.triangles), (10_001, 10_000 * 80 + 2));
    let (small, _) = info("builtin:instances?n=3");
    assert_eq!(small.instances, 4);
}

#[test]
fn many_lights_has_hundreds_of_emitters_and_punctual_lights() {
    let (i, _) = info("builtin:many-lights");
    assert_eq!(i.emissive_triangles, 256 * 2);
    assert_eq!(lights(&i), [171, 85, 0]);
    let (few, _) = info("builtin:many-lights?quads=3&lights=6");
    assert_eq!(few.emissive_triangles, 6);
    assert_eq!(lights(&few), [4, 2, 0]);
}

#[test]
fn unknown_case_is_an_error_naming_the_scene() {
    let mut world = World::new();
    let err = load_scene(&mut world, "builtin:hard-cases?case=nope")
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("builtin:hard-cases?case=nope: unknown case 'nope'"),
        "{err}"
    );
}
