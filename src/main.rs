//! The `chiaro` command line.

mod args;
mod bench;
mod compare;
mod frame_args;
mod render;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use bevy_ecs::world::World;
use clap::{Args, Parser, Subcommand};

use chiaro::gpu::FrameSettings;
use chiaro::reference::{
    Integrator, LightSampling, PathSettings, RenderSettings, Sampler, render_world, write_exr,
    write_png,
};
use chiaro::scene::{Environment, LoadOptions, SceneInfo, load_scene_with};
use chiaro::shading::tonemap::{Tonemapper, exposure_from_ev};
use frame_args::FrameArgs;

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
    /// A .gltf or .glb file, or builtin:NAME (caustic, cornell, door, furnace, hard-cases,
    /// instances, lamp, many-lights, walkthrough), e.g. builtin:instances?n=10000.
    scene: String,
    /// Replaces the scene's environment: an equirectangular .hdr or .exr image, or a constant
    /// linear colour R,G,B.
    #[arg(long, value_parser = args::env)]
    env: Option<args::EnvArg>,
    /// Multiplies the environment's radiance (0..=1e9).
    #[arg(long, default_value_t = 1.0, value_parser = args::env_strength, allow_negative_numbers = true)]
    env_strength: f32,
    /// Let a glTF read buffers and images outside its own folder (absolute paths, file: URIs,
    /// `..` leaving the folder), which are refused by default.
    #[arg(long)]
    allow_outside_files: bool,
    #[command(flatten)]
    light_units: args::LightUnitsArgs,
    #[command(flatten)]
    time: args::TimeArgs,
}

/// The memory a render may take.
#[derive(Args)]
struct MemoryArgs {
    /// Most memory a render may take, e.g. 512M or 8G (default: what the system has available).
    /// A scene and image size whose estimate is larger are refused before anything is built.
    #[arg(long, value_parser = chiaro::scene::memory::parse_bytes)]
    memory_limit: Option<u64>,
}

impl MemoryArgs {
    /// Refuses the render of `scene` (loaded in `world`) at `size` when its estimate is over
    /// the limit.
    fn check(&self, scene: &str, world: &mut World, size: (u32, u32)) -> Result<()> {
        let limit = self
            .memory_limit
            .or_else(chiaro::scene::memory::available_memory)
            .unwrap_or(u64::MAX);
        chiaro::scene::MemoryEstimate::of_world(world, size.0, size.1)
            .check(limit)
            .map_err(|e| anyhow::anyhow!("{scene}: {e}; --memory-limit sets the limit"))
    }
}

#[derive(Subcommand)]
enum Command {
    /// Print what a scene holds: meshes, triangles, instances, materials and their texture
    /// slots, lights by kind, skinned instances and their skins' joints, emissive triangles,
    /// camera, environment, bounds, and what import repaired.
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
        #[arg(long, value_parser = args::env)]
        env: Option<args::EnvArg>,
        /// Multiplies the environment's radiance (0..=1e9).
        #[arg(long, default_value_t = 1.0, value_parser = args::env_strength, allow_negative_numbers = true)]
        env_strength: f32,
        /// Let a glTF read files outside its own folder (refused by default).
        #[arg(long)]
        allow_outside_files: bool,
        #[command(flatten)]
        light_units: args::LightUnitsArgs,
        #[command(flatten)]
        time: args::TimeArgs,
        /// Plays the animations: each frame advances the time by 1 / --fps from --time (or 0).
        #[arg(long)]
        animate: bool,
        /// Frames per second of the animation time with --animate (0.001..=10000).
        #[arg(long, default_value_t = 30.0, value_parser = args::frame_rate)]
        fps: f64,
        #[command(flatten)]
        memory: MemoryArgs,
        /// Image size, WxH.
        #[arg(long, default_value = "512x512", value_parser = args::size)]
        size: (u32, u32),
        /// Frames to render, 1..=1000000 (the realtime image is the last; the other modes
        /// average them).
        #[arg(long, default_value_t = 16,
              value_parser = clap::value_parser!(u32).range(1..=args::MAX_FRAMES as i64))]
        frames: u32,
        /// Output file, .png or .exr.
        #[arg(long, default_value = "chiaro.png")]
        out: PathBuf,
        #[command(flatten)]
        frame: FrameArgs,
        /// Seed of the random numbers.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        #[command(flatten)]
        frames_in_flight: args::FramesInFlightArgs,
    },
    /// Render the converged ground truth with the CPU reference path tracer: an EXR (linear) and
    /// a PNG (tonemapped) beside it, plus the EXR of an independent half of the samples.
    Reference {
        #[command(flatten)]
        scene: SceneArgs,
        /// Samples per pixel (2..=1048576).
        #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(2..=1 << 20))]
        spp: u32,
        /// Image size, WxH.
        #[arg(long, default_value = "256x256", value_parser = args::size)]
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
        /// Exposure of the PNG in stops: linear radiance times 2^STOPS before tonemapping
        /// (-30..=30). The EXR stays linear radiance, unscaled, so that its error against
        /// another image means the same at any exposure.
        #[arg(long, default_value_t = 0.0, value_parser = args::exposure_stops,
              allow_negative_numbers = true)]
        exposure: f32,
        /// Worker threads, 1..=1024 (default: one per core).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=args::MAX_THREADS as u64))]
        threads: Option<u64>,
        /// Most bounces per path: 0 shows emitters only, 1 is direct light, and the light the
        /// last bounce's ray reaches is counted (Russian roulette ends most paths well before).
        #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(0..=1024))]
        max_depth: u32,
        /// How a light is picked for next-event estimation: tree (by importance to the shading
        /// point, through a light tree) or power (by power alone).
        #[arg(long, default_value = "tree")]
        light_sampling: LightSampling,
        /// The estimator: pt (paths from the camera, next-event estimation, MIS); ptlt (pt
        /// plus light tracing: light subpaths joined to the camera, MIS-weighted with pt's
        /// strategies; light out of enclosed emitters); bdpt
        /// (bidirectional: camera and light subpaths joined by every strategy, MIS-weighted;
        /// finds light camera paths rarely reach; light paths pick lights by power); mlt
        /// (Metropolis light transport over bdpt: Markov chains that mutate the bidirectional
        /// samples, spending them where light reaches the image; --spp is mutations per
        /// pixel); or mmlt (multiplexed Metropolis: each mutation one strategy of one path
        /// length, MIS-weighted, so far cheaper ones; best on caustics).
        #[arg(long, default_value = "pt")]
        integrator: Integrator,
        /// Where the samples' numbers come from: sobol (Owen-scrambled Sobol points, each
        /// draw of a path stratified over the pixel's samples: randomised quasi-Monte Carlo) or
        /// independent (independent random numbers: plain Monte Carlo). mlt and mmlt mutate
        /// their own.
        #[arg(long, default_value = "sobol")]
        sampler: Sampler,
        #[command(flatten)]
        memory: MemoryArgs,
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
        #[arg(long, value_parser = args::env)]
        env: Option<args::EnvArg>,
        /// Multiplies the environment's radiance (0..=1e9).
        #[arg(long, default_value_t = 1.0, value_parser = args::env_strength, allow_negative_numbers = true)]
        env_strength: f32,
        /// Let a glTF read files outside its own folder (refused by default).
        #[arg(long)]
        allow_outside_files: bool,
        #[command(flatten)]
        light_units: args::LightUnitsArgs,
        #[command(flatten)]
        time: args::TimeArgs,
        #[command(flatten)]
        memory: MemoryArgs,
        /// Window size, WxH.
        #[arg(long, default_value = "1280x720", value_parser = args::size)]
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

/// Mesa's Vulkan device-select layer (an implicit layer, loaded into every Vulkan program)
/// looks for a Wayland compositor while wgpu lists the adapters, and libwayland prints
/// `error: XDG_RUNTIME_DIR is invalid or not set in the environment.` where there can be
/// none. chiaro ranks the adapters itself, so where no Wayland display can exist (no
/// `WAYLAND_DISPLAY` and no runtime directory) the layer is turned off through its own switch,
/// `NODEVICE_SELECT`. A user's own setting of it is kept, and drivers' messages still print.
fn skip_the_wayland_probe_without_wayland() {
    let set = |name| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    let runtime_dir =
        std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|dir| Path::new(&dir).is_dir());
    if !runtime_dir && !set("WAYLAND_DISPLAY") && std::env::var_os("NODEVICE_SELECT").is_none() {
        // SAFETY: called first in main, before any other thread runs (no concurrent reads of
        // the environment).
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}

fn main() -> Result<()> {
    skip_the_wayland_probe_without_wayland();
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
            allow_outside_files,
            light_units,
            time,
            animate,
            fps,
            memory,
            size,
            frames,
            out,
            frame,
            seed,
            frames_in_flight,
        } => {
            let scene = SceneArgs {
                scene,
                env,
                env_strength,
                allow_outside_files,
                light_units,
                time,
            };
            let animation = animate.then_some(fps);
            render::run(
                &scene,
                &memory,
                size,
                frames,
                &out,
                frame.settings(),
                seed,
                animation,
                &frames_in_flight,
            )
        }
        Command::Compare(args) => compare::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::View {
            scene,
            env,
            env_strength,
            allow_outside_files,
            light_units,
            time,
            memory,
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
                allow_outside_files,
                light_units,
                time,
            };
            view(
                &scene,
                &memory,
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
            exposure,
            threads,
            max_depth,
            light_sampling,
            integrator,
            sampler,
            memory,
        } => {
            let path = PathSettings {
                max_depth,
                direct_only,
                light_sampling,
                integrator,
                ..PathSettings::default()
            };
            let settings = RenderSettings {
                width: size.0,
                height: size.1,
                spp,
                seed,
                sampler,
                threads: threads.map(|t| t as usize),
                path,
            };
            reference(&scene, &memory, &settings, &out, exposure_from_ev(exposure))
        }
    }
}

/// Loads the scene and applies the environment options.
fn load(args: &SceneArgs) -> Result<World> {
    let mut world = World::new();
    let options = LoadOptions {
        allow_outside_files: args.allow_outside_files,
        light_units: args.light_units.units(),
    };
    load_scene_with(&mut world, &args.scene, &options)?;
    if let Some(env) = &args.env {
        let environment = match env {
            args::EnvArg::Color(color) => {
                let mut environment = Environment::constant(*color);
                environment.strength = args.env_strength;
                environment
            }
            args::EnvArg::Image(path) => {
                let (environment, repairs) = Environment::from_file(path, args.env_strength)?;
                for r in repairs {
                    log::warn!("{}: {r}", path.display());
                }
                environment
            }
        };
        world.insert_resource(environment);
    }
    if let Some(seconds) = args.time.time {
        chiaro::scene::pose_at(&mut world, seconds);
    }
    Ok(world)
}

fn info(args: &SceneArgs) -> Result<()> {
    let start = Instant::now();
    let mut world = load(args)?;
    let elapsed = start.elapsed();
    let info = SceneInfo::gather(&mut world);
    println!("scene: {}", args.scene);
    print!("{info}");
    println!(
        "memory to render at 512x512: {}",
        chiaro::scene::MemoryEstimate::of_world(&mut world, 512, 512)
    );
    println!("load time: {:.1} ms", elapsed.as_secs_f64() * 1e3);
    Ok(())
}

fn view(
    args: &SceneArgs,
    memory: &MemoryArgs,
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
    memory.check(&args.scene, &mut world, size)?;
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

fn reference(
    args: &SceneArgs,
    memory: &MemoryArgs,
    settings: &RenderSettings,
    out: &Path,
    exposure: f32,
) -> Result<()> {
    let (exr, png) = match out.extension().and_then(|e| e.to_str()) {
        Some("exr") => (out.to_path_buf(), out.with_extension("png")),
        Some("png") => (out.with_extension("exr"), out.to_path_buf()),
        _ => bail!("{}: the output must end in .exr or .png", out.display()),
    };
    let mut world = load(args)?;
    memory.check(&args.scene, &mut world, (settings.width, settings.height))?;
    let output = render_world(&mut world, settings, true).context("cannot render")?;
    write_exr(&exr, output.width, output.height, &output.image)?;
    write_png(
        &png,
        output.width,
        output.height,
        &output.image,
        Tonemapper::PbrNeutral,
        exposure,
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
