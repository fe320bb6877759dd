//! The material extensions' textures on the GPU against the CPU reference: four cards under a
//! white sky, each over a dark base, with a 4x4 texture of different patterns per channel
//! (nearest texels) driving a mirror clear coat and its roughness, a sheen's colour and
//! roughness, a specular layer's strength and colour, and a thin-walled transmission. Both GPU
//! modes must agree with the CPU reference (`gpu_modes_match_the_cpu`): the cards' primary hits
//! find their UVs through the G-buffer's triangle target, the reflected and transmitted rays'
//! through their hits. The same cards without the textures are far from the textured reference,
//! so a frame that ignored the textures would fail. The pipeline feature is on for this scene
//! only.

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::Renderer;
use chiaro_scene::builtin::shapes::quad;
use chiaro_scene::material::{Filter, Sampler};
use chiaro_scene::texture::{ColorSpace, Texture};
use chiaro_scene::{LayerTextures, Material, SceneBuilder, SceneFeatures, TextureRef, Transform};
use glam::{Affine2, Vec3};
use hard_cases_common::{cpu_reference_unlike, gpu_modes_match_the_cpu};

/// Texel (x, y) of the 4x4 pattern: R stripes along x, G along y, B a checker of 2x2 blocks, A
/// a checker of texels.
fn texel(x: u8, y: u8) -> [u8; 4] {
    let on = |b: bool| if b { 255 } else { 0 };
    [
        on(x.is_multiple_of(2)),
        on(y.is_multiple_of(2)),
        on((x / 2 + y / 2).is_multiple_of(2)),
        on((x + y) % 2 == 1),
    ]
}

/// The cards; without `textured` their materials keep the factors alone.
fn cards(textured: bool) -> World {
    let mut b = SceneBuilder::new("layer textures");
    let rgba8: Vec<u8> = (0..16).flat_map(|i| texel(i % 4, i / 4)).collect();
    let mut pattern = |color_space| TextureRef {
        texture: b.add_texture(Texture {
            name: format!("pattern {color_space:?}"),
            width: 4,
            height: 4,
            rgba8: rgba8.clone(),
            color_space,
        }),
        uv_set: 0,
        transform: Affine2::IDENTITY,
        sampler: Sampler {
            mag_filter: Filter::Nearest,
            min_filter: Filter::Nearest,
            ..Sampler::default()
        },
    };
    let linear = Some(pattern(ColorSpace::Linear));
    let srgb = Some(pattern(ColorSpace::Srgb));
    let dark = |name| Material::diffuse(name, Vec3::splat(0.05), 0.7);
    let layers = |layer_textures: LayerTextures| {
        if textured {
            layer_textures
        } else {
            LayerTextures::default()
        }
    };
    let materials = [
        Material {
            clearcoat: 1.0,
            clearcoat_roughness: 0.6,
            layer_textures: layers(LayerTextures {
                clearcoat: linear,
                clearcoat_roughness: linear,
                ..LayerTextures::default()
            }),
            ..dark("coat")
        },
        Material {
            sheen_color: Vec3::ONE,
            sheen_roughness: 0.8,
            layer_textures: layers(LayerTextures {
                sheen_color: srgb,
                sheen_roughness: linear,
                ..LayerTextures::default()
            }),
            ..dark("sheen")
        },
        Material {
            roughness: 0.1,
            specular_color: Vec3::splat(8.0),
            layer_textures: layers(LayerTextures {
                specular: linear,
                specular_color: srgb,
                ..LayerTextures::default()
            }),
            ..dark("specular")
        },
        Material {
            transmission: 1.0,
            roughness: 0.0,
            layer_textures: layers(LayerTextures {
                transmission: linear,
                ..LayerTextures::default()
            }),
            ..dark("pane")
        },
    ];
    let corners = [(-0.45, -0.45), (0.45, -0.45), (0.45, 0.45), (-0.45, 0.45)]
        .map(|(x, y)| Vec3::new(x, y, 0.0));
    let mesh = b
        .add_mesh("mesh", "card", quad(corners, Vec3::Z))
        .unwrap()
        .unwrap();
    for (material, (x, y)) in
        materials
            .into_iter()
            .zip([(-0.5, 0.5), (0.5, 0.5), (-0.5, -0.5), (0.5, -0.5)])
    {
        let name = material.name.clone();
        let id = b.add_material(material);
        b.add_instance(
            &name,
            mesh,
            id,
            Transform::from_translation(Vec3::new(x, y, 0.0)),
        );
    }
    common::spawn_under_white_sky(b, Vec3::new(0.3, 0.2, 2.8))
}

#[test]
fn extension_textures_match_the_cpu_reference() {
    let size = 48;
    let mut world = cards(true);
    let cpu = cpu_reference_unlike(&mut world, &mut cards(false), "the textures", size, 256);
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    gpu_modes_match_the_cpu(&mut renderer, &mut world, &cpu, size, 48);
    let features = *world.resource::<SceneFeatures>();
    assert!(features.layer_textures, "{features:?}");
}
