//! `chiaro bench`: speed against error of the GPU frame's configurations, per scene, against
//! the converged reference; writes results.json, results.md and the plots.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use chiaro::eval::bench::{
    BenchProgress, BenchScene, BenchSettings, ReferenceRenderer, default_configs, default_scenes,
    extra_configs, run_bench, write_outputs,
};
use chiaro::reference::Integrator;

/// What `chiaro bench` takes.
#[derive(Args)]
pub struct BenchArgs {
    /// Scenes (.gltf, .glb or builtin:NAME); by default the built-in set, and the models of
    /// ../shared/scenes under its environment map when that folder is there.
    #[arg(long, num_args = 1..)]
    scenes: Vec<String>,
    /// An equirectangular .hdr or .exr environment for the scenes given with --scenes.
    #[arg(long)]
    env: Option<PathBuf>,
    #[command(flatten)]
    light_units: crate::args::LightUnitsArgs,
    /// Image size, WxH.
    #[arg(long, default_value = "256x256", value_parser = crate::args::size)]
    size: (u32, u32),
    /// Where results.json, results.md and the plots go.
    #[arg(long, default_value = "bench")]
    out: PathBuf,
    /// Frame counts after which the error is measured (the last is how many are rendered).
    #[arg(long, value_delimiter = ',', default_value = "1,4,16,64",
          value_parser = clap::value_parser!(u32).range(1..=crate::args::MAX_FRAMES as i64))]
    checkpoints: Vec<u32>,
    /// Samples per pixel of the converged references (cached in OUT/cache).
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(2..=1 << 20))]
    reference_spp: u32,
    /// What renders the converged references: cpu, the CPU reference path tracer (code apart
    /// from the GPU frame under test); or gpu, the GPU reference mode in two halves of other
    /// seeds, for a real GPU at sizes where the CPU would take far longer than the runs.
    #[arg(long, value_enum, default_value_t = ReferenceArg::Cpu)]
    reference: ReferenceArg,
    /// The CPU reference's integrator (with --reference cpu): pt, ptlt, bdpt, mlt or mmlt, as
    /// `chiaro reference --integrator` (for mlt and mmlt, --reference-spp is mutations per
    /// pixel).
    #[arg(long, default_value = "pt")]
    reference_integrator: Integrator,
    /// Frames rendered before timing starts.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(0..=1000))]
    warmup: u32,
    /// These configurations, by name, instead of the default set (direct, realtime,
    /// realtime-no-denoise, realtime-spp2, realtime-spp4, realtime-bounces1,
    /// realtime-bounces2, naive, reference); also known: direct-power, realtime-power,
    /// realtime-all-features, realtime-moving-average, realtime-restir-di, realtime-restir-gi,
    /// realtime-restir-gi-temporal (with last frame's reservoirs), realtime-restir-gi-unbiased
    /// (pairwise MIS with visibility), realtime-restir (both).
    #[arg(long, value_delimiter = ',')]
    configs: Vec<String>,
    /// Leaves out the realtime run along the scripted camera path (`realtime-path`: the
    /// camera looks to the side and back between checkpoints).
    #[arg(long)]
    no_camera_path: bool,
    #[command(flatten)]
    frames_in_flight: crate::args::FramesInFlightArgs,
}

/// `--reference`'s values.
#[derive(Clone, Copy, clap::ValueEnum)]
enum ReferenceArg {
    /// The CPU reference path tracer.
    Cpu,
    /// The GPU frame's reference mode.
    Gpu,
}

/// What draws the references: `--reference` with `--reference-integrator`.
fn reference_renderer(args: &BenchArgs) -> Result<ReferenceRenderer> {
    match (args.reference, args.reference_integrator) {
        (ReferenceArg::Cpu, integrator) => Ok(ReferenceRenderer::Cpu(integrator)),
        (ReferenceArg::Gpu, Integrator::Pt) => Ok(ReferenceRenderer::Gpu),
        (ReferenceArg::Gpu, other) => bail!(
            "--reference-integrator {other} applies to the CPU reference: the GPU reference \
             mode traces paths from the camera"
        ),
    }
}

/// Runs the benchmark, showing progress, and prints the markdown table.
pub fn run(args: &BenchArgs) -> Result<()> {
    let scenes: Vec<BenchScene> = if args.scenes.is_empty() {
        if args.env.is_some() {
            bail!("--env applies to the scenes given with --scenes");
        }
        default_scenes(&PathBuf::from("../shared/scenes"))
    } else {
        args.scenes
            .iter()
            .map(|scene| BenchScene {
                scene: scene.clone(),
                env: args.env.clone(),
                light_units: args.light_units.units(),
            })
            .collect()
    };
    let mut configs = default_configs();
    if !args.configs.is_empty() {
        configs.extend(extra_configs());
        if let Some(unknown) = args
            .configs
            .iter()
            .find(|name| !configs.iter().any(|c| &c.name == *name))
        {
            let known: Vec<_> = configs.iter().map(|c| c.name.as_str()).collect();
            bail!(
                "unknown configuration '{unknown}' (known: {})",
                known.join(", ")
            );
        }
        configs.retain(|c| args.configs.contains(&c.name));
    }
    let settings = BenchSettings {
        width: args.size.0,
        height: args.size.1,
        checkpoints: args.checkpoints.clone(),
        reference_spp: args.reference_spp,
        reference_renderer: reference_renderer(args)?,
        cache_dir: args.out.join("cache"),
        warmup_frames: args.warmup,
        camera_path: !args.no_camera_path,
    };
    let context = chiaro::gpu::GpuContext::new_headless()?;
    eprintln!("adapter: {}", context.describe());
    let mut renderer = chiaro::gpu::Renderer::new(context);
    args.frames_in_flight.apply(&mut renderer);
    let path_steps = usize::from(settings.camera_path);
    let bar = ProgressBar::new((scenes.len() * (configs.len() + 1 + path_steps)) as u64);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    let mut started = false;
    let mut progress = |step: BenchProgress| {
        if started {
            bar.inc(1);
        }
        started = true;
        bar.set_message(match step {
            BenchProgress::Reference(scene) => format!("{scene}: reference"),
            BenchProgress::Run { scene, config } => format!("{scene}: {config}"),
        });
    };
    let results = run_bench(&mut renderer, &scenes, &configs, &settings, &mut progress)?;
    bar.inc(1);
    bar.finish_with_message("done");
    for path in write_outputs(&results, &args.out)? {
        eprintln!("wrote {}", path.display());
    }
    println!("{}", results.to_markdown());
    Ok(())
}
