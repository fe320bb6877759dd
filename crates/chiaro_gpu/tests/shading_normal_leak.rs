//! Shading normals do not leak light through a surface. A floor whose normal map tilts the
//! shading normal 60 degrees is lit only from below, by an emitter it hides from the camera; the
//! sky is black. A BRDF sample about the tilted normal can point below the geometric surface;
//! if the path went on through the floor it would find the emitter. The rule (DESIGN.md, hard
//! cases): a direction below the geometric surface, drawn from the BRDF or towards a light,
//! carries nothing, in every tracer. The floor's exact radiance is then 0: the CPU reference,
//! the GPU reference mode and the realtime frame must all return it (mean below 1e-6 of the
//! emitter's radiance of 10; before the rule the CPU reference's mean was 0.34).

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_reference::PathSettings;
use chiaro_scene::{
    Camera, ColorSpace, Material, MeshData, Node, Projection, SceneBuilder, Texture, TextureRef,
    Transform,
};
use glam::{Affine2, Vec2, Vec3, Vec4};
use hard_cases_common::{cpu_reference, mode, settings};

/// The emitter's radiance.
const EMITTED: f32 = 10.0;

/// A square of side `2 half` in the plane y = `height`, facing +y, with UVs and +x tangents.
fn square(half: f32, height: f32) -> MeshData {
    let p = |x: f32, z: f32| Vec3::new(x * half, height, z * half);
    MeshData {
        positions: vec![p(-1.0, -1.0), p(-1.0, 1.0), p(1.0, 1.0), p(1.0, -1.0)],
        normals: Some(vec![Vec3::Y; 4]),
        tangents: Some(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4]),
        uvs: [
            Some(vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(1.0, 0.0),
            ]),
            None,
        ],
        indices: Some(vec![0, 1, 2, 0, 2, 3]),
        ..MeshData::default()
    }
}

/// The floor (normal-mapped, tilted 60 degrees towards +x), the emitter 1 below it, and an
/// orthographic camera looking straight down at the floor's middle.
fn leak_scene() -> World {
    let (mut b, _) = tilted_floor(Material::lambertian("floor", Vec3::splat(0.8)));
    let emitter = b.add_material(Material {
        specular: 0.0,
        ..Material::emitter("emitter", Vec3::splat(EMITTED))
    });
    let emitter_mesh = b
        .add_mesh("mesh", "emitter", square(4.0, -1.0))
        .unwrap()
        .unwrap();
    b.add_instance("emitter", emitter_mesh, emitter, Transform::IDENTITY);
    let mut world = World::new();
    b.spawn(&mut world);
    world
}

/// A builder holding a floor of `material` with the 60-degree normal map, seen straight down by
/// an orthographic camera, and the floor's instance material.
fn tilted_floor(material: Material) -> (SceneBuilder, chiaro_scene::MaterialId) {
    let mut b = SceneBuilder::new("shading normal leak");
    // Tangent-space normal (sin 60, 0, cos 60), encoded as (n + 1) / 2.
    let tilt = Vec3::new(60f32.to_radians().sin(), 0.0, 60f32.to_radians().cos());
    let texel = ((tilt + Vec3::ONE) * 0.5 * 255.0).round();
    let normal_map = b.add_texture(Texture {
        name: "tilted normal".into(),
        width: 1,
        height: 1,
        rgba8: vec![texel.x as u8, texel.y as u8, texel.z as u8, 255],
        color_space: ColorSpace::Linear,
    });
    let mut floor = material;
    floor.normal_texture = Some(TextureRef {
        texture: normal_map,
        uv_set: 0,
        transform: Affine2::IDENTITY,
        sampler: Default::default(),
    });
    let floor = b.add_material(floor);
    let floor_mesh = b
        .add_mesh("mesh", "floor", square(2.0, 0.0))
        .unwrap()
        .unwrap();
    b.add_instance("floor", floor_mesh, floor, Transform::IDENTITY);
    b.add_node(Node {
        name: Some("camera".into()),
        transform: Transform::looking_at(Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, Vec3::NEG_Z),
        camera: Some(Camera {
            projection: Projection::Orthographic {
                xmag: 1.0,
                ymag: 1.0,
                znear: 0.0,
                zfar: 10.0,
            },
        }),
        ..Node::default()
    });
    (b, floor)
}

fn mean(image: &[Vec3]) -> f64 {
    image
        .iter()
        .map(|p| f64::from(p.x + p.y + p.z))
        .sum::<f64>()
        / (3 * image.len()) as f64
}

#[test]
fn the_cpu_reference_does_not_leak_through_a_normal_mapped_floor() {
    let mut world = leak_scene();
    let out = cpu_reference(&mut world, 16, 64, PathSettings::default());
    let m = mean(&out.image);
    eprintln!("CPU reference: floor mean {m:.3e} (emitter {EMITTED})");
    assert!(m < 1e-6 * f64::from(EMITTED), "light leaked: mean {m}");
}

#[test]
fn the_gpu_modes_do_not_leak_through_a_normal_mapped_floor() {
    let Some(gpu) = common::gpu() else { return };
    let mut world = leak_scene();
    let mut renderer = Renderer::new(gpu);
    for frame in [
        FrameSettings {
            spp: 4,
            ..mode(RenderMode::Reference)
        },
        mode(RenderMode::Realtime),
        mode(RenderMode::Naive),
    ] {
        let out = renderer
            .render(&mut world, &settings(16, 8, 1, frame))
            .unwrap();
        let m = mean(&out.hdr);
        eprintln!("{:?}: floor mean {m:.3e} (emitter {EMITTED})", frame.mode);
        assert!(
            m < 1e-6 * f64::from(EMITTED),
            "{:?}: light leaked, mean {m}",
            frame.mode
        );
    }
}

/// The other side of the rule: a smooth white metal floor with the same 60-degree normal map,
/// seen straight down under a white sky of radiance 1. The view's mirror reflection about the
/// mapped normal would point 30 degrees below the surface and carry nothing, so the floor would
/// be black; the shading normal is turned back just enough for the reflection to clear the
/// surface (chiaro_shading::shading_normal), and the floor reflects the sky: mean 1 within 2%
/// in the CPU reference and the GPU reference mode (it read 0 before the correction).
#[test]
fn a_mirror_with_a_steep_normal_map_still_reflects_the_sky() {
    let mirror = Material {
        metallic: 1.0,
        ..Material::diffuse("mirror", Vec3::ONE, 0.0)
    };
    let (mut b, _) = tilted_floor(mirror);
    b.set_environment(chiaro_scene::Environment::constant(Vec3::ONE));
    let mut world = World::new();
    b.spawn(&mut world);
    let cpu = cpu_reference(&mut world, 16, 16, PathSettings::default());
    eprintln!("CPU reference: mirror mean {:.4}", mean(&cpu.image));
    assert!(
        (mean(&cpu.image) - 1.0).abs() < 0.02,
        "{}",
        mean(&cpu.image)
    );
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let frame = FrameSettings {
        spp: 4,
        ..mode(RenderMode::Reference)
    };
    let out = renderer
        .render(&mut world, &settings(16, 4, 1, frame))
        .unwrap();
    eprintln!("GPU reference mode: mirror mean {:.4}", mean(&out.hdr));
    assert!((mean(&out.hdr) - 1.0).abs() < 0.02, "{}", mean(&out.hdr));
}
