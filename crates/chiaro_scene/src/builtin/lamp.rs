//! A room lit by one small emitter, a 5 cm glowing cube, hidden in a pendant lamp: an opaque
//! shade (a truncated cone closed at the top, open below, diffuse on both faces) hanging over a
//! table. The cube is seen only from under the shade, within about 40 degrees of straight down;
//! everything else in the room, the camera's view included, is lit through the shade's opening:
//! directly in the pool of light on the table and floor below it, after bounces elsewhere. Units
//! are metres: a room 5 m square and 2.7 m high, Lambertian surfaces. No environment.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use crate::error::SceneError;
use crate::material::Material;
use crate::mesh_repair::MeshData;
use crate::scene_builder::SceneBuilder;
use crate::transform::Transform;

use super::add_shape;
use super::shapes::{self, append_band, cuboid, icosphere, room};

/// Half the room's side.
const HALF: f32 = 2.5;
/// The room's height.
const HEIGHT: f32 = 2.7;
/// The shade's rim (radius, height) below and its top above.
const SHADE: [Vec2; 2] = [Vec2::new(0.25, 1.6), Vec2::new(0.1, 2.05)];
/// Segments around the shade.
const SEGMENTS: u32 = 32;
/// Half the glowing cube's side.
const BULB: f32 = 0.025;
/// Where the cube's centre is, on the shade's axis (x = z = 0).
const BULB_HEIGHT: f32 = 1.95;
/// The cube's radiance.
const RADIANCE: f32 = 1500.0;

/// Builds the room into `b`: 10 meshes, 548 triangles, one camera.
pub(super) fn build(b: &mut SceneBuilder) -> Result<(), SceneError> {
    let wall = b.add_material(Material::lambertian("wall", Vec3::new(0.75, 0.74, 0.7)));
    let floor = b.add_material(Material::lambertian("floor", Vec3::new(0.55, 0.42, 0.3)));
    let oak = b.add_material(Material::lambertian("table", Vec3::new(0.5, 0.35, 0.22)));
    let cloth = b.add_material(Material::lambertian("sofa", Vec3::new(0.25, 0.35, 0.55)));
    let white = b.add_material(Material::lambertian("cabinet", Vec3::splat(0.8)));
    let shade = b.add_material(Material {
        double_sided: true,
        ..Material::lambertian("shade", Vec3::new(0.85, 0.8, 0.7))
    });
    let light = b.add_material(Material::emitter(
        "bulb",
        Vec3::new(1.0, 0.8, 0.55) * RADIANCE,
    ));

    let (walls, ground) = room(Vec3::new(-HALF, 0.0, -HALF), Vec3::new(HALF, HEIGHT, HALF));
    add_shape(b, "walls", wall, walls, Transform::IDENTITY)?;
    add_shape(b, "floor", floor, ground, Transform::IDENTITY)?;

    // The lamp: the shade's wall and its closed top, a cord to the ceiling, the cube inside.
    let [rim, top] = SHADE;
    let mut lamp = MeshData::default();
    append_band(&mut lamp, rim, top, 0.0..TAU, SEGMENTS);
    append_band(&mut lamp, top, Vec2::new(0.0, top.y), 0.0..TAU, SEGMENTS);
    add_shape(b, "shade", shade, lamp, Transform::IDENTITY)?;
    add_shape(
        b,
        "cord",
        shade,
        cuboid(
            Vec3::new(-0.005, top.y, -0.005),
            Vec3::new(0.005, HEIGHT, 0.005),
        ),
        Transform::IDENTITY,
    )?;
    add_shape(
        b,
        "bulb",
        light,
        cuboid(Vec3::splat(-BULB), Vec3::splat(BULB)),
        Transform::from_translation(Vec3::Y * BULB_HEIGHT),
    )?;

    // Furniture: the table under the lamp with a vase on it, a sofa, a cabinet.
    add_shape(
        b,
        "table",
        oak,
        shapes::table(Vec3::new(-0.7, 0.0, -0.45), Vec3::new(0.7, 0.75, 0.45)),
        Transform::IDENTITY,
    )?;
    add_shape(
        b,
        "vase",
        white,
        icosphere(2, false),
        Transform::from_translation(Vec3::new(0.25, 0.95, 0.1))
            .with_scale(Vec3::new(0.1, 0.2, 0.1)),
    )?;
    for (name, material, min, max) in [
        (
            "sofa seat",
            cloth,
            Vec3::new(-2.4, 0.0, -1.2),
            Vec3::new(-1.6, 0.45, 1.0),
        ),
        (
            "sofa back",
            cloth,
            Vec3::new(-2.5, 0.0, -1.2),
            Vec3::new(-2.3, 0.9, 1.0),
        ),
        (
            "cabinet",
            white,
            Vec3::new(0.6, 0.0, -2.5),
            Vec3::new(1.8, 1.0, -2.05),
        ),
    ] {
        add_shape(b, name, material, cuboid(min, max), Transform::IDENTITY)?;
    }

    b.add_camera(Vec3::new(2.1, 1.5, 2.2), Vec3::new(-0.3, 0.8, -0.2), 60.0);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::sight::Sight;
    use super::*;

    #[test]
    fn the_bulb_is_seen_only_from_under_the_shade() {
        let scene = Sight::load("builtin:lamp");
        scene.assert_lit_by_emitters_alone();
        assert_eq!(scene.info.emissive_triangles, 12);
        assert_eq!(scene.info.triangles, 548);
        assert!(scene.emitters_seen_from(scene.camera).is_empty());
        // Not from anywhere in the room 1.7 m or more from the lamp's axis, at any height.
        for x in [-2.2, -1.2, 1.2, 2.2] {
            for z in [-2.2, -1.2, 1.2, 2.2] {
                for y in [0.5, 1.2, 1.9, 2.6] {
                    let at = Vec3::new(x, y, z);
                    assert!(scene.emitters_seen_from(at).is_empty(), "seen from {at}");
                }
            }
        }
        // The table under it sees it through the opening.
        assert!(
            !scene
                .emitters_seen_from(Vec3::new(0.0, 0.8, 0.0))
                .is_empty()
        );
    }
}
