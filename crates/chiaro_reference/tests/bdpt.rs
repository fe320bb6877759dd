//! The bidirectional estimator converges to the path tracer's image: the whole estimator on the
//! Cornell box and the furnace, each of its strategies alone (light tracing's splats among them)
//! against the path tracer's light of the same number of bounces, and the image independent of
//! the thread count.

mod common;

use bevy_ecs::world::World;
use chiaro_reference::{
    Integrator, PathSettings, RenderOutput, RenderSettings, rel_mse, render_world,
};
use chiaro_scene::load_scene;

use common::{mean, standard_error_of_halves};

fn render(spec: &str, integrator: Integrator, spp: u32, max_depth: u32, seed: u64) -> RenderOutput {
    let mut world = World::new();
    load_scene(&mut world, spec).unwrap();
    let settings = RenderSettings {
        width: 32,
        height: 32,
        spp,
        seed,
        path: PathSettings {
            integrator,
            max_depth,
            ..PathSettings::default()
        },
        ..RenderSettings::default()
    };
    let out = render_world(&mut world, &settings, false).unwrap();
    assert_eq!(out.non_finite_samples, 0, "{spec} {integrator:?}");
    out
}

/// The whole estimator against the path tracer: their relMSE is within 2.5 times what their own
/// noise explains (each image's error about a quarter of its halves' relMSE), and their means
/// agree.
#[test]
fn bdpt_matches_the_path_tracer_on_the_cornell_box() {
    let pt = render("builtin:cornell", Integrator::Pt, 512, 64, 1);
    let bdpt = render("builtin:cornell", Integrator::Bdpt, 256, 64, 2);
    let noise = (pt.halves_rel_mse() + bdpt.halves_rel_mse()) / 4.0;
    let error = rel_mse(&bdpt.image, &pt.image);
    assert!(error < 2.5 * noise, "relMSE {error:.3e}, noise {noise:.3e}");
    let (a, b) = (mean(&bdpt.image), mean(&pt.image));
    let se =
        (standard_error_of_halves(&pt).powi(2) + standard_error_of_halves(&bdpt).powi(2)).sqrt();
    assert!(
        (a - b).abs() < 4.0 * se + 1e-3 * b,
        "mean {a} against {b}, se {se}"
    );
}

/// Inside the furnace every strategy sees radiance 1.
#[test]
fn bdpt_furnace_converges_to_one() {
    let out = render("builtin:furnace", Integrator::Bdpt, 64, 64, 3);
    let (m, se) = (mean(&out.image), standard_error_of_halves(&out));
    assert!((m - 1.0).abs() < 4.0 * se + 5e-3, "mean {m}, se {se}");
}

/// Every strategy of paths with two bounces, alone and unweighted, has the mean of the path
/// tracer's two-bounce light (its image at depth 2 less its image at depth 1): the camera path
/// reaching the light (0, 4), next-event estimation (1, 3), two subpaths joined (2, 2) and light
/// tracing splatted to the camera (3, 1).
#[test]
fn each_strategy_alone_estimates_the_two_bounce_light() {
    let two = render("builtin:cornell", Integrator::Pt, 512, 2, 4);
    let one = render("builtin:cornell", Integrator::Pt, 512, 1, 5);
    let expected = mean(&two.image) - mean(&one.image);
    let expected_se =
        (standard_error_of_halves(&two).powi(2) + standard_error_of_halves(&one).powi(2)).sqrt();
    assert!(expected > 5e-3, "two-bounce light {expected}");
    for (s, t) in [(0, 4), (1, 3), (2, 2), (3, 1)] {
        let out = render(
            "builtin:cornell",
            Integrator::BdptStrategy { s, t },
            256,
            2,
            6,
        );
        let (m, se) = (mean(&out.image), standard_error_of_halves(&out));
        let bound = 4.0 * (se * se + expected_se * expected_se).sqrt() + 2e-3 * expected;
        eprintln!("strategy ({s}, {t}): mean {m:.5} (se {se:.1e}), path tracer {expected:.5}");
        assert!(
            (m - expected).abs() < bound,
            "strategy ({s}, {t}): mean {m}, expected {expected}, bound {bound}"
        );
    }
}

/// Splats are merged in tile order: the image is the same on one thread as on several.
#[test]
fn bdpt_image_does_not_depend_on_the_thread_count() {
    let mut images = Vec::new();
    for threads in [1, 3] {
        let mut world = World::new();
        load_scene(&mut world, "builtin:cornell").unwrap();
        let settings = RenderSettings {
            width: 24,
            height: 20,
            spp: 4,
            threads: Some(threads),
            path: PathSettings {
                integrator: Integrator::Bdpt,
                ..PathSettings::default()
            },
            ..RenderSettings::default()
        };
        images.push(render_world(&mut world, &settings, false).unwrap().image);
    }
    assert_eq!(images[0], images[1]);
}
