//! Resampled indirect light (ReSTIR GI) in motion: each pixel's reservoir carries last frame's
//! paths while the camera pans, a jump to a view whose surfaces last frame did not see
//! restarts them, and a NaN or an infinity written into last frame's reservoirs does not reach
//! the image; an image too wide for the reservoirs' texture is refused with an error. (The
//! estimate's mean and noise are in `restir_gi.rs`.)

mod common;

use chiaro_gpu::{FrameSettings, RenderSettings, Renderer, RestirSettings};
use chiaro_scene::{ActiveCamera, Transform};
use common::{cornell, read_words, renderer_and_queue as renderer, turn};
use glam::Vec3;

const SIZE: u32 = 32;
/// Texels of one reservoir (`GI_RESERVOIR_TEXELS` in `shaders/lib/gi_sample.wgsl`): the
/// third holds the count M in its third word.
const TEXELS: usize = 3;

fn settings() -> RenderSettings {
    RenderSettings {
        width: SIZE,
        height: SIZE,
        frames: 1,
        seed: 9,
        frame: FrameSettings {
            restir: RestirSettings {
                indirect: true,
                indirect_history_cap: 20,
                ..RestirSettings::default()
            },
            ..FrameSettings::default()
        },
    }
}

/// The count M of each pixel's reservoir after this frame's temporal merge.
fn counts(renderer: &Renderer, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<u32> {
    let texture = &renderer.frame().unwrap().targets.gi_reservoirs.texture;
    read_words(device, queue, texture)
        .chunks_exact(4 * TEXELS)
        .map(|r| r[4 * (TEXELS - 1) + 2])
        .collect()
}

#[test]
fn indirect_reservoirs_keep_history_in_motion_and_restart_after_a_jump() {
    let Some((mut renderer, device, queue)) = renderer() else {
        return;
    };
    let mut world = cornell();
    let s = settings();
    renderer.render(&mut world, &s).unwrap();
    assert!(
        counts(&renderer, &device, &queue).iter().all(|&m| m == 1),
        "the first frame has history"
    );
    for _ in 0..6 {
        turn(&mut world, 0.5);
        renderer.accumulate(&mut world, &s, 1).unwrap();
    }
    let panning = counts(&renderer, &device, &queue);
    let with_history = panning.iter().filter(|&&m| m > 1).count();
    let most = panning.iter().max().copied().unwrap_or(0);
    eprintln!(
        "panning: {with_history} of {} pixels carry history, the most M {most}",
        panning.len()
    );
    assert!(with_history > panning.len() / 2, "{with_history}");
    assert!(most <= 1 + s.frame.restir.indirect_history_cap, "{most}");

    // Closer by 40%: every surface's view depth changes by more than the 10% reuse allows.
    let camera = world.resource::<ActiveCamera>().0;
    let mut transform = world.get_mut::<Transform>(camera).unwrap();
    let forward = transform.rotation * Vec3::NEG_Z;
    let step = forward * 0.4 * transform.translation.length();
    transform.translation += step;
    renderer.accumulate(&mut world, &s, 1).unwrap();
    // The test compares a surface's view depth and normal only, so a pixel whose previous
    // point lands on another surface at a like depth passes it (9 of 1024 pixels here).
    let jumped = counts(&renderer, &device, &queue);
    let kept = jumped.iter().filter(|&&m| m > 1).count();
    eprintln!(
        "after the jump: {kept} of {} pixels carry history",
        jumped.len()
    );
    assert!(kept < jumped.len() / 50, "{kept} pixels kept their history");
    assert!(jumped.iter().all(|&m| m >= 1), "a reservoir counts nothing");
}

#[test]
fn a_nan_in_last_frames_indirect_reservoirs_does_not_reach_the_image() {
    let Some((mut renderer, device, queue)) = renderer() else {
        return;
    };
    let s = settings();
    // Two runs of the same frames; the second's history is poisoned before its last frame.
    let mut images = Vec::new();
    for poisoned in [false, true] {
        let mut world = cornell();
        renderer.render(&mut world, &s).unwrap();
        for _ in 0..3 {
            turn(&mut world, 0.5);
            renderer.accumulate(&mut world, &s, 1).unwrap();
        }
        if poisoned {
            // Every reservoir keeps its surface, so it passes the similarity test, but its
            // point, weight and light become NaN, +inf or -inf and its count huge.
            let texture = &renderer.frame().unwrap().targets.gi_history.texture;
            let mut history = read_words(&device, &queue, texture);
            for (i, r) in history.chunks_exact_mut(4 * TEXELS).enumerate() {
                let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY][i % 3].to_bits();
                r[..7].fill(bad);
                r[4 * (TEXELS - 1) + 2] = u32::MAX;
            }
            common::write_words(&queue, texture, &history);
        }
        turn(&mut world, 0.5);
        renderer.accumulate(&mut world, &s, 1).unwrap();
        images.push(renderer.read(&s).unwrap().hdr);
    }
    let (clean, image) = (&images[0], &images[1]);
    assert!(image.iter().all(|p| p.is_finite()), "a non-finite pixel");
    let mean = |img: &[Vec3]| img.iter().sum::<Vec3>() / img.len() as f32;
    let (got, expected) = (mean(image), mean(clean));
    eprintln!("mean radiance {got} against {expected} without the poison");
    assert!(
        (got - expected).abs().max_element() < 0.25 * expected.max_element(),
        "{got} against {expected}"
    );
}

#[test]
fn an_image_too_wide_for_the_reservoirs_is_refused() {
    let Some((mut renderer, device, _)) = renderer() else {
        return;
    };
    let max = device.limits().max_texture_dimension_2d;
    let mut s = settings();
    s.width = max / TEXELS as u32 + 1;
    s.height = 1;
    let err = renderer.render(&mut cornell(), &s).unwrap_err().to_string();
    assert!(err.contains("--restir-gi"), "{err}");
    // The same width renders without resampled indirect light.
    s.frame.restir.indirect = false;
    s.frame.denoise.enabled = false;
    renderer.render(&mut cornell(), &s).unwrap();
}
