//! One world drawn by two renderers, each on a device of its own, turn by turn: no error, and
//! each renders the scene whole (the world's GPU buffers are made again on the device that
//! draws it), the same image for the same seed.

mod common;

use bevy_ecs::world::World;
use chiaro_gpu::{FrameSettings, RenderMode, RenderSettings, Renderer};
use chiaro_scene::load_scene;

#[test]
fn a_world_moves_between_devices() {
    let (Some(first), Some(second)) = (common::gpu(), common::gpu()) else {
        return;
    };
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    let settings = RenderSettings {
        width: 16,
        height: 16,
        frames: 2,
        seed: 7,
        frame: FrameSettings {
            mode: RenderMode::Direct,
            ..FrameSettings::default()
        },
    };
    let (mut a, mut b) = (Renderer::new(first), Renderer::new(second));
    let images = [
        a.render(&mut world, &settings).unwrap().hdr,
        b.render(&mut world, &settings).unwrap().hdr,
        a.render(&mut world, &settings).unwrap().hdr,
    ];
    let lit = images[0].iter().filter(|p| p.max_element() > 0.0).count();
    assert!(lit > 128, "{lit} of 256 pixels lit");
    for (i, image) in images.iter().enumerate().skip(1) {
        let largest = image
            .iter()
            .zip(&images[0])
            .map(|(x, y)| (*x - *y).abs().max_element())
            .fold(0.0f32, f32::max);
        assert!(largest < 1e-5, "render {i}: differs by {largest}");
    }
}
