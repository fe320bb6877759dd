//! Veach's door (Veach 1997, "Robust Monte Carlo Methods for Light Transport Simulation", fig.
//! 10.3): a room lit only through a door that stands ajar. The emitter, a panel on the far side
//! of the dividing wall, faces away from the door into the next room, so its light bounces at
//! least once before it slips into the camera's room, through the gap (12 cm) between the
//! door's free edge and its jamb or over the leaf, whose top leaves open the wedge between it
//! and the wall. Units are metres: two rooms 4 m wide and 2.6 m high either side of a 12 cm
//! wall, Lambertian walls, floor and furniture, and a glossy copper sphere on the table. No
//! environment: the panel is the only light.

use glam::{Quat, Vec3};

use crate::error::SceneError;
use crate::material::Material;
use crate::scene_builder::SceneBuilder;
use crate::transform::Transform;

use super::add_shape;
use super::shapes::{self, cuboid, icosphere, quad, room};

/// Half the rooms' width (along X).
const HALF_WIDTH: f32 = 2.0;
/// The rooms' height.
const HEIGHT: f32 = 2.6;
/// The dividing wall's thickness; it spans z from -WALL to 0, the camera's room z > 0.
const WALL: f32 = 0.12;
/// The camera's room's depth (along +Z).
const NEAR_DEPTH: f32 = 4.5;
/// The next room's depth (along -Z, from the dividing wall).
const FAR_DEPTH: f32 = 4.0;
/// The doorway's sides (x) and height.
const DOORWAY: [f32; 3] = [0.6, 1.5, 2.1];
/// The door leaf's thickness.
const LEAF: f32 = 0.04;
/// The opening between the door's free edge and the jamb.
const GAP: f32 = 0.12;
/// The panel's radiance.
const RADIANCE: f32 = 2500.0;

/// How far the leaf, hinged on the doorway's left side, is swung into the next room (radians)
/// for its free edge to stand GAP from the right jamb: a chord of the leaf's circle,
/// 2 w sin(angle / 2).
fn leaf_angle() -> f32 {
    let [left, right, _] = DOORWAY;
    2.0 * (0.5 * GAP / (right - left)).asin()
}

/// Builds the two rooms into `b`: 11 meshes, 1,426 triangles, one camera.
pub(super) fn build(b: &mut SceneBuilder) -> Result<(), SceneError> {
    let wall = b.add_material(Material::lambertian("wall", Vec3::new(0.75, 0.73, 0.7)));
    let floor = b.add_material(Material::lambertian("floor", Vec3::new(0.6, 0.48, 0.36)));
    let wood = b.add_material(Material::lambertian("door", Vec3::new(0.7, 0.66, 0.6)));
    let oak = b.add_material(Material::lambertian("table", Vec3::new(0.45, 0.3, 0.2)));
    let boxes = b.add_material(Material::lambertian("boxes", Vec3::new(0.65, 0.68, 0.72)));
    let copper = b.add_material(Material {
        metallic: 1.0,
        ..Material::diffuse("copper", Vec3::new(0.95, 0.64, 0.54), 0.25)
    });
    let light = b.add_material(Material::emitter(
        "panel",
        Vec3::new(1.0, 0.85, 0.65) * RADIANCE,
    ));

    // Both rooms' shell, seen from inside.
    let (min, max) = (
        Vec3::new(-HALF_WIDTH, 0.0, -WALL - FAR_DEPTH),
        Vec3::new(HALF_WIDTH, HEIGHT, NEAR_DEPTH),
    );
    let (shell, ground) = room(min, max);
    add_shape(b, "walls", wall, shell, Transform::IDENTITY)?;
    add_shape(b, "floor", floor, ground, Transform::IDENTITY)?;

    // The dividing wall around the doorway: left of it, right of it, above it.
    let [left, right, top] = DOORWAY;
    for (name, from, to) in [
        (
            "wall left of the door",
            Vec3::new(-HALF_WIDTH, 0.0, -WALL),
            Vec3::new(left, HEIGHT, 0.0),
        ),
        (
            "wall right of the door",
            Vec3::new(right, 0.0, -WALL),
            Vec3::new(HALF_WIDTH, HEIGHT, 0.0),
        ),
        (
            "wall over the door",
            Vec3::new(left, top, -WALL),
            Vec3::new(right, HEIGHT, 0.0),
        ),
    ] {
        add_shape(b, name, wall, cuboid(from, to), Transform::IDENTITY)?;
    }

    // The leaf, hinged on the doorway's left side, swung into the next room.
    let width = right - left;
    add_shape(
        b,
        "door leaf",
        wood,
        cuboid(Vec3::new(0.0, 0.0, -LEAF), Vec3::new(width, top, 0.0)),
        Transform::from_translation(Vec3::new(left, 0.0, -WALL))
            .with_rotation(Quat::from_rotation_y(leaf_angle())),
    )?;

    // The panel on the next room's side of the dividing wall, facing away from the door.
    let z = -WALL - 0.02;
    let panel = [
        Vec3::new(-1.6, 1.7, z),
        Vec3::new(-0.4, 1.7, z),
        Vec3::new(-0.4, 2.3, z),
        Vec3::new(-1.6, 2.3, z),
    ];
    add_shape(
        b,
        "panel",
        light,
        quad(panel, Vec3::NEG_Z),
        Transform::IDENTITY,
    )?;

    // The camera's room: a table with a copper sphere on it, and two boxes.
    let (table_min, table_max) = (Vec3::new(-1.5, 0.0, 1.6), Vec3::new(-0.3, 0.76, 2.4));
    add_shape(
        b,
        "table",
        oak,
        shapes::table(table_min, table_max),
        Transform::IDENTITY,
    )?;
    let radius = 0.14;
    add_shape(
        b,
        "copper sphere",
        copper,
        icosphere(3, false),
        Transform::from_translation(Vec3::new(-0.8, table_max.y + radius, 2.0))
            .with_scale(Vec3::splat(radius)),
    )?;
    add_shape(
        b,
        "box",
        boxes,
        cuboid(Vec3::new(1.0, 0.0, 2.6), Vec3::new(1.6, 0.5, 3.2)),
        Transform::IDENTITY,
    )?;
    add_shape(
        b,
        "turned box",
        boxes,
        cuboid(Vec3::new(-0.25, 0.0, -0.25), Vec3::new(0.25, 0.45, 0.25)),
        Transform::from_translation(Vec3::new(-1.3, 0.0, 0.7))
            .with_rotation(Quat::from_rotation_y(0.4)),
    )?;

    b.add_camera(Vec3::new(-1.6, 1.55, 4.3), Vec3::new(0.7, 0.85, 0.3), 60.0);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::sight::Sight;
    use super::*;

    #[test]
    fn the_camera_s_room_sees_the_panel_from_nowhere() {
        let scene = Sight::load("builtin:door");
        scene.assert_lit_by_emitters_alone();
        assert_eq!(scene.info.emissive_triangles, 2);
        assert_eq!(scene.info.triangles, 1426);
        assert!(scene.camera.z > 0.0, "the camera is in its room");
        assert!(scene.emitters_seen_from(scene.camera).is_empty());
        // Nor does any point of the camera's room: light reaches it after a bounce at least.
        for x in [-1.9, -1.0, 0.0, 1.0, 1.9] {
            for y in [0.05, 1.0, 2.0, 2.55] {
                for z in [0.05, 1.0, 2.5, 4.4] {
                    let at = Vec3::new(x, y, z);
                    assert!(scene.emitters_seen_from(at).is_empty(), "seen from {at}");
                }
            }
        }
        // The next room does see it.
        assert_eq!(
            scene.emitters_seen_from(Vec3::new(-1.0, 1.2, -3.0)).len(),
            2
        );
    }

    #[test]
    fn the_door_stands_open_by_the_gap() {
        let scene = Sight::load("builtin:door");
        // Through the middle of the gap, between the leaf's free edge and the jamb, from the
        // camera's room to the next one.
        let [left, right, _] = DOORWAY;
        let angle = leaf_angle();
        let edge = Vec3::new(
            left + (right - left) * angle.cos(),
            1.0,
            -WALL - (right - left) * angle.sin(),
        );
        let jamb = Vec3::new(right, 1.0, -WALL);
        assert!((edge.distance(jamb) - GAP).abs() < 1e-4);
        let middle = 0.5 * (edge + jamb);
        let across = Vec3::new(-0.2, 0.0, 1.0);
        let (near, far) = (middle + across, middle - 2.0 * across);
        assert!(near.z > 0.0 && far.z < -WALL && far.x < HALF_WIDTH);
        assert!(scene.clear(near, far));
        // A little to the left, the leaf is in the way.
        let left_by = Vec3::new(-0.3, 0.0, 0.0);
        assert!(!scene.clear(near + left_by, far + left_by));
    }
}
