//! Loads a scene into a bevy_ecs World, keeps its world matrices current with chiaro's system in
//! the app's own schedule, and lists the entities: what an ECS app sees after a load.
//!
//! `cargo run --example inspect_scene -- [SCENE]` (default builtin:cornell).

use bevy_ecs::prelude::*;
use chiaro::scene::{
    Camera, GlobalTransform, Light, MeshInstance, Name, load_scene, propagate_transforms,
};

fn main() -> anyhow::Result<()> {
    let spec = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "builtin:cornell".to_owned());
    let mut world = World::new();
    let spawned = load_scene(&mut world, &spec)?;
    for repair in &spawned.repairs {
        println!("repaired: {repair}");
    }
    let mut schedule = Schedule::default();
    schedule.add_systems(propagate_transforms);
    schedule.run(&mut world);

    let mut query = world.query::<(Entity, Option<&Name>, &GlobalTransform)>();
    for (entity, name, global) in query.iter(&world) {
        let what = if let Some(i) = world.get::<MeshInstance>(entity) {
            format!("mesh {} material {}", i.mesh.0, i.material.0)
        } else if let Some(l) = world.get::<Light>(entity) {
            format!("{:?} light", l.kind)
        } else if world.get::<Camera>(entity).is_some() {
            "camera".to_owned()
        } else {
            "node".to_owned()
        };
        let name = name.map_or_else(|| entity.to_string(), |n| n.to_string());
        println!("{name}: {what} at {:.3}", global.translation());
    }
    Ok(())
}
