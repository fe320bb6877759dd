//! The render loop: square tiles on rayon, each pixel with its own random stream seeded by
//! (seed, pixel index), so the image for a seed is the same whatever the thread count. Samples
//! alternate between two halves, kept apart so the reference's own noise can be measured.

use std::time::{Duration, Instant};

use chiaro_shading::rng::Pcg32;
use glam::Vec3;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use crate::error::ReferenceError;
use crate::integrator::{PathSettings, radiance};
use crate::scene::RenderScene;

/// Side of the square tiles the image is split into.
pub const TILE: u32 = 16;

/// Most worker threads a render starts: more only cost memory and scheduling, and a count in
/// the hundreds of thousands would take minutes to start.
pub const MAX_THREADS: usize = 1024;

/// What to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Samples (paths) per pixel.
    pub spp: u32,
    /// Seed of every pixel's random stream.
    pub seed: u64,
    /// Worker threads, `1..=MAX_THREADS` (`None`: rayon's default, one per core).
    pub threads: Option<usize>,
    /// Path tracing options.
    pub path: PathSettings,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 256,
            height: 256,
            spp: 64,
            seed: 0,
            threads: None,
            path: PathSettings::default(),
        }
    }
}

/// A finished render: linear RGB radiance, row-major, top row first.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Mean over all samples.
    pub image: Vec<Vec3>,
    /// Means over the even-numbered and the odd-numbered samples: two independent estimates.
    pub halves: [Vec<Vec3>; 2],
    /// Samples that came out non-finite and were dropped (should be zero).
    pub non_finite_samples: u64,
    /// Paths traced.
    pub paths: u64,
    /// Wall time of the render.
    pub elapsed: Duration,
}

/// Sums of one pixel's samples, split by parity, and its count of dropped samples.
type PixelSums = ([Vec3; 2], u64);

fn render_tile(
    scene: &RenderScene,
    settings: &RenderSettings,
    tile: (u32, u32),
) -> Vec<(u32, PixelSums)> {
    let (x0, y0) = (tile.0 * TILE, tile.1 * TILE);
    let mut out = Vec::with_capacity((TILE * TILE) as usize);
    for y in y0..(y0 + TILE).min(settings.height) {
        for x in x0..(x0 + TILE).min(settings.width) {
            let index = y * settings.width + x;
            let mut rng = Pcg32::new(settings.seed, index as u64);
            let mut sums = [Vec3::ZERO; 2];
            let mut dropped = 0;
            for s in 0..settings.spp {
                let ray = scene.camera.ray(x, y, rng.next_vec2());
                let l = radiance(scene, ray, &mut rng, &settings.path);
                if l.is_finite() {
                    sums[(s % 2) as usize] += l;
                } else {
                    dropped += 1;
                }
            }
            out.push((index, (sums, dropped)));
        }
    }
    out
}

/// Renders `scene`; `progress` shows a bar with ETA on the terminal.
pub fn render(
    scene: &RenderScene,
    settings: &RenderSettings,
    progress: bool,
) -> Result<RenderOutput, ReferenceError> {
    if settings.width == 0 || settings.height == 0 || settings.spp < 2 {
        return Err(ReferenceError::Settings(format!(
            "{}x{} at {} spp: need a non-empty image and at least 2 samples (two halves)",
            settings.width, settings.height, settings.spp
        )));
    }
    if let Some(threads) = settings.threads
        && !(1..=MAX_THREADS).contains(&threads)
    {
        return Err(ReferenceError::Settings(format!(
            "{threads} worker threads: need 1..={MAX_THREADS}"
        )));
    }
    let tiles: Vec<(u32, u32)> = (0..settings.height.div_ceil(TILE))
        .flat_map(|ty| (0..settings.width.div_ceil(TILE)).map(move |tx| (tx, ty)))
        .collect();
    let bar = if progress {
        ProgressBar::new(tiles.len() as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} tiles, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let work = || {
        tiles
            .par_iter()
            .map(|&tile| {
                let pixels = render_tile(scene, settings, tile);
                bar.inc(1);
                pixels
            })
            .collect::<Vec<_>>()
    };
    let results = match settings.threads {
        Some(threads) => rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| ReferenceError::Settings(format!("cannot start {threads} threads: {e}")))?
            .install(work),
        None => work(),
    };
    bar.finish_and_clear();
    let pixels = (settings.width * settings.height) as usize;
    let mut halves = [vec![Vec3::ZERO; pixels], vec![Vec3::ZERO; pixels]];
    let mut non_finite_samples = 0;
    let counts = [settings.spp.div_ceil(2) as f32, (settings.spp / 2) as f32];
    for (index, (sums, dropped)) in results.into_iter().flatten() {
        for k in 0..2 {
            halves[k][index as usize] = sums[k] / counts[k];
        }
        non_finite_samples += dropped;
    }
    let image = halves[0]
        .iter()
        .zip(&halves[1])
        .map(|(a, b)| (*a * counts[0] + *b * counts[1]) / settings.spp as f32)
        .collect();
    Ok(RenderOutput {
        width: settings.width,
        height: settings.height,
        image,
        halves,
        non_finite_samples,
        paths: pixels as u64 * settings.spp as u64,
        elapsed: start.elapsed(),
    })
}

impl RenderOutput {
    /// relMSE between the two independent halves, mean((a - b)^2 / (b^2 + 0.01)) over pixels
    /// and channels: the reference's own noise. Each half holds half the samples, so its variance
    /// is twice the full image's and their difference four times: the full image's expected
    /// relMSE against the truth is about a quarter of this figure.
    pub fn halves_rel_mse(&self) -> f64 {
        let [a, b] = &self.halves;
        let sum: f64 = a
            .iter()
            .zip(b)
            .flat_map(|(x, y)| (0..3).map(move |c| (x[c] as f64, y[c] as f64)))
            .map(|(x, y)| (x - y).powi(2) / (y * y + 0.01))
            .sum();
        sum / (3 * a.len()).max(1) as f64
    }
}
