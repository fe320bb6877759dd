//! `chiaro bench`: speed against error. For each scene, the converged reference (by default
//! the CPU reference path tracer's, or the GPU reference mode's: [`ReferenceRenderer`]; cached
//! on disk), then each GPU configuration from a fresh start on a static camera: the wall time
//! of every frame and the median time of each pass, and relMSE and mean LDR-FLIP against the
//! reference after each checkpoint's frame count; then the realtime configuration along a
//! scripted camera path ([`camera_path`]), measured after each checkpoint against the same
//! converged reference, every checkpoint being at the camera's own pose (`realtime-path`).
//! Results go to `results.json`, `results.md` and one error-against-time plot per scene (see
//! [`write_outputs`]).

pub mod animation_run;
pub mod camera_path;
mod configs;
mod plot;
mod reference_cache;
pub mod results;

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use bevy_ecs::world::World;
use chiaro_gpu::{RenderError, RenderSettings, Renderer};
use chiaro_scene::{Environment, LightUnits, LoadOptions, load_scene_with};
use thiserror::Error;

use crate::{CompareSettings, EvalError, HdrImage, compare};
use camera_path::{camera_transform, pan_at, set_pan};
use chiaro_scene::Transform;
use configs::path_configs;
pub use configs::{
    ALL_FEATURES_CONFIG, BenchConfig, RESTIR_CONFIG, RESTIR_DI_CONFIG, RESTIR_GI_CONFIG,
    RESTIR_GI_TEMPORAL_CONFIG, RESTIR_GI_UNBIASED_CONFIG, default_configs, extra_configs,
};
pub use reference_cache::{Reference, ReferenceRenderer, converged_reference};
use results::{BenchResults, Checkpoint, RunResult, SceneResult};

/// Why a benchmark stopped.
#[derive(Debug, Error)]
pub enum BenchError {
    /// A scene did not load.
    #[error("{scene}: {message}")]
    Scene {
        /// The scene.
        scene: String,
        /// What failed.
        message: String,
    },
    /// The CPU reference failed.
    #[error(transparent)]
    Reference(#[from] chiaro_reference::ReferenceError),
    /// The GPU renderer failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A comparison failed.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// A file could not be written.
    #[error("{path}: {message}")]
    Io {
        /// The file or folder.
        path: String,
        /// What failed.
        message: String,
    },
    /// A plot could not be drawn.
    #[error("plot: {0}")]
    Plot(String),
    /// A setting out of its range.
    #[error("{0}")]
    Settings(String),
}

impl BenchError {
    fn io(path: &Path, error: &std::io::Error) -> Self {
        Self::Io {
            path: path.display().to_string(),
            message: error.to_string(),
        }
    }
}

/// A scene to benchmark: a built-in scene or a glTF file, optionally under an environment
/// image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BenchScene {
    /// A .gltf or .glb path, or builtin:NAME.
    pub scene: String,
    /// An equirectangular .hdr or .exr environment replacing the scene's.
    pub env: Option<PathBuf>,
    /// How a glTF's punctual light intensities are read.
    pub light_units: LightUnits,
}

impl BenchScene {
    /// `scene` with its own environment.
    pub fn builtin(scene: &str) -> Self {
        Self {
            scene: scene.to_owned(),
            env: None,
            light_units: LightUnits::default(),
        }
    }

    /// The scene's name, with the environment file's when it has one.
    pub fn label(&self) -> String {
        match &self.env {
            Some(env) => format!(
                "{} under {}",
                self.scene,
                env.file_name().unwrap_or_default().to_string_lossy()
            ),
            None => self.scene.clone(),
        }
    }

    /// A World holding the scene.
    pub fn load(&self) -> Result<World, BenchError> {
        let fault = |message: String| BenchError::Scene {
            scene: self.label(),
            message,
        };
        let mut world = World::new();
        let options = LoadOptions {
            light_units: self.light_units,
            ..LoadOptions::default()
        };
        load_scene_with(&mut world, &self.scene, &options).map_err(|e| fault(e.to_string()))?;
        if let Some(path) = &self.env {
            let (environment, _) =
                Environment::from_file(path, 1.0).map_err(|e| fault(e.to_string()))?;
            world.insert_resource(environment);
        }
        Ok(world)
    }
}

/// The default scenes: the built-in set, and each model of `shared_scenes` (when that folder
/// exists) under the first `.hdr` environment found there.
pub fn default_scenes(shared_scenes: &Path) -> Vec<BenchScene> {
    let mut scenes: Vec<BenchScene> = [
        "builtin:cornell",
        "builtin:hard-cases",
        "builtin:instances",
        "builtin:many-lights",
        "builtin:walkthrough",
    ]
    .map(BenchScene::builtin)
    .to_vec();
    let Ok(entries) = fs::read_dir(shared_scenes) else {
        return scenes;
    };
    let mut files: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.sort();
    let has = |p: &PathBuf, ext: &str| p.extension().is_some_and(|e| e == ext);
    let env = files.iter().find(|p| has(p, "hdr")).cloned();
    scenes.extend(
        files
            .iter()
            .filter(|p| has(p, "glb") || has(p, "gltf"))
            .map(|p| BenchScene {
                scene: p.display().to_string(),
                env: env.clone(),
                light_units: LightUnits::default(),
            }),
    );
    scenes
}

/// How the benchmark runs.
#[derive(Clone, Debug)]
pub struct BenchSettings {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frame counts after which the error is measured, increasing; the last is how many
    /// frames each configuration renders.
    pub checkpoints: Vec<u32>,
    /// Samples per pixel of the converged reference.
    pub reference_spp: u32,
    /// What draws the converged references.
    pub reference_renderer: ReferenceRenderer,
    /// Where the references are cached.
    pub cache_dir: PathBuf,
    /// Frames rendered and thrown away before timing (pipelines and caches warm).
    pub warmup_frames: u32,
    /// Whether the realtime configuration also runs along the camera path
    /// ([`camera_path`]), against the same reference.
    pub camera_path: bool,
}

/// What the benchmark is doing, for a progress display.
#[derive(Clone, Debug)]
pub enum BenchProgress {
    /// Rendering or reading the reference of a scene.
    Reference(String),
    /// Running a configuration on a scene.
    Run {
        /// The scene.
        scene: String,
        /// The configuration.
        config: String,
    },
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

/// Runs `config` on `world` and measures it after the i-th checkpoint against
/// `references[i]`; with `path` (the camera's own transform), the camera pans along the
/// scripted path before each frame ([`camera_path`]) and is put back after the run.
fn measure(
    renderer: &mut Renderer,
    world: &mut World,
    config: &BenchConfig,
    settings: &BenchSettings,
    references: &[&HdrImage],
    path: Option<&Transform>,
) -> Result<RunResult, BenchError> {
    let render = RenderSettings {
        width: settings.width,
        height: settings.height,
        ..config.settings
    };
    if settings.warmup_frames > 0 {
        renderer.render(
            world,
            &RenderSettings {
                frames: settings.warmup_frames,
                seed: render.seed ^ 0x77a2,
                ..render
            },
        )?;
    }
    // On a real GPU the comparisons (FLIP takes most of a second at 1920x1080) run on other
    // cores while the GPU renders on; on a CPU adapter (lavapipe) they run between frames, so
    // that they take no cores from the frames being timed.
    let in_background = !renderer.context.runs_on_cpu();
    let mut frame_ms = Vec::new();
    let mut latency_ms = Vec::new();
    let mut pass_ms: Vec<(String, Vec<f64>)> = Vec::new();
    let mut gpu_timestamps = false;
    let mut seconds = 0.0;
    let mut add_times = |times: Vec<chiaro_gpu::PassTimes>| {
        for t in times {
            gpu_timestamps = t.gpu_timestamps;
            latency_ms.push(t.wall_ms);
            for (i, (name, ms)) in t.passes.iter().enumerate() {
                match pass_ms.get_mut(i) {
                    Some((_, all)) => all.push(*ms),
                    None => pass_ms.push(((*name).to_owned(), vec![*ms])),
                }
            }
        }
    };
    let last = settings.checkpoints.last().copied().unwrap_or(1);
    let checkpoints = std::thread::scope(|scope| -> Result<Vec<Checkpoint>, BenchError> {
        let mut pending = Vec::new();
        for frame in 1..=last {
            if let Some(base) = path {
                set_pan(world, base, pan_at(frame, &settings.checkpoints));
            }
            let start = Instant::now();
            let times = if frame == 1 {
                renderer
                    .render(
                        world,
                        &RenderSettings {
                            frames: 1,
                            ..render
                        },
                    )?
                    .times
            } else {
                renderer.accumulate(world, &render, 1)?
            };
            let elapsed = start.elapsed().as_secs_f64();
            seconds += elapsed;
            frame_ms.push(elapsed * 1e3);
            add_times(times);
            if let Some(k) = settings.checkpoints.iter().position(|c| *c == frame) {
                // The frames still in flight count towards the time the image took.
                let drain = Instant::now();
                add_times(renderer.finish());
                seconds += drain.elapsed().as_secs_f64();
                let output = renderer.read(&render)?;
                let image = HdrImage::new(&config.name, output.width, output.height, output.hdr)?;
                let reference = references[k];
                let measure_at = move || -> Result<Checkpoint, BenchError> {
                    let metrics = compare(&image, reference, &CompareSettings::default())?.metrics;
                    Ok(Checkpoint {
                        frames: frame,
                        seconds,
                        rel_mse: metrics.rel_mse,
                        flip_mean: metrics.flip_mean,
                    })
                };
                pending.push(if in_background {
                    Pending::Running(scope.spawn(measure_at))
                } else {
                    Pending::Done(measure_at())
                });
            }
        }
        pending.into_iter().map(Pending::finish).collect()
    })?;
    if let Some(base) = path {
        set_pan(world, base, 0.0);
    }
    Ok(RunResult {
        config: config.name.clone(),
        median_frame_ms: median(&mut frame_ms),
        median_latency_ms: median(&mut latency_ms),
        frames_per_second: f64::from(last) / seconds.max(f64::MIN_POSITIVE),
        pass_ms: pass_ms
            .into_iter()
            .map(|(name, mut all)| (name, median(&mut all)))
            .collect(),
        gpu_timestamps,
        checkpoints,
    })
}

/// A checkpoint's comparison: measured already, or running on another thread.
enum Pending<'scope> {
    Done(Result<Checkpoint, BenchError>),
    Running(std::thread::ScopedJoinHandle<'scope, Result<Checkpoint, BenchError>>),
}

impl Pending<'_> {
    fn finish(self) -> Result<Checkpoint, BenchError> {
        match self {
            Pending::Done(result) => result,
            Pending::Running(handle) => handle.join().expect("a comparison does not panic"),
        }
    }
}

/// `config` along the camera path, against the scene's converged reference (every checkpoint
/// is at the camera's own pose).
fn measure_path(
    renderer: &mut Renderer,
    world: &mut World,
    (scene, config): (&BenchScene, &BenchConfig),
    settings: &BenchSettings,
    reference: &HdrImage,
) -> Result<RunResult, BenchError> {
    let base = camera_transform(world, &scene.label())?;
    let references = vec![reference; settings.checkpoints.len()];
    measure(renderer, world, config, settings, &references, Some(&base))
}

/// The converged reference of `scene` as `world` holds it (posed, if it is), at the
/// benchmark's size and sample count, from the cache when it is there.
fn scene_reference(
    renderer: &mut Renderer,
    scene: &BenchScene,
    world: &mut World,
    settings: &BenchSettings,
) -> Result<Reference, BenchError> {
    converged_reference(
        scene,
        world,
        (settings.width, settings.height, settings.reference_spp),
        settings.reference_renderer,
        renderer,
        &settings.cache_dir,
    )
}

/// Runs every configuration on every scene; `progress` hears of each step before it starts.
pub fn run_bench(
    renderer: &mut Renderer,
    scenes: &[BenchScene],
    configs: &[BenchConfig],
    settings: &BenchSettings,
    progress: &mut dyn FnMut(BenchProgress),
) -> Result<BenchResults, BenchError> {
    if settings.checkpoints.is_empty() || !settings.checkpoints.is_sorted() {
        return Err(BenchError::Settings(format!(
            "checkpoints {:?} must be a non-empty increasing list of frame counts",
            settings.checkpoints
        )));
    }
    if settings.checkpoints[0] == 0 || settings.reference_spp < 2 {
        return Err(BenchError::Settings(
            "checkpoints start at 1 frame and the reference needs at least 2 spp".into(),
        ));
    }
    let info = &renderer.context.info;
    let mut results = BenchResults {
        adapter: renderer.context.describe(),
        driver: format!("{} {}", info.driver, info.driver_info),
        width: settings.width,
        height: settings.height,
        rel_mse_epsilon: CompareSettings::default().rel_mse_epsilon,
        flip_tonemapping: "Khronos PBR Neutral, exposure 1, 67 pixels per degree".into(),
        reference_renderer: settings.reference_renderer.name(),
        frames_in_flight: renderer.frames_in_flight(),
        scenes: Vec::new(),
    };
    for scene in scenes {
        progress(BenchProgress::Reference(scene.label()));
        let mut world = scene.load()?;
        let reference = scene_reference(renderer, scene, &mut world, settings)?;
        let mut runs = Vec::new();
        let statics = vec![&reference.image; settings.checkpoints.len()];
        for config in configs {
            progress(BenchProgress::Run {
                scene: scene.label(),
                config: config.name.clone(),
            });
            runs.push(measure(
                renderer, &mut world, config, settings, &statics, None,
            )?);
        }
        for config in settings
            .camera_path
            .then(|| path_configs(configs))
            .into_iter()
            .flatten()
        {
            progress(BenchProgress::Run {
                scene: scene.label(),
                config: config.name.clone(),
            });
            runs.push(measure_path(
                renderer,
                &mut world,
                (scene, &config),
                settings,
                &reference.image,
            )?);
        }
        if animation_run::animated(&world) {
            progress(BenchProgress::Run {
                scene: scene.label(),
                config: animation_run::ANIMATED_CONFIG.into(),
            });
        }
        let animation = animation_run::measure_animation(renderer, &mut world, scene, settings)?;
        results.scenes.push(SceneResult {
            scene: scene.label(),
            reference_spp: settings.reference_spp,
            reference_noise: reference.noise,
            reference_seconds: if reference.cached {
                0.0
            } else {
                reference.seconds
            },
            runs,
            animation,
        });
    }
    Ok(results)
}

/// Writes `results.json`, `results.md` and `error_vs_time_N.png` (N the scene's index) into
/// `dir`; returns the files written. A plot that cannot be drawn (no font for its labels) is
/// logged and left out; the tables are always written.
pub fn write_outputs(results: &BenchResults, dir: &Path) -> Result<Vec<PathBuf>, BenchError> {
    fs::create_dir_all(dir).map_err(|e| BenchError::io(dir, &e))?;
    let json_path = dir.join("results.json");
    let json = serde_json::to_string_pretty(results).expect("plain data");
    fs::write(&json_path, json).map_err(|e| BenchError::io(&json_path, &e))?;
    let md_path = dir.join("results.md");
    fs::write(&md_path, results.to_markdown()).map_err(|e| BenchError::io(&md_path, &e))?;
    let mut written = vec![json_path, md_path];
    for (i, scene) in results.scenes.iter().enumerate() {
        let path = dir.join(format!("error_vs_time_{i}.png"));
        match plot::plot_scene(&path, results, scene) {
            Ok(()) => written.push(path),
            Err(e) => log::warn!("{}: {e}", path.display()),
        }
    }
    Ok(written)
}
