//! The render loop: square tiles on rayon, each pixel with its own random numbers seeded by
//! (seed, pixel index): a PCG32 stream, or one Owen-scrambled Sobol sequence per half. So the
//! image for a seed is the same whatever the thread count. Samples alternate between two
//! halves, kept apart (independent scrambles) so the reference's own noise can be measured.
//! Bidirectional samples also land on other pixels (light tracing): each tile returns those
//! splats, and they are added in tile order, so that image too is independent of threads.

use std::time::{Duration, Instant};

use chiaro_shading::rng::Pcg32;
use glam::Vec3;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use crate::bdpt::{self, Splat, Strategies, Subpaths};
use crate::error::ReferenceError;
use crate::integrator::{Integrator, PathSettings, radiance};
use crate::mlt;
use crate::random::{RandomSource, Sampler};
use crate::scene::RenderScene;
use crate::sobol::OwenSobol;

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
    /// Where the samples' numbers come from (Metropolis light transport mutates its own).
    pub sampler: Sampler,
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
            sampler: Sampler::default(),
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

/// What one tile renders: its pixels' sums, and the splats its samples left on any pixel
/// (with the half they count in).
struct TileOutput {
    pixels: Vec<(u32, PixelSums)>,
    splats: [Vec<Splat>; 2],
}

/// What a tile's samples share: the scene, the settings, which bidirectional strategies count,
/// the subpath buffers and the splats of each half.
struct TileSampler<'a> {
    scene: &'a RenderScene<'a>,
    settings: &'a RenderSettings,
    strategy: Strategies,
    subpaths: Subpaths,
    splats: [Vec<Splat>; 2],
}

impl TileSampler<'_> {
    /// One sample of pixel (x, y) in `half`, from the numbers `rng` draws.
    fn sample(&mut self, (x, y): (u32, u32), half: usize, rng: &mut impl RandomSource) -> Vec3 {
        let path = &self.settings.path;
        match path.integrator {
            Integrator::Pt => {
                let ray = self.scene.camera.ray(x, y, rng.next_vec2());
                radiance(self.scene, ray, rng, path)
            }
            // Metropolis sampling does not render by tiles.
            Integrator::Bdpt
            | Integrator::PtLt
            | Integrator::BdptStrategy { .. }
            | Integrator::Mlt
            | Integrator::Mmlt => {
                let jitter = rng.next_vec2();
                bdpt::sample(
                    self.scene,
                    (x, y),
                    jitter,
                    rng,
                    path,
                    self.strategy,
                    &mut self.subpaths,
                    &mut self.splats[half],
                )
            }
        }
    }
}

fn render_tile(scene: &RenderScene, settings: &RenderSettings, tile: (u32, u32)) -> TileOutput {
    let (x0, y0) = (tile.0 * TILE, tile.1 * TILE);
    let mut pixels = Vec::with_capacity((TILE * TILE) as usize);
    let mut tile_sampler = TileSampler {
        scene,
        settings,
        strategy: match settings.path.integrator {
            Integrator::BdptStrategy { s, t } => Strategies::One(s as usize, t as usize),
            Integrator::PtLt => Strategies::CameraAndLightTracing,
            _ => Strategies::All,
        },
        subpaths: Subpaths::default(),
        splats: [Vec::new(), Vec::new()],
    };
    for y in y0..(y0 + TILE).min(settings.height) {
        for x in x0..(x0 + TILE).min(settings.width) {
            let index = y * settings.width + x;
            let mut sums = [Vec3::ZERO; 2];
            let mut dropped = 0;
            let mut add = |half: usize, l: Vec3| {
                if l.is_finite() {
                    sums[half] += l;
                } else {
                    dropped += 1;
                }
            };
            // Even samples make half 0, odd ones half 1.
            match settings.sampler {
                Sampler::Independent => {
                    let mut rng = Pcg32::new(settings.seed, index as u64);
                    for s in 0..settings.spp {
                        let half = (s % 2) as usize;
                        add(half, tile_sampler.sample((x, y), half, &mut rng));
                    }
                }
                Sampler::Sobol => {
                    let mut sequences =
                        [0, 1].map(|half| OwenSobol::new(settings.seed, index as u64, half));
                    for s in 0..settings.spp {
                        let half = (s % 2) as usize;
                        sequences[half].start_sample(s / 2);
                        add(
                            half,
                            tile_sampler.sample((x, y), half, &mut sequences[half]),
                        );
                    }
                }
            }
            pixels.push((index, (sums, dropped)));
        }
    }
    TileOutput {
        pixels,
        splats: tile_sampler.splats,
    }
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
    if settings.path.integrator != Integrator::Pt && !scene.camera.is_perspective() {
        return Err(ReferenceError::Settings(
            "ptlt, bdpt, mlt and mmlt need a perspective camera: light paths cannot reach an orthographic one"
                .to_string(),
        ));
    }
    if let Some(threads) = settings.threads
        && !(1..=MAX_THREADS).contains(&threads)
    {
        return Err(ReferenceError::Settings(format!(
            "{threads} worker threads: need 1..={MAX_THREADS}"
        )));
    }
    let bar = if progress {
        ProgressBar::new(0)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let work = || match settings.path.integrator {
        Integrator::Mlt => {
            bar.set_message("chains");
            mlt::render(scene, settings, mlt::Form::AllStrategies, &bar)
        }
        Integrator::Mmlt => {
            bar.set_message("chains");
            mlt::render(scene, settings, mlt::Form::Multiplexed, &bar)
        }
        _ => {
            bar.set_message("tiles");
            render_tiles(scene, settings, &bar)
        }
    };
    let rendered = match settings.threads {
        Some(threads) => rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| ReferenceError::Settings(format!("cannot start {threads} threads: {e}")))?
            .install(work),
        None => work(),
    };
    bar.finish_and_clear();
    Ok(RenderOutput {
        width: settings.width,
        height: settings.height,
        image: rendered.image,
        halves: rendered.halves,
        non_finite_samples: rendered.non_finite_samples,
        paths: rendered.paths,
        elapsed: start.elapsed(),
    })
}

/// What an estimator renders: the image, its two independent halves, the samples dropped and
/// the paths traced.
pub(crate) struct Rendered {
    pub image: Vec<Vec3>,
    pub halves: [Vec<Vec3>; 2],
    pub non_finite_samples: u64,
    pub paths: u64,
}

impl Rendered {
    /// The image from its halves, each the mean of `counts` samples (two halves of no samples
    /// weigh alike).
    pub fn from_halves(
        halves: [Vec<Vec3>; 2],
        counts: [u64; 2],
        non_finite_samples: u64,
        paths: u64,
    ) -> Self {
        let weights = if counts == [0, 0] {
            [1.0; 2]
        } else {
            counts.map(|c| c as f32)
        };
        let total = (weights[0] + weights[1]).max(1.0);
        let image = halves[0]
            .iter()
            .zip(&halves[1])
            .map(|(a, b)| (*a * weights[0] + *b * weights[1]) / total)
            .collect();
        Self {
            image,
            halves,
            non_finite_samples,
            paths,
        }
    }
}

/// Renders the image tile by tile, a path (or a bidirectional sample) at a time per pixel;
/// `bar` counts tiles.
pub(crate) fn render_tiles(
    scene: &RenderScene,
    settings: &RenderSettings,
    bar: &ProgressBar,
) -> Rendered {
    let tiles: Vec<(u32, u32)> = (0..settings.height.div_ceil(TILE))
        .flat_map(|ty| (0..settings.width.div_ceil(TILE)).map(move |tx| (tx, ty)))
        .collect();
    bar.set_length(tiles.len() as u64);
    let pixels = (settings.width * settings.height) as usize;
    let mut sums = vec![PixelSums::default(); pixels];
    let mut splatted = [vec![Vec3::ZERO; pixels], vec![Vec3::ZERO; pixels]];
    let mut non_finite_samples = 0;
    // Tiles go in batches so that their splats are merged (in tile order) before they pile up.
    let batch = 4 * rayon::current_num_threads();
    for chunk in tiles.chunks(batch) {
        let outputs: Vec<TileOutput> = chunk
            .par_iter()
            .map(|&tile| {
                let output = render_tile(scene, settings, tile);
                bar.inc(1);
                output
            })
            .collect();
        for output in outputs {
            for (index, pixel) in output.pixels {
                sums[index as usize] = pixel;
            }
            for (half, list) in output.splats.iter().enumerate() {
                for splat in list {
                    if splat.value.is_finite() {
                        splatted[half][splat.pixel(settings.width, settings.height)] += splat.value;
                    } else {
                        non_finite_samples += 1;
                    }
                }
            }
        }
    }
    let mut halves = [vec![Vec3::ZERO; pixels], vec![Vec3::ZERO; pixels]];
    let counts = [settings.spp.div_ceil(2) as u64, (settings.spp / 2) as u64];
    for (index, (pixel, dropped)) in sums.iter().enumerate() {
        for k in 0..2 {
            halves[k][index] = (pixel[k] + splatted[k][index]) / counts[k] as f32;
        }
        non_finite_samples += dropped;
    }
    let paths = pixels as u64 * settings.spp as u64;
    Rendered::from_halves(halves, counts, non_finite_samples, paths)
}

impl RenderOutput {
    /// relMSE between the two independent halves, mean((a - b)^2 / (b^2 + 0.01)) over pixels
    /// and channels: the reference's own noise. Each half holds half the samples, so its variance
    /// is twice the full image's and their difference four times: the full image's expected
    /// relMSE against the truth is about a quarter of this figure.
    pub fn halves_rel_mse(&self) -> f64 {
        let [a, b] = &self.halves;
        rel_mse(a, b)
    }
}

/// relMSE of `image` against `reference`, mean((x - y)^2 / (y^2 + 0.01)) over pixels and
/// channels (the bench's metric, on linear HDR).
pub fn rel_mse(image: &[Vec3], reference: &[Vec3]) -> f64 {
    let sum: f64 = image
        .iter()
        .zip(reference)
        .flat_map(|(x, y)| (0..3).map(move |c| (x[c] as f64, y[c] as f64)))
        .map(|(x, y)| (x - y).powi(2) / (y * y + 0.01))
        .sum();
    sum / (3 * image.len()).max(1) as f64
}
