//! Spawning into a world that already holds textures shifts every texture slot of the new
//! materials past the old textures.

use bevy_ecs::world::World;
use glam::{Affine2, Vec3};

use super::SceneBuilder;
use crate::material::Sampler;
use crate::{ColorSpace, Material, Materials, Texture, TextureId, TextureRef};

fn one_texel(name: &str) -> Texture {
    Texture {
        name: name.into(),
        width: 1,
        height: 1,
        rgba8: vec![255; 4],
        color_space: ColorSpace::Linear,
    }
}

#[test]
fn every_texture_slot_is_remapped_when_spawning_into_a_world_with_textures() {
    let mut world = World::new();
    let mut first = SceneBuilder::new("first");
    first.add_texture(one_texel("first's"));
    first.spawn(&mut world);

    let mut second = SceneBuilder::new("second");
    let own = second.add_texture(one_texel("second's"));
    let mut material = Material::diffuse("every slot", Vec3::ONE, 0.5);
    for slot in material.texture_slots_mut() {
        *slot = Some(TextureRef {
            texture: own,
            uv_set: 0,
            transform: Affine2::IDENTITY,
            sampler: Sampler::default(),
        });
    }
    second.add_material(material);
    second.spawn(&mut world);

    let materials = world.resource::<Materials>();
    let (_, spawned) = materials.iter().last().expect("the material was spawned");
    let slots: Vec<_> = spawned.texture_slots().collect();
    assert_eq!(slots.len(), 12, "every slot is still filled");
    for (name, slot) in slots {
        assert_eq!(
            slot.texture,
            TextureId(1),
            "the {name} slot points at the wrong texture"
        );
    }
}
