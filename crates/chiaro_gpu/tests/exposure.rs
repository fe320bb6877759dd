//! The frame's exposure (`FrameSettings::exposure`, `--exposure STOPS` as 2^STOPS) multiplies
//! the linear image before the tonemap pass reads it, and nothing else: at +1 stop the LDR
//! image is the one of twice the radiance, and the linear HDR image is unchanged.

mod common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, RenderSettings, Renderer};
use chiaro_scene::load_scene;
use chiaro_shading::color::linear_to_srgb;
use chiaro_shading::tonemap::{Tonemapper, exposure_from_ev};

/// The 8-bit sRGB code of a linear display value.
fn code(linear: f32) -> i32 {
    (linear_to_srgb(linear) * 255.0).round() as i32
}

#[test]
fn one_stop_doubles_what_the_tonemapper_reads() {
    let Some(gpu) = common::gpu() else { return };
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    let mut renderer = Renderer::new(gpu);
    let mut render = |stops: f32| {
        let frame = FrameSettings {
            mode: RenderMode::Direct,
            tonemapper: Tonemapper::Clamp,
            exposure: exposure_from_ev(stops),
            ..FrameSettings::default()
        };
        let settings = RenderSettings {
            width: 32,
            height: 32,
            frames: 2,
            seed: 3,
            frame,
        };
        renderer.render(&mut world, &settings).unwrap()
    };
    let plain = render(0.0);
    let bright = render(1.0);
    assert!(
        plain.hdr == bright.hdr,
        "the exposure changed the linear image"
    );
    let (mut off, mut moved) = (0, 0);
    for (p, (hdr, ldr)) in plain.hdr.iter().zip(bright.ldr.chunks(4)).enumerate() {
        for c in 0..3 {
            let twice = code((hdr[c] * 2.0).clamp(0.0, 1.0));
            let once = code(hdr[c].clamp(0.0, 1.0));
            if (i32::from(ldr[c]) - twice).abs() > 1 {
                off += 1;
                eprintln!("pixel {p} channel {c}: {} where 2x gives {twice}", ldr[c]);
            }
            if (twice - once).abs() > 2 {
                moved += 1;
            }
        }
    }
    assert_eq!(
        off, 0,
        "{off} channels are not the tonemap of twice the radiance"
    );
    assert!(
        moved > 100,
        "only {moved} channels tell 2x from 1x: the test shows nothing"
    );
}
