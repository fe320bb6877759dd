//! Caustics from one small emitter, a 15 cm square, low to one side and out of the camera's
//! view: a polished metal ring (half a cylinder, roughness 0.02, its concave side to the light)
//! reflects it into a bright curve on the diffuse floor inside it (with a wall behind), and a glass sphere (a closed
//! volume of IOR 1.5) focuses it into a spot on the floor beyond it. Both are light that paths
//! from the camera reach only through a specular bounce toward a small light. Units are metres.
//! No environment: the emitter is the only light.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::error::SceneError;
use crate::material::{Material, Volume};
use crate::mesh_repair::MeshData;
use crate::scene_builder::SceneBuilder;
use crate::transform::Transform;

use super::add_shape;
use super::shapes::{append_band, floor, icosphere, quad};

/// Where the emitter's centre is.
const LIGHT: Vec3 = Vec3::new(2.8, 1.7, 1.2);
/// The emitter's side.
const LIGHT_SIZE: f32 = 0.15;
/// The emitter's radiance.
const RADIANCE: f32 = 1000.0;
/// The ring's centre on the floor, radius and height.
const RING: (Vec3, f32, f32) = (Vec3::new(-0.4, 0.0, -0.5), 0.4, 0.3);
/// Where the back wall stands (z), behind the ring.
const BACK_WALL: f32 = -1.5;
/// The glass sphere's centre and radius (it rests on the floor).
const SPHERE: (Vec3, f32) = (Vec3::new(0.5, 0.25, 0.7), 0.25);

/// Builds the scene into `b`: 5 meshes, 1,414 triangles, one camera.
pub(super) fn build(b: &mut SceneBuilder) -> Result<(), SceneError> {
    let ground = b.add_material(Material::lambertian("floor", Vec3::splat(0.7)));
    let metal = b.add_material(Material {
        metallic: 1.0,
        double_sided: true,
        ..Material::diffuse("polished metal", Vec3::new(0.97, 0.96, 0.91), 0.02)
    });
    let glass = b.add_material(Material {
        transmission: 1.0,
        volume: Some(Volume::default()),
        ..Material::diffuse("glass", Vec3::ONE, 0.0)
    });
    let light = b.add_material(Material::emitter(
        "light",
        Vec3::new(1.0, 0.95, 0.85) * RADIANCE,
    ));

    add_shape(b, "floor", ground, floor(6.0), Transform::IDENTITY)?;
    let back = [
        Vec3::new(-3.0, 0.0, BACK_WALL),
        Vec3::new(3.0, 0.0, BACK_WALL),
        Vec3::new(3.0, 2.5, BACK_WALL),
        Vec3::new(-3.0, 2.5, BACK_WALL),
    ];
    add_shape(
        b,
        "back wall",
        ground,
        quad(back, Vec3::Z),
        Transform::IDENTITY,
    )?;

    // The emitter, square to the line from it to the ring and the sphere between them.
    let (ring_center, ring_radius, ring_height) = RING;
    let (sphere_center, sphere_radius) = SPHERE;
    let aim = (0.5 * (ring_center + sphere_center) - LIGHT).normalize();
    let across = aim.cross(Vec3::Y).normalize() * (0.5 * LIGHT_SIZE);
    let up = across.cross(aim);
    let corners = [
        LIGHT - across - up,
        LIGHT + across - up,
        LIGHT + across + up,
        LIGHT - across + up,
    ];
    add_shape(b, "light", light, quad(corners, aim), Transform::IDENTITY)?;

    // The ring: the half turn that faces the light across its centre.
    let toward_light = LIGHT - ring_center;
    let light_angle = (-toward_light.z).atan2(toward_light.x);
    let mut ring = MeshData::default();
    append_band(
        &mut ring,
        Vec2::new(ring_radius, 0.0),
        Vec2::new(ring_radius, ring_height),
        light_angle + 0.5 * PI..light_angle + 1.5 * PI,
        64,
    );
    add_shape(
        b,
        "metal ring",
        metal,
        ring,
        Transform::from_translation(ring_center),
    )?;

    add_shape(
        b,
        "glass sphere",
        glass,
        icosphere(3, false),
        Transform::from_translation(sphere_center).with_scale(Vec3::splat(sphere_radius)),
    )?;

    b.add_camera(Vec3::new(0.2, 1.8, 2.6), Vec3::new(-0.1, 0.0, -0.1), 45.0);
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::Materials;
    use crate::load_scene;
    use bevy_ecs::world::World;

    use super::super::sight::Sight;
    use super::*;

    #[test]
    fn a_small_emitter_out_of_view_lights_it_alone() {
        let scene = Sight::load("builtin:caustic");
        scene.assert_lit_by_emitters_alone();
        assert_eq!(scene.info.emissive_triangles, 2);
        assert_eq!(scene.info.triangles, 1414);
        // Outside the view of any image up to twice as wide as high.
        let camera = scene.info.camera.as_ref().unwrap();
        let crate::Projection::Perspective { yfov, .. } = camera.projection else {
            panic!("a perspective camera");
        };
        let half_diagonal = ((0.5 * yfov).tan() * 5f32.sqrt()).atan();
        for c in scene.emitter_centroids() {
            let angle = camera.forward.angle_between(c - camera.position);
            assert!(angle > half_diagonal, "{angle} within {half_diagonal}");
        }
    }

    #[test]
    fn it_has_polished_metal_and_glass() {
        let mut world = World::new();
        load_scene(&mut world, "builtin:caustic").unwrap();
        let materials = world.resource::<Materials>();
        assert!(
            materials
                .iter()
                .any(|(_, m)| m.metallic == 1.0 && m.roughness <= 0.05)
        );
        assert!(
            materials
                .iter()
                .any(|(_, m)| m.transmission == 1.0 && m.volume.is_some() && m.ior > 1.0)
        );
    }

    #[test]
    fn the_ring_and_the_sphere_send_the_light_to_the_floor_near_them() {
        // The mirror's middle, half-way up, sends the emitter's centre back into the ring.
        let (center, radius, height) = RING;
        let toward_light = (LIGHT - center).with_y(0.0).normalize();
        let mirror = center - toward_light * radius + Vec3::Y * (0.5 * height);
        let incoming = (mirror - LIGHT).normalize();
        let reflected = incoming - 2.0 * incoming.dot(toward_light) * toward_light;
        assert!(reflected.y < 0.0);
        let landing = mirror + reflected * (mirror.y / -reflected.y);
        assert!(
            landing.with_y(0.0).distance(center) < 0.5 * radius,
            "{landing}"
        );
        // The ball lens's focus (paraxial, focal length n R / 2 (n - 1) from the centre, imaging
        // the emitter's distance) is near the floor.
        let (center, radius) = SPHERE;
        let focal = 1.5 * radius / (2.0 * 0.5);
        let distance = center.distance(LIGHT);
        let image = 1.0 / (1.0 / focal - 1.0 / distance);
        let focus = center + (center - LIGHT).normalize() * image;
        assert!(focus.y.abs() < 0.25 * radius, "{focus}");
    }
}
