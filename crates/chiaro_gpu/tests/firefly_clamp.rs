//! The realtime mode's firefly clamp (`FrameSettings::firefly_clamp`): in what units it caps a
//! sample, and which samples. (`hard_cases_firefly.rs`: what it does to the error on the tiny
//! bright emitter.)

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_scene::load_scene;
use chiaro_shading::color::luminance;
use hard_cases_common::{mode, settings};

/// The clamp is in units of the display's white at the frame's exposure: at exposure 4 a clamp
/// of 2 caps a path's scene luminance at 0.5, so the linear HDR image (before exposure) is the
/// one of exposure 1 and a clamp of 0.5, bit for bit (and not the one without a clamp).
#[test]
fn the_clamp_scales_with_the_exposure() {
    let Some(gpu) = common::gpu() else { return };
    let (size, frames) = (32, 16);
    let mut world = World::new();
    load_scene(&mut world, "builtin:hard-cases?case=tiny-emitter").unwrap();
    let mut renderer = Renderer::new(gpu);
    let mut render = |firefly_clamp: f32, exposure: f32| {
        let realtime = FrameSettings {
            firefly_clamp,
            exposure,
            ..mode(RenderMode::Realtime)
        };
        renderer
            .render(&mut world, &settings(size, frames, 1, realtime))
            .unwrap()
            .hdr
    };
    let exposed = render(2.0, 4.0);
    let plain = render(0.5, 1.0);
    let unclamped = render(0.0, 1.0);
    assert!(
        exposed == plain,
        "exposure 4, clamp 2 differs from exposure 1, clamp 0.5"
    );
    assert!(plain != unclamped, "a clamp of 0.5 changed nothing");
}

/// The direct pass's samples that can be rare and huge are clamped too: on
/// `builtin:many-lights?quads=0` (256 punctual lights, so one is picked per sample; no
/// emissive quads, whose light-sampled estimate the clamp leaves alone) no covered pixel's
/// direct light in a realtime frame exceeds the clamp's luminance, while without the clamp
/// some do (the picked light's 1 / r^2 over its probability: the fireflies the temporal
/// history keeps).
#[test]
fn the_direct_lights_samples_are_clamped() {
    let Some(gpu) = common::gpu() else { return };
    let mut world = World::new();
    load_scene(&mut world, "builtin:many-lights?quads=0").unwrap();
    let mut renderer = Renderer::new(gpu);
    let most = 0.5;
    let mut brightest = |firefly_clamp: f32| {
        let realtime = FrameSettings {
            firefly_clamp,
            ..mode(RenderMode::Realtime)
        };
        renderer
            .render(&mut world, &settings(32, 2, 4, realtime))
            .unwrap();
        let covered = renderer.read_gbuffer().unwrap().instance;
        let direct = renderer.direct_light().unwrap();
        direct
            .iter()
            .zip(&covered)
            .filter(|(_, c)| c.is_some())
            .map(|(d, _)| luminance(*d))
            .fold(0.0f32, f32::max)
    };
    let clamped = brightest(most);
    let unclamped = brightest(0.0);
    eprintln!("brightest direct luminance: {clamped} clamped at {most}, {unclamped} without");
    assert!(clamped <= most * 1.0001, "{clamped} above the clamp {most}");
    assert!(
        unclamped > most,
        "no sample reached {most}: the test shows nothing"
    );
}
