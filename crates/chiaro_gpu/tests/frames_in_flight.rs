//! Frames in flight: the CPU submits frame N+1 while the GPU renders frame N, the images are
//! the same as when every frame is waited for, and every frame's times come back once, in
//! order, with its number.

mod common;

use bevy_ecs::world::World;
use chiaro_gpu::{FrameSettings, PassTimes, RenderMode, RenderSettings, Renderer};

fn cornell() -> World {
    let mut world = World::new();
    chiaro_scene::load_scene(&mut world, "builtin:cornell").unwrap();
    world
}

fn settings(size: u32, mode: RenderMode) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        frames: 1,
        seed: 5,
        frame: FrameSettings {
            mode,
            ..FrameSettings::default()
        },
    }
}

/// Renders `frames` frames one call each with up to `in_flight` frames in flight; returns the
/// image, the times each call returned, the most frames running after a call, and the times
/// `finish` returned.
fn render(
    renderer: &mut Renderer,
    in_flight: u32,
    frames: u32,
) -> (Vec<glam::Vec3>, Vec<Vec<PassTimes>>, usize, Vec<PassTimes>) {
    let mut world = cornell();
    let s = settings(24, RenderMode::Realtime);
    renderer.set_frames_in_flight(in_flight);
    let mut per_call = vec![renderer.render(&mut world, &s).unwrap().times];
    let mut most_running = 0;
    for _ in 1..frames {
        per_call.push(renderer.accumulate(&mut world, &s, 1).unwrap());
        most_running = most_running.max(renderer.frames_running());
    }
    let rest = renderer.finish();
    assert_eq!(renderer.frames_running(), 0);
    (renderer.read(&s).unwrap().hdr, per_call, most_running, rest)
}

#[test]
fn frames_in_flight_render_the_same_image_and_report_every_frame_once() {
    let Some(context) = common::gpu() else {
        return;
    };
    let mut renderer = Renderer::new(context);
    let frames = 6;
    let (waited, per_call, running, rest) = render(&mut renderer, 1, frames);
    // One in flight: each call returns its own frame's times, nothing is left running.
    assert_eq!(running, 0);
    assert!(rest.is_empty());
    for (k, times) in per_call.iter().enumerate() {
        let numbers: Vec<u32> = times.iter().map(|t| t.frame).collect();
        assert_eq!(numbers, [k as u32], "call {k}");
    }
    for in_flight in [2, 3] {
        let (image, per_call, running, rest) = render(&mut renderer, in_flight, frames);
        let limit = renderer.frames_in_flight() as usize;
        // The same random numbers and history, whatever the GPU overlapped.
        assert!(image == waited, "{in_flight} in flight changed the image");
        assert!(
            running < limit,
            "{running} frames running with {limit} allowed"
        );
        let numbers: Vec<u32> = per_call
            .iter()
            .flatten()
            .chain(&rest)
            .map(|t| t.frame)
            .collect();
        assert_eq!(
            numbers,
            (0..frames).collect::<Vec<_>>(),
            "{in_flight} in flight"
        );
        for t in per_call.iter().flatten().chain(&rest) {
            assert!(t.wall_ms > 0.0 && t.wall_ms.is_finite(), "{t:?}");
            assert_eq!(
                t.passes.len(),
                chiaro_gpu::frame::passes(&FrameSettings::default()).len(),
                "{t:?}"
            );
        }
    }
}

#[test]
fn a_submitted_frame_does_not_wait_for_the_gpu() {
    let Some(context) = common::gpu() else {
        return;
    };
    // llvmpipe runs a GL submission's commands before the submission returns: there the CPU
    // is the GPU, and nothing can overlap.
    if context.info.backend == wgpu::Backend::Gl && context.runs_on_cpu() {
        eprintln!(
            "skipped: {} executes GL commands as they are submitted",
            context.describe()
        );
        return;
    }
    let mut renderer = Renderer::new(context);
    renderer.set_frames_in_flight(2);
    if renderer.frames_in_flight() == 1 {
        eprintln!("skipped: the passes are timed by the wall clock, which waits for each");
        return;
    }
    // A frame heavy enough that the GPU (lavapipe, or a real one) is still on it when the call
    // returns: the reference mode's unbounded paths over 128 x 128 pixels.
    let mut world = cornell();
    let s = settings(128, RenderMode::Reference);
    renderer.render(&mut world, &s).unwrap(); // pipelines built, nothing in flight
    let mut calls = Vec::new();
    let mut times = Vec::new();
    for _ in 0..4 {
        let start = std::time::Instant::now();
        times.extend(renderer.accumulate(&mut world, &s, 1).unwrap());
        calls.push(start.elapsed().as_secs_f64() * 1e3);
    }
    times.extend(renderer.finish());
    assert_eq!(times.len(), 4);
    // The first call submits and returns: it neither waited for its own frame nor for an
    // earlier one, so it took far less than a frame's latency.
    let latency = times[0].wall_ms;
    assert!(
        calls[0] < 0.5 * latency,
        "the first call took {:.2} ms, its frame {latency:.2} ms",
        calls[0]
    );
}

#[test]
fn an_image_read_later_is_the_frame_it_was_asked_after() {
    let Some(context) = common::gpu() else {
        return;
    };
    let mut renderer = Renderer::new(context);
    renderer.set_frames_in_flight(2);
    let mut world = cornell();
    let s = settings(24, RenderMode::Realtime);
    renderer.render(&mut world, &s).unwrap();
    renderer.accumulate(&mut world, &s, 2).unwrap();
    let waited = renderer.read(&s).unwrap();
    // Again from a fresh start, asking for the third frame's image and rendering on.
    renderer.render(&mut world, &s).unwrap();
    renderer.accumulate(&mut world, &s, 2).unwrap();
    let pending = renderer.read_later(&s).unwrap();
    renderer.accumulate(&mut world, &s, 3).unwrap();
    renderer.finish();
    let device = &renderer.context.device;
    assert!(
        pending.ready(device),
        "the copy was not done after the frames after it"
    );
    let later = pending.wait(device).unwrap();
    assert!(later.hdr == waited.hdr && later.ldr == waited.ldr);
    assert_eq!(later.frames, waited.frames);
    // The frames after it changed the image, so the copy was made when it was asked for.
    let last = renderer.read(&s).unwrap();
    assert!(last.hdr != waited.hdr);
}
