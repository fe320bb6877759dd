//! The GPU's path-traced modes converge to the CPU reference's full path tracer
//! (`chiaro_reference::render_world`, Russian roulette from depth 3): the reference mode
//! (direct + indirect passes, BRDF sampling with next-event estimation and MIS at every vertex),
//! the naive mode (uniform hemisphere directions, emission found by chance), and the bounce cap
//! of the realtime mode (without the denoiser): `bounces` = b is the CPU reference with
//! max_depth b + 1. Linear HDR, small images.
//!
//! The bound, as in `direct_image.rs`: without bias the expected relMSE of two independent
//! estimates is the sum of their own noises, both measured: the reference's from its two
//! independent halves (their relMSE is four times the full image's), the GPU's from a second
//! render with another seed (the two GPU images' relMSE is twice either one's). Each test
//! asserts relMSE < FACTOR x (GPU noise + reference noise), the factor above 1 because relMSE
//! is dominated by a few pixels that an emitter's edge covers by a sliver. A bias of relative
//! size b adds about b^2 on every lit pixel, so the lit interior's sum (pixels the reference
//! sees below radiance 1) is also compared per channel: the difference must stay within 4
//! standard errors (estimated from the two GPU seeds and the reference's two halves).
//!
//! Pixels compared: all but the 1% whose reference halves disagree most (the reference's own
//! fireflies: on the model under the sky one pixel's halves differ so much that the untrimmed
//! reference noise is 8.8e2, which would make any bound vacuous); the interior sums also
//! leave out pixels next to an emitter (see [`interior`]).
//!
//! Measured on lavapipe, 32x32, the CPU reference at 512 spp (256 for the model), GPU seeds 1
//! and 2 (relMSE; bound; interior difference in standard errors, R G B):
//! - reference mode, Cornell box, 128 frames x 2 paths: 1.4e-3; 3.3e-3; -0.9 -0.7 -1.4.
//! - reference mode, NormalTangentTest.glb under qwantani_afternoon_puresky_1k.hdr, 128 x 2:
//!   1.0e-2; 1.6e-2; 1.3 1.0 -1.6. Many frames of few paths: the sub-pixel jitter is one point
//!   a frame for every pixel, an error the pixels share that per-pixel standard errors miss,
//!   so it must be small next to the Sobol draws' noise (32 frames x 8 paths: -4.7 in blue).
//! - naive mode, Cornell box, 32 frames x 32 paths: 3.8e-2; 0.12; 0.8 0.4 0.4.
//! - realtime mode without the denoiser, Cornell box, 64 frames x 4 paths read back one by
//!   one: bounces 1 against max_depth 2, 1.1e-3; 5.9e-3; -1.5 -2.2 -1.9; bounces 2 against
//!   max_depth 3, 1.2e-3; 5.6e-3; -1.0 -1.9 -1.6. A cap off by one fails on the interior
//!   sums, not on relMSE: the cap of 1 against max_depth 3 measures relMSE 5.5e-3 under its
//!   bound 6.4e-3 (emitter-edge noise dominates relMSE at 32x32) but -73 -62 -39 standard
//!   errors (interior sums 70.5 and 82.8 in red; 94.9 uncapped).
//!
//! The whole file takes 2.7 minutes on lavapipe (two shared cores; 159 s of tests).

mod common;

use std::path::{Path, PathBuf};

use bevy_ecs::world::World;
use chiaro_gpu::{DenoiseSettings, FrameSettings, RenderMode, RenderSettings, Renderer};
use chiaro_reference::{PathSettings, render_world};
use chiaro_scene::{Environment, load_scene};
use glam::Vec3;

fn world(scene: &str, env: Option<&Path>) -> World {
    let mut world = World::new();
    load_scene(&mut world, scene).unwrap();
    if let Some(path) = env {
        let (environment, _) = Environment::from_file(path, 1.0).unwrap();
        world.insert_resource(environment);
    }
    world
}

/// The normal-mapped model of ../shared/scenes and its sky, or `None` (after a message) when
/// the folder is absent.
fn shared_model() -> Option<(String, PathBuf)> {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    let model = shared.join("NormalTangentTest.glb");
    let sky = shared.join("qwantani_afternoon_puresky_1k.hdr");
    if !model.exists() || !sky.exists() {
        eprintln!("skipped: {} or {} missing", model.display(), sky.display());
        return None;
    }
    Some((model.to_str().unwrap().to_owned(), sky))
}

/// A converged CPU image and its measured noise.
struct Reference {
    image: Vec<Vec3>,
    halves: [Vec<Vec3>; 2],
    /// Its own relMSE (a quarter of its halves').
    noise: f64,
}

fn cpu_reference(
    scene: &str,
    env: Option<&Path>,
    size: u32,
    spp: u32,
    max_depth: u32,
) -> Reference {
    let mut w = world(scene, env);
    let out = render_world(
        &mut w,
        &chiaro_reference::RenderSettings {
            width: size,
            height: size,
            spp,
            seed: 7,
            sampler: chiaro_reference::Sampler::default(),
            threads: None,
            path: PathSettings {
                max_depth,
                ..PathSettings::default()
            },
        },
        false,
    )
    .unwrap();
    Reference {
        noise: out.halves_rel_mse() / 4.0,
        halves: out.halves.clone(),
        image: out.image,
    }
}

/// The mean of `frames` GPU frames of `scene` in `frame`'s mode, rendered twice (seeds 1 and
/// 2). The accumulating modes average on the GPU; the realtime mode's frames are read back one
/// by one and averaged here.
fn gpu_images(
    scene: &str,
    env: Option<&Path>,
    size: u32,
    frames: u32,
    frame: FrameSettings,
) -> Option<[Vec<Vec3>; 2]> {
    let gpu = common::gpu()?;
    let mut renderer = Renderer::new(gpu);
    let mut render = |seed| {
        let mut w = world(scene, env);
        let settings = RenderSettings {
            width: size,
            height: size,
            frames,
            seed,
            frame,
        };
        if frame.mode.accumulates() {
            return renderer.render(&mut w, &settings).unwrap().hdr;
        }
        let first = renderer
            .render(
                &mut w,
                &RenderSettings {
                    frames: 1,
                    ..settings
                },
            )
            .unwrap();
        let mut sum = first.hdr;
        for _ in 1..frames {
            renderer.accumulate(&mut w, &settings, 1).unwrap();
            let out = renderer.read(&settings).unwrap();
            for (s, x) in sum.iter_mut().zip(&out.hdr) {
                *s += *x;
            }
        }
        sum.iter().map(|s| *s / frames as f32).collect()
    };
    Some([render(1), render(2)])
}

/// Fraction of pixels a comparison leaves out: those whose reference halves disagree most
/// (`common::trusted_pixels`).
const TRIMMED: f64 = 0.01;

/// The pixels a comparison against `reference` trusts.
fn trusted(reference: &Reference) -> Vec<bool> {
    let halves = [&reference.halves[0][..], &reference.halves[1][..]];
    common::trusted_pixels(halves, &reference.image, TRIMMED)
}

/// Trusted pixels inside the lit interior: the reference below radiance 1 over the pixel's
/// 3 x 3 neighbourhood, so no emitter edge (whose pixels the jitter of a few frames covers
/// by chance, a heavy-tailed error) counts.
fn interior(reference: &Reference, size: usize, keep: &[bool]) -> Vec<bool> {
    let dim = |x: usize, y: usize| reference.image[y * size + x].max_element() < 1.0;
    (0..size * size)
        .map(|i| {
            let (x, y) = ((i % size) as i64, (i / size) as i64);
            keep[i]
                && (-1..=1).all(|dy| {
                    (-1..=1).all(|dx| {
                        let (u, v) = (x + dx, y + dy);
                        u < 0
                            || v < 0
                            || u >= size as i64
                            || v >= size as i64
                            || dim(u as usize, v as usize)
                    })
                })
        })
        .collect()
}

/// What a comparison measured over the trusted pixels.
struct Measured {
    error: f64,
    bound: f64,
    /// The lit interior's sums, GPU minus reference, in standard errors per channel.
    z: Vec3,
}

/// Compares the GPU images with the reference over the trusted pixels: relMSE, its bound
/// `factor` x the summed noise, and the lit interior's sums.
fn measure(name: &str, gpu: &[Vec<Vec3>; 2], reference: &Reference, factor: f64) -> Measured {
    let size = (gpu[0].len() as f64).sqrt() as usize;
    let keep = trusted(reference);
    let error = common::masked_rel_mse(&gpu[0], &reference.image, &keep);
    let gpu_noise = common::masked_rel_mse(&gpu[0], &gpu[1], &keep) / 2.0;
    let reference_noise =
        common::masked_rel_mse(&reference.halves[0], &reference.halves[1], &keep) / 4.0;
    let bound = factor * (gpu_noise + reference_noise);
    let inside = interior(reference, size, &keep);
    let (mut gpu_sum, mut ref_sum, mut variance) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    for (i, (a, b)) in gpu[0].iter().zip(&reference.image).enumerate() {
        if inside[i] {
            gpu_sum += *a;
            ref_sum += *b;
            let g = *a - gpu[1][i];
            let h = reference.halves[0][i] - reference.halves[1][i];
            variance += g * g / 2.0 + h * h / 4.0;
        }
    }
    let z =
        (gpu_sum - ref_sum) / Vec3::new(variance.x.sqrt(), variance.y.sqrt(), variance.z.sqrt());
    eprintln!(
        "{name}: relMSE {error:.3e}, bound {bound:.3e} (GPU noise {gpu_noise:.3e}, reference \
         noise {reference_noise:.3e}, untrimmed {:.3e}); interior sums GPU {gpu_sum} CPU \
         {ref_sum}, {z} standard errors",
        reference.noise
    );
    Measured { error, bound, z }
}

/// Asserts that the GPU images converge to the reference: relMSE below the bound, the
/// interior sums within 4 standard errors.
fn check(name: &str, gpu: &[Vec<Vec3>; 2], reference: &Reference, factor: f64) {
    let m = measure(name, gpu, reference, factor);
    assert!(
        m.error < m.bound,
        "{name}: relMSE {:.3e}, bound {:.3e}",
        m.error,
        m.bound
    );
    assert!(
        m.z.abs().max_element() < 4.0,
        "{name}: interior sums {} standard errors apart",
        m.z
    );
}

fn mode(mode: RenderMode, spp: u32, bounces: u32) -> FrameSettings {
    FrameSettings {
        mode,
        spp,
        bounces,
        denoise: DenoiseSettings {
            enabled: false,
            ..DenoiseSettings::default()
        },
        ..FrameSettings::default()
    }
}

/// Checks `frames` frames of `frame` (32x32) against the full CPU reference at `reference_spp`.
fn full_paths_converge(
    name: &str,
    scene: &str,
    env: Option<&Path>,
    reference_spp: u32,
    frames: u32,
    frame: FrameSettings,
) {
    let reference = cpu_reference(scene, env, 32, reference_spp, 64);
    if let Some(gpu) = gpu_images(scene, env, 32, frames, frame) {
        check(name, &gpu, &reference, 3.0);
    }
}

/// Reference mode on the Cornell box against the CPU reference at max_depth 64.
#[test]
fn reference_mode_converges_on_the_cornell_box() {
    let frame = mode(RenderMode::Reference, 2, 2);
    full_paths_converge(
        "cornell reference",
        "builtin:cornell",
        None,
        512,
        128,
        frame,
    );
}

/// Reference mode on the normal-mapped model under the sky.
#[test]
fn reference_mode_converges_on_a_model_under_the_sky() {
    if let Some((model, sky)) = shared_model() {
        let frame = mode(RenderMode::Reference, 2, 2);
        full_paths_converge("model reference", &model, Some(&sky), 256, 128, frame);
    }
}

/// Naive mode on the Cornell box.
#[test]
fn naive_mode_converges_on_the_cornell_box() {
    let frame = mode(RenderMode::Naive, 32, 2);
    full_paths_converge("cornell naive", "builtin:cornell", None, 512, 32, frame);
}

/// The realtime mode's bounce cap b (denoiser off) is the CPU reference at max_depth b + 1;
/// and the test can tell one bounce from the next: the cap of 1 measured against max_depth 3
/// lies more than 4 standard errors below it.
#[test]
fn bounce_caps_match_the_capped_reference() {
    let references = [2, 3].map(|depth| cpu_reference("builtin:cornell", None, 32, 512, depth));
    let mut capped = Vec::new();
    for (bounces, reference) in [1, 2].into_iter().zip(&references) {
        let Some(gpu) = gpu_images(
            "builtin:cornell",
            None,
            32,
            64,
            mode(RenderMode::Realtime, 4, bounces),
        ) else {
            return;
        };
        check(&format!("cornell bounces {bounces}"), &gpu, reference, 3.0);
        capped.push(gpu);
    }
    let off = measure(
        "cornell bounces 1 against max_depth 3",
        &capped[0],
        &references[1],
        3.0,
    );
    assert!(off.z.max_element() < -4.0, "{}", off.z);
}
