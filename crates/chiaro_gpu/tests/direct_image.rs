//! The GPU direct-light render, accumulated over frames with fresh random numbers, converges
//! to the CPU reference's direct-only render (`chiaro reference --direct-only`): linear HDR
//! relMSE below a stated bound, and falling as frames accumulate.
//!
//! The bound: both images are Monte Carlo estimates of the same integral, so with no bias their
//! expected relMSE is the sum of their own noises. Both are measured, not assumed: the
//! reference's from its two independent halves (their relMSE is four times the full image's),
//! the GPU's from a second accumulation with another seed (the two GPU images' relMSE is twice
//! either one's). The test asserts relMSE < 3 x (GPU noise + reference noise): the factor is
//! above 1 because relMSE is dominated by a few pixels that an emitter's edge covers by a
//! sliver (their error is far from Gaussian: seed 1 measures 1.85x the noise sum on the Cornell
//! box, seed 2 0.55x). Measured on lavapipe, 32x32, 256 frames: Cornell box 1.18e-3 against a
//! bound of 1.9e-3, the normal-mapped model under the sky 6.2e-4 against 1.8e-3, the hard
//! cases 1.5e-2 against 4.4e-2, 256 punctual lights 0.26 against 0.47. A bias of
//! relative size b adds about b^2 on every lit pixel, so the lit interior's sum (pixels the
//! reference sees below radiance 1, so emitter edges do not dominate it) is also compared per
//! channel: the difference must stay within 4 standard errors, the standard error estimated
//! from the same two GPU seeds and the reference's two halves (pixel by pixel, (a - b)^2 / 2
//! for a GPU image, (h1 - h2)^2 / 4 for the reference).
//!
//! Error falls: every sixteenfold increase of the frames at least halves the relMSE (pure
//! noise would fall sixteenfold; pixels that an emitter covers by a sliver keep
//! it lumpy at low frame counts, as a box filter sampled at a few points must be).

mod common;

use std::path::Path;

use bevy_ecs::prelude::{Entity, Name};
use bevy_ecs::world::World;
use chiaro_gpu::{FrameSettings, RenderMode, RenderSettings, Renderer, RestirSettings};
use chiaro_reference::{PathSettings, render_world};
use chiaro_scene::{AlphaMode, Environment, Materials, MeshInstance, load_scene};
use glam::Vec3;

/// Gives the Cornell box's tall block a copy of its material with alpha 0.25 under an alpha
/// mask of cutoff 0.5: the block is a hole for the rasterizer, the shadow rays and the BRDF
/// rays alike.
fn mask_tall_block(world: &mut World) {
    let mut query = world.query::<(Entity, &Name, &MeshInstance)>();
    let (entity, instance) = query
        .iter(world)
        .find(|(_, name, _)| name.as_str() == "tall block")
        .map(|(e, _, i)| (e, *i))
        .expect("the Cornell box has a tall block");
    let mut materials = world.resource_mut::<Materials>();
    let mut masked = materials.get(instance.material).unwrap().clone();
    masked.base_color.w = 0.25;
    masked.alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
    let id = materials.add(masked);
    world.get_mut::<MeshInstance>(entity).unwrap().material = id;
}

/// A scene edit applied after loading.
type Edit = fn(&mut World);

fn no_edit(_: &mut World) {}

fn world(scene: &str, env: Option<&Path>, edit: Edit) -> World {
    let mut world = World::new();
    load_scene(&mut world, scene).unwrap();
    edit(&mut world);
    if let Some(path) = env {
        let (environment, _) = Environment::from_file(path, 1.0).unwrap();
        world.insert_resource(environment);
    }
    world
}

/// What [`compare`] measured.
struct Measured {
    /// The reference's own relMSE (a quarter of its halves').
    reference_noise: f64,
    /// The GPU image's own relMSE at the last checkpoint (half that between two seeds).
    gpu_noise: f64,
    /// (frames, relMSE against the reference).
    errors: Vec<(u32, f64)>,
    /// Sums over the lit interior, GPU and reference.
    interior: (Vec3, Vec3),
    /// The variance of the difference of the two sums (estimated).
    interior_variance: Vec3,
}

/// Renders `scene` on the CPU (direct only, `spp`) and on the GPU at `checkpoints` frames
/// (twice, with two seeds).
fn compare(
    scene: &str,
    env: Option<&Path>,
    edit: Edit,
    size: u32,
    spp: u32,
    checkpoints: &[u32],
) -> Option<Measured> {
    compare_resampled(scene, env, edit, size, spp, checkpoints, false)
}

/// [`compare`], the GPU's area light resampled (ReSTIR DI) when `resampled`.
fn compare_resampled(
    scene: &str,
    env: Option<&Path>,
    edit: Edit,
    size: u32,
    spp: u32,
    checkpoints: &[u32],
    resampled: bool,
) -> Option<Measured> {
    let gpu = common::gpu()?;
    let mut cpu_world = world(scene, env, edit);
    let reference = render_world(
        &mut cpu_world,
        &chiaro_reference::RenderSettings {
            width: size,
            height: size,
            spp,
            seed: 7,
            sampler: chiaro_reference::Sampler::default(),
            threads: None,
            path: PathSettings {
                direct_only: true,
                ..PathSettings::default()
            },
        },
        false,
    )
    .unwrap();
    let reference_noise = reference.halves_rel_mse() / 4.0;

    let mut gpu_world = world(scene, env, edit);
    let mut renderer = Renderer::new(gpu);
    let settings = RenderSettings {
        width: size,
        height: size,
        frames: checkpoints[0],
        seed: 1,
        frame: FrameSettings {
            mode: RenderMode::Direct,
            restir: RestirSettings {
                direct: resampled,
                ..RestirSettings::default()
            },
            ..FrameSettings::default()
        },
    };
    let mut out = renderer.render(&mut gpu_world, &settings).unwrap();
    let mut errors = Vec::new();
    for &total in checkpoints {
        let more = total - out.frames;
        renderer
            .accumulate(&mut gpu_world, &settings, more)
            .unwrap();
        out = renderer.read(&settings).unwrap();
        errors.push((total, common::rel_mse(&out.hdr, &reference.image)));
    }
    let other = RenderSettings {
        frames: out.frames,
        seed: 2,
        ..settings
    };
    let mut other_world = world(scene, env, edit);
    let second = renderer.render(&mut other_world, &other).unwrap();
    let gpu_noise = common::rel_mse(&out.hdr, &second.hdr) / 2.0;
    let clip = 1.0;
    let (mut gpu_sum, mut ref_sum, mut variance) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    for (i, (a, b)) in out.hdr.iter().zip(&reference.image).enumerate() {
        if b.max_element() < clip {
            gpu_sum += *a;
            ref_sum += *b;
            let g = *a - second.hdr[i];
            let h = reference.halves[0][i] - reference.halves[1][i];
            variance += g * g / 2.0 + h * h / 4.0;
        }
    }
    eprintln!(
        "{scene}: reference noise {reference_noise:.2e}, GPU noise {gpu_noise:.2e}, GPU relMSE \
         by frames {errors:?}, interior sums GPU {gpu_sum} CPU {ref_sum}"
    );
    Some(Measured {
        reference_noise,
        gpu_noise,
        errors,
        interior: (gpu_sum, ref_sum),
        interior_variance: variance,
    })
}

fn check(m: Measured) {
    let last = m.errors[m.errors.len() - 1];
    let bound = 3.0 * (m.gpu_noise + m.reference_noise);
    assert!(
        last.1 < bound,
        "relMSE {} after {} frames, bound {bound:.3e}",
        last.1,
        last.0
    );
    for (i, &(f0, e0)) in m.errors.iter().enumerate() {
        for &(f1, e1) in &m.errors[i + 1..] {
            if f1 >= 16 * f0 {
                assert!(e1 < 0.5 * e0, "{e1} at {f1} frames against {e0} at {f0}");
            }
        }
    }
    let z = (m.interior.0 - m.interior.1)
        / Vec3::new(
            m.interior_variance.x.sqrt(),
            m.interior_variance.y.sqrt(),
            m.interior_variance.z.sqrt(),
        );
    eprintln!("interior difference in standard errors {z}");
    assert!(
        z.abs().max_element() < 4.0,
        "interior sums GPU {} CPU {}: {z} standard errors",
        m.interior.0,
        m.interior.1
    );
}

#[test]
fn cornell_direct_light_converges_to_the_reference() {
    if let Some(result) = compare("builtin:cornell", None, no_edit, 32, 1024, &[4, 64, 256]) {
        check(result);
    }
}

#[test]
fn textured_model_under_the_environment_converges_to_the_reference() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    let model = shared.join("NormalTangentTest.glb");
    let sky = shared.join("qwantani_afternoon_puresky_1k.hdr");
    if !model.exists() || !sky.exists() {
        eprintln!("skipped: {} or {} missing", model.display(), sky.display());
        return;
    }
    if let Some(result) = compare(
        model.to_str().unwrap(),
        Some(&sky),
        no_edit,
        32,
        512,
        &[4, 64, 256],
    ) {
        check(result);
    }
}

#[test]
fn many_lights_converge_to_the_reference() {
    // 256 punctual lights (more than the pass evaluates one by one: picked by power) and 512
    // emissive triangles.
    if let Some(result) = compare("builtin:many-lights", None, no_edit, 32, 512, &[4, 64, 256]) {
        check(result);
    }
}

#[test]
fn hard_cases_converge_to_the_reference() {
    // A far copy of the scene 1e5 units away, tiny emitters, a directional and point lights.
    if let Some(result) = compare("builtin:hard-cases", None, no_edit, 32, 512, &[4, 64, 256]) {
        check(result);
    }
}

#[test]
fn alpha_masked_block_is_a_hole_as_in_the_reference() {
    if let Some(result) = compare(
        "builtin:cornell",
        None,
        mask_tall_block,
        32,
        512,
        &[4, 64, 256],
    ) {
        check(result);
    }
}

/// `scene`'s resampled direct light (32x32, 4, 64 and 256 frames) against a reference of `spp`.
fn check_resampled(scene: &str, spp: u32) {
    if let Some(result) = compare_resampled(scene, None, no_edit, 32, spp, &[4, 64, 256], true) {
        check(result);
    }
}

#[test]
fn resampled_cornell_direct_light_converges_to_the_reference() {
    check_resampled("builtin:cornell", 1024);
}

#[test]
fn resampled_hard_cases_converge_to_the_reference() {
    check_resampled("builtin:hard-cases", 512);
}

#[test]
fn resampled_many_lights_converge_to_the_reference() {
    // The reservoirs hold the punctual lights too: there are more than the pass evaluates.
    check_resampled("builtin:many-lights", 512);
}
