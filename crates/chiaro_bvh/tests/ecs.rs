//! Change detection: `update_scene_bvh` does exactly the work changes call for, and queries
//! see the result.

mod common;

use bevy_ecs::prelude::*;
use chiaro_bvh::{BvhStats, InstanceRejection, Ray, SceneBvh, add_bvh_systems};
use chiaro_scene::builtin::shapes::{cuboid, icosphere};
use chiaro_scene::{MaterialId, Mesh, MeshId, MeshInstance, Meshes, Transform};
use common::{add_mesh, spawn_instance};
use glam::Vec3;

struct App {
    world: World,
    schedule: Schedule,
}

impl App {
    fn new() -> Self {
        let mut schedule = Schedule::default();
        add_bvh_systems(&mut schedule);
        Self {
            world: World::new(),
            schedule,
        }
    }

    fn run(&mut self) -> BvhStats {
        self.schedule.run(&mut self.world);
        self.world.resource::<BvhStats>().clone()
    }

    fn bvh(&self) -> &SceneBvh {
        self.world.resource::<SceneBvh>()
    }

    /// The entity the ray straight down onto `x` hits first, if any.
    fn hit_below(&self, x: f32) -> Option<Entity> {
        let ray = Ray::new(Vec3::new(x, 10.0, 0.0), Vec3::NEG_Y);
        let hit = self.bvh().closest_hit(&ray)?;
        Some(self.bvh().instances()[hit.instance as usize].entity)
    }
}

/// Ten unit cubes along X at x = 0, 3, 6, ...
fn ten_cubes() -> (App, MeshId, Vec<Entity>) {
    let mut app = App::new();
    let cube = add_mesh(&mut app.world, cuboid(Vec3::splat(-0.5), Vec3::splat(0.5)));
    let cubes = (0..10)
        .map(|i| {
            spawn_instance(
                &mut app.world,
                cube,
                Transform::from_translation(Vec3::X * 3.0 * i as f32),
            )
        })
        .collect();
    (app, cube, cubes)
}

#[test]
fn nothing_changed_means_nothing_done() {
    let (mut app, _, cubes) = ten_cubes();
    let first = app.run();
    assert_eq!(
        (first.blas_builds, first.tlas_builds, first.tlas_updates),
        (1, 1, 0)
    );
    assert_eq!(first.instances, 10);
    let tick = app.world.resource_ref::<SceneBvh>().last_changed();
    for _ in 0..3 {
        assert_eq!(app.run(), first, "idle frames count nothing");
    }
    assert_eq!(
        app.world.resource_ref::<SceneBvh>().last_changed(),
        tick,
        "SceneBvh untouched"
    );
    assert_eq!(app.hit_below(3.0), Some(cubes[1]));
    // Writing an identical transform is not a move either (propagation writes only changes).
    app.world
        .get_mut::<Transform>(cubes[2])
        .unwrap()
        .translation = Vec3::X * 6.0;
    assert_eq!(app.run(), first);
}

#[test]
fn moving_one_instance_refits_and_hits_follow() {
    let (mut app, _, cubes) = ten_cubes();
    let before = app.run();
    // A small move (a large one may trigger a rebuild, see the last test).
    app.world
        .get_mut::<Transform>(cubes[4])
        .unwrap()
        .translation = Vec3::new(13.2, 0.0, 0.0);
    let after = app.run();
    assert_eq!(after.tlas_updates, before.tlas_updates + 1);
    assert_eq!(
        after.tlas_builds, before.tlas_builds,
        "a move is a refit, not a rebuild"
    );
    assert_eq!(after.blas_builds, before.blas_builds);
    assert_eq!(app.hit_below(12.0), None, "gone from where it was");
    assert_eq!(app.hit_below(13.5), Some(cubes[4]), "found where it went");
    assert_eq!(app.hit_below(15.0), Some(cubes[5]));
    let index = app.bvh().instance_of(cubes[4]).unwrap() as usize;
    assert_eq!(
        app.bvh().instances()[index].world.translation,
        Vec3::new(13.2, 0.0, 0.0).into()
    );

    // Moving a parent moves its child's hits too.
    let parent = app.world.spawn(Transform::IDENTITY).id();
    app.world
        .entity_mut(cubes[7])
        .insert(bevy_ecs::hierarchy::ChildOf(parent));
    let parented = app.run();
    assert_eq!(app.hit_below(22.0), None);
    app.world.get_mut::<Transform>(parent).unwrap().translation = Vec3::new(0.6, 0.0, 0.0);
    let moved = app.run();
    assert_eq!(
        (moved.tlas_builds, moved.tlas_updates),
        (parented.tlas_builds, parented.tlas_updates + 1)
    );
    assert_eq!(app.hit_below(22.0), Some(cubes[7]), "child at 21 + 0.6");
}

#[test]
fn adding_a_mesh_builds_exactly_one_blas() {
    let (mut app, _, _) = ten_cubes();
    let before = app.run();
    let sphere = add_mesh(&mut app.world, icosphere(2, false));
    let after = app.run();
    assert_eq!(after.blas_builds, before.blas_builds + 1);
    assert_eq!(
        (after.tlas_builds, after.tlas_updates),
        (before.tlas_builds, before.tlas_updates),
        "no instance uses it yet"
    );
    assert!(app.bvh().blas(sphere).is_some());

    let ball = spawn_instance(
        &mut app.world,
        sphere,
        Transform::from_translation(Vec3::new(40.0, 0.0, 0.0)),
    );
    let added = app.run();
    assert_eq!(
        added.blas_builds, after.blas_builds,
        "the BLAS is shared, not rebuilt"
    );
    assert_eq!(added.tlas_builds, after.tlas_builds + 1);
    assert_eq!(added.instances, 11);
    assert_eq!(app.hit_below(40.0), Some(ball));
    // A second instance of it: no BLAS either.
    spawn_instance(
        &mut app.world,
        sphere,
        Transform::from_translation(Vec3::new(50.0, 0.0, 0.0)),
    );
    assert_eq!(app.run().blas_builds, added.blas_builds);
    assert_eq!(app.bvh().blases().count(), 2);
}

#[test]
fn removing_an_instance_removes_its_hits() {
    let (mut app, _, cubes) = ten_cubes();
    let before = app.run();
    app.world.entity_mut(cubes[3]).remove::<MeshInstance>();
    let after = app.run();
    assert_eq!(after.tlas_builds, before.tlas_builds + 1);
    assert_eq!(after.instances, 9);
    assert_eq!(app.hit_below(9.0), None);
    assert_eq!(app.bvh().instance_of(cubes[3]), None);

    app.world.despawn(cubes[5]);
    let despawned = app.run();
    assert_eq!(despawned.tlas_builds, after.tlas_builds + 1);
    assert_eq!(app.hit_below(15.0), None);
    assert_eq!(app.hit_below(18.0), Some(cubes[6]));
    assert_eq!(app.run(), despawned, "removal is seen once");
}

#[test]
fn editing_a_material_updates_the_record_only() {
    let (mut app, _, cubes) = ten_cubes();
    let before = app.run();
    app.world
        .get_mut::<MeshInstance>(cubes[2])
        .unwrap()
        .material = MaterialId(5);
    let after = app.run();
    assert_eq!(
        (after.tlas_builds, after.tlas_updates),
        (before.tlas_builds, before.tlas_updates + 1)
    );
    let index = app.bvh().instance_of(cubes[2]).unwrap() as usize;
    assert_eq!(app.bvh().instances()[index].material, MaterialId(5));
}

#[test]
fn an_instance_waits_for_its_mesh() {
    let (mut app, _, _) = ten_cubes();
    app.run();
    // Refers to the next mesh id, not added yet.
    let waiting = spawn_instance(
        &mut app.world,
        MeshId(1),
        Transform::from_translation(Vec3::new(60.0, 0.0, 0.0)),
    );
    let before = app.run();
    assert_eq!(before.left_out_instances, 1);
    assert_eq!(
        app.bvh().left_out().collect::<Vec<_>>(),
        vec![(waiting, InstanceRejection::MissingMesh(MeshId(1)))]
    );
    assert_eq!(app.hit_below(60.0), None);
    let mesh = Mesh::new("late", cuboid(Vec3::splat(-1.0), Vec3::ONE))
        .unwrap()
        .0;
    app.world.resource_mut::<Meshes>().add(mesh);
    let after = app.run();
    assert_eq!(after.blas_builds, before.blas_builds + 1);
    assert_eq!(after.tlas_builds, before.tlas_builds + 1);
    assert_eq!((after.instances, after.left_out_instances), (11, 0));
    assert_eq!(app.hit_below(60.0), Some(waiting));
}

#[test]
fn far_moves_reinsert_and_scattering_many_rebuilds() {
    let mut app = App::new();
    let cube = add_mesh(&mut app.world, cuboid(Vec3::splat(-0.5), Vec3::splat(0.5)));
    let grid = |i: usize| Vec3::new((i % 32) as f32 * 2.0, 0.0, (i / 32) as f32 * 2.0);
    let cubes: Vec<Entity> = (0..1000)
        .map(|i| spawn_instance(&mut app.world, cube, Transform::from_translation(grid(i))))
        .collect();
    let before = app.run();
    // One cube thrown far away, then another across the grid: re-inserted, not rebuilt.
    app.world
        .get_mut::<Transform>(cubes[0])
        .unwrap()
        .translation
        .y = 1.0e4;
    app.world
        .get_mut::<Transform>(cubes[1])
        .unwrap()
        .translation = grid(999) + Vec3::Y * 3.0;
    let far = app.run();
    assert_eq!(
        (far.tlas_builds, far.tlas_updates),
        (before.tlas_builds, before.tlas_updates + 1)
    );
    assert_eq!(app.hit_below(0.0), None, "cube 0 went up");
    assert_eq!(app.hit_below(4.0), Some(cubes[2]));
    // Scattering a third of them (more than an eighth: one refit pass) degrades the tree past
    // the rebuild threshold.
    for (k, &e) in cubes.iter().enumerate().take(333) {
        app.world.get_mut::<Transform>(e).unwrap().translation =
            grid((k * 389) % 1000) + Vec3::Y * 0.5;
    }
    let scattered = app.run();
    assert_eq!(scattered.tlas_builds, far.tlas_builds + 1);
    let bvh = app.bvh();
    for x in [0.0, 10.0, 20.0, 40.0] {
        let ray = Ray::new(Vec3::new(x, 1.0e5, 0.0), Vec3::NEG_Y);
        assert_eq!(
            bvh.closest_hit(&ray).map(|h| h.t),
            bvh.closest_hit_brute_force(&ray).map(|h| h.t)
        );
    }
}

#[test]
fn a_replaced_meshes_store_rebuilds_everything() {
    let (mut app, _, cubes) = ten_cubes();
    let before = app.run();
    // A new store whose mesh 0 is a big sphere instead of the cube.
    let mut meshes = Meshes::default();
    meshes.add(Mesh::new("ball", icosphere(2, false)).unwrap().0);
    app.world.insert_resource(meshes);
    let after = app.run();
    assert_eq!(after.blas_builds, before.blas_builds + 1);
    assert_eq!(after.tlas_builds, before.tlas_builds + 1);
    // The sphere has radius 1 where the cube had half-width 0.5.
    let hit = app
        .bvh()
        .closest_hit(&Ray::new(Vec3::new(0.0, 10.0, 0.0), Vec3::NEG_Y))
        .unwrap();
    assert!((hit.t - 9.0).abs() < 0.01, "{}", hit.t);
    assert_eq!(app.hit_below(0.0), Some(cubes[0]));
    assert_eq!(app.run(), after);

    // A mesh replaced in place under its id is noticed too.
    let tall = Mesh::new(
        "tall",
        cuboid(Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 5.0, 0.5)),
    )
    .unwrap()
    .0;
    *app.world
        .resource_mut::<Meshes>()
        .get_mut(MeshId(0))
        .unwrap() = tall;
    let edited = app.run();
    assert_eq!(edited.blas_builds, after.blas_builds + 1);
    assert_eq!(edited.tlas_builds, after.tlas_builds + 1);
    let hit = app
        .bvh()
        .closest_hit(&Ray::new(Vec3::new(0.0, 10.0, 0.0), Vec3::NEG_Y))
        .unwrap();
    assert_eq!(hit.t, 5.0);
}
