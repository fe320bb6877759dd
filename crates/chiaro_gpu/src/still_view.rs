//! The realtime mode's histories on a still view: while nothing changes (camera, scene,
//! settings), the temporal averages of the denoiser and of the composite's resolve become
//! running means, so a still image converges as a progressive renderer's does, instead of
//! keeping the moving average's noise for ever.
//!
//! The moving average weighs the new frame `max(1 / history length, floor)` with the floor
//! [`crate::DenoiseSettings::temporal_floor`] = a. After k frames of running mean, the floor is
//! 1 / (1/a + k): the mean of the k new frames and the history, which counts as 1/a frames (so
//! k = 0 gives a, with no jump). A history restarted from nothing starts its running mean at
//! once. After a change it would keep what the history held before the change (lighting that
//! is no longer there) for longer than the moving average does, so the running mean waits
//! [`settle_frames`] still frames first, the moving average's time to bring that part under 1%.
//!
//! The variance pass needs the variance of the average relative to one frame's sample (for its
//! luminance edge-stopping): a / (2 - a) for the moving average's steady state, then
//! (N^2 a / (2 - a) + k) / (N + k)^2 with N = 1/a.
//!
//! The resolve clamps its history to the range of this frame's 3 x 3 neighbourhood, which
//! keeps a moving view from ghosting. On a still view nothing can ghost, and the clamp does
//! harm: a feature thinner than a pixel (a letter's stroke in a texture) is missed by every
//! pixel's jittered sample in some frames, and each such frame clamps the history to the
//! colours around it, so the mean of the frames that did see it is lost. So the clamp fades out
//! over the running mean, weighing (K / (K + k))^2 after k frames ([`resolve_clamp`]): at first
//! it still cuts the noise of a short history, then the history keeps what it saw. The square
//! matters: what the clamp takes off in frame k is still in the mean n frames later with the
//! weight k / n, so a clamp fading as 1/k would leave a bias that never falls, one fading as
//! 1/k^2 leaves one that falls as log(n) / n.

use crate::settings::DenoiseSettings;

/// What of the stale part a history holds after a change the running mean may keep.
const STALE_WEIGHT: f64 = 0.01;

/// K of [`resolve_clamp`]: the running-mean frames after which the clamp weighs a quarter.
/// Measured on the bench's nine scenes (docs/experiments/resolve-clamp-on-a-still-view.md): of
/// the fades tried, the lowest error after 64 frames, and within 4% of the clamp
/// kept whole after 4.
const CLAMP_FADE_FRAMES: f32 = 4.0;

/// How long the view has been still, as the renderer counts it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stillness {
    /// Frames in a row before this one with the same camera, scene and settings (0: this
    /// frame has a change, or restarts the history).
    pub frames: u32,
    /// Whether those frames began with a restarted history (nothing stale in it) rather than a
    /// change.
    pub since_reset: bool,
}

/// The temporal averages' parameters for one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistoryWeights {
    /// The least weight of the new frame ([`history_floor`]).
    pub floor: f32,
    /// The variance of a long history's average relative to one frame's sample
    /// ([`history_variance`]).
    pub variance: f32,
    /// How much of the resolve's neighbourhood clamp its history gets ([`resolve_clamp`]).
    pub clamp: f32,
}

/// Still frames after a change before the running mean starts, for the moving average's floor
/// `temporal_floor`: the fewest n with (1 - a)^n at most 1%.
pub fn settle_frames(temporal_floor: f32) -> u32 {
    let a = f64::from(temporal_floor);
    if a >= 1.0 {
        return 0;
    }
    (STALE_WEIGHT.ln() / (1.0 - a).ln()).ceil() as u32
}

/// The frames of running mean (k above) after `stillness` under `settings`: none when
/// [`DenoiseSettings::converge_when_still`] is off.
pub fn running_mean_frames(settings: &DenoiseSettings, stillness: Stillness) -> u32 {
    if !settings.converge_when_still {
        0
    } else if stillness.since_reset {
        stillness.frames
    } else {
        stillness
            .frames
            .saturating_sub(settle_frames(settings.temporal_floor))
    }
}

/// The weights of a frame after `stillness` under `settings`.
pub fn history_weights(settings: &DenoiseSettings, stillness: Stillness) -> HistoryWeights {
    let k = running_mean_frames(settings, stillness);
    HistoryWeights {
        floor: history_floor(settings.temporal_floor, k),
        variance: history_variance(settings.temporal_floor, k),
        clamp: resolve_clamp(k),
    }
}

/// How much of the resolve's neighbourhood clamp the history gets after `k` frames of running
/// mean: all of it in the moving average (k = 0), then (K / (K + k))^2 with K =
/// `CLAMP_FADE_FRAMES`.
pub fn resolve_clamp(k: u32) -> f32 {
    (CLAMP_FADE_FRAMES / (CLAMP_FADE_FRAMES + k as f32)).powi(2)
}

/// The least weight of the new frame after `k` frames of running mean, for the moving
/// average's floor `temporal_floor` (in (0, 1]).
pub fn history_floor(temporal_floor: f32, k: u32) -> f32 {
    let n = 1.0 / f64::from(temporal_floor);
    (1.0 / (n + f64::from(k))) as f32
}

/// The variance of the temporal average relative to one frame's sample after `k` frames of
/// running mean, for a history in the moving average's steady state when they began.
pub fn history_variance(temporal_floor: f32, k: u32) -> f32 {
    let a = f64::from(temporal_floor);
    let n = 1.0 / a;
    let k = f64::from(k);
    ((n * n * a / (2.0 - a) + k) / ((n + k) * (n + k))) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still(frames: u32, since_reset: bool) -> Stillness {
        Stillness {
            frames,
            since_reset,
        }
    }

    #[test]
    fn off_keeps_the_moving_average_however_still() {
        let off = DenoiseSettings {
            converge_when_still: false,
            ..DenoiseSettings::default()
        };
        let moving = history_weights(&off, still(0, false));
        assert_eq!(history_weights(&off, still(500, true)), moving);
        let on = DenoiseSettings::default();
        assert_eq!(history_weights(&on, still(0, true)), moving);
        assert!(history_weights(&on, still(500, true)).floor < moving.floor / 10.0);
    }

    #[test]
    fn a_change_keeps_the_moving_average() {
        for a in [0.05, 0.2, 1.0] {
            assert_eq!(history_floor(a, 0), a);
            let steady = a / (2.0 - a);
            assert!((history_variance(a, 0) - steady).abs() < 1e-7 * steady.max(1.0));
        }
    }

    #[test]
    fn still_frames_make_a_running_mean() {
        // With a = 0.05 the history counts as 20 frames: after 44 frames of running mean the
        // new frame weighs 1/64, as in the plain mean of 64 frames.
        assert!((history_floor(0.05, 44) - 1.0 / 64.0).abs() < 1e-9);
        // The closed form matches the recursion v' = (1 - w)^2 v + w^2 frame by frame.
        let a = 0.05_f64;
        let mut v = a / (2.0 - a);
        for k in 1..=300u32 {
            let w = f64::from(history_floor(a as f32, k));
            v = (1.0 - w) * (1.0 - w) * v + w * w;
            let closed = f64::from(history_variance(a as f32, k));
            assert!((closed - v).abs() < 1e-6 * v, "k {k}: {closed} against {v}");
        }
        // And it falls as 1/k, far below the moving average's: between the plain mean's of k
        // frames and of k + 2/a.
        let k = 1000;
        let v = history_variance(0.05, k);
        assert!(v < 0.05 * (0.05 / 1.95));
        assert!(v < 1.0 / k as f32 && v > 1.0 / (k as f32 + 40.0));
    }

    /// The resolve's clamp: whole in the moving average and while the view settles after a
    /// change, then fading, a quarter left after K frames of running mean.
    #[test]
    fn the_clamp_fades_over_the_running_mean() {
        let settings = DenoiseSettings::default();
        let settle = settle_frames(settings.temporal_floor);
        for j in 0..=settle {
            assert_eq!(
                history_weights(&settings, still(j, false)).clamp,
                1.0,
                "frame {j}"
            );
        }
        let fade = CLAMP_FADE_FRAMES as u32;
        assert_eq!(history_weights(&settings, still(fade, true)).clamp, 0.25);
        assert_eq!(
            history_weights(&settings, still(settle + fade, false)).clamp,
            0.25
        );
        let mut last = 1.0;
        for k in 1..200 {
            let clamp = history_weights(&settings, still(k, true)).clamp;
            assert!(clamp < last && clamp > 0.0, "k {k}: {clamp}");
            last = clamp;
        }
        // Faster than 1/k: k^2 times the clamp grows no further.
        assert!(last * 199.0 * 199.0 <= CLAMP_FADE_FRAMES * CLAMP_FADE_FRAMES);
        let off = DenoiseSettings {
            converge_when_still: false,
            ..DenoiseSettings::default()
        };
        assert_eq!(history_weights(&off, still(500, true)).clamp, 1.0);
    }

    /// The weight left on what the history held before a change, frame by frame after it:
    /// the moving average's (1 - a)^j while the view settles, never above 1% after.
    #[test]
    fn stale_light_fades_as_fast_as_in_the_moving_average() {
        let settings = DenoiseSettings::default();
        let a = f64::from(settings.temporal_floor);
        let settle = settle_frames(settings.temporal_floor);
        assert_eq!(settle, 21);
        let mut stale = 1.0_f64;
        for j in 0..2000u32 {
            let w = f64::from(history_weights(&settings, still(j, false)).floor);
            stale *= 1.0 - w;
            let moving_average = (1.0 - a).powi(j as i32 + 1);
            if j < settle {
                assert!((stale - moving_average).abs() < 1e-9, "frame {j}");
            } else {
                assert!(stale <= STALE_WEIGHT, "frame {j}: {stale}");
            }
        }
        assert_eq!(settle_frames(1.0), 0);
    }
}
