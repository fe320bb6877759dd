//! KHR_materials_clearcoat's own normal texture on the GPU against the CPU reference: two
//! cards under a checkered sky, their glossy coats bent by a 4x4 normal texture of different
//! tilts (nearest texels). One has a dark base; the other a rough metal base with its own,
//! different normal texture, which must not reach the coat. Both GPU modes must agree with the
//! CPU reference (`gpu_modes_match_the_cpu`): the primary hits rebuild the coat's normal from
//! the G-buffer's triangle target, the reflected rays' at their hits. The same cards without
//! the coat's texture are far from the textured reference, so a frame that ignored it would
//! fail.

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::Renderer;
use chiaro_scene::builtin::shapes::quad;
use chiaro_scene::material::{Filter, Sampler};
use chiaro_scene::texture::{ColorSpace, Texture};
use chiaro_scene::{
    Environment, EnvironmentSource, EquirectImage, Material, MeshData, SceneBuilder, SceneFeatures,
    TextureRef, Transform,
};
use glam::{Affine2, Vec3};
use hard_cases_common::{cpu_reference_unlike, gpu_modes_match_the_cpu};

/// A 4x4 normal texture: texel (x, y) tilts toward +X by `x` steps and toward +Y by `y` (or
/// the other way round when `transposed`), up to about 30 degrees.
fn normal_texture(transposed: bool) -> Texture {
    let tilt = |i: u8| 64 + 42 * i;
    let rgba8 = (0..16u8)
        .flat_map(|i| {
            let (x, y) = if transposed {
                (i / 4, i % 4)
            } else {
                (i % 4, i / 4)
            };
            [tilt(x), tilt(y), 230, 255]
        })
        .collect();
    Texture {
        name: format!("tilts (transposed: {transposed})"),
        width: 4,
        height: 4,
        rgba8,
        color_space: ColorSpace::Linear,
    }
}

/// A sky of 16 x 8 patches, bright and dim in a checker, so a glossy reflection shows where
/// its normal points.
fn checkered_sky() -> Environment {
    let (width, height) = (64, 32);
    let texels = (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            if (x / 4 + y / 4) % 2 == 0 {
                Vec3::new(8.0, 7.0, 6.0)
            } else {
                Vec3::new(0.4, 0.5, 0.6)
            }
        })
        .collect();
    Environment {
        source: EnvironmentSource::Equirect(EquirectImage {
            path: "checkered sky".into(),
            width,
            height,
            texels,
        }),
        strength: 1.0,
        rotation: 0.3,
    }
}

/// The cards; without `coat_textured` the coats keep the interpolated normal.
fn cards(coat_textured: bool) -> World {
    let mut b = SceneBuilder::new("coat normals");
    let nearest = Sampler {
        mag_filter: Filter::Nearest,
        min_filter: Filter::Nearest,
        ..Sampler::default()
    };
    let mut slot = |transposed| TextureRef {
        texture: b.add_texture(normal_texture(transposed)),
        uv_set: 0,
        transform: Affine2::IDENTITY,
        sampler: nearest,
    };
    let coat_map = slot(false);
    let base_map = slot(true);
    let coat = |name, clearcoat_roughness, base: Material| Material {
        clearcoat: 1.0,
        clearcoat_roughness,
        clearcoat_normal_texture: coat_textured.then_some(coat_map),
        clearcoat_normal_scale: 1.5,
        ..Material { name, ..base }
    };
    let materials = [
        coat(
            "coat over a dark base".into(),
            0.05,
            Material::diffuse("", Vec3::ZERO, 0.7),
        ),
        coat(
            "coat over a mapped metal".into(),
            0.02,
            Material {
                metallic: 1.0,
                normal_texture: Some(base_map),
                ..Material::diffuse("", Vec3::new(0.4, 0.3, 0.2), 0.1)
            },
        ),
    ];
    let corners = [(-0.45, -0.45), (0.45, -0.45), (0.45, 0.45), (-0.45, 0.45)]
        .map(|(x, y)| Vec3::new(x, y, 0.0));
    let data = MeshData {
        tangent_uv_set: Some(0),
        ..quad(corners, Vec3::Z)
    };
    let mesh = b.add_mesh("mesh", "card", data).unwrap().unwrap();
    for (material, x) in materials.into_iter().zip([-0.5, 0.5]) {
        let name = material.name.clone();
        let id = b.add_material(material);
        let at = Transform::from_translation(Vec3::new(x, 0.0, 0.0));
        b.add_instance(&name, mesh, id, at);
    }
    b.add_camera(Vec3::new(0.15, -0.9, 1.6), Vec3::ZERO, 45.0);
    b.set_environment(checkered_sky());
    let mut world = World::new();
    b.spawn(&mut world);
    world
}

#[test]
fn coat_normal_texture_matches_the_cpu_reference() {
    let size = 48;
    let mut world = cards(true);
    let without = &mut cards(false);
    let cpu = cpu_reference_unlike(&mut world, without, "the coat's texture", size, 1024);
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    gpu_modes_match_the_cpu(&mut renderer, &mut world, &cpu, size, 192);
    let features = *world.resource::<SceneFeatures>();
    assert!(features.normal_maps && features.clearcoat, "{features:?}");
}
