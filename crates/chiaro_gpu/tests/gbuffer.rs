//! The G-buffer's motion vectors: after one instance moves, the pixels showing it point back to
//! where its surface was in the previous frame (projected on the CPU), and the pixels of the
//! static rest point nowhere; after the camera moves, every pixel's vector is the camera's
//! reprojection. Its geometric normals: each pixel's is the face normal of the triangle its
//! position lies on. And the renderer's bad input (no camera, a zero or oversized image, a read
//! before any render) gives an error naming the fault.

mod common;

use std::collections::HashMap;

use bevy_ecs::prelude::*;
use chiaro_gpu::{FrameSettings, GpuContext, RenderMode, RenderSettings, Renderer};
use chiaro_scene::{
    ActiveCamera, GlobalTransform, Materials, MeshInstance, Meshes, Transform, load_scene,
};
use glam::{Mat4, Vec2, Vec3};

/// Pixel coordinates of world point `p` under `view_proj` in a `size` image.
fn pixel(view_proj: Mat4, p: Vec3, size: f32) -> Vec2 {
    let c = view_proj * p.extend(1.0);
    Vec2::new(
        (c.x / c.w + 1.0) * 0.5 * size,
        (1.0 - c.y / c.w) * 0.5 * size,
    )
}

/// `scene` loaded and rendered for `frames` frames of the direct mode at `size` x `size` (the
/// G-buffer is all these tests read): the world, the renderer and the settings, for more frames.
fn rendered(
    gpu: GpuContext,
    scene: &str,
    size: u32,
    frames: u32,
) -> (World, Renderer, RenderSettings) {
    let mut world = World::new();
    load_scene(&mut world, scene).unwrap();
    let mut renderer = Renderer::new(gpu);
    let settings = RenderSettings {
        width: size,
        height: size,
        frames,
        frame: FrameSettings {
            mode: RenderMode::Direct,
            ..FrameSettings::default()
        },
        ..RenderSettings::default()
    };
    renderer.render(&mut world, &settings).unwrap();
    (world, renderer, settings)
}

#[test]
fn motion_vectors_follow_instances_and_the_camera() {
    let Some(gpu) = common::gpu() else { return };
    let size = 32;
    let (mut world, mut renderer, settings) = rendered(gpu, "builtin:cornell", size, 2);
    let still = renderer.read_gbuffer().unwrap();
    let covered = still.instance.iter().filter(|i| i.is_some()).count();
    assert!(covered > 900, "{covered} pixels covered");
    for (i, m) in still.motion.iter().enumerate() {
        assert!(m.length() < 1e-3, "pixel {i} moves by {m} in a still scene");
    }

    // Move the first non-emissive instance's entity sideways.
    let materials = world.resource::<Materials>();
    let emissive: Vec<bool> = materials.iter().map(|(_, m)| m.is_emissive()).collect();
    let mut query = world.query::<(Entity, &MeshInstance)>();
    let (entity, _) = query
        .iter(&world)
        .find(|(_, mi)| !emissive[mi.material.0 as usize])
        .unwrap();
    let step = Vec3::new(0.05, 0.0, 0.0);
    world.get_mut::<Transform>(entity).unwrap().translation += step;
    renderer.accumulate(&mut world, &settings, 1).unwrap();
    let moved = renderer.read_gbuffer().unwrap();
    let bvh = world.resource::<chiaro_bvh::SceneBvh>();
    let index = bvh.instance_of(entity).unwrap();
    let camera_entity = world.resource::<ActiveCamera>().0;
    let (camera, global) = (
        *world.get::<chiaro_scene::Camera>(camera_entity).unwrap(),
        *world
            .get::<chiaro_scene::GlobalTransform>(camera_entity)
            .unwrap(),
    );
    let view_proj =
        chiaro_gpu::camera::GpuCamera::new(&camera, &global, size, size, Vec2::ZERO, None)
            .unjittered();
    let mut checked = 0;
    for (i, instance) in moved.instance.iter().enumerate() {
        let Some(instance) = instance else { continue };
        let m = moved.motion[i];
        if *instance == index {
            let p = moved.position[i];
            let expected =
                pixel(view_proj, p - step, size as f32) - pixel(view_proj, p, size as f32);
            assert!(
                (m - expected).length() < 1e-2 && expected.length() > 0.1,
                "pixel {i}: motion {m}, expected {expected}"
            );
            checked += 1;
        } else {
            assert!(m.length() < 1e-3, "static pixel {i} moves by {m}");
        }
    }
    assert!(
        checked > 10,
        "only {checked} pixels show the moved instance"
    );

    // Turn the camera a little: every pixel moves by the camera's reprojection.
    let mut transform = world.get_mut::<Transform>(camera_entity).unwrap();
    transform.rotation = glam::Quat::from_rotation_y(0.02) * transform.rotation;
    renderer.accumulate(&mut world, &settings, 1).unwrap();
    let turned = renderer.read_gbuffer().unwrap();
    let global = *world
        .get::<chiaro_scene::GlobalTransform>(camera_entity)
        .unwrap();
    let now = chiaro_gpu::camera::GpuCamera::new(&camera, &global, size, size, Vec2::ZERO, None)
        .unjittered();
    let mut checked = 0;
    for (i, instance) in turned.instance.iter().enumerate() {
        if instance.is_none() {
            continue;
        }
        let p = turned.position[i];
        let expected = pixel(view_proj, p, size as f32) - pixel(now, p, size as f32);
        assert!(
            (turned.motion[i] - expected).length() < 1e-2,
            "pixel {i}: motion {}, expected {expected}",
            turned.motion[i]
        );
        checked += 1;
    }
    assert!(
        checked > 800,
        "only {checked} pixels covered after the turn"
    );
    eprintln!("{checked} pixels checked after the turn");
}

/// Whether `p` lies on triangle `t`, within `tolerance` of its plane and of its edges.
fn lies_on(t: &[Vec3; 3], p: Vec3, tolerance: f32) -> bool {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let n = e1.cross(e2);
    if (d.dot(n) / n.length()).abs() > tolerance {
        return false;
    }
    // Barycentrics of p's projection, each scaled to a distance from its edge.
    let area = n.length_squared();
    let b1 = d.cross(e2).dot(n) / area;
    let b2 = e1.cross(d).dot(n) / area;
    let heights = [e1.length(), e2.length(), (t[2] - t[1]).length()].map(|l| n.length() / l);
    let distances = [
        (1.0 - b1 - b2) * heights[2],
        b1 * heights[1],
        b2 * heights[0],
    ];
    distances.iter().all(|&h| h >= -tolerance)
}

#[test]
fn geometric_normals_are_the_faces_seen() {
    // Icosphere instances (80 faces each; neighbouring faces differ by about 20 degrees) over a
    // ground plane, each triangle reaching the fragment stage with its own index
    // (chiaro_gpu::gpu_scene::raster) and its normal made there.
    let Some(gpu) = common::gpu() else { return };
    let size = 48;
    let (mut world, renderer, _) = rendered(gpu, "builtin:instances?n=16", size, 1);
    let g = renderer.read_gbuffer().unwrap();
    // Every instance's world-space triangles, by its index in the BVH.
    let mut triangles: HashMap<u32, Vec<[Vec3; 3]>> = HashMap::new();
    let mut query = world.query::<(Entity, &MeshInstance, &GlobalTransform)>();
    let (bvh, meshes) = (
        world.resource::<chiaro_bvh::SceneBvh>(),
        world.resource::<Meshes>(),
    );
    for (entity, instance, global) in query.iter(&world) {
        let mesh = meshes.get(instance.mesh).unwrap();
        let p = mesh.positions();
        let corners = |t: &[u32]| [0, 1, 2].map(|k| global.0.transform_point3(p[t[k] as usize]));
        let index = bvh.instance_of(entity).unwrap();
        triangles.insert(index, mesh.indices().chunks_exact(3).map(corners).collect());
    }
    let mut inside = 0;
    for (i, instance) in g.instance.iter().enumerate() {
        let Some(instance) = instance else { continue };
        let (point, normal) = (g.position[i], g.geometric_normal[i]);
        // The faces the point lies on: one, or two or more on an edge or a corner.
        let faces: Vec<Vec3> = triangles[instance]
            .iter()
            .filter(|t| lies_on(t, point, 1e-4))
            .map(|t| (t[1] - t[0]).cross(t[2] - t[0]).normalize())
            .collect();
        assert!(
            !faces.is_empty(),
            "pixel {i}: {point} on no triangle of instance {instance}"
        );
        assert!(
            faces.iter().any(|f| f.dot(normal).abs() > 0.9999),
            "pixel {i}: geometric normal {normal}, but {point} lies on faces {faces:?}"
        );
        inside += usize::from(faces.len() == 1);
    }
    assert!(
        inside > (size * size / 4) as usize,
        "{inside} pixels inside one face"
    );
}

#[test]
fn a_camera_inside_a_closed_mesh_sees_its_inside() {
    // The icosphere is closed and faces outward, so seen from outside its back faces are culled
    // (chiaro_gpu::gpu_scene::back_faces); from its centre they are all there is to see.
    let Some(gpu) = common::gpu() else { return };
    let size = 32;
    // A first frame places everything in the world.
    let (mut world, mut renderer, settings) = rendered(gpu, "builtin:instances?n=1", size, 1);
    let mut query = world.query::<(Entity, &MeshInstance, &GlobalTransform)>();
    let meshes = world.resource::<Meshes>();
    let (sphere, centre) = query
        .iter(&world)
        .find(|(_, instance, _)| meshes.get(instance.mesh).unwrap().indices().len() == 3 * 80)
        .map(|(entity, _, global)| (entity, Vec3::from(global.0.translation)))
        .unwrap();
    let camera = world.resource::<ActiveCamera>().0;
    world.get_mut::<Transform>(camera).unwrap().translation = centre;
    renderer.render(&mut world, &settings).unwrap();
    let g = renderer.read_gbuffer().unwrap();
    let index = world
        .resource::<chiaro_bvh::SceneBvh>()
        .instance_of(sphere)
        .unwrap();
    let inside = g.instance.iter().filter(|i| **i == Some(index)).count();
    assert_eq!(
        inside,
        g.instance.len(),
        "pixels seeing the sphere from its centre"
    );
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let settings = RenderSettings {
        width: 8,
        height: 8,
        frames: 1,
        ..RenderSettings::default()
    };
    assert!(matches!(
        renderer.read(&settings),
        Err(chiaro_gpu::RenderError::NotRendered)
    ));
    // A world without a camera.
    let mut world = World::new();
    let err = renderer.render(&mut world, &settings).unwrap_err();
    assert!(err.to_string().contains("no active camera"), "{err}");
    // A zero or oversized image.
    load_scene(&mut world, "builtin:cornell").unwrap();
    for (width, height) in [(0, 8), (8, 1 << 20)] {
        let err = renderer
            .render(
                &mut world,
                &RenderSettings {
                    width,
                    height,
                    ..settings
                },
            )
            .unwrap_err();
        assert!(
            err.to_string().contains(&format!("{width}x{height}")),
            "{err}"
        );
    }
    // The same renderer still renders afterwards.
    let image = renderer.render(&mut world, &settings).unwrap();
    assert_eq!(image.hdr.len(), 64);
}
