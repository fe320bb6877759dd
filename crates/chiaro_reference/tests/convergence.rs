//! The reference converges to known answers: the white furnace, a point light over a Lambertian
//! plane (closed form), noise falling as 1/spp, its own-noise estimate predicting its error,
//! Russian roulette unbiased, and images that do not depend on the thread count.

mod common;

use bevy_ecs::world::World;
use chiaro_reference::{
    LightSampling, PathSettings, RenderOutput, RenderSettings, Sampler, rel_mse, render_world,
};
use chiaro_scene::builtin::shapes::floor;
use chiaro_scene::{
    Camera, Light, LightKind, Material, Node, Projection, SceneBuilder, Transform, load_scene,
};
use glam::Vec3;

use common::{mean, standard_error};

fn render(spec: &str, settings: RenderSettings) -> RenderOutput {
    let mut world = World::new();
    load_scene(&mut world, spec).unwrap();
    render_world(&mut world, &settings, false).unwrap()
}

#[test]
fn furnace_converges_to_one() {
    let out = render(
        "builtin:furnace",
        RenderSettings {
            width: 16,
            height: 16,
            spp: 32,
            ..RenderSettings::default()
        },
    );
    let (m, se) = (mean(&out.image), standard_error(&out));
    assert_eq!(out.non_finite_samples, 0);
    assert!(
        (m - 1.0).abs() < 4.0 * se + 1e-3,
        "mean {m}, standard error {se}"
    );
    assert!(se < 0.02, "standard error {se}");
}

/// A Lambertian plane (albedo 0.5, no specular layer) lit by a point light of intensity I at
/// height h, seen straight down by an orthographic camera. Nothing else is visible and the plane
/// cannot see itself, so the radiance at a point at distance d from the light is exactly
/// (albedo / pi) * I * h / d^3.
#[test]
fn point_light_over_a_plane_matches_the_closed_form() {
    let (albedo, intensity, height, half_view) = (0.5f32, 10.0f32, 2.0f32, 2.0f32);
    let mut b = SceneBuilder::new("point light over a plane");
    let material = b.add_material(Material::lambertian("plane", Vec3::splat(albedo)));
    let mesh = b.add_mesh("mesh", "plane", floor(20.0)).unwrap().unwrap();
    b.add_instance("plane", mesh, material, Transform::IDENTITY);
    b.add_node(Node {
        name: Some("light".into()),
        transform: Transform::from_translation(Vec3::new(0.0, height, 0.0)),
        light: Some(Light {
            kind: LightKind::Point,
            color: Vec3::ONE,
            intensity,
            range: None,
        }),
        ..Node::default()
    });
    b.add_node(Node {
        name: Some("camera".into()),
        transform: Transform::looking_at(Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO, Vec3::NEG_Z),
        camera: Some(Camera {
            projection: Projection::Orthographic {
                xmag: half_view,
                ymag: half_view,
                znear: 0.0,
                zfar: 10.0,
            },
        }),
        ..Node::default()
    });
    let mut world = World::new();
    b.spawn(&mut world);
    let n = 16u32;
    let settings = RenderSettings {
        width: n,
        height: n,
        spp: 1024,
        ..RenderSettings::default()
    };
    let out = render_world(&mut world, &settings, false).unwrap();

    // Camera right is +X, up is -Z: pixel (x, y) covers world x in [-2, 2] left to right and
    // z in [-2, 2] top to bottom. Average the closed form over each pixel on a fine grid.
    let pixel = 2.0 * half_view / n as f32;
    let mut worst = 0.0f32;
    for y in 0..n {
        for x in 0..n {
            let mut expected = 0.0;
            let sub = 8;
            for sy in 0..sub {
                for sx in 0..sub {
                    let wx = -half_view + (x as f32 + (sx as f32 + 0.5) / sub as f32) * pixel;
                    let wz = -half_view + (y as f32 + (sy as f32 + 0.5) / sub as f32) * pixel;
                    let d = (wx * wx + wz * wz + height * height).sqrt();
                    expected += albedo / std::f32::consts::PI * intensity * height / d.powi(3);
                }
            }
            expected /= (sub * sub) as f32;
            let got = out.image[(y * n + x) as usize];
            for c in 0..3 {
                worst = worst.max((got[c] - expected).abs() / expected);
            }
        }
    }
    assert!(worst < 0.01, "largest relative error {worst}");
}

#[test]
fn noise_between_halves_falls_as_one_over_spp() {
    // relMSE between halves divides by a noisy half: at a few samples per half that inflates it
    // (and a pixel on an emitter's edge that sees the light in one half only dominates it), so
    // the decade starts at 64 spp, on a scene whose emitters are out of view. Each spp's figure
    // is the mean over three seeds: one seed's halves relMSE at 12x12 strays by tens of percent
    // (seed 7 alone: slope -0.72; the mean of seeds 7, 8 and 9: -0.97).
    let halves_noise = |spp| {
        let seeds = [7, 8, 9];
        seeds
            .iter()
            .map(|&seed| {
                let settings = RenderSettings {
                    width: 12,
                    height: 12,
                    spp,
                    seed,
                    sampler: Sampler::Independent,
                    ..RenderSettings::default()
                };
                render("builtin:hard-cases?case=lit-group", settings).halves_rel_mse()
            })
            .sum::<f64>()
            / seeds.len() as f64
    };
    let (low, high) = (halves_noise(64), halves_noise(640));
    let slope = (high / low).log10();
    eprintln!("halves relMSE {low:.3e} at 64 spp, {high:.3e} at 640: slope {slope:.3}");
    assert!(
        (slope + 1.0).abs() <= 0.1,
        "log-log slope {slope} (relMSE {low} at 64 spp, {high} at 640)"
    );
}

/// The reference's own-noise estimate, a quarter of its halves' relMSE, predicts its error
/// against a render 16 times longer: over three seeds, the measured relMSE is within a third of
/// the prediction (the short render's own noise plus the long one's).
#[test]
fn own_noise_predicts_the_error_against_a_longer_render() {
    let scene = "builtin:hard-cases?case=lit-group";
    let settings = |spp, seed| RenderSettings {
        width: 16,
        height: 16,
        spp,
        seed,
        ..RenderSettings::default()
    };
    let long = render(scene, settings(64 * 16, 100));
    let long_noise = long.halves_rel_mse() / 4.0;
    let (mut predicted, mut measured) = (0.0, 0.0);
    for seed in [1, 2, 3] {
        let short = render(scene, settings(64, seed));
        predicted += short.halves_rel_mse() / 4.0 + long_noise;
        measured += rel_mse(&short.image, &long.image);
    }
    let ratio = measured / predicted;
    eprintln!("relMSE against the long render {measured:.3e}, predicted {predicted:.3e}");
    assert!(
        (0.75..=1.33).contains(&ratio),
        "measured {measured:.3e} against predicted {predicted:.3e}: ratio {ratio:.2}"
    );
}

#[test]
fn russian_roulette_leaves_the_mean_unchanged() {
    let path = |rr| PathSettings {
        max_depth: 12,
        russian_roulette_from: rr,
        ..PathSettings::default()
    };
    let settings = |rr| RenderSettings {
        width: 16,
        height: 16,
        spp: 32,
        path: path(rr),
        ..RenderSettings::default()
    };
    let with = render("builtin:cornell", settings(Some(2)));
    let without = render("builtin:cornell", settings(None));
    let (a, b) = (mean(&with.image), mean(&without.image));
    let se = (standard_error(&with).powi(2) + standard_error(&without).powi(2)).sqrt();
    assert!(
        (a - b).abs() < 4.0 * se,
        "with RR {a}, without {b}, standard error {se}"
    );
}

/// Picking lights through the tree or by power changes the noise, not the mean; and on many
/// lights the tree's noise is lower.
#[test]
fn light_tree_and_power_sampling_agree_and_the_tree_is_less_noisy() {
    let settings = |light_sampling| RenderSettings {
        width: 24,
        height: 24,
        spp: 64,
        path: PathSettings {
            max_depth: 3,
            light_sampling,
            ..PathSettings::default()
        },
        ..RenderSettings::default()
    };
    let scene = "builtin:many-lights?quads=16&lights=16";
    let tree = render(scene, settings(LightSampling::Tree));
    let power = render(scene, settings(LightSampling::Power));
    let (a, b) = (mean(&tree.image), mean(&power.image));
    let se = (standard_error(&tree).powi(2) + standard_error(&power).powi(2)).sqrt();
    assert!(
        (a - b).abs() < 4.0 * se,
        "tree {a}, power {b}, standard error {se}"
    );
    let (noise_tree, noise_power) = (tree.halves_rel_mse(), power.halves_rel_mse());
    assert!(
        noise_tree < 0.5 * noise_power,
        "halves' relMSE: tree {noise_tree}, power {noise_power}"
    );
}

#[test]
fn image_does_not_depend_on_the_thread_count() {
    let settings = |threads| RenderSettings {
        width: 20,
        height: 12,
        spp: 4,
        threads: Some(threads),
        ..RenderSettings::default()
    };
    let one = render("builtin:hard-cases?case=spheres", settings(1));
    let two = render("builtin:hard-cases?case=spheres", settings(2));
    assert_eq!(one.image, two.image);
    assert_eq!(one.non_finite_samples, 0);
}

#[test]
fn direct_only_is_at_most_the_full_estimate_and_differs_in_the_cornell_box() {
    let settings = |direct_only| RenderSettings {
        width: 16,
        height: 16,
        spp: 16,
        path: PathSettings {
            direct_only,
            ..PathSettings::default()
        },
        ..RenderSettings::default()
    };
    let direct = mean(&render("builtin:cornell", settings(true)).image);
    let full = mean(&render("builtin:cornell", settings(false)).image);
    assert!(
        direct > 0.0 && direct < full * 0.9,
        "direct {direct}, full {full}"
    );
}

/// The lit group copied 1e5 units from the origin renders like the original. Same seed: the two
/// renders draw the same random numbers, so they differ far less than two independent renders
/// would (paths that diverge by rounding decorrelate after a few bounces); shadow acne or light
/// leaks in the copy would show as a difference at least as large as independent noise. Summed
/// over four seeds: one seed's ratio strays (0.26 to 0.51 over seeds 3 to 6, measured).
#[test]
fn far_copy_renders_like_the_original() {
    let (mut rel_mse, mut independent) = (0.0, 0.0);
    let (mut near_mean, mut far_mean) = (0.0, 0.0);
    for seed in 3..=6 {
        let settings = RenderSettings {
            width: 24,
            height: 24,
            spp: 16,
            seed,
            ..RenderSettings::default()
        };
        let near = render("builtin:hard-cases?case=lit-group", settings);
        let far = render("builtin:hard-cases?case=far-copy", settings);
        assert_eq!(far.non_finite_samples, 0);
        rel_mse += far
            .image
            .iter()
            .zip(&near.image)
            .flat_map(|(x, y)| {
                (0..3).map(move |c| ((x[c] - y[c]) as f64).powi(2) / ((y[c] as f64).powi(2) + 0.01))
            })
            .sum::<f64>()
            / (3 * near.image.len()) as f64;
        // Two independent renders at this sample count differ by about the halves' relMSE / 2.
        independent += near.halves_rel_mse() / 2.0;
        near_mean += mean(&near.image);
        far_mean += mean(&far.image);
    }
    eprintln!("same seeds {rel_mse:.3e}, independent {independent:.3e}");
    assert!(
        rel_mse < 0.5 * independent,
        "relMSE {rel_mse} against the original, independent {independent} (sums over 4 seeds)"
    );
    let (a, b) = (near_mean, far_mean);
    assert!((a - b).abs() < 0.01 * a, "mean {a} near, {b} far");
}
