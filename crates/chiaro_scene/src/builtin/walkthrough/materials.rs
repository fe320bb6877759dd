//! The walkthrough's materials: textured stone and marble, metals, a dielectric sculpture
//! stone, wood, alpha-masked foliage, a glass ball with a tinted medium, and emissive signs.

use glam::{Affine2, Vec3, Vec4};

use crate::material::{AlphaMode, Material, MaterialId, Sampler, TextureRef, Volume};
use crate::scene_builder::SceneBuilder;
use crate::texture::TextureId;

use super::textures::Textures;

/// The materials, as added to a builder.
pub struct Palette {
    /// Dressed stone (columns, arches, facades, stairs, planters).
    pub stone: MaterialId,
    /// Polished marble tiles (the paving).
    pub marble: MaterialId,
    /// Sculpture materials, used in turn: bronze, gold, white stone.
    pub sculptures: [MaterialId; 3],
    /// Dark wood (doors, benches).
    pub wood: MaterialId,
    /// Brushed steel (the fan, a ball).
    pub steel: MaterialId,
    /// Leaves, cut out by their texture's alpha.
    pub foliage: MaterialId,
    /// Clear glass, green-tinted inside.
    pub glass: MaterialId,
    /// Sign colours, used in turn.
    pub signs: [MaterialId; 4],
}

fn texture(texture: TextureId) -> Option<TextureRef> {
    Some(TextureRef {
        texture,
        uv_set: 0,
        transform: Affine2::IDENTITY,
        sampler: Sampler::default(),
    })
}

/// A fully textured dielectric: base colour, normal and metallic-roughness maps.
fn textured(name: &str, [color, normal, metal_rough]: [TextureId; 3]) -> Material {
    Material {
        name: name.to_owned(),
        base_color_texture: texture(color),
        normal_texture: texture(normal),
        metallic_roughness_texture: texture(metal_rough),
        ..Material::default()
    }
}

fn metal(name: &str, color: Vec3, roughness: f32) -> Material {
    Material {
        name: name.to_owned(),
        base_color: color.extend(1.0),
        metallic: 1.0,
        roughness,
        ..Material::default()
    }
}

/// Adds the textures and materials to `b`.
pub fn add(b: &mut SceneBuilder, textures: Textures) -> Palette {
    let stone = [
        b.add_texture(textures.stone_color),
        b.add_texture(textures.stone_normal),
        b.add_texture(textures.stone_metal_rough),
    ];
    let marble = [
        b.add_texture(textures.marble_color),
        b.add_texture(textures.marble_normal),
        b.add_texture(textures.marble_metal_rough),
    ];
    let leaf = b.add_texture(textures.leaf);
    let sign_colors = [
        Vec3::new(1.0, 0.35, 0.1),
        Vec3::new(0.2, 0.6, 1.0),
        Vec3::new(1.0, 0.2, 0.5),
        Vec3::new(0.4, 1.0, 0.3),
    ];
    Palette {
        stone: b.add_material(textured("stone", stone)),
        marble: b.add_material(textured("marble", marble)),
        sculptures: [
            b.add_material(metal("bronze", Vec3::new(0.8, 0.5, 0.3), 0.35)),
            b.add_material(metal("gold", Vec3::new(1.0, 0.78, 0.34), 0.2)),
            b.add_material(Material::diffuse(
                "white stone",
                Vec3::new(0.85, 0.83, 0.8),
                0.25,
            )),
        ],
        wood: b.add_material(Material::diffuse("wood", Vec3::new(0.3, 0.15, 0.07), 0.6)),
        steel: b.add_material(metal("steel", Vec3::new(0.6, 0.6, 0.62), 0.4)),
        foliage: b.add_material(Material {
            name: "foliage".into(),
            base_color_texture: texture(leaf),
            metallic: 0.0,
            roughness: 0.7,
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            double_sided: true,
            ..Material::default()
        }),
        glass: b.add_material(Material {
            name: "glass".into(),
            base_color: Vec4::ONE,
            metallic: 0.0,
            roughness: 0.0,
            transmission: 1.0,
            volume: Some(Volume {
                attenuation_color: Vec3::new(0.7, 0.95, 0.85),
                attenuation_distance: 0.5,
            }),
            ..Material::default()
        }),
        signs: sign_colors.map(|c| b.add_material(Material::emitter("sign", c * 6.0))),
    }
}
