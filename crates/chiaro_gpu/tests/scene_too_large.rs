//! A scene larger than the device can bind is refused with an error naming what does not fit,
//! not a panic in the graphics API: here the Cornell box with a texture whose texels are one
//! more than the device's largest storage binding holds.

mod common;

use bevy_ecs::prelude::*;
use chiaro_gpu::{FrameSettings, RenderError, RenderSettings, Renderer};
use chiaro_scene::material::Sampler;
use chiaro_scene::{ColorSpace, Materials, Texture, TextureRef, Textures, load_scene};

/// Above this binding size the test's texture would take too much memory to be worth it.
const LARGEST_TESTED: u64 = 256 << 20;

#[test]
fn texels_past_the_largest_binding_are_an_error_naming_them() {
    let Some(gpu) = common::gpu() else { return };
    let max = gpu.device.limits().max_storage_buffer_binding_size;
    if max > LARGEST_TESTED {
        eprintln!("skipped: this device binds {max} bytes; the test goes to {LARGEST_TESTED}");
        return;
    }
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    let width = 4096u32;
    let height = (max / 4).div_ceil(u64::from(width)) as u32 + 1;
    let texture = world.resource_mut::<Textures>().add(Texture {
        name: "huge".into(),
        width,
        height,
        rgba8: vec![200; (width * height * 4) as usize],
        color_space: ColorSpace::Srgb,
    });
    let ids: Vec<_> = world
        .resource::<Materials>()
        .iter()
        .map(|(id, _)| id)
        .collect();
    let mut materials = world.resource_mut::<Materials>();
    for id in ids {
        materials.get_mut(id).unwrap().base_color_texture = Some(TextureRef {
            texture,
            uv_set: 0,
            transform: glam::Affine2::IDENTITY,
            sampler: Sampler::default(),
        });
    }
    let mut renderer = Renderer::new(gpu);
    let settings = RenderSettings {
        width: 8,
        height: 8,
        frames: 1,
        seed: 0,
        frame: FrameSettings::default(),
    };
    let error = renderer.render(&mut world, &settings).unwrap_err();
    assert!(matches!(error, RenderError::SceneTooLarge(_)), "{error:?}");
    let message = error.to_string();
    assert!(
        message.contains("scene texels") && message.contains(&max.to_string()),
        "{message}"
    );
}
