//! Metropolis light transport, in both forms (every strategy per sample, and multiplexed),
//! converges to the path tracer's image: on the Cornell box and in the furnace, and the image
//! for a seed does not depend on the thread count.

mod common;

use bevy_ecs::world::World;
use chiaro_reference::{
    Integrator, PathSettings, RenderOutput, RenderSettings, rel_mse, render_world,
};
use chiaro_scene::load_scene;
use glam::Vec3;

use common::mean;

fn settings(integrator: Integrator, spp: u32, seed: u64, threads: Option<usize>) -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 32,
        spp,
        seed,
        sampler: chiaro_reference::Sampler::default(),
        threads,
        path: PathSettings {
            integrator,
            ..PathSettings::default()
        },
    }
}

fn render(spec: &str, settings: &RenderSettings) -> RenderOutput {
    let mut world = World::new();
    load_scene(&mut world, spec).unwrap();
    let out = render_world(&mut world, settings, false).unwrap();
    assert_eq!(out.non_finite_samples, 0, "{spec}");
    out
}

/// Against the path tracer: their relMSE is within 2.5 times what their own noise explains
/// (each image's error about a quarter of its halves' relMSE), and the means agree within 5%.
/// The halves share the normalisation b, so the mean's tolerance is relative: over seven seeds
/// the mean's spread was 1.4% (standard deviation), about the path tracer's mean. A sampler
/// that read some coordinates as 0 made it 10% low.
#[test]
fn mlt_matches_the_path_tracer_on_the_cornell_box() {
    let pt = render("builtin:cornell", &settings(Integrator::Pt, 512, 1, None));
    for integrator in [Integrator::Mlt, Integrator::Mmlt] {
        let mlt = render("builtin:cornell", &settings(integrator, 512, 2, None));
        let noise = (pt.halves_rel_mse() + mlt.halves_rel_mse()) / 4.0;
        let error = rel_mse(&mlt.image, &pt.image);
        eprintln!("{integrator}: relMSE {error:.3e}, noise {noise:.3e}");
        assert!(
            error < 2.5 * noise,
            "{integrator}: relMSE {error:.3e}, noise {noise:.3e}"
        );
        let (a, b) = (mean(&mlt.image), mean(&pt.image));
        assert!(
            (a / b - 1.0).abs() < 0.05,
            "{integrator}: mean {a} against {b}"
        );
    }
}

/// Inside the furnace every sample sees radiance 1: the mean is b, the normalisation. In the
/// multiplexed form, paths of k bounces carry 0.5^(k + 1) of it, so every length counts.
#[test]
fn mlt_furnace_converges_to_one() {
    for integrator in [Integrator::Mlt, Integrator::Mmlt] {
        let out = render("builtin:furnace", &settings(integrator, 16, 3, None));
        let m = mean(&out.image);
        assert!((m - 1.0).abs() < 0.01, "{integrator}: mean {m}");
    }
}

/// Chains have films of their own, summed in chain order.
#[test]
fn mlt_image_does_not_depend_on_the_thread_count() {
    for integrator in [Integrator::Mlt, Integrator::Mmlt] {
        let images: Vec<Vec<Vec3>> = [1, 3]
            .into_iter()
            .map(|threads| {
                render(
                    "builtin:cornell",
                    &settings(integrator, 8, 4, Some(threads)),
                )
                .image
            })
            .collect();
        assert_eq!(images[0], images[1], "{integrator}");
        assert!(mean(&images[0]) > 0.0, "{integrator}");
    }
}
