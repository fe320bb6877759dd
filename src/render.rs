//! `chiaro render`: the GPU frame of a scene, accumulated over frames (with `--animate`, the
//! animation time advancing per frame), written as PNG or EXR, with the throughput, the
//! frames' latency and the passes' times.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use chiaro::gpu::FrameSettings;
use chiaro::reference::write_exr;

use super::{MemoryArgs, SceneArgs, load};

/// Renders `args`' scene on the GPU; with `animation` (frames per second) each frame advances
/// the animation time by 1 / fps from `--time`, with the frames in flight `frames_in_flight`
/// asks for.
#[allow(clippy::too_many_arguments)]
pub fn run(
    args: &SceneArgs,
    memory: &MemoryArgs,
    size: (u32, u32),
    frames: u32,
    out: &Path,
    frame: FrameSettings,
    seed: u64,
    animation: Option<f64>,
    frames_in_flight: &crate::args::FramesInFlightArgs,
) -> Result<()> {
    let exr = match out.extension().and_then(|e| e.to_str()) {
        Some("exr") => true,
        Some("png") => false,
        _ => bail!("{}: the output must end in .png or .exr", out.display()),
    };
    frame.validate()?;
    let load_start = Instant::now();
    let mut world = load(args)?;
    let load_seconds = load_start.elapsed().as_secs_f64();
    memory.check(&args.scene, &mut world, size)?;
    let context = chiaro::gpu::GpuContext::new_headless()?;
    let adapter = context.describe();
    let mut renderer = chiaro::gpu::Renderer::new(context);
    frames_in_flight.apply(&mut renderer);
    let settings = chiaro::gpu::RenderSettings {
        width: size.0,
        height: size.1,
        frames,
        seed,
        frame,
    };
    let start = Instant::now();
    let start_time = args.time.time.unwrap_or(0.0);
    let mut frame_starts = Vec::new();
    let output = renderer
        .render_with(&mut world, &settings, |world, k| {
            frame_starts.push(Instant::now());
            if let Some(fps) = animation {
                world.insert_resource(chiaro::scene::Time {
                    seconds: start_time + f64::from(k) / fps,
                });
            }
        })
        .context("cannot render")?;
    let seconds = start.elapsed().as_secs_f64();
    if exr {
        write_exr(out, output.width, output.height, &output.hdr)?;
    } else {
        chiaro::reference::write_png_pixels(
            out,
            output.width,
            output.height,
            &output.ldr,
            image::ExtendedColorType::Rgba8,
        )?;
    }
    println!("wrote {}", out.display());
    println!(
        "{}x{}, {} frames of {} in {seconds:.2} s on {adapter}, primary visibility {}",
        output.width,
        output.height,
        output.times.len(),
        frame.mode.name(),
        renderer
            .frame()
            .map_or(frame.primary, |f| f.primary())
            .name(),
    );
    if let (Some(setup), Some(first)) = (renderer.setup_times(), output.times.first()) {
        let triangles = chiaro::scene::SceneInfo::gather(&mut world).mesh_triangles;
        let to_first = load_seconds + setup.systems + (first.wall_ms - first.compile_ms) / 1e3;
        println!(
            "startup: load {:.0} ms, BVH build {:.0} ms ({:.2} M triangles/s), upload {:.0} ms, \
             pipelines {:.0} ms, first frame {:.0} ms; file to first frame {:.2} s without \
             pipelines",
            load_seconds * 1e3,
            setup.bvh * 1e3,
            triangles as f64 / setup.bvh.max(1e-9) / 1e6,
            setup.upload * 1e3,
            first.compile_ms,
            first.wall_ms - first.compile_ms,
            to_first,
        );
    }
    let (gpu, mirrors) = world.resource::<chiaro::gpu::GpuScene>().memory();
    println!(
        "memory: scene on the GPU {}, its CPU copies {}{}",
        chiaro::scene::memory::human_bytes(gpu),
        chiaro::scene::memory::human_bytes(mirrors),
        chiaro::scene::memory::peak_resident()
            .map(|peak| format!(
                ", peak resident {}",
                chiaro::scene::memory::human_bytes(peak)
            ))
            .unwrap_or_default()
    );
    let timed = &output.times[output.times.len() / 2..];
    let median = |pick: &dyn Fn(&chiaro::gpu::PassTimes) -> f64| {
        let mut ms: Vec<f64> = timed.iter().map(pick).collect();
        ms.sort_by(f64::total_cmp);
        ms.get(ms.len() / 2).copied().unwrap_or(0.0)
    };
    // Throughput from the starts of the second half's frames, which the frames in flight pace:
    // neither the first frame's pipelines nor the last one's wait and readback count.
    let steady = &frame_starts[frame_starts.len() / 2..];
    let throughput = match steady {
        [first, .., last] if last > first => format!(
            "{:.1} frames/s",
            (steady.len() - 1) as f64 / last.duration_since(*first).as_secs_f64()
        ),
        _ => "not measured (too few frames)".into(),
    };
    println!(
        "throughput {throughput}, latency {:.2} ms, CPU to submit {:.2} ms (medians over the \
         last half, up to {} frames in flight)",
        median(&|t| t.wall_ms),
        median(&|t| t.submit_ms),
        renderer.frames_in_flight(),
    );
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
        let ms = median(&|t| t.passes[index].1);
        println!("  {name:<10} {ms:8.3} ms (median, {clock})");
    }
    Ok(())
}
