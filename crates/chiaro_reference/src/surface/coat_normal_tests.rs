//! KHR_materials_clearcoat's `clearcoatNormalTexture`: the coat's normal is its own texture in
//! the interpolated frame, never the base's normal map, and exactly the shading normal (local
//! +Z) when there is no coat texture or no coat.

use bevy_ecs::world::World;
use chiaro_bvh::Ray;
use chiaro_scene::builtin::shapes::quad;
use chiaro_scene::material::Sampler;
use chiaro_scene::{
    ColorSpace, Environment, Material, MeshData, SceneBuilder, Texture, TextureId, TextureRef,
    Transform,
};
use glam::{Affine2, Vec3};

use super::{SurfaceHit, surface_at};
use crate::light_table::LightSampling;
use crate::scene::{RenderScene, prepare};

/// The base's normal texel and the coat's: tilted different ways.
const BASE_TEXEL: [u8; 4] = [100, 60, 220, 255];
const COAT_TEXEL: [u8; 4] = [200, 128, 230, 255];
/// The coat's normal scale.
const COAT_SCALE: f32 = 0.5;

fn slot(texture: u32) -> Option<TextureRef> {
    Some(TextureRef {
        texture: TextureId(texture),
        uv_set: 0,
        transform: Affine2::IDENTITY,
        sampler: Sampler::default(),
    })
}

/// The surface seen straight down at a point of a 2x2 card in the XY plane facing +Z (U along
/// +X, V along +Y: the image upside down in glTF's terms, so the tangent is +X and the
/// bitangent, up the image, -Y).
fn hit_card(material: Material) -> SurfaceHit {
    let mut b = SceneBuilder::new("card");
    for (name, rgba8) in [("base normal", BASE_TEXEL), ("coat normal", COAT_TEXEL)] {
        b.add_texture(Texture {
            name: name.into(),
            width: 1,
            height: 1,
            rgba8: rgba8.to_vec(),
            color_space: ColorSpace::Linear,
        });
    }
    let tangent_uv_set = material.tangent_uv_set().map(|set| set as usize);
    let id = b.add_material(material);
    let corners =
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
    let data = MeshData {
        tangent_uv_set,
        ..quad(corners, Vec3::Z)
    };
    let mesh = b.add_mesh("mesh", "card", data).unwrap().unwrap();
    b.add_instance("card", mesh, id, Transform::IDENTITY);
    b.add_camera(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, 60.0);
    b.set_environment(Environment::constant(Vec3::ONE));
    let mut world = World::new();
    b.spawn(&mut world);
    let prepared = prepare(&mut world, LightSampling::Power);
    let scene = RenderScene::new(&world, prepared, 8, 8).unwrap();
    let ray = Ray::new(Vec3::new(0.2, 0.3, 2.0), -Vec3::Z);
    let hit = scene.closest_hit(&ray).expect("the ray hits the card");
    surface_at(&scene, &ray, &hit)
}

/// glTF's tangent-space normal for `texel`, XY scaled, with tangent +X and bitangent -Y.
fn mapped(texel: [u8; 4], scale: f32) -> Vec3 {
    let m = Vec3::new(
        f32::from(texel[0]) / 255.0 * 2.0 - 1.0,
        f32::from(texel[1]) / 255.0 * 2.0 - 1.0,
        f32::from(texel[2]) / 255.0 * 2.0 - 1.0,
    );
    (m * Vec3::new(scale, -scale, 1.0)).normalize()
}

fn coated() -> Material {
    Material {
        clearcoat: 1.0,
        clearcoat_roughness: 0.1,
        ..Material::diffuse("card", Vec3::splat(0.5), 0.5)
    }
}

fn assert_close(what: &str, got: Vec3, want: Vec3) {
    assert!(
        got.abs_diff_eq(want, 1e-5),
        "{what}: {got} instead of {want}"
    );
}

#[test]
fn the_coat_takes_its_own_normal_texture_and_the_base_its_own() {
    let hit = hit_card(Material {
        normal_texture: slot(0),
        clearcoat_normal_texture: slot(1),
        clearcoat_normal_scale: COAT_SCALE,
        ..coated()
    });
    assert_close("base normal", hit.frame.normal, mapped(BASE_TEXEL, 1.0));
    let coat = hit.frame.to_world(hit.params.coat_normal);
    assert_close("coat normal", coat, mapped(COAT_TEXEL, COAT_SCALE));
}

#[test]
fn the_base_normal_texture_does_not_reach_the_coat() {
    let hit = hit_card(Material {
        normal_texture: slot(0),
        ..coated()
    });
    assert_close("base normal", hit.frame.normal, mapped(BASE_TEXEL, 1.0));
    let coat = hit.frame.to_world(hit.params.coat_normal);
    assert_close("coat normal", coat, Vec3::Z);
}

#[test]
fn without_a_coat_texture_or_a_coat_the_coat_normal_is_the_shading_normal() {
    let untextured = hit_card(coated());
    assert_eq!(untextured.params.coat_normal, Vec3::Z);
    let uncoated = hit_card(Material {
        clearcoat: 0.0,
        clearcoat_normal_texture: slot(1),
        ..coated()
    });
    assert_eq!(uncoated.params.coat_normal, Vec3::Z);
}
