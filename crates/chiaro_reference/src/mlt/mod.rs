//! Metropolis light transport in primary sample space over the bidirectional tracer (Kelemen,
//! Szirmay-Kalos, Antal and Csonka 2002; Veach 1997, chapter 11), in two forms: every
//! connection strategy of a bidirectional sample at each point, or, multiplexed (Hachisuka,
//! Kaplanyan and Dachsbacher 2014), one strategy of one path length at each point, weighted by
//! MIS, which costs a few rays where the other joins every pair of vertices.
//!
//! A sample is a point of the unit hypercube ([`primary_sample`]); the tracer turns it into a
//! film position and contributions, to that pixel and, by light tracing, to others
//! ([`evaluate`]). The scalar I(u) is the sum of the contributions' luminances, each weighted
//! by its pixel's weight from a pilot image ([`pilot`]). Markov chains walk the hypercube
//! with the density I / b, proposing small and large steps and accepting them with
//! probability min(1, I(new) / I(old)); both the proposal and the current state are recorded
//! at every step, weighted by the acceptance probability and its complement (Veach's expected
//! values), so pixel j's value is W H b / M times the sum of f_j / I over the M records.
//!
//! The normalisation b, the mean of I over the hypercube, is estimated from independent
//! uniform samples: a bootstrap before the chains start, which also picks each chain's start
//! in proportion to I (so there is little start-up bias to burn in), and every large step's
//! proposal after it. Each chain has its own film and the films are summed in chain order, so
//! the image for a seed does not depend on the thread count. Even chains make one half of the
//! image and odd chains the other; the two share b, so their difference does not see b's
//! error.

mod evaluate;
mod lengths;
mod pilot;
mod primary_sample;

use chiaro_shading::distribution::Distribution1D;
use chiaro_shading::rng::Pcg32;
use glam::Vec3;
use indicatif::ProgressBar;
use rayon::prelude::*;

use crate::render::{RenderSettings, Rendered};
use crate::scene::RenderScene;
use evaluate::{Contributions, Paths, Workspace, evaluate};
use lengths::{emitters_seen, length_distribution, probe_size};
use primary_sample::PrimarySamples;

/// Markov chains a render runs (fewer when there are fewer mutations than this many times
/// 64): many short chains cover the image evenly and keep every core busy.
pub const CHAINS: u64 = 512;

/// Uniform samples drawn before the chains start, per pixel (at least [`MIN_BOOTSTRAP`]).
pub const BOOTSTRAP_PER_PIXEL: u64 = 4;

/// Fewest uniform samples drawn before the chains start.
pub const MIN_BOOTSTRAP: u64 = 16_384;

/// Probability that a mutation is a large step (Kelemen et al. use 0.3).
pub const LARGE_STEP_PROBABILITY: f32 = 0.3;

/// Standard deviation of a small step's offset to a coordinate (in the unit interval).
pub const SMALL_STEP_SIGMA: f32 = 0.01;

/// Stream of the bootstrap's random numbers (the seed's other streams are the chains').
const BOOTSTRAP_STREAM: u64 = 1 << 40;

/// Stream of the multiplexed form's probe of path lengths.
const LENGTH_PROBE_STREAM: u64 = 1 << 44;

/// Which form of Metropolis sampling renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// Every connection strategy of a bidirectional sample at each point.
    AllStrategies,
    /// One strategy of one path length at each point.
    Multiplexed,
}

/// The sampler whose first evaluation is bootstrap sample `index`.
fn bootstrap_samples(seed: u64, index: u64) -> PrimarySamples {
    PrimarySamples::new(
        Pcg32::new(seed, BOOTSTRAP_STREAM + index),
        SMALL_STEP_SIGMA,
        LARGE_STEP_PROBABILITY,
    )
}

/// What one chain returns.
struct ChainOutput {
    film: Vec<Vec3>,
    /// Sum of I over its large steps' proposals, and their count.
    large_steps: (f64, u64),
    non_finite: u64,
}

/// Adds `c`'s values, each times `weight` / I, to `film`.
fn record(film: &mut [Vec3], c: &Contributions, weight: f32) {
    if weight <= 0.0 || c.importance <= 0.0 {
        return;
    }
    let scale = weight / c.importance;
    for &(pixel, value) in &c.values {
        film[pixel as usize] += value * scale;
    }
}

/// Runs chain `chain` over `paths` for `mutations` steps from bootstrap sample `start`.
fn run_chain(
    scene: &RenderScene,
    settings: &RenderSettings,
    paths: Paths,
    weights: &[f32],
    chain: u64,
    start: u64,
    mutations: u64,
) -> ChainOutput {
    let pixels = (settings.width * settings.height) as usize;
    let mut film = vec![Vec3::ZERO; pixels];
    let mut work = Workspace::default();
    let mut samples = bootstrap_samples(settings.seed, start);
    let mut current = Contributions::default();
    evaluate(
        scene,
        settings,
        paths,
        weights,
        &mut samples,
        &mut work,
        &mut current,
    );
    samples.reseed(Pcg32::new(settings.seed, chain));
    let mut accept_rng = Pcg32::new(settings.seed ^ 0x6d6c_7400, chain);
    let mut proposed = Contributions::default();
    let (mut large_sum, mut large_count, mut non_finite) = (0.0f64, 0u64, 0u64);
    for _ in 0..mutations {
        samples.start_iteration();
        evaluate(
            scene,
            settings,
            paths,
            weights,
            &mut samples,
            &mut work,
            &mut proposed,
        );
        non_finite += proposed.non_finite as u64;
        if samples.is_large_step() {
            large_sum += proposed.importance as f64;
            large_count += 1;
        }
        let accept = if current.importance > 0.0 {
            (proposed.importance / current.importance).min(1.0)
        } else {
            1.0
        };
        record(&mut film, &proposed, accept);
        record(&mut film, &current, 1.0 - accept);
        if accept_rng.next_f32() < accept {
            samples.accept();
            std::mem::swap(&mut current, &mut proposed);
        } else {
            samples.reject();
        }
    }
    ChainOutput {
        film,
        large_steps: (large_sum, large_count),
        non_finite,
    }
}

/// What the chains of a render return: the two halves' films (in the image's units), the
/// mutations each half made, the samples that were not finite and the paths traced.
struct ChainsOutput {
    films: [Vec<Vec3>; 2],
    counts: [u64; 2],
    non_finite: u64,
    traced: u64,
}

/// Draws `bootstrap` uniform samples of `paths`, then runs the chains: `settings.spp`
/// mutations per pixel in all.
fn run_chains(
    scene: &RenderScene,
    settings: &RenderSettings,
    paths: Paths,
    weights: &[f32],
    bootstrap: u64,
    bar: &ProgressBar,
) -> ChainsOutput {
    let pixels = settings.width as u64 * settings.height as u64;
    let importance: Vec<(f32, bool)> = (0..bootstrap)
        .into_par_iter()
        .map_init(
            || (Workspace::default(), Contributions::default()),
            |(work, out), index| {
                let mut samples = bootstrap_samples(settings.seed, index);
                evaluate(scene, settings, paths, weights, &mut samples, work, out);
                (out.importance, out.non_finite)
            },
        )
        .collect();
    let sum: f64 = importance.iter().map(|(i, _)| *i as f64).sum();
    let mut non_finite = importance.iter().filter(|(_, bad)| *bad).count() as u64;
    let mutations = pixels * settings.spp as u64;
    let chains = CHAINS.min(mutations / 64).max(2);
    bar.set_length(chains);
    let mut films = [
        vec![Vec3::ZERO; pixels as usize],
        vec![Vec3::ZERO; pixels as usize],
    ];
    let mut counts = [0u64; 2];
    let (mut b_sum, mut b_count) = (sum, bootstrap);
    let weights_of_starts: Vec<f32> = importance.iter().map(|(i, _)| *i).collect();
    // None when no bootstrap sample carries light: the image is black.
    if let Some(start_distribution) = Distribution1D::new(&weights_of_starts) {
        let mut start_rng = Pcg32::new(settings.seed, BOOTSTRAP_STREAM - 1);
        let starts: Vec<u64> = (0..chains)
            .map(|_| start_distribution.sample(start_rng.next_f32()).0 as u64)
            .collect();
        let batch = 2 * rayon::current_num_threads() as u64;
        for first in (0..chains).step_by(batch as usize) {
            let outputs: Vec<(u64, u64, ChainOutput)> = (first..(first + batch).min(chains))
                .into_par_iter()
                .map(|chain| {
                    let steps = mutations / chains + (chain < mutations % chains) as u64;
                    let out = run_chain(
                        scene,
                        settings,
                        paths,
                        weights,
                        chain,
                        starts[chain as usize],
                        steps,
                    );
                    bar.inc(1);
                    (chain, steps, out)
                })
                .collect();
            for (chain, steps, out) in outputs {
                let half = (chain % 2) as usize;
                for (total, value) in films[half].iter_mut().zip(&out.film) {
                    *total += *value;
                }
                counts[half] += steps;
                b_sum += out.large_steps.0;
                b_count += out.large_steps.1;
                non_finite += out.non_finite;
            }
        }
    }
    // Every pixel's value: W H b / M times the sum of f / I recorded in it.
    let b = b_sum / b_count as f64;
    for (film, count) in films.iter_mut().zip(counts) {
        let scale = (pixels as f64 * b / count.max(1) as f64) as f32;
        for value in film.iter_mut() {
            *value *= scale;
        }
    }
    ChainsOutput {
        films,
        counts,
        non_finite,
        traced: bootstrap + counts[0] + counts[1],
    }
}

/// Renders `settings.spp` mutations per pixel by Metropolis sampling in `form`; `bar` counts
/// chains. Runs on the current rayon pool. The multiplexed form renders the emitters seen
/// directly (paths of no bounce) apart, with the path tracer, and its chains walk the longer
/// paths: a small light seen in a few pixels is then no island that only large steps reach.
pub fn render(
    scene: &RenderScene,
    settings: &RenderSettings,
    form: Form,
    bar: &ProgressBar,
) -> Rendered {
    let pixels = settings.width as u64 * settings.height as u64;
    let bootstrap = (pixels * BOOTSTRAP_PER_PIXEL).max(MIN_BOOTSTRAP);
    let weights = pilot::pixel_weights(scene, settings, bootstrap);
    let max_bounces = if settings.path.direct_only {
        1
    } else {
        settings.path.max_depth
    };
    let mut out = match form {
        Form::AllStrategies => run_chains(
            scene,
            settings,
            Paths::AllStrategies,
            &weights,
            bootstrap,
            bar,
        ),
        Form::Multiplexed => {
            let seen = emitters_seen(scene, settings);
            let probe = |index| bootstrap_samples(settings.seed, LENGTH_PROBE_STREAM + index);
            let (lengths, non_finite) =
                length_distribution(scene, settings, &weights, max_bounces, probe);
            // None at depth 0: the emitters seen are the whole image.
            let Some(lengths) = lengths else {
                return Rendered {
                    paths: bootstrap + seen.paths,
                    ..seen
                };
            };
            let mut out = run_chains(
                scene,
                settings,
                Paths::AnyLength(&lengths),
                &weights,
                bootstrap,
                bar,
            );
            for (film, seen) in out.films.iter_mut().zip(&seen.halves) {
                for (total, value) in film.iter_mut().zip(seen) {
                    *total += *value;
                }
            }
            out.non_finite += non_finite + seen.non_finite_samples;
            out.traced += probe_size(max_bounces) + seen.paths;
            out
        }
    };
    out.traced += bootstrap;
    Rendered::from_halves(out.films, out.counts, out.non_finite, out.traced)
}
