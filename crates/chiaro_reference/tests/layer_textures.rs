//! Each material extension's texture multiplies its factor by the channel its extension names:
//! a card whose texture is one texel of four different channel values renders as the same card
//! with no texture and the factor times that channel (decoded from sRGB for the colour
//! textures), pixel for pixel with the same seed.

use bevy_ecs::world::World;
use chiaro_reference::{PathSettings, RenderSettings, rel_mse, render_world};
use chiaro_scene::builtin::shapes::quad;
use chiaro_scene::material::Sampler;
use chiaro_scene::texture::{ColorSpace, Texture};
use chiaro_scene::{Environment, LayerTextures, Material, SceneBuilder, TextureRef, Transform};
use chiaro_shading::color::srgb_to_linear;
use glam::{Affine2, Vec3, Vec4};

/// The single texel: a different value in each channel.
const TEXEL: [u8; 4] = [51, 153, 204, 102];

/// The card's image under a white sky, 16x16, 16 paths a pixel, seed 3.
fn render(material: Material, texture: Option<Texture>) -> Vec<Vec3> {
    let mut b = SceneBuilder::new("card");
    if let Some(texture) = texture {
        b.add_texture(texture);
    }
    let id = b.add_material(material);
    let corners =
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
    let mesh = b
        .add_mesh("mesh", "card", quad(corners, Vec3::Z))
        .unwrap()
        .unwrap();
    b.add_instance("card", mesh, id, Transform::IDENTITY);
    b.add_camera(Vec3::new(0.5, 0.8, 2.0), Vec3::ZERO, 60.0);
    b.set_environment(Environment::constant(Vec3::ONE));
    let mut world = World::new();
    b.spawn(&mut world);
    let settings = RenderSettings {
        width: 16,
        height: 16,
        spp: 16,
        seed: 3,
        sampler: chiaro_reference::Sampler::default(),
        threads: Some(1),
        path: PathSettings::default(),
    };
    render_world(&mut world, &settings, false).unwrap().image
}

/// A base with every layer on, so each texture has a factor to act on.
fn layered() -> Material {
    Material {
        specular: 0.9,
        specular_color: Vec3::new(1.5, 1.0, 0.5),
        clearcoat: 0.8,
        clearcoat_roughness: 0.5,
        transmission: 0.7,
        sheen_color: Vec3::new(0.9, 0.6, 0.3),
        sheen_roughness: 0.6,
        ..Material::diffuse("card", Vec3::new(0.3, 0.2, 0.1), 0.4)
    }
}

#[test]
fn each_texture_multiplies_its_factor_by_its_channel() {
    let linear = Vec4::from_array(TEXEL.map(|c| f32::from(c) / 255.0));
    let srgb = Vec4::new(
        srgb_to_linear(linear.x),
        srgb_to_linear(linear.y),
        srgb_to_linear(linear.z),
        linear.w,
    );
    type Apply = fn(&mut Material, Vec4, &mut LayerTextures, Option<TextureRef>);
    let cases: [(&str, ColorSpace, Apply); 7] = [
        ("specular (A)", ColorSpace::Linear, |m, t, l, r| {
            m.specular *= t.w;
            l.specular = r;
        }),
        ("specular colour (RGB)", ColorSpace::Srgb, |m, t, l, r| {
            m.specular_color *= t.truncate();
            l.specular_color = r;
        }),
        ("clear coat (R)", ColorSpace::Linear, |m, t, l, r| {
            m.clearcoat *= t.x;
            l.clearcoat = r;
        }),
        (
            "clear coat roughness (G)",
            ColorSpace::Linear,
            |m, t, l, r| {
                m.clearcoat_roughness *= t.y;
                l.clearcoat_roughness = r;
            },
        ),
        ("transmission (R)", ColorSpace::Linear, |m, t, l, r| {
            m.transmission *= t.x;
            l.transmission = r;
        }),
        ("sheen colour (RGB)", ColorSpace::Srgb, |m, t, l, r| {
            m.sheen_color *= t.truncate();
            l.sheen_color = r;
        }),
        ("sheen roughness (A)", ColorSpace::Linear, |m, t, l, r| {
            m.sheen_roughness *= t.w;
            l.sheen_roughness = r;
        }),
    ];
    let untextured = render(layered(), None);
    for (name, space, apply) in cases {
        let decoded = if space == ColorSpace::Srgb {
            srgb
        } else {
            linear
        };
        let slot = Some(TextureRef {
            texture: chiaro_scene::TextureId(0),
            uv_set: 0,
            transform: Affine2::IDENTITY,
            sampler: Sampler::default(),
        });
        let mut textured = layered();
        let mut scaled = layered();
        apply(&mut scaled, decoded, &mut LayerTextures::default(), None);
        apply(
            &mut Material::default(),
            decoded,
            &mut textured.layer_textures,
            slot,
        );
        let texture = Texture {
            name: "texel".into(),
            width: 1,
            height: 1,
            rgba8: TEXEL.to_vec(),
            color_space: space,
        };
        let with_texture = render(textured, Some(texture));
        let with_factor = render(scaled, None);
        let error = rel_mse(&with_texture, &with_factor);
        let change = rel_mse(&untextured, &with_factor);
        eprintln!("{name}: relMSE {error:.2e} against the scaled factor ({change:.2e} from none)");
        assert!(error < 1e-8, "{name}: relMSE {error}");
        assert!(
            change > 1e-5,
            "{name}: the factor's change is not seen ({change})"
        );
    }
}
