//! The realtime frame on a scene whose animations play (the walkthrough's camera path, doors,
//! fan and balls; a glTF's clips): the scene's time advances by 1 / [`FPS`] a frame, and at each
//! checkpoint the frame is measured against a converged reference of the scene posed at that
//! frame's time. Beside the error: frame time percentiles, what the scene systems (animation,
//! skinning, BVH update, upload) cost the CPU a frame, and temporal stability: the mean relMSE
//! between consecutive frames at the checkpoints, beside the same figure for the converged
//! references of those two poses (flicker the reference does not have is the frame's own).

use std::time::Instant;

use bevy_ecs::world::World;
use chiaro_gpu::{FrameSettings, RenderSettings, Renderer};
use chiaro_scene::{Animations, Time, pose_at};
use glam::Vec3;

use super::results::{AnimationRun, PoseCheckpoint};
use super::{BenchError, BenchScene, BenchSettings};
use crate::metrics::rel_mse;
use crate::{CompareSettings, HdrImage, compare};

/// The configuration's name in the results.
pub const ANIMATED_CONFIG: &str = "realtime-animated";
/// Frames per second of scene time.
pub const FPS: f64 = 30.0;

/// The scene time of frame `frame` (counted from 1, which shows time 0).
pub fn time_of(frame: u32) -> f64 {
    f64::from(frame.saturating_sub(1)) / FPS
}

/// The value below which `fraction` of `sorted` (ascending) lies, nearest rank.
pub fn percentile(sorted: &[f64], fraction: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let rank = (fraction * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// Whether `world` holds animations that play: clips of positive length.
pub fn animated(world: &World) -> bool {
    world
        .get_resource::<Animations>()
        .is_some_and(|a| a.duration() > 0.0)
}

/// The converged reference of `scene` posed at `seconds`.
fn reference_at(
    renderer: &mut Renderer,
    scene: &BenchScene,
    settings: &BenchSettings,
    seconds: f64,
) -> Result<super::Reference, BenchError> {
    let mut world = scene.load()?;
    pose_at(&mut world, seconds);
    super::scene_reference(renderer, scene, &mut world, settings)
}

/// Plays `world`'s animations under the realtime frame; `None` for a scene without any.
pub fn measure_animation(
    renderer: &mut Renderer,
    world: &mut World,
    scene: &BenchScene,
    settings: &BenchSettings,
) -> Result<Option<AnimationRun>, BenchError> {
    if !animated(world) {
        return Ok(None);
    }
    let render = RenderSettings {
        width: settings.width,
        height: settings.height,
        frames: 1,
        seed: 1,
        frame: FrameSettings::default(),
    };
    let last = settings.checkpoints.last().copied().unwrap_or(1);
    let mut frame_ms = Vec::new();
    let mut systems_ms = Vec::new();
    let mut before: Option<Vec<Vec3>> = None;
    let mut checkpoints = Vec::new();
    let (mut flicker, mut reference_flicker) = (Vec::new(), Vec::new());
    for frame in 1..=last {
        world.insert_resource(Time {
            seconds: time_of(frame),
        });
        let start = Instant::now();
        if frame == 1 {
            renderer.render(world, &render)?;
        } else {
            renderer.accumulate(world, &render, 1)?;
        }
        frame_ms.push(start.elapsed().as_secs_f64() * 1e3);
        systems_ms.push(renderer.last_systems_seconds() * 1e3);
        let checkpoint = settings.checkpoints.contains(&frame);
        if !checkpoint && !settings.checkpoints.contains(&(frame + 1)) {
            continue;
        }
        let image = renderer.read(&render)?.hdr;
        if !checkpoint {
            before = Some(image);
            continue;
        }
        let reference = reference_at(renderer, scene, settings, time_of(frame))?;
        let epsilon = CompareSettings::default().rel_mse_epsilon;
        if let Some(previous) = before.take() {
            flicker.push(rel_mse(&image, &previous, epsilon));
            let earlier = reference_at(renderer, scene, settings, time_of(frame - 1))?;
            reference_flicker.push(rel_mse(
                &reference.image.pixels,
                &earlier.image.pixels,
                epsilon,
            ));
        }
        let image = HdrImage::new(ANIMATED_CONFIG, settings.width, settings.height, image)?;
        let metrics = compare(&image, &reference.image, &CompareSettings::default())?.metrics;
        checkpoints.push(PoseCheckpoint {
            frames: frame,
            scene_seconds: time_of(frame),
            rel_mse: metrics.rel_mse,
            flip_mean: metrics.flip_mean,
            reference_noise: reference.noise,
        });
    }
    world.remove_resource::<Time>();
    frame_ms.sort_by(f64::total_cmp);
    systems_ms.sort_by(f64::total_cmp);
    let mean = |v: &[f64]| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
    Ok(Some(AnimationRun {
        fps: FPS,
        frame_ms_p50: percentile(&frame_ms, 0.5),
        frame_ms_p95: percentile(&frame_ms, 0.95),
        frame_ms_p99: percentile(&frame_ms, 0.99),
        systems_ms_median: percentile(&systems_ms, 0.5),
        checkpoints,
        flicker: mean(&flicker),
        reference_flicker: mean(&reference_flicker),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_take_the_nearest_rank() {
        let sorted: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&sorted, 0.5), 50.0);
        assert_eq!(percentile(&sorted, 0.95), 95.0);
        assert_eq!(percentile(&sorted, 0.99), 99.0);
        assert_eq!(percentile(&[3.0], 0.99), 3.0);
        assert_eq!(percentile(&[], 0.5), 0.0);
    }

    #[test]
    fn the_first_frame_shows_time_zero() {
        assert_eq!(time_of(1), 0.0);
        assert!((time_of(31) - 1.0).abs() < 1e-12);
    }
}
