//! The hard-case suite, ground truth: the GPU reference mode agrees with the CPU reference case
//! by case of `builtin:hard-cases` (one world, each case from its own camera; `scale` alone in
//! its own): linear HDR relMSE
//! below 3 x the two images' combined own noise (both measured: the GPU's from two seeds, the
//! CPU's from its two halves), the bound of `direct_image.rs`.
//!
//! Frames are few and paths per frame many, as in `hard_cases.rs`.
//!
//! On GL the `coplanar` case is left out: which of two coplanar quads the G-buffer's raster
//! keeps rests on a tie in depth, and wgpu's GL backend remaps every depth (z' = 2z - w, GL's
//! clip space), whose rounding breaks the tie one way or the other pixel by pixel (relMSE 1.4e-2
//! against a bound of 7.6e-3 on llvmpipe). The ray-traced modes have no such tie.

mod common;
mod hard_cases_common;

use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_reference::{PathSettings, render_world};
use chiaro_scene::builtin::HARD_CASES;
use hard_cases_common::{CaseWorlds, mode, settings};

#[test]
fn gpu_and_cpu_references_agree_case_by_case() {
    let Some(gpu) = common::gpu() else { return };
    let gl = gpu.info.backend == wgpu::Backend::Gl;
    let (size, frames) = (24, 32);
    let mut worlds = CaseWorlds::load();
    let mut renderer = Renderer::new(gpu);
    let mut failures = Vec::new();
    for case in HARD_CASES {
        if gl && case == "coplanar" {
            eprintln!("coplanar: left out on GL (raster depth ties, see the module docs)");
            continue;
        }
        let world = worlds.view(case);
        let cpu = render_world(
            world,
            &chiaro_reference::RenderSettings {
                width: size,
                height: size,
                spp: 256,
                seed: 7,
                sampler: chiaro_reference::Sampler::default(),
                threads: None,
                path: PathSettings::default(),
            },
            false,
        )
        .unwrap();
        let cpu_noise = cpu.halves_rel_mse() / 4.0;
        let reference = FrameSettings {
            spp: 4,
            ..mode(RenderMode::Reference)
        };
        let a = renderer
            .render(world, &settings(size, frames, 1, reference))
            .unwrap();
        let b = renderer
            .render(world, &settings(size, frames, 2, reference))
            .unwrap();
        let gpu_noise = common::rel_mse(&a.hdr, &b.hdr) / 2.0;
        let error = common::rel_mse(&a.hdr, &cpu.image);
        let bound = 3.0 * (gpu_noise + cpu_noise);
        eprintln!(
            "{case}: relMSE {error:.3e}, bound {bound:.3e} (GPU noise {gpu_noise:.2e}, CPU \
             noise {cpu_noise:.2e})"
        );
        if error >= bound {
            failures.push(format!("{case}: relMSE {error:.3e} against {bound:.3e}"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
