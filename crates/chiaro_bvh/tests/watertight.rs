//! Closed meshes are closed: rays aimed exactly at shared vertices and edges of a cube and an
//! icosphere, through the BVH, from inside and from up to 1e5 units outside, never escape, and
//! agree with brute force. Each mesh is placed three ways: as is, rotated and non-uniformly
//! scaled, and translated 1e5 units.

mod common;

use bevy_ecs::prelude::*;
use chiaro_bvh::{Ray, SceneBvh};
use chiaro_scene::Transform;
use chiaro_scene::builtin::shapes::{cuboid, icosphere};
use common::{Rng, add_mesh, assert_agrees, compare, ray_count, spawn_instance};
use glam::{Quat, Vec3};

/// Builds a world with one instance of the mesh placed by `transform`.
fn scene(data: chiaro_scene::MeshData, transform: Transform) -> SceneBvh {
    let mut world = World::new();
    let mesh = add_mesh(&mut world, data);
    spawn_instance(&mut world, mesh, transform);
    SceneBvh::build(&mut world)
}

/// Targets: every vertex, every edge midpoint and a random point of every edge, object space.
fn targets(bvh: &SceneBvh, rng: &mut Rng) -> Vec<Vec3> {
    let mut out = Vec::new();
    let blas = bvh.blas(bvh.instances()[0].mesh).unwrap();
    for t in blas.triangles() {
        let v = t.vertices();
        for k in 0..3 {
            let (a, b) = (v[k], v[(k + 1) % 3]);
            out.extend([a, a.lerp(b, 0.5), a.lerp(b, rng.f32())]);
        }
    }
    out
}

fn placements() -> [(&'static str, Transform); 3] {
    [
        ("as is", Transform::IDENTITY),
        (
            "rotated and scaled",
            Transform::from_translation(Vec3::new(3.0, -2.0, 1.0))
                .with_rotation(Quat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.7))
                .with_scale(Vec3::new(2.5, 0.5, 1.5)),
        ),
        (
            "1e5 away",
            Transform::from_translation(Vec3::new(1.0e5, -3.0e4, 2.0e4)),
        ),
    ]
}

fn check_closed(name: &str, data: chiaro_scene::MeshData, center_object: Vec3) {
    for (placement, transform) in placements() {
        let bvh = scene(data.clone(), transform);
        let world = bvh.instances()[0].world;
        let center = world.transform_point3(center_object);
        let mut rng = Rng::new(7);
        let mut rays = Vec::new();
        for target in targets(&bvh, &mut rng) {
            let p = world.transform_point3(target);
            // From the inside, straight at the vertex or edge point.
            rays.push(Ray::new(center, p - center));
            // From outside, through the point towards the inside: the line enters the solid
            // (chosen in object space, where the shapes are convex and round enough that a
            // direction within ~12 degrees of the centre's enters; an affine map keeps lines).
            for distance in [1.0f32, 10.0, 1e3, 1e5] {
                let outward =
                    ((target - center_object).normalize() + rng.unit_vector() * 0.2).normalize();
                let origin = world.transform_point3(target + outward * distance);
                rays.push(Ray::new(origin, p - origin));
            }
        }
        let rays: Vec<Ray> = rays
            .into_iter()
            .take(ray_count(usize::MAX, 20_000))
            .collect();
        let escaped: Vec<&Ray> = rays
            .iter()
            .filter(|r| bvh.closest_hit(r).is_none())
            .collect();
        assert!(
            escaped.is_empty(),
            "{name} {placement}: {} of {} rays escaped, e.g. {:?}",
            escaped.len(),
            rays.len(),
            &escaped[..escaped.len().min(3)]
        );
        assert!(rays.iter().all(|r| bvh.any_hit(r)));
        assert_agrees(&format!("{name} {placement}"), &compare(&bvh, &rays), 1.0);
    }
}

#[test]
fn cube_has_no_cracks() {
    check_closed(
        "cube",
        cuboid(Vec3::splat(-1.0), Vec3::splat(1.0)),
        Vec3::ZERO,
    );
}

#[test]
fn icosphere_has_no_cracks() {
    check_closed("icosphere", icosphere(3, false), Vec3::ZERO);
}
