//! Closest-hit and any-hit agree with brute force (every triangle of every instance, same
//! watertight test) on the built-in scenes.
//!
//! Rays per scene: 100,000 in optimised builds (`cargo test --release`); fewer in debug builds,
//! where the crate under test is unoptimised (numbers in each test). `CHIARO_BVH_RAYS=N`
//! overrides both.

mod common;

use bevy_ecs::prelude::*;
use chiaro_bvh::SceneBvh;
use common::{assert_agrees, compare, ray_count, scene_rays};

fn check_scene(spec: &str, debug_rays: usize, min_hit_fraction: f64) {
    let mut world = World::new();
    chiaro_scene::load_scene(&mut world, spec).unwrap();
    let bvh = SceneBvh::build(&mut world);
    assert!(bvh.left_out().next().is_none());
    let rays = scene_rays(
        &bvh,
        ray_count(100_000, debug_rays),
        0x5eed ^ spec.len() as u64,
    );
    assert_agrees(spec, &compare(&bvh, &rays), min_hit_fraction);
}

#[test]
fn cornell_agrees_with_brute_force() {
    check_scene("builtin:cornell", 50_000, 0.5);
}

#[test]
fn hard_cases_agree_with_brute_force() {
    check_scene("builtin:hard-cases", 2_000, 0.3);
}

#[test]
fn instances_agree_with_brute_force() {
    check_scene("builtin:instances?n=400", 2_000, 0.3);
}

#[test]
fn far_copy_agrees_with_brute_force() {
    // The lit group alone and its copy 1e5 units away: rays there start and end at 1e5.
    check_scene("builtin:hard-cases?case=far-copy", 10_000, 0.3);
}
