//! Primary-sample-space Metropolis light transport over the bidirectional tracer (Kelemen,
//! Szirmay-Kalos, Antal and Csonka 2002; Veach 1997, chapter 11). A sample is a point of the
//! unit hypercube ([`primary_sample`]); the bidirectional tracer turns it into a film position
//! and every strategy's contribution, to that pixel and, by light tracing, to others. The
//! scalar I(u) is the sum of the contributions' luminances, each weighted by its pixel's
//! weight from a pilot image ([`pixel_weights`]). Markov chains walk the hypercube
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

mod primary_sample;

use chiaro_shading::color::luminance;
use chiaro_shading::distribution::Distribution1D;
use chiaro_shading::rng::Pcg32;
use glam::{Vec2, Vec3};
use indicatif::ProgressBar;
use rayon::prelude::*;

use crate::bdpt::{self, Splat, Strategies, Subpaths};
use crate::random::{RandomSource, Stream};
use crate::render::{RenderSettings, Rendered};
use crate::scene::RenderScene;
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

/// Stream of the pilot image's random numbers.
const PILOT_STREAM: u64 = 1 << 48;

/// One evaluation of the bidirectional tracer at a point of primary sample space.
#[derive(Default)]
struct Contributions {
    /// (pixel index, value): the camera subpath's pixel first, then light tracing's splats.
    values: Vec<(u32, Vec3)>,
    /// Sum of the values' luminances: the density the chains follow.
    importance: f32,
    /// True when a value was not finite (the sample then counts as zero).
    non_finite: bool,
}

/// Reusable storage of one chain.
#[derive(Default)]
struct Workspace {
    subpaths: Subpaths,
    splats: Vec<Splat>,
}

/// Traces the point `samples` stands at into `out`; each value's luminance counts in the
/// importance times its pixel's entry of `weights` (1 where it is empty).
fn evaluate(
    scene: &RenderScene,
    settings: &RenderSettings,
    weights: &[f32],
    samples: &mut PrimarySamples,
    work: &mut Workspace,
    out: &mut Contributions,
) {
    let (width, height) = (settings.width, settings.height);
    samples.start_stream(Stream::Camera);
    let film = samples.next_vec2() * Vec2::new(width as f32, height as f32);
    let x = (film.x as u32).min(width - 1);
    let y = (film.y as u32).min(height - 1);
    let jitter = (film - Vec2::new(x as f32, y as f32)).clamp(Vec2::ZERO, Vec2::splat(1.0));
    work.splats.clear();
    let l = bdpt::sample(
        scene,
        (x, y),
        jitter,
        samples,
        &settings.path,
        Strategies::All,
        &mut work.subpaths,
        &mut work.splats,
    );
    out.values.clear();
    if l != Vec3::ZERO {
        out.values.push((y * width + x, l));
    }
    for splat in &work.splats {
        out.values
            .push((splat.pixel(width, height) as u32, splat.value));
    }
    out.non_finite = out.values.iter().any(|(_, v)| !v.is_finite());
    out.importance = if out.non_finite {
        0.0
    } else {
        out.values
            .iter()
            .map(|(pixel, v)| luminance(*v).max(0.0) * weights.get(*pixel as usize).unwrap_or(&1.0))
            .sum()
    };
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

/// Runs chain `chain` for `mutations` steps from bootstrap sample `start`.
fn run_chain(
    scene: &RenderScene,
    settings: &RenderSettings,
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

/// Side of the square box that blurs the pilot image.
const PILOT_BLUR: i64 = 5;

/// Least brightness a pixel's weight assumes, as a fraction of the pilot image's mean.
const PILOT_FLOOR: f32 = 0.05;

/// Each pixel's weight in the importance: 1 / the square root of its brightness, as a pilot
/// image of `count` uniform samples (on streams of their own) blurred by a box shows it, and
/// at most that of 1/20 of the mean brightness. The chains then spend more of their samples
/// where the image is dark than the luminance alone would (Hoberock and Hart 2010, "Arbitrary
/// Importance Functions for Metropolis Light Transport"); any positive weights leave the
/// estimate unbiased. The square root was measured against the full inverse at 64x64: the
/// inverse followed the pilot's fireflies on builtin:door (relMSE 0.36 against 0.14).
fn pixel_weights(scene: &RenderScene, settings: &RenderSettings, count: u64) -> Vec<f32> {
    let (width, height) = (settings.width as i64, settings.height as i64);
    let pixels = (width * height) as usize;
    let chunk = count.div_ceil(64);
    let films: Vec<Vec<f32>> = (0..count.div_ceil(chunk))
        .into_par_iter()
        .map(|c| {
            let mut film = vec![0.0f32; pixels];
            let (mut work, mut out) = (Workspace::default(), Contributions::default());
            for index in c * chunk..((c + 1) * chunk).min(count) {
                let mut samples = bootstrap_samples(settings.seed, PILOT_STREAM + index);
                evaluate(scene, settings, &[], &mut samples, &mut work, &mut out);
                if !out.non_finite {
                    for (pixel, value) in &out.values {
                        film[*pixel as usize] += luminance(*value).max(0.0);
                    }
                }
            }
            film
        })
        .collect();
    let mut pilot = vec![0.0f32; pixels];
    for film in &films {
        for (total, value) in pilot.iter_mut().zip(film) {
            *total += value;
        }
    }
    let mut blurred = vec![0.0f32; pixels];
    let r = PILOT_BLUR / 2;
    for y in 0..height {
        for x in 0..width {
            let (mut sum, mut n) = (0.0, 0.0);
            for yy in (y - r).max(0)..=(y + r).min(height - 1) {
                for xx in (x - r).max(0)..=(x + r).min(width - 1) {
                    sum += pilot[(yy * width + xx) as usize];
                    n += 1.0;
                }
            }
            blurred[(y * width + x) as usize] = sum / n;
        }
    }
    let mean = blurred.iter().sum::<f32>() / pixels as f32;
    if mean <= 0.0 || !mean.is_finite() {
        return Vec::new();
    }
    blurred
        .iter()
        .map(|b| 1.0 / b.max(PILOT_FLOOR * mean).sqrt())
        .collect()
}

/// Renders `settings.spp` mutations per pixel by Metropolis sampling; `bar` counts chains.
/// Runs on the current rayon pool.
pub fn render(scene: &RenderScene, settings: &RenderSettings, bar: &ProgressBar) -> Rendered {
    let pixels = settings.width as u64 * settings.height as u64;
    let bootstrap = (pixels * BOOTSTRAP_PER_PIXEL).max(MIN_BOOTSTRAP);
    let weights = pixel_weights(scene, settings, bootstrap);
    let importance: Vec<(f32, bool)> = (0..bootstrap)
        .into_par_iter()
        .map_init(
            || (Workspace::default(), Contributions::default()),
            |(work, out), index| {
                let mut samples = bootstrap_samples(settings.seed, index);
                evaluate(scene, settings, &weights, &mut samples, work, out);
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
                        &weights,
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
    let paths = 2 * bootstrap + counts[0] + counts[1];
    Rendered::from_halves(films, counts, non_finite, paths)
}
