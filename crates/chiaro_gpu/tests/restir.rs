//! Resampled direct light (ReSTIR DI, `FrameSettings::restir`) in motion: the reservoirs carry
//! history while the camera pans, a jump to a view whose surfaces last frame did not see
//! restarts them, and a NaN or an infinity written into last frame's reservoirs does not reach
//! the image. (Its convergence to the CPU reference is in `direct_image.rs`; its reservoir
//! arithmetic against brute force in `chiaro_shading::reservoir`.)

mod common;

use chiaro_gpu::{FrameSettings, RenderSettings, Renderer, RestirSettings};
use chiaro_scene::{ActiveCamera, Transform};
use common::{cornell, renderer_and_queue as renderer, turn};
use glam::Vec3;

const SIZE: u32 = 32;

fn settings() -> RenderSettings {
    RenderSettings {
        width: SIZE,
        height: SIZE,
        frames: 1,
        seed: 5,
        frame: FrameSettings {
            restir: RestirSettings {
                direct: true,
                temporal: true,
                ..RestirSettings::default()
            },
            ..FrameSettings::default()
        },
    }
}

/// The count M of each pixel's final reservoir.
fn counts(renderer: &Renderer, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<u32> {
    let texture = &renderer.frame().unwrap().targets.reservoirs.texture;
    common::read_words(device, queue, texture)
        .chunks_exact(4)
        .map(|t| t[3])
        .collect()
}

#[test]
fn reservoirs_keep_history_in_motion_and_restart_after_a_jump() {
    let Some((mut renderer, device, queue)) = renderer() else {
        return;
    };
    let mut world = cornell();
    let s = settings();
    let r = s.frame.restir;
    renderer.render(&mut world, &s).unwrap();
    for _ in 0..6 {
        turn(&mut world, 0.5);
        renderer.accumulate(&mut world, &s, 1).unwrap();
    }
    // With no history a final reservoir has seen at most its own candidates and its
    // neighbours'.
    let fresh = r.candidates * (1 + r.spatial_samples);
    let panning = counts(&renderer, &device, &queue);
    let with_history = panning.iter().filter(|&&m| m > fresh).count();
    eprintln!(
        "panning: {with_history} of {} pixels carry history",
        panning.len()
    );
    assert!(with_history > panning.len() / 2, "{with_history}");

    // Closer by 40%: every surface's view depth changes by more than the 10% reuse allows.
    let camera = world.resource::<ActiveCamera>().0;
    let mut transform = world.get_mut::<Transform>(camera).unwrap();
    let forward = transform.rotation * Vec3::NEG_Z;
    let step = forward * 0.4 * transform.translation.length();
    transform.translation += step;
    renderer.accumulate(&mut world, &s, 1).unwrap();
    let jumped = counts(&renderer, &device, &queue);
    let most = jumped.iter().max().copied().unwrap_or(0);
    assert!(
        most <= fresh,
        "after the jump a reservoir counts {most} > {fresh}"
    );
    assert!(most > 0, "no reservoir after the jump");
}

#[test]
fn a_nan_in_last_frames_reservoirs_does_not_reach_the_image() {
    let Some((mut renderer, _, queue)) = renderer() else {
        return;
    };
    let mut world = cornell();
    let s = settings();
    renderer.render(&mut world, &s).unwrap();
    turn(&mut world, 0.5);
    renderer.accumulate(&mut world, &s, 1).unwrap();
    let clean = {
        let mut other = cornell();
        let mut second = Renderer::new(common::gpu().unwrap());
        second.render(&mut other, &s).unwrap();
        turn(&mut other, 0.5);
        second.accumulate(&mut other, &s, 1).unwrap();
        turn(&mut other, 0.5);
        second.accumulate(&mut other, &s, 1).unwrap();
        second.read(&s).unwrap().hdr
    };
    // Every reservoir: entry 0 or one past any table, W NaN, +inf or -inf, M huge.
    let poison: Vec<u32> = (0..SIZE * SIZE)
        .flat_map(|i| {
            let w = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY][i as usize % 3];
            let entry = if i % 2 == 0 { 0 } else { 0x7fff_fff0 };
            [entry, 0x8000_8000, w.to_bits(), u32::MAX]
        })
        .collect();
    let texture = &renderer.frame().unwrap().targets.reservoirs.texture;
    common::write_words(&queue, texture, &poison);
    turn(&mut world, 0.5);
    renderer.accumulate(&mut world, &s, 1).unwrap();
    let image = renderer.read(&s).unwrap().hdr;
    assert!(image.iter().all(|p| p.is_finite()), "a non-finite pixel");
    let mean = |img: &[Vec3]| img.iter().sum::<Vec3>() / img.len() as f32;
    let (got, expected) = (mean(&image), mean(&clean));
    eprintln!("mean radiance {got} against {expected} without the poison");
    assert!(
        (got - expected).abs().max_element() < 0.25 * expected.max_element(),
        "{got} against {expected}"
    );
}
