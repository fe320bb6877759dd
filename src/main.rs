//! The `chiaro` command line.

mod bench;
mod compare;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use bevy_ecs::world::World;
use clap::{Args, Parser, Subcommand, ValueEnum};
use glam::Vec3;

use chiaro::gpu::{FrameSettings, RenderMode};
use chiaro::reference::{
    LightSampling, PathSettings, RenderSettings, render_world, write_exr, write_png,
};
use chiaro::scene::{Environment, SceneInfo, load_scene};
use chiaro::shading::tonemap::Tonemapper;

#[derive(Parser)]
#[command(
    name = "chiaro",
    version,
    about = "A real-time hybrid path tracer for bevy_ecs applications"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Options shared by every command that takes a scene.
#[derive(Args)]
struct SceneArgs {
    /// A .gltf or .glb file, or builtin:NAME (cornell, furnace, hard-cases, instances,
    /// many-lights), e.g. builtin:instances?n=10000.
    scene: String,
    /// Replaces the scene's environment: an equirectangular .hdr or .exr image, or a constant
    /// linear colour R,G,B.
    #[arg(long)]
    env: Option<String>,
    /// Multiplies the environment's radiance.
    #[arg(long, default_value_t = 1.0)]
    env_strength: f32,
}

#[derive(Subcommand)]
enum Command {
    /// Print what a scene holds: meshes, triangles, instances, materials and their texture
    /// slots, lights by kind, emissive triangles, camera, environment, bounds, and what import
    /// repaired.
    Info {
        #[command(flatten)]
        scene: SceneArgs,
    },
    /// Render on the GPU (any adapter wgpu finds, lavapipe included), accumulating frames:
    /// a PNG (tonemapped) or an EXR (linear HDR).
    Render {
        /// A .gltf or .glb file, or builtin:NAME.
        #[arg(default_value = "builtin:cornell")]
        scene: String,
        /// Replaces the scene's environment: an .hdr or .exr image, or a colour R,G,B.
        #[arg(long)]
        env: Option<String>,
        /// Multiplies the environment's radiance.
        #[arg(long, default_value_t = 1.0)]
        env_strength: f32,
        /// Image size, WxH.
        #[arg(long, default_value = "512x512", value_parser = parse_size)]
        size: (u32, u32),
        /// Frames to render (the realtime image is the last; the other modes average them).
        #[arg(long, default_value_t = 16)]
        frames: u32,
        /// Output file, .png or .exr.
        #[arg(long, default_value = "chiaro.png")]
        out: PathBuf,
        #[command(flatten)]
        frame: FrameArgs,
        /// Seed of the random numbers.
        #[arg(long, default_value_t = 0)]
        seed: u64,
    },
    /// Render the converged ground truth with the CPU reference path tracer: an EXR (linear) and
    /// a PNG (tonemapped) beside it, plus the EXR of an independent half of the samples.
    Reference {
        #[command(flatten)]
        scene: SceneArgs,
        /// Samples per pixel (at least 2).
        #[arg(long, default_value_t = 256)]
        spp: u32,
        /// Image size, WxH.
        #[arg(long, default_value = "256x256", value_parser = parse_size)]
        size: (u32, u32),
        /// Output file, .exr or .png (the other format is written beside it).
        #[arg(long, default_value = "reference.exr")]
        out: PathBuf,
        /// Emission plus direct light at the first hit only.
        #[arg(long)]
        direct_only: bool,
        /// Seed of the random streams.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Worker threads (default: one per core).
        #[arg(long)]
        threads: Option<usize>,
        /// Most bounces per path: 0 shows emitters only, 1 is direct light, and the light the
        /// last bounce's ray reaches is counted (Russian roulette ends most paths well before).
        #[arg(long, default_value_t = 64)]
        max_depth: u32,
        /// How a light is picked for next-event estimation: tree (by importance to the shading
        /// point, through a light tree) or power (by power alone).
        #[arg(long, default_value = "tree")]
        light_sampling: LightSampling,
    },
    /// Measure an image against a reference: relMSE (linear HDR, epsilon 0.01) and SMAPE, then
    /// PSNR (dB) and mean LDR-FLIP of the tonemapped 8-bit images; one `name value` per line.
    Compare(compare::CompareArgs),
    /// Speed against error: each GPU configuration on each scene against the converged CPU
    /// reference (cached), error after 1, 4, 16 and 64 frames, frame and pass times; writes
    /// results.json, results.md and an error-against-time plot per scene.
    Bench(bench::BenchArgs),
    /// Open a window on the realtime frame: W/A/S/D and Q/E move, the right mouse button held
    /// turns the view, the wheel sets the speed, shift is fast; Tab shows the settings panel;
    /// F12 saves chiaro-NNNN.png and .exr; drop a .glb, .gltf, .hdr or .exr to load it.
    View {
        /// A .gltf or .glb file, or builtin:NAME.
        #[arg(default_value = "builtin:cornell")]
        scene: String,
        /// Replaces the scene's environment: an .hdr or .exr image, or a colour R,G,B.
        #[arg(long)]
        env: Option<String>,
        /// Multiplies the environment's radiance.
        #[arg(long, default_value_t = 1.0)]
        env_strength: f32,
        /// Window size, WxH.
        #[arg(long, default_value = "1280x720", value_parser = parse_size)]
        size: (u32, u32),
        /// Replays the input in this file (frames N, key W N, look DX DY, resize W H,
        /// drop PATH, screenshot PATH, panel on|off; one a line), then exits.
        #[arg(long)]
        script: Option<PathBuf>,
        /// Saves the last frame when the script ends (after 16 frames without --script):
        /// .png (tonemapped) or .exr (linear HDR).
        #[arg(long)]
        screenshot: Option<PathBuf>,
        #[command(flatten)]
        frame: FrameArgs,
        /// Seed of the random numbers.
        #[arg(long, default_value_t = 0)]
        seed: u64,
    },
}

/// What `chiaro render` computes per frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Mode {
    /// Direct and indirect light, temporal accumulation and a-trous denoising: the real-time
    /// frame (the last frame is the image).
    Realtime,
    /// Progressive unbiased path tracing on the GPU, the mean of the frames (each frame one
    /// camera ray and direct-light estimate a pixel, and --spp indirect paths from it).
    Reference,
    /// Pure path tracing with uniform hemisphere directions and no light sampling (the
    /// baseline), the mean of the frames.
    Naive,
    /// Emission and direct light with shadow rays (MIS for area lights and the environment),
    /// the mean of the frames.
    Direct,
}

impl From<Mode> for RenderMode {
    fn from(mode: Mode) -> Self {
        match mode {
            Mode::Realtime => RenderMode::Realtime,
            Mode::Reference => RenderMode::Reference,
            Mode::Naive => RenderMode::Naive,
            Mode::Direct => RenderMode::Direct,
        }
    }
}

/// What each frame of `chiaro render` computes.
#[derive(Args)]
struct FrameArgs {
    /// What the frame computes.
    #[arg(long, value_enum, default_value_t = Mode::Realtime)]
    mode: Mode,
    /// Indirect paths per pixel per frame (1..=64).
    #[arg(long, default_value_t = 1)]
    spp: u32,
    /// Surfaces after the first at which a realtime path gathers light (1..=64).
    #[arg(long, default_value_t = chiaro::gpu::settings::DEFAULT_BOUNCES)]
    bounces: u32,
    /// Turns the realtime mode's denoiser (temporal, variance, a-trous) off.
    #[arg(long)]
    no_denoise: bool,
    /// How next-event estimation picks a light: tree (by importance to the shading point,
    /// through light trees) or power (by power alone).
    #[arg(long, default_value = "tree")]
    light_sampling: LightSampling,
    /// Most luminance one realtime light sample (an indirect path, the direct light's BRDF
    /// sample or randomly picked light) may bring, in units of display white at the exposure, a
    /// brighter one scaled down to it (fewer fireflies, some energy lost); 0 is off.
    #[arg(long, default_value_t = chiaro::gpu::settings::DEFAULT_FIREFLY_CLAMP)]
    firefly_clamp: f32,
}

impl FrameArgs {
    fn settings(&self) -> FrameSettings {
        let mut settings = FrameSettings {
            mode: self.mode.into(),
            spp: self.spp,
            bounces: self.bounces,
            light_sampling: self.light_sampling,
            firefly_clamp: self.firefly_clamp,
            ..FrameSettings::default()
        };
        settings.denoise.enabled = !self.no_denoise;
        settings
    }
}

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once('x')
        .ok_or_else(|| format!("'{text}' is not WxH"))?;
    match (w.parse::<u32>(), h.parse::<u32>()) {
        (Ok(w), Ok(h)) if w > 0 && h > 0 && w <= 16384 && h <= 16384 => Ok((w, h)),
        _ => Err(format!("'{text}' is not WxH with sides in 1..=16384")),
    }
}

/// A reader that closes its end early (`chiaro compare A B | head -1`) ends the program
/// quietly, as it does other command-line tools, rather than in a panic of the next print.
#[cfg(unix)]
fn end_quietly_on_a_closed_pipe() {
    // SAFETY: called first in main, before any other thread runs; SIG_DFL is a valid
    // disposition for SIGPIPE (Rust's runtime set it to ignored).
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> Result<()> {
    #[cfg(unix)]
    end_quietly_on_a_closed_pipe();
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = match std::env::args_os().len() {
        1 => Cli::parse_from(["chiaro", "render"]),
        _ => Cli::parse(),
    };
    match cli.command {
        Command::Info { scene } => info(&scene),
        Command::Render {
            scene,
            env,
            env_strength,
            size,
            frames,
            out,
            frame,
            seed,
        } => {
            let scene = SceneArgs {
                scene,
                env,
                env_strength,
            };
            render(&scene, size, frames, &out, frame.settings(), seed)
        }
        Command::Compare(args) => compare::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::View {
            scene,
            env,
            env_strength,
            size,
            script,
            screenshot,
            frame,
            seed,
        } => {
            let scene = SceneArgs {
                scene,
                env,
                env_strength,
            };
            view(
                &scene,
                size,
                script.as_deref(),
                screenshot,
                frame.settings(),
                seed,
            )
        }
        Command::Reference {
            scene,
            spp,
            size,
            out,
            direct_only,
            seed,
            threads,
            max_depth,
            light_sampling,
        } => {
            let path = PathSettings {
                max_depth,
                direct_only,
                light_sampling,
                ..PathSettings::default()
            };
            let settings = RenderSettings {
                width: size.0,
                height: size.1,
                spp,
                seed,
                threads,
                path,
            };
            reference(&scene, &settings, &out)
        }
    }
}

/// Loads the scene and applies the environment options.
fn load(args: &SceneArgs) -> Result<World> {
    let mut world = World::new();
    load_scene(&mut world, &args.scene)?;
    if let Some(env) = &args.env {
        let environment = match parse_color(env) {
            Some(color) => {
                let mut environment = Environment::constant(color);
                environment.strength = args.env_strength;
                environment
            }
            None => {
                let path = Path::new(env);
                let (environment, repairs) = Environment::from_file(path, args.env_strength)?;
                for r in repairs {
                    log::warn!("{}: {r}", path.display());
                }
                environment
            }
        };
        world.insert_resource(environment);
    }
    Ok(world)
}

/// `R,G,B` as a colour, if `text` is one.
fn parse_color(text: &str) -> Option<Vec3> {
    let parts: Vec<f32> = text
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .ok()?;
    match parts[..] {
        [r, g, b] if [r, g, b].iter().all(|c| c.is_finite() && *c >= 0.0) => {
            Some(Vec3::new(r, g, b))
        }
        _ => None,
    }
}

fn info(args: &SceneArgs) -> Result<()> {
    let start = Instant::now();
    let mut world = load(args)?;
    let elapsed = start.elapsed();
    let info = SceneInfo::gather(&mut world);
    println!("scene: {}", args.scene);
    print!("{info}");
    println!("load time: {:.1} ms", elapsed.as_secs_f64() * 1e3);
    Ok(())
}

fn render(
    args: &SceneArgs,
    size: (u32, u32),
    frames: u32,
    out: &Path,
    frame: FrameSettings,
    seed: u64,
) -> Result<()> {
    let exr = match out.extension().and_then(|e| e.to_str()) {
        Some("exr") => true,
        Some("png") => false,
        _ => bail!("{}: the output must end in .png or .exr", out.display()),
    };
    frame.validate()?;
    let mut world = load(args)?;
    let context = chiaro::gpu::GpuContext::new_headless()?;
    let adapter = context.describe();
    let mut renderer = chiaro::gpu::Renderer::new(context);
    let settings = chiaro::gpu::RenderSettings {
        width: size.0,
        height: size.1,
        frames: frames.max(1),
        seed,
        frame,
    };
    let start = Instant::now();
    let output = renderer
        .render(&mut world, &settings)
        .context("cannot render")?;
    let seconds = start.elapsed().as_secs_f64();
    if exr {
        write_exr(out, output.width, output.height, &output.hdr)?;
    } else {
        image::RgbaImage::from_raw(output.width, output.height, output.ldr)
            .context("image size")?
            .save_with_format(out, image::ImageFormat::Png)
            .with_context(|| format!("cannot write {}", out.display()))?;
    }
    println!("wrote {}", out.display());
    println!(
        "{}x{}, {} frames of {} in {seconds:.2} s on {adapter}",
        output.width,
        output.height,
        output.times.len(),
        frame.mode.name()
    );
    let timed = &output.times[output.times.len() / 2..];
    let clock = match timed.first() {
        Some(t) if t.gpu_timestamps => "GPU timestamps",
        _ => "wall clock",
    };
    for (index, (name, _)) in timed
        .first()
        .map_or(&[][..], |t| &t.passes)
        .iter()
        .enumerate()
    {
        let mut ms: Vec<f64> = timed.iter().map(|t| t.passes[index].1).collect();
        ms.sort_by(f64::total_cmp);
        println!("  {name:<10} {:8.3} ms (median, {clock})", ms[ms.len() / 2]);
    }
    Ok(())
}

fn view(
    args: &SceneArgs,
    size: (u32, u32),
    script: Option<&Path>,
    screenshot: Option<PathBuf>,
    frame: FrameSettings,
    seed: u64,
) -> Result<()> {
    frame.validate()?;
    let script = match script {
        Some(path) => Some(chiaro_viewer::read_script(path)?),
        None => screenshot
            .as_ref()
            .map(|_| vec![chiaro_viewer::script::Command::Frames(16)]),
    };
    let mut world = load(args)?;
    world.insert_resource(frame);
    let options = chiaro_viewer::ViewerOptions {
        title: format!("chiaro: {}", args.scene),
        size,
        script,
        screenshot,
        seed,
    };
    Ok(chiaro_viewer::run(world, options)?)
}

fn reference(args: &SceneArgs, settings: &RenderSettings, out: &Path) -> Result<()> {
    let (exr, png) = match out.extension().and_then(|e| e.to_str()) {
        Some("exr") => (out.to_path_buf(), out.with_extension("png")),
        Some("png") => (out.with_extension("exr"), out.to_path_buf()),
        _ => bail!("{}: the output must end in .exr or .png", out.display()),
    };
    let mut world = load(args)?;
    let output = render_world(&mut world, settings, true).context("cannot render")?;
    write_exr(&exr, output.width, output.height, &output.image)?;
    write_png(
        &png,
        output.width,
        output.height,
        &output.image,
        Tonemapper::PbrNeutral,
        1.0,
    )?;
    let half = exr.with_extension("half.exr");
    write_exr(&half, output.width, output.height, &output.halves[0])?;
    let seconds = output.elapsed.as_secs_f64();
    println!(
        "wrote {}, {} and {}",
        exr.display(),
        png.display(),
        half.display()
    );
    println!(
        "{}x{} at {} spp in {seconds:.2} s",
        output.width, output.height, settings.spp
    );
    println!("paths/s: {:.0}", output.paths as f64 / seconds);
    println!(
        "relMSE between independent halves: {:.3e} (the full image's own error is about a quarter of it)",
        output.halves_rel_mse()
    );
    if output.non_finite_samples > 0 {
        log::warn!(
            "{} non-finite samples were dropped",
            output.non_finite_samples
        );
    }
    Ok(())
}
