//! Edge cases and hostile input: an empty scene, a single triangle, 40,000 coincident
//! instances, NaN and infinite rays and instance transforms, and secondary rays leaving large
//! triangles 1e5 units away.

mod common;

use std::time::Instant;

use bevy_ecs::prelude::*;
use bevy_ecs::system::RunSystemOnce;
use chiaro_bvh::{BvhStats, InstanceRejection, Ray, SceneBvh, add_bvh_systems, offset_ray_origin};
use chiaro_scene::builtin::shapes::{icosphere, quad};
use chiaro_scene::{MaterialId, MeshId, MeshInstance, Transform, propagate_transforms};
use common::{Rng, add_mesh, spawn_instance, triangle_data};
use glam::{Quat, Vec3};

fn bad_rays() -> Vec<Ray> {
    let good = Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z);
    let mut rays = vec![
        Ray::new(Vec3::NAN, Vec3::NEG_Z),
        Ray::new(Vec3::new(0.2, f32::INFINITY, 1.0), Vec3::NEG_Z),
        Ray::new(good.origin, Vec3::new(0.0, 0.0, f32::NEG_INFINITY)),
        Ray::new(good.origin, Vec3::new(f32::NAN, 0.0, -1.0)),
        Ray::new(good.origin, Vec3::ZERO),
        Ray::new(good.origin, Vec3::new(0.0, 0.0, -1e-30)),
        Ray::new(good.origin, Vec3::new(0.0, 0.0, -1e30)),
        Ray::new(Vec3::splat(1e30), Vec3::NEG_Z),
        good.with_interval(f32::NAN, 10.0),
        good.with_interval(0.0, f32::NAN),
        good.with_interval(f32::INFINITY, f32::INFINITY),
        good.with_interval(5.0, 2.0),
    ];
    rays.push(good.with_interval(f32::NEG_INFINITY, 2.0));
    rays
}

fn assert_no_hits(bvh: &SceneBvh, rays: &[Ray]) {
    for ray in rays {
        assert_eq!(bvh.closest_hit(ray), None, "{ray:?}");
        assert!(!bvh.any_hit(ray), "{ray:?}");
        assert_eq!(bvh.closest_hit_with(ray, &|_| true), None, "{ray:?}");
        assert!(!bvh.any_hit_with(ray, &|_| true), "{ray:?}");
        assert_eq!(bvh.closest_hit_brute_force(ray), None, "{ray:?}");
    }
}

#[test]
fn empty_scene_has_no_hits() {
    let mut world = World::new();
    let bvh = SceneBvh::build(&mut world);
    assert!(bvh.instances().is_empty());
    assert!(bvh.bounds().is_empty());
    let mut rays = bad_rays();
    rays.push(Ray::new(Vec3::ZERO, Vec3::X));
    assert_no_hits(&bvh, &rays);

    // The system on an empty world creates both resources and stays idle afterwards.
    let mut schedule = Schedule::default();
    add_bvh_systems(&mut schedule);
    schedule.run(&mut world);
    schedule.run(&mut world);
    assert!(world.resource::<SceneBvh>().instances().is_empty());
    assert_eq!(world.resource::<BvhStats>().tlas_updates, 0);
}

#[test]
fn single_triangle_hits_and_misses() {
    let mut world = World::new();
    let mesh = add_mesh(&mut world, triangle_data([Vec3::ZERO, Vec3::X, Vec3::Y]));
    spawn_instance(&mut world, mesh, Transform::IDENTITY);
    let bvh = SceneBvh::build(&mut world);
    let hit = bvh
        .closest_hit(&Ray::new(Vec3::new(0.25, 0.5, 2.0), Vec3::NEG_Z))
        .unwrap();
    assert_eq!((hit.t, hit.instance, hit.triangle), (2.0, 0, 0));
    assert!((hit.barycentrics - glam::Vec2::new(0.25, 0.5)).length() < 1e-6);
    assert!(bvh.any_hit(&Ray::new(Vec3::new(0.25, 0.5, -2.0), Vec3::Z)));
    assert!(!bvh.any_hit(&Ray::new(Vec3::new(0.75, 0.75, 2.0), Vec3::NEG_Z)));
    // Invalid rays aimed straight at it still get nothing.
    assert_no_hits(&bvh, &bad_rays()[..12]);
    // The one valid ray of that list (t_min = -inf) hits.
    assert!(bvh.any_hit(&bad_rays()[12]));
}

#[test]
fn forty_thousand_coincident_instances_build_fast() {
    let mut world = World::new();
    let mesh = add_mesh(&mut world, icosphere(1, false));
    let instance = MeshInstance {
        mesh,
        material: MaterialId(0),
    };
    world.spawn_batch((0..40_000).map(|_| (instance, Transform::IDENTITY)));
    world.run_system_once(propagate_transforms).unwrap();

    let start = Instant::now();
    let bvh = SceneBvh::build(&mut world);
    let build = start.elapsed();
    eprintln!("SceneBvh::build, 40,000 coincident instances: {build:?}");
    assert_eq!(bvh.instances().len(), 40_000);
    assert!(build.as_secs_f64() < 1.0, "{build:?}");

    // Through the ECS system too, and a move of one of them.
    let mut schedule = Schedule::default();
    add_bvh_systems(&mut schedule);
    let start = Instant::now();
    schedule.run(&mut world);
    let first = start.elapsed();
    let moved = world.resource::<SceneBvh>().instances()[123].entity;
    world.get_mut::<Transform>(moved).unwrap().translation = Vec3::new(0.0, 0.0, 0.25);
    let start = Instant::now();
    schedule.run(&mut world);
    let update = start.elapsed();
    eprintln!("system: first run {first:?}, moving one of them {update:?}");
    assert!(first.as_secs_f64() < 1.0, "{first:?}");
    let stats = world.resource::<BvhStats>();
    assert_eq!((stats.tlas_builds, stats.tlas_updates), (1, 1));

    // Rays through the pile agree with brute force.
    let bvh = world.resource::<SceneBvh>();
    for ray in [
        Ray::new(Vec3::new(0.1, 0.2, 5.0), Vec3::NEG_Z),
        Ray::new(Vec3::new(3.0, 0.0, 0.0), Vec3::NEG_X),
    ] {
        assert_eq!(
            bvh.closest_hit(&ray).map(|h| h.t),
            bvh.closest_hit_brute_force(&ray).map(|h| h.t)
        );
        assert!(bvh.any_hit(&ray));
    }
}

#[test]
fn bad_instance_transforms_are_left_out_and_counted() {
    let mut world = World::new();
    let mesh = add_mesh(&mut world, triangle_data([Vec3::ZERO, Vec3::X, Vec3::Y]));
    let good = spawn_instance(&mut world, mesh, Transform::IDENTITY);
    let bad = [
        Transform::from_translation(Vec3::NAN),
        Transform::from_translation(Vec3::new(f32::INFINITY, 0.0, 0.0)),
        Transform::IDENTITY.with_scale(Vec3::new(1.0, 0.0, 1.0)),
        Transform::IDENTITY.with_scale(Vec3::splat(1e20)),
        Transform::IDENTITY.with_scale(Vec3::new(1e5, 1e-5, 1.0)),
        Transform::IDENTITY.with_rotation(Quat::from_xyzw(f32::NAN, 0.0, 0.0, 1.0)),
    ];
    let bad_entities: Vec<Entity> = bad
        .into_iter()
        .map(|t| spawn_instance(&mut world, mesh, t))
        .collect();
    let missing = spawn_instance(&mut world, MeshId(99), Transform::IDENTITY);

    let mut schedule = Schedule::default();
    add_bvh_systems(&mut schedule);
    schedule.run(&mut world);
    let stats = world.resource::<BvhStats>().clone();
    assert_eq!((stats.instances, stats.left_out_instances), (1, 7));
    let bvh = world.resource::<SceneBvh>();
    assert_eq!(bvh.instances()[0].entity, good);
    let reasons: std::collections::HashMap<Entity, InstanceRejection> = bvh.left_out().collect();
    assert_eq!(
        reasons[&missing],
        InstanceRejection::MissingMesh(MeshId(99))
    );
    assert_eq!(reasons[&bad_entities[2]], InstanceRejection::Singular);
    assert_eq!(reasons[&bad_entities[3]], InstanceRejection::HugeBounds);
    assert!(matches!(
        reasons[&bad_entities[4]],
        InstanceRejection::IllConditioned(_)
    ));
    for e in [bad_entities[0], bad_entities[1], bad_entities[5]] {
        assert_eq!(reasons[&e], InstanceRejection::NonFiniteMatrix);
    }
    assert!(bvh.any_hit(&Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z)));

    // Fixing one lets it in; breaking the good one takes it out.
    world
        .get_mut::<Transform>(bad_entities[0])
        .unwrap()
        .translation = Vec3::new(5.0, 0.0, 0.0);
    world.get_mut::<Transform>(good).unwrap().scale = Vec3::ZERO;
    schedule.run(&mut world);
    let stats = world.resource::<BvhStats>();
    assert_eq!((stats.instances, stats.left_out_instances), (1, 7));
    let bvh = world.resource::<SceneBvh>();
    assert_eq!(bvh.instances()[0].entity, bad_entities[0]);
    assert!(!bvh.any_hit(&Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z)));
    assert!(bvh.any_hit(&Ray::new(Vec3::new(5.2, 0.2, 1.0), Vec3::NEG_Z)));
}

/// Secondary rays leaving a hit point, offset with `offset_ray_origin`, never hit the triangle
/// they leave, on large triangles 1e5 units from the origin (placed directly and by a rotated
/// instance transform), in every direction of the side they leave from, grazing ones included.
#[test]
fn offset_secondary_rays_never_rehit_their_triangle() {
    let mut world = World::new();
    let h = 5.0e3;
    let corners = [
        Vec3::new(-h, 0.0, -h),
        Vec3::new(h, 300.0, -h),
        Vec3::new(h, -200.0, h),
        Vec3::new(-h, 100.0, h),
    ];
    let far = Vec3::new(1.0e5, -4.0e4, 7.0e4);
    let direct = add_mesh(&mut world, quad(corners.map(|c| c + far), Vec3::Y));
    let local = add_mesh(&mut world, quad(corners, Vec3::Y));
    spawn_instance(&mut world, direct, Transform::IDENTITY);
    spawn_instance(
        &mut world,
        local,
        Transform::from_translation(far + Vec3::new(0.0, 0.0, 3.0e4))
            .with_rotation(Quat::from_euler(glam::EulerRot::XYZ, 0.4, 0.3, -0.2)),
    );
    let bvh = SceneBvh::build(&mut world);
    let mut rng = Rng::new(99);
    let count = common::ray_count(20_000, 2_000);
    let (mut hits, mut secondary) = (0, 0);
    for i in 0..count {
        let instance = (i % 2) as u32;
        let tri = bvh.world_triangle(instance, rng.below(2) as u32).unwrap();
        let (a, b) = (rng.f32(), rng.f32());
        let (a, b) = if a + b > 1.0 {
            (1.0 - a, 1.0 - b)
        } else {
            (a, b)
        };
        let target = tri[0] + (tri[1] - tri[0]) * a + (tri[2] - tri[0]) * b;
        let origin = target + rng.unit_vector() * rng.range(10.0, 2.0e5);
        let Some(hit) = bvh.closest_hit(&Ray::new(origin, target - origin)) else {
            continue;
        };
        hits += 1;
        let p = bvh.hit_point(&hit).unwrap();
        let n = bvh.geometric_normal(&hit).unwrap();
        // Reflection leaves on the side the ray came from, transmission on the other.
        let incoming_side = if n.dot(origin - p) > 0.0 { n } else { -n };
        for side in [incoming_side, -incoming_side] {
            let start = offset_ray_origin(p, side);
            for k in 0..4 {
                // Uniform over the hemisphere, plus some within a milliradian of grazing.
                let mut d = rng.unit_vector();
                if d.dot(side) < 0.0 {
                    d = -d;
                }
                if k == 3 {
                    d = (d - side * d.dot(side)).normalize() + side * 1e-3;
                }
                secondary += 1;
                let ray = Ray::new(start, d);
                if let Some(again) = bvh.closest_hit(&ray) {
                    assert!(
                        (again.instance, again.triangle) != (hit.instance, hit.triangle),
                        "re-hit {hit:?} from {p} via {start} along {d}: {again:?}"
                    );
                }
            }
        }
    }
    eprintln!("{hits} hits, {secondary} secondary rays, none re-hit its own triangle");
    assert!(hits > count / 2);
}
