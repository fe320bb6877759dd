//! Resampled indirect light (ReSTIR GI, `RestirSettings::indirect`) on the Cornell box, read
//! from the frame's indirect-light target before the denoiser: without neighbours it is the
//! path tracer's estimate (its mean over frames agrees with the indirect pass's within their
//! noise); with neighbours one frame's error against the converged indirect light is lower,
//! and its mean stays close (weighted by counts) or equal within the noise (by pairwise MIS
//! with visibility); with last frame's reservoirs merged as well (a still camera whose
//! frames are not averaged), lower again, the mean still close; a NaN or an infinity in a
//! pixel's sample reaches no pixel. (The reservoirs' history in motion is in
//! `restir_gi_history.rs`.)

mod common;

use chiaro_gpu::{FrameSettings, RenderSettings, Renderer, RestirBias, RestirSettings};
use common::cornell;
use glam::Vec3;

const SIZE: u32 = 32;
/// Frames averaged for each converged estimate.
const FRAMES: u32 = 128;
/// Frames of the path tracer's and the unbiased reuse's estimates, whose image means are
/// compared: enough that a bias of 1% is about 4 standard errors.
const BIAS_FRAMES: u32 = 1024;

/// Realtime frames whose indirect light is resampled with `neighbours` (`None`: not
/// resampled), weighted by counts, and last frame's reservoirs counting up to `history` paths
/// (0: none), without the firefly clamp (its bias differs between the estimators) and without
/// the still view's running mean (which turns reuse off).
fn settings(neighbours: Option<u32>, history: u32, seed: u64) -> RenderSettings {
    let mut frame = FrameSettings {
        firefly_clamp: 0.0,
        restir: RestirSettings {
            indirect: neighbours.is_some(),
            indirect_spatial_samples: neighbours.unwrap_or(0),
            indirect_history_cap: history,
            spatial_radius: 4.0,
            ..RestirSettings::default()
        },
        ..FrameSettings::default()
    };
    frame.denoise.converge_when_still = false;
    RenderSettings {
        width: SIZE,
        height: SIZE,
        frames: 1,
        seed,
        frame,
    }
}

/// A renderer, and the device and queue it renders with (for reading the indirect light).
struct Gpu {
    renderer: Renderer,
    device: wgpu::Device,
    queue: wgpu::Queue,
}

fn gpu() -> Option<Gpu> {
    let context = common::gpu()?;
    let (device, queue) = (context.device.clone(), context.queue.clone());
    Some(Gpu {
        renderer: Renderer::new(context),
        device,
        queue,
    })
}

/// Each frame's indirect light, for `frames` frames.
fn indirect_frames(gpu: &mut Gpu, s: &RenderSettings, frames: u32) -> Vec<Vec<Vec3>> {
    let mut world = cornell();
    gpu.renderer.render(&mut world, s).unwrap();
    let mut out = vec![read_indirect(gpu)];
    for _ in 1..frames {
        gpu.renderer.accumulate(&mut world, s, 1).unwrap();
        out.push(read_indirect(gpu));
    }
    out
}

fn read_indirect(gpu: &mut Gpu) -> Vec<Vec3> {
    gpu.renderer.finish();
    let texture = &gpu.renderer.frame().unwrap().targets.indirect.texture;
    let bytes = chiaro_gpu::readback::read_texture(&gpu.device, &gpu.queue, texture, 16).unwrap();
    let texels: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes);
    texels
        .chunks_exact(4)
        .map(|t| Vec3::new(t[0], t[1], t[2]))
        .collect()
}

fn mean_image(frames: &[Vec<Vec3>]) -> Vec<Vec3> {
    let n = frames.len() as f32;
    (0..frames[0].len())
        .map(|i| frames.iter().map(|f| f[i]).sum::<Vec3>() / n)
        .collect()
}

/// The mean luminance-like sum (r + g + b) over the image of each frame.
fn frame_means(frames: &[Vec<Vec3>]) -> Vec<f64> {
    frames
        .iter()
        .map(|f| f.iter().map(|c| f64::from(c.x + c.y + c.z)).sum::<f64>() / f.len() as f64)
        .collect()
}

/// Mean and standard error of `values`.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The mean over frames of one frame's relMSE against `converged`.
fn frame_error(frames: &[Vec<Vec3>], converged: &[Vec3]) -> f64 {
    frames
        .iter()
        .map(|f| common::rel_mse(f, converged))
        .sum::<f64>()
        / frames.len() as f64
}

#[test]
fn resampled_indirect_light_is_the_path_tracers_without_reuse_and_less_noisy_with_it() {
    let Some(mut gpu) = gpu() else {
        return;
    };
    let paths = indirect_frames(&mut gpu, &settings(None, 0, 1), BIAS_FRAMES);
    let own = indirect_frames(&mut gpu, &settings(Some(0), 0, 2), FRAMES);
    let reused = indirect_frames(&mut gpu, &settings(Some(4), 0, 3), FRAMES);
    let temporal = indirect_frames(&mut gpu, &settings(Some(4), 20, 5), FRAMES);
    let mut unbiased_settings = settings(Some(4), 0, 3);
    unbiased_settings.frame.restir.bias = RestirBias::Unbiased;
    let pairwise = indirect_frames(&mut gpu, &unbiased_settings, BIAS_FRAMES);
    let converged = mean_image(&paths);

    let (paths_mean, paths_se) = mean_and_error(&frame_means(&paths));
    let (own_mean, own_se) = mean_and_error(&frame_means(&own));
    let (reused_mean, reused_se) = mean_and_error(&frame_means(&reused));
    let z = (own_mean - paths_mean) / (own_se.powi(2) + paths_se.powi(2)).sqrt();
    let bias = reused_mean / paths_mean - 1.0;
    eprintln!(
        "image mean: paths {paths_mean:.5} +- {paths_se:.5}, own samples {own_mean:.5} +- \
         {own_se:.5} ({z:.2} SE), reused {reused_mean:.5} +- {reused_se:.5} ({:.2}%)",
        bias * 100.0
    );
    assert!(paths_mean > 0.01, "no indirect light: {paths_mean}");
    assert!(
        z.abs() < 4.0,
        "own samples differ from the paths by {z:.2} SE"
    );
    // The per-pixel means agree within the noise of two independent 128-frame means.
    let own_converged = mean_image(&own);
    let noise = frame_error(&paths, &converged) / f64::from(FRAMES);
    let between = common::rel_mse(&own_converged, &converged);
    eprintln!("per-pixel relMSE of the two means {between:.3e}, one mean's noise {noise:.3e}");
    assert!(between < 3.0 * noise, "{between:.3e} against {noise:.3e}");

    // Reuse: a biased estimator whose image mean stays within 5% and whose single frames are
    // closer to the converged image.
    assert!(bias.abs() < 0.05, "reuse moves the image mean by {bias:.3}");
    let paths_error = frame_error(&paths, &converged);
    let reused_error = frame_error(&reused, &converged);
    eprintln!("one frame's relMSE: paths {paths_error:.3e}, reused {reused_error:.3e}");
    assert!(
        reused_error < 0.8 * paths_error,
        "reuse: {reused_error:.3e}, paths {paths_error:.3e}"
    );

    // Weighted by pairwise MIS with visibility: the paths' image mean within the noise of
    // BIAS_FRAMES frames each (the counts' weights fail this: -1.7%, 6 SE), and single frames
    // as close to the converged image.
    let (pairwise_mean, pairwise_se) = mean_and_error(&frame_means(&pairwise));
    let z = (pairwise_mean - paths_mean) / (pairwise_se.powi(2) + paths_se.powi(2)).sqrt();
    let pairwise_error = frame_error(&pairwise, &converged);
    eprintln!(
        "pairwise MIS: image mean {pairwise_mean:.5} +- {pairwise_se:.5} ({:.2}%, {z:.2} SE), \
         one frame's relMSE {pairwise_error:.3e}",
        (pairwise_mean / paths_mean - 1.0) * 100.0
    );
    assert!(
        z.abs() < 4.0,
        "pairwise MIS moves the image mean by {z:.2} SE"
    );
    assert!(
        pairwise_error < 0.8 * paths_error,
        "pairwise MIS: {pairwise_error:.3e}, paths {paths_error:.3e}"
    );

    // Temporal reuse as well (a still camera whose frames are not averaged merges history
    // every frame): the mean within 5% again, one frame's error lower than spatial reuse's.
    let (temporal_mean, temporal_se) = mean_and_error(&frame_means(&temporal));
    let bias = temporal_mean / paths_mean - 1.0;
    // The first frames have no history yet: one frame's error is read from the 17th on.
    let spatial_error = frame_error(&reused[16..], &converged);
    let temporal_error = frame_error(&temporal[16..], &converged);
    eprintln!(
        "image mean: paths {paths_mean:.5}, temporal {temporal_mean:.5} +- {temporal_se:.5} \
         ({:.2}%); one frame's relMSE: spatial {spatial_error:.3e}, temporal {temporal_error:.3e}",
        bias * 100.0
    );
    assert!(
        bias.abs() < 0.05,
        "temporal reuse moves the image mean by {bias:.3}"
    );
    assert!(
        temporal_error < 0.7 * spatial_error,
        "temporal {temporal_error:.3e}, spatial {spatial_error:.3e}"
    );
}

#[test]
fn a_nan_in_a_pixels_sample_reaches_no_pixel() {
    let Some(mut gpu) = gpu() else {
        return;
    };
    let s = settings(Some(8), 20, 4);
    let clean = indirect_frames(&mut gpu, &s, 4);
    gpu.renderer.inject_non_finite(true);
    let poisoned = indirect_frames(&mut gpu, &s, 4);
    for (k, frame) in poisoned.iter().enumerate() {
        let bad = frame.iter().filter(|c| !c.is_finite()).count();
        assert_eq!(bad, 0, "frame {k}: {bad} pixels not finite");
    }
    // The poisoned samples (the centre pixel and the one to its right) are lit surfaces'
    // whose neighbours reuse them: the 9 x 9 block around them keeps the clean run's light.
    let centre = (SIZE / 2) as usize;
    let block = |frames: &[Vec<Vec3>]| -> f32 {
        let image = mean_image(frames);
        (centre - 4..=centre + 4)
            .flat_map(|y| (centre - 4..=centre + 4).map(move |x| (x, y)))
            .map(|(x, y)| image[y * SIZE as usize + x].element_sum())
            .sum()
    };
    let (clean_block, poisoned_block) = (block(&clean), block(&poisoned));
    eprintln!("block around the poison: clean {clean_block:.4}, poisoned {poisoned_block:.4}");
    assert!(clean_block > 0.0, "the centre is black");
    assert!(
        (poisoned_block / clean_block - 1.0).abs() < 0.25,
        "{poisoned_block} against {clean_block}"
    );
}
