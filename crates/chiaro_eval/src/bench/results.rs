//! What a benchmark measured, as `results.json` and as a markdown table, with the equal-time
//! comparison read off the error-against-time curves.

use serde::Serialize;

/// Everything one `chiaro bench` run measured.
#[derive(Clone, Debug, Serialize)]
pub struct BenchResults {
    /// The adapter, its backend and device type.
    pub adapter: String,
    /// The adapter's driver and its version.
    pub driver: String,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// relMSE's epsilon.
    pub rel_mse_epsilon: f32,
    /// How the 8-bit images FLIP reads were made.
    pub flip_tonemapping: String,
    /// What drew the converged references ([`super::ReferenceRenderer::name`]).
    pub reference_renderer: String,
    /// The most frames the renderer kept in flight
    /// ([`chiaro_gpu::Renderer::set_frames_in_flight`]).
    pub frames_in_flight: u32,
    /// Per scene.
    pub scenes: Vec<SceneResult>,
}

/// One scene's reference and runs.
#[derive(Clone, Debug, Serialize)]
pub struct SceneResult {
    /// The scene, with its environment when it has one.
    pub scene: String,
    /// Samples per pixel of the converged reference.
    pub reference_spp: u32,
    /// The reference's own relMSE noise (a quarter of the relMSE between its halves): errors
    /// near it are limited by the reference.
    pub reference_noise: f64,
    /// Seconds the reference took to render (0 when read from the cache).
    pub reference_seconds: f64,
    /// One per configuration.
    pub runs: Vec<RunResult>,
    /// The realtime frame while the scene's animations play, for a scene that has any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub animation: Option<AnimationRun>,
}

/// The realtime frame on an animated scene as it plays ([`super::animation_run`]).
#[derive(Clone, Debug, Serialize)]
pub struct AnimationRun {
    /// Frames per second of scene time.
    pub fps: f64,
    /// Wall time from one frame's start to the next's (scene systems, recording, submission,
    /// and the wait for the GPU once the frames in flight are at their limit), percentiles,
    /// milliseconds.
    pub frame_ms_p50: f64,
    /// The 95th percentile.
    pub frame_ms_p95: f64,
    /// The 99th percentile.
    pub frame_ms_p99: f64,
    /// Median CPU time per frame of the scene systems: animation, skinning, BVH update and
    /// upload, milliseconds.
    pub systems_ms_median: f64,
    /// Error at each checkpoint against the reference posed at its time.
    pub checkpoints: Vec<PoseCheckpoint>,
    /// Mean relMSE between consecutive frames at the checkpoints (after the first).
    pub flicker: Option<f64>,
    /// Mean relMSE between the converged references of the same consecutive poses.
    pub reference_flicker: Option<f64>,
}

/// The error of an animated run at one checkpoint.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PoseCheckpoint {
    /// Frames rendered.
    pub frames: u32,
    /// The scene time shown, seconds.
    pub scene_seconds: f64,
    /// relMSE against the reference at that time.
    pub rel_mse: f64,
    /// Mean LDR-FLIP against it.
    pub flip_mean: f64,
    /// That reference's own noise.
    pub reference_noise: f64,
}

impl AnimationRun {
    /// The run as a paragraph of markdown.
    fn to_markdown(&self) -> String {
        let errors: Vec<String> = self
            .checkpoints
            .iter()
            .map(|c| {
                format!(
                    "@{} ({:.2} s) {:.3e} / {:.4}",
                    c.frames, c.scene_seconds, c.rel_mse, c.flip_mean
                )
            })
            .collect();
        let flicker = match (self.flicker, self.reference_flicker) {
            (Some(f), Some(r)) => format!(
                " Temporal stability: consecutive frames differ by relMSE {f:.3e} on average, \
                 consecutive converged references by {r:.3e}."
            ),
            _ => String::new(),
        };
        format!(
            "\n`{}`: the realtime frame while the scene's animations play at {} frames a \
             second of scene time. Frame time p50 {:.2} ms, p95 {:.2} ms, p99 {:.2} ms; the \
             scene systems (animation, skinning, BVH update, upload) {:.2} ms a frame (median). \
             relMSE / FLIP against the reference posed at each checkpoint's time: {}.{flicker}\n",
            super::animation_run::ANIMATED_CONFIG,
            self.fps,
            self.frame_ms_p50,
            self.frame_ms_p95,
            self.frame_ms_p99,
            self.systems_ms_median,
            errors.join("; "),
        )
    }
}

/// One configuration's figures on one scene.
#[derive(Clone, Debug, Serialize)]
pub struct RunResult {
    /// The configuration's name.
    pub config: String,
    /// Median wall time from one frame's start on the CPU to the next's, milliseconds: with
    /// frames in flight, what the GPU takes per frame once the pipeline is full (1 / the
    /// throughput); with one in flight, the frame's latency.
    pub median_frame_ms: f64,
    /// Median latency of a frame, from its start on the CPU to the CPU seeing it finished,
    /// milliseconds ([`chiaro_gpu::PassTimes::wall_ms`]).
    pub median_latency_ms: f64,
    /// Frames per second over the run: its frames over the wall time they took, the frames
    /// in flight at each checkpoint waited for (the image readbacks left out).
    pub frames_per_second: f64,
    /// Median time of each pass, milliseconds, in frame order.
    pub pass_ms: Vec<(String, f64)>,
    /// True when the pass times are GPU timestamps, false when wall clock.
    pub gpu_timestamps: bool,
    /// Error after each checkpoint's frame count, static camera.
    pub checkpoints: Vec<Checkpoint>,
}

/// The error after a number of frames.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Checkpoint {
    /// Frames rendered.
    pub frames: u32,
    /// Wall time of those frames, seconds.
    pub seconds: f64,
    /// relMSE against the converged reference (linear HDR).
    pub rel_mse: f64,
    /// Mean LDR-FLIP against the converged reference.
    pub flip_mean: f64,
}

impl RunResult {
    /// The relMSE at `seconds` of rendering, interpolated log-log between the checkpoints
    /// around it; `None` outside the measured span.
    pub fn rel_mse_at(&self, seconds: f64) -> Option<f64> {
        let points: Vec<(f64, f64)> = self
            .checkpoints
            .iter()
            .filter(|c| c.seconds > 0.0 && c.rel_mse > 0.0)
            .map(|c| (c.seconds.ln(), c.rel_mse.ln()))
            .collect();
        let t = seconds.ln();
        if let [(t0, e0)] = points[..] {
            return ((t - t0).abs() < 1e-9).then(|| e0.exp());
        }
        points.windows(2).find_map(|w| {
            let ((t0, e0), (t1, e1)) = (w[0], w[1]);
            (t0 <= t && t <= t1).then(|| {
                let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
                (e0 + s * (e1 - e0)).exp()
            })
        })
    }
}

impl SceneResult {
    /// The equal-time budget: the longest time every run reached, seconds.
    pub fn equal_time_budget(&self) -> Option<f64> {
        self.runs
            .iter()
            .filter_map(|r| r.checkpoints.last().map(|c| c.seconds))
            .reduce(f64::min)
    }

    /// The realtime frame specialised to the scene's features against the same frame with
    /// every feature compiled in: the time ratio, and whether the two images agree (the same
    /// error against the reference at every checkpoint); `None` when either was not run.
    pub fn specialization_summary(&self) -> Option<String> {
        let run = |name: &str| self.runs.iter().find(|r| r.config == name);
        let (specialized, all) = (run("realtime")?, run(super::ALL_FEATURES_CONFIG)?);
        let same_image = specialized
            .checkpoints
            .iter()
            .zip(&all.checkpoints)
            .all(|(a, b)| a.rel_mse == b.rel_mse);
        Some(format!(
            "Specialised pipelines: the realtime frame takes {:.2} ms specialised to the scene's \
             features against {:.2} ms with every feature compiled in, {:.3}x faster; the images \
             {} (relMSE against the reference at each checkpoint).",
            specialized.median_frame_ms,
            all.median_frame_ms,
            all.median_frame_ms / specialized.median_frame_ms,
            if same_image { "are the same" } else { "DIFFER" },
        ))
    }
}

fn pass_summary(run: &RunResult) -> String {
    run.pass_ms
        .iter()
        .map(|(name, ms)| format!("{name} {ms:.2}"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl BenchResults {
    /// The results as markdown: a header naming the adapter, driver and size; per scene a
    /// table of frame time and error after each checkpoint, then the equal-time comparison.
    pub fn to_markdown(&self) -> String {
        let mut md = format!(
            "Adapter: {}; driver: {}; {}x{}. Error: relMSE (linear HDR, epsilon {}) and mean \
             LDR-FLIP ({}) against the converged reference ({}), static camera; time, with up \
             to {} frames in flight: frame, the median wall time from one frame's start to the \
             next's (1 / throughput once the GPU is busy); latency, the median from a frame's \
             start to its end; fps, frames over the run's time; and per pass (ms).\n",
            self.adapter,
            self.driver,
            self.width,
            self.height,
            self.rel_mse_epsilon,
            self.flip_tonemapping,
            self.reference_renderer,
            self.frames_in_flight,
        );
        for scene in &self.scenes {
            md += &format!(
                "\n### {}\n\nReference: {} spp, own noise {:.2e}.\n\n",
                scene.scene, scene.reference_spp, scene.reference_noise
            );
            let frames: Vec<u32> = scene
                .runs
                .first()
                .map(|r| r.checkpoints.iter().map(|c| c.frames).collect())
                .unwrap_or_default();
            md += "| config | frame (ms) | latency (ms) | fps |";
            for f in &frames {
                md += &format!(" relMSE @{f} | FLIP @{f} |");
            }
            md += " passes (ms) |\n|---|---|---|---|";
            md += &"---|---|".repeat(frames.len());
            md += "---|\n";
            for run in &scene.runs {
                md += &format!(
                    "| {} | {:.2} | {:.2} | {:.1} |",
                    run.config, run.median_frame_ms, run.median_latency_ms, run.frames_per_second
                );
                for c in &run.checkpoints {
                    md += &format!(" {:.3e} | {:.4} |", c.rel_mse, c.flip_mean);
                }
                md += &format!(" {} |\n", pass_summary(run));
            }
            if let Some(budget) = scene.equal_time_budget() {
                md += &format!("\nAt equal time ({budget:.3} s of frames): ");
                let at: Vec<String> = scene
                    .runs
                    .iter()
                    .map(|r| match r.rel_mse_at(budget) {
                        Some(e) => format!("{} {e:.3e}", r.config),
                        None => format!("{} (slower than the budget)", r.config),
                    })
                    .collect();
                md += &at.join("; ");
                md += ".\n";
            }
            if let Some(path) = scene
                .runs
                .iter()
                .find(|r| r.config == super::camera_path::PATH_CONFIG)
            {
                let frames: Vec<u32> = path.checkpoints.iter().map(|c| c.frames).collect();
                md += &format!(
                    "\n`{}`: the realtime configuration while the camera pans about its up axis \
                     at {} degrees a frame, out and back between checkpoints (up to {} degrees), \
                     each checkpoint at the camera's own pose, against the same reference.\n",
                    super::camera_path::PATH_CONFIG,
                    super::camera_path::PAN_DEGREES_PER_FRAME,
                    super::camera_path::largest_pan(&frames)
                );
            }
            if let Some(line) = scene.specialization_summary() {
                md += &format!("\n{line}\n");
            }
            if let Some(animation) = &scene.animation {
                md += &animation.to_markdown();
            }
        }
        md
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(points: &[(f64, f64)]) -> RunResult {
        RunResult {
            config: "x".into(),
            median_frame_ms: 1.0,
            median_latency_ms: 1.0,
            frames_per_second: 1000.0,
            pass_ms: vec![("direct".into(), 1.0)],
            gpu_timestamps: false,
            checkpoints: points
                .iter()
                .enumerate()
                .map(|(i, &(seconds, rel_mse))| Checkpoint {
                    frames: 1 << (2 * i),
                    seconds,
                    rel_mse,
                    flip_mean: 0.1,
                })
                .collect(),
        }
    }

    #[test]
    fn error_at_a_time_follows_the_log_log_line_and_is_none_outside_it() {
        // Error halving per doubling of time: a slope of -1 on log-log.
        let r = run(&[(1.0, 1.0), (4.0, 0.25)]);
        assert!((r.rel_mse_at(2.0).unwrap() - 0.5).abs() < 1e-9);
        assert!((r.rel_mse_at(4.0).unwrap() - 0.25).abs() < 1e-9);
        assert_eq!(r.rel_mse_at(0.5), None);
        assert_eq!(r.rel_mse_at(8.0), None);
    }

    #[test]
    fn the_budget_is_the_shortest_run_and_the_table_names_every_run() {
        let results = BenchResults {
            adapter: "a".into(),
            driver: "d".into(),
            width: 8,
            height: 8,
            rel_mse_epsilon: 0.01,
            flip_tonemapping: "t".into(),
            reference_renderer: "CPU reference".into(),
            frames_in_flight: 2,
            scenes: vec![SceneResult {
                scene: "builtin:cornell".into(),
                reference_spp: 4,
                reference_noise: 1e-3,
                reference_seconds: 1.0,
                runs: vec![run(&[(1.0, 1.0), (4.0, 0.25)]), {
                    let mut fast = run(&[(0.5, 2.0), (2.0, 1.0)]);
                    fast.config = "fast".into();
                    fast
                }],
                animation: Some(AnimationRun {
                    fps: 30.0,
                    frame_ms_p50: 10.0,
                    frame_ms_p95: 12.5,
                    frame_ms_p99: 20.0,
                    systems_ms_median: 1.25,
                    checkpoints: vec![PoseCheckpoint {
                        frames: 4,
                        scene_seconds: 0.1,
                        rel_mse: 0.5,
                        flip_mean: 0.25,
                        reference_noise: 1e-3,
                    }],
                    flicker: Some(0.02),
                    reference_flicker: Some(0.01),
                }),
            }],
        };
        assert_eq!(results.scenes[0].equal_time_budget(), Some(2.0));
        let md = results.to_markdown();
        assert!(md.contains("| x | 1.00 |"), "{md}");
        assert!(md.contains("| fast | 1.00 |"), "{md}");
        assert!(md.contains("x 5.000e-1; fast 1.000e0"), "{md}");
        assert!(
            md.contains("p50 10.00 ms, p95 12.50 ms, p99 20.00 ms"),
            "{md}"
        );
        assert!(md.contains("@4 (0.10 s) 5.000e-1 / 0.2500"), "{md}");
        assert!(md.contains("by relMSE 2.000e-2 on average"), "{md}");
    }
}
