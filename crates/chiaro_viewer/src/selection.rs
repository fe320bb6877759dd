//! Picking: the entity under a pixel of the frame, found by a CPU ray from the active camera
//! through the scene BVH (the `SceneBvh` resource the renderer's systems keep current).

use bevy_ecs::prelude::*;
use chiaro_bvh::{Ray, SceneBvh};
use chiaro_gpu::camera::{GpuCamera, active_camera};
use glam::{Vec2, Vec3};

/// The primary ray through the point (`x`, `y`) of a `width` x `height` image (pixels from the
/// top-left corner; (0.5, 0.5) is the first pixel's centre) from the active camera, built the way
/// the frame builds its rays.
pub fn camera_ray(world: &World, x: f32, y: f32, width: u32, height: u32) -> Option<Ray> {
    let (camera, global) = active_camera(world).ok()?;
    let c = GpuCamera::new(&camera, &global, width, height, Vec2::splat(0.5), None);
    let ndc = Vec2::new(2.0 * x / width as f32 - 1.0, 1.0 - 2.0 * y / height as f32);
    let (right, up, forward) = (Vec3::from(c.right), Vec3::from(c.up), Vec3::from(c.forward));
    let origin = Vec3::from(c.origin);
    let ray = if c.orthographic == 1 {
        Ray::new(origin + right * ndc.x + up * ndc.y, forward)
    } else {
        Ray::new(origin, forward + right * ndc.x + up * ndc.y)
    };
    ray.is_valid().then_some(ray)
}

/// The mesh instance seen at (`x`, `y`) of a `width` x `height` frame, if any.
pub fn pick(world: &World, x: f32, y: f32, width: u32, height: u32) -> Option<Entity> {
    let ray = camera_ray(world, x, y, width, height)?;
    let bvh = world.get_resource::<SceneBvh>()?;
    let hit = bvh.closest_hit(&ray)?;
    Some(bvh.instances().get(hit.instance as usize)?.entity)
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{MeshInstance, Name, load_scene};

    fn name(world: &World, entity: Entity) -> String {
        world
            .get::<Name>(entity)
            .map_or(String::new(), |n| n.as_str().to_ascii_lowercase())
    }

    #[test]
    fn picks_the_walls_of_the_cornell_box() {
        let mut world = World::new();
        load_scene(&mut world, "builtin:cornell").unwrap();
        let bvh = SceneBvh::build(&mut world);
        world.insert_resource(bvh);
        let (w, h) = (64, 64);
        let left = pick(&world, 1.5, 20.5, w, h).expect("the left wall");
        let right = pick(&world, 62.5, 20.5, w, h).expect("the right wall");
        let middle = pick(&world, 32.0, 40.0, w, h).expect("something in the middle");
        for entity in [left, right, middle] {
            assert!(world.get::<MeshInstance>(entity).is_some());
        }
        assert_ne!(left, right);
        assert!(
            name(&world, left).contains("left"),
            "{}",
            name(&world, left)
        );
        assert!(
            name(&world, right).contains("right"),
            "{}",
            name(&world, right)
        );
        // The ray through the image centre is the camera's axis.
        let ray = camera_ray(&world, 32.0, 32.0, w, h).unwrap();
        let (_, global) = active_camera(&world).unwrap();
        let axis = global.transform_vector(Vec3::NEG_Z).normalize();
        assert!(ray.direction.normalize().dot(axis) > 0.99999);
    }
}
