//! The multiplexed form's path lengths: the distribution p(k) its chains draw lengths of one
//! bounce or more from, which follows each length's share of the image as a short probe
//! measures it (any p that is positive wherever light is leaves the estimate unbiased), and the
//! emitters seen directly (no bounce), rendered apart by the path tracer.

use chiaro_shading::distribution::Distribution1D;
use indicatif::ProgressBar;
use rayon::prelude::*;

use super::evaluate::{Contributions, Paths, Workspace, evaluate};
use super::primary_sample::PrimarySamples;
use crate::integrator::{Integrator, PathSettings};
use crate::render::{RenderSettings, Rendered, render_tiles};
use crate::scene::RenderScene;

/// Fewest samples the probe of [`length_distribution`] draws of each path length.
pub const LENGTH_PROBE: u64 = 256;

/// Rays the probe spends at least on each path length: a length of k bounces gets this many over
/// k + 2 samples where that is more than [`LENGTH_PROBE`], so short paths, such as an emitter
/// seen directly, are probed the most, and a small light is not missed.
pub const LENGTH_PROBE_RAYS: u64 = 4096;

/// Share of p(k) spread evenly over the lengths, so that a length the probe saw no light in
/// keeps a chance.
const LENGTH_FLOOR: f32 = 0.01;

/// The samples the probe draws of paths of `bounces` bounces.
fn probe_samples(bounces: u64) -> u64 {
    LENGTH_PROBE_RAYS.div_ceil(bounces + 2).max(LENGTH_PROBE)
}

/// The samples the probe of [`length_distribution`] draws, over every length from 1 to
/// `max_bounces`.
pub fn probe_size(max_bounces: u32) -> u64 {
    (1..=max_bounces as u64).map(probe_samples).sum()
}

/// The distribution of path lengths, 1 to `max_bounces` bounces (None when that is none), for
/// the multiplexed form: each length's mean importance over uniform samples of its own
/// ([`probe_samples`]; numbered one after another by `samples_at`), plus an even floor.
/// Returns it and the samples that were not finite.
pub fn length_distribution(
    scene: &RenderScene,
    settings: &RenderSettings,
    weights: &[f32],
    max_bounces: u32,
    samples_at: impl Fn(u64) -> PrimarySamples + Sync,
) -> (Option<Distribution1D>, u64) {
    let lengths = max_bounces as u64;
    if lengths == 0 {
        return (None, 0);
    }
    // (length, its first sample's number)
    let probes: Vec<(u64, u64)> = (1..=lengths)
        .scan(0, |first, k| {
            *first += probe_samples(k);
            Some((k, *first - probe_samples(k)))
        })
        .collect();
    let drawn: Vec<(f32, u64)> = probes
        .into_par_iter()
        .map_init(
            || (Workspace::default(), Contributions::default()),
            |(work, out), (k, first)| {
                let (mut sum, mut non_finite) = (0.0f64, 0);
                for index in first..first + probe_samples(k) {
                    let mut samples = samples_at(index);
                    let paths = Paths::Bounces(k as u32);
                    evaluate(scene, settings, paths, weights, &mut samples, work, out);
                    sum += out.importance as f64;
                    non_finite += out.non_finite as u64;
                }
                ((sum / probe_samples(k) as f64) as f32, non_finite)
            },
        )
        .collect();
    let non_finite = drawn.iter().map(|(_, bad)| bad).sum();
    let means: Vec<f32> = drawn
        .iter()
        .map(|(m, _)| if m.is_finite() { *m } else { 0.0 })
        .collect();
    let mean = means.iter().sum::<f32>() / lengths as f32;
    let floor = if mean > 0.0 && mean.is_finite() {
        LENGTH_FLOOR * mean
    } else {
        1.0
    };
    let weights: Vec<f32> = means.iter().map(|m| m + floor).collect();
    (Distribution1D::new(&weights), non_finite)
}

/// The light of emitters and the sky seen directly (paths of no bounce): the path tracer at
/// depth 0, a quarter of `settings.spp` samples a pixel (at least 2; a ray each, where a
/// mutation traces several), in its two halves.
pub fn emitters_seen(scene: &RenderScene, settings: &RenderSettings) -> Rendered {
    let direct_view = RenderSettings {
        spp: settings.spp.div_ceil(4).max(2),
        path: PathSettings {
            max_depth: 0,
            direct_only: false,
            integrator: Integrator::Pt,
            ..settings.path
        },
        ..*settings
    };
    render_tiles(scene, &direct_view, &ProgressBar::hidden())
}
