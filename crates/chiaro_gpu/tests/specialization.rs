//! Specialised pipelines (`chiaro_gpu::specialization`) render the image of the general
//! pipeline, and the specialisation is real: each flag's code runs only when the flag is on.
//!
//! - On the Cornell box (it uses emissive triangles only), the specialised frame, the
//!   all-features frame and every frame with one more flag than the scene needs are the same
//!   image with the same seed: relMSE at most [`ROUNDING`].
//! - On a Cornell box given every feature (textures of each kind, a normal-mapped panel, an
//!   alpha-masked block, vertex colours on the panel, which is alpha-blended, a clear-coated
//!   left wall (its coat textured), a transmissive right wall, a sheen on the ceiling (its
//!   colour textured), point, spot and directional lights, an environment image, an
//!   emitting short block, whose triangles with the light's are enough for a light tree), the
//!   pipeline for exactly the scene's features renders the all-features image, and turning any
//!   one flag off changes the image (relMSE above [`MISSING`]). The one flag a setting rather
//!   than the scene turns on, resampled direct light, is checked in the realtime mode, which
//!   alone resamples.
//!
//! Each frame is two reference-mode frames at 32x32, which run every scene-reading pass.

mod common;

use bevy_ecs::prelude::*;
use chiaro_gpu::{
    FrameSettings, GpuScene, PipelineChoice, PipelineFeatures, RenderMode, RenderSettings, Renderer,
};
use chiaro_scene::{
    AlphaMode, Environment, EnvironmentSource, EquirectImage, Light, LightKind, Material,
    Materials, Mesh, MeshData, MeshInstance, Meshes, SceneFeatures, Texture, TextureRef, Textures,
    Transform, load_scene,
};
use glam::{Affine2, Quat, Vec2, Vec3, Vec4};

use common::rel_mse;

/// Same image: floating-point rounding only. Measured 0 (the images are bit-identical).
const ROUNDING: f64 = 1e-9;
/// A missing feature shows: the smallest relMSE measured with one flag off is 2.1e-3 (the spot
/// light), the largest 3.4 (the normal map).
const MISSING: f64 = 1e-4;

fn settings(pipeline: PipelineChoice) -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 32,
        frames: 2,
        seed: 7,
        frame: FrameSettings {
            mode: RenderMode::Reference,
            pipeline,
            ..Default::default()
        },
    }
}

fn render(renderer: &mut Renderer, world: &mut World, pipeline: PipelineChoice) -> Vec<Vec3> {
    let image = renderer.render(world, &settings(pipeline)).unwrap();
    assert!(image.hdr.iter().all(|p| p.is_finite()));
    image.hdr
}

fn cornell() -> World {
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    world
}

/// The features the scene's systems derived, after one frame: the scene's own, and light trees
/// where the GPU scene built one (the frames pick lights through trees, the default).
fn scene_features(world: &World) -> PipelineFeatures {
    let features = PipelineFeatures::of_scene(world.resource::<SceneFeatures>());
    if world.resource::<GpuScene>().light_trees() {
        features.with(PipelineFeatures::LIGHT_TREES)
    } else {
        features
    }
}

#[test]
fn flags_a_scene_lacks_change_nothing() {
    let Some(context) = common::gpu() else {
        return;
    };
    let mut renderer = Renderer::new(context);
    let mut world = cornell();
    let specialized = render(&mut renderer, &mut world, PipelineChoice::Specialized);
    let needed = scene_features(&world);
    assert_eq!(needed, PipelineFeatures::EMISSIVE_TRIANGLES);
    let all = render(&mut renderer, &mut world, PipelineChoice::AllFeatures);
    let e = rel_mse(&all, &specialized);
    eprintln!("cornell: all features against specialised: relMSE {e:.3e}");
    assert!(e <= ROUNDING, "all-features image differs: {e:.3e}");
    for flag in PipelineFeatures::FLAGS {
        if needed.contains(flag.bit) {
            continue;
        }
        let with = PipelineChoice::Exactly(needed.with(flag.bit));
        let e = rel_mse(&render(&mut renderer, &mut world, with), &specialized);
        eprintln!("cornell + {}: relMSE {e:.3e}", flag.name);
        assert!(e <= ROUNDING, "{} changes the image: {e:.3e}", flag.name);
    }
}

/// A 4x4 RGBA8 texture whose texels cycle through `texels`.
fn texture(textures: &mut Textures, name: &str, texels: &[[u8; 4]], srgb: bool) -> TextureRef {
    let rgba8 = (0..16).flat_map(|i| texels[i % texels.len()]).collect();
    let id = textures.add(Texture {
        name: name.into(),
        width: 4,
        height: 4,
        rgba8,
        color_space: if srgb {
            chiaro_scene::ColorSpace::Srgb
        } else {
            chiaro_scene::ColorSpace::Linear
        },
    });
    TextureRef {
        texture: id,
        uv_set: 0,
        transform: Affine2::IDENTITY,
        sampler: Default::default(),
    }
}

/// The material of the instance named `name`, replaced by `edit` of a copy of it.
fn edit_material(world: &mut World, name: &str, edit: impl FnOnce(&mut Material)) {
    let mut query = world.query::<(Entity, &Name, &MeshInstance)>();
    let (entity, instance) = query
        .iter(world)
        .find(|(_, n, _)| n.as_str() == name)
        .map(|(e, _, i)| (e, *i))
        .unwrap_or_else(|| panic!("the Cornell box has a {name}"));
    let mut materials = world.resource_mut::<Materials>();
    let mut material = materials.get(instance.material).unwrap().clone();
    edit(&mut material);
    let id = materials.add(material);
    world.get_mut::<MeshInstance>(entity).unwrap().material = id;
}

/// Makes the tall block a hole: alpha 0.25 under a mask of cutoff 0.5.
fn mask_tall_block(world: &mut World) {
    edit_material(world, "tall block", |m| {
        m.base_color.w = 0.25;
        m.alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
    });
}

/// The Cornell box with every feature a flag guards.
fn cornell_with_every_feature() -> World {
    let mut world = cornell();
    let mut textures = world.remove_resource::<Textures>().unwrap_or_default();
    let checker = texture(
        &mut textures,
        "checker",
        &[[255, 255, 255, 255], [40, 40, 200, 255]],
        true,
    );
    let metal_rough = texture(
        &mut textures,
        "metal-rough",
        &[[0, 40, 255, 255], [0, 255, 0, 255]],
        false,
    );
    let emissive = texture(
        &mut textures,
        "emissive",
        &[[255, 255, 255, 255], [0, 0, 0, 255]],
        true,
    );
    let bumps = texture(
        &mut textures,
        "bumps",
        &[
            [230, 128, 200, 255],
            [25, 128, 200, 255],
            [128, 230, 200, 255],
        ],
        false,
    );
    world.insert_resource(textures);
    edit_material(&mut world, "back wall", |m| {
        m.base_color_texture = Some(checker);
    });
    edit_material(&mut world, "floor", |m| {
        m.metallic = 1.0;
        m.roughness = 1.0;
        m.metallic_roughness_texture = Some(metal_rough);
    });
    edit_material(&mut world, "light", |m| m.emissive_texture = Some(emissive));
    edit_material(&mut world, "left wall", |m| {
        m.clearcoat = 1.0;
        m.clearcoat_roughness = 0.1;
        m.layer_textures.clearcoat = Some(bumps);
    });
    edit_material(&mut world, "right wall", |m| {
        m.roughness = 0.3;
        m.transmission = 0.8;
    });
    edit_material(&mut world, "ceiling", |m| {
        m.sheen_color = Vec3::new(0.2, 0.9, 0.5);
        m.sheen_roughness = 0.4;
        m.layer_textures.sheen_color = Some(checker);
    });
    mask_tall_block(&mut world);
    edit_material(&mut world, "short block", |m| {
        m.emissive = Vec3::new(0.2, 0.1, 0.05);
        m.transmission = 0.9;
        m.roughness = 0.2;
        m.volume = Some(chiaro_scene::Volume {
            attenuation_color: Vec3::new(0.9, 0.6, 0.3),
            attenuation_distance: 0.2,
        });
    });
    // A normal-mapped panel in front of the back wall (the box is 0.555 m wide) (tangents generated from its UVs).
    let (panel, _) = Mesh::new(
        "panel",
        MeshData {
            positions: vec![
                Vec3::new(0.40, 0.10, 0.55),
                Vec3::new(0.15, 0.10, 0.55),
                Vec3::new(0.15, 0.40, 0.55),
                Vec3::new(0.40, 0.40, 0.55),
            ],
            normals: Some(vec![Vec3::NEG_Z; 4]),
            uvs: [Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]), None],
            colors: Some(vec![
                Vec4::new(1.0, 0.3, 0.3, 1.0),
                Vec4::new(0.3, 1.0, 0.3, 1.0),
                Vec4::new(0.3, 0.3, 1.0, 1.0),
                Vec4::ONE,
            ]),
            indices: Some(vec![0, 1, 2, 0, 2, 3]),
            tangent_uv_set: Some(0),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(panel.tangents().is_some());
    let mesh = world.resource_mut::<Meshes>().add(panel);
    let material = world.resource_mut::<Materials>().add(Material {
        normal_texture: Some(bumps),
        metallic: 1.0,
        roughness: 0.2,
        base_color: Vec4::new(0.9, 0.9, 0.9, 0.6),
        alpha_mode: AlphaMode::Blend,
        ..Material::diffuse("bumpy", Vec3::splat(0.9), 0.2)
    });
    world.spawn((
        Name::new("panel"),
        MeshInstance { mesh, material },
        Transform::IDENTITY,
    ));
    let light = |kind, intensity| Light {
        kind,
        color: Vec3::new(1.0, 0.9, 0.8),
        intensity,
        range: None,
    };
    world.spawn((
        light(LightKind::Point, 0.15),
        Transform::from_translation(Vec3::new(0.15, 0.45, 0.15)),
    ));
    let down = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    world.spawn((
        light(
            LightKind::Spot {
                inner_cone_angle: 0.2,
                outer_cone_angle: 0.4,
            },
            0.3,
        ),
        Transform::from_translation(Vec3::new(0.40, 0.54, 0.40)).with_rotation(down),
    ));
    // Travelling into the box through its open front (+Z), from above.
    let into_box = Quat::from_rotation_arc(Vec3::NEG_Z, Vec3::new(0.0, -0.5, 1.0).normalize());
    world.spawn((
        light(LightKind::Directional, 2.0),
        Transform::IDENTITY.with_rotation(into_box),
    ));
    let texels = (0..8 * 4)
        .map(|i| Vec3::new(0.5 + (i % 3) as f32, 1.0, 0.5 + (i % 5) as f32 * 0.3))
        .collect();
    world.insert_resource(Environment {
        source: EnvironmentSource::Equirect(EquirectImage {
            path: "in-memory sky".into(),
            width: 8,
            height: 4,
            texels,
        }),
        strength: 1.0,
        rotation: 0.0,
    });
    world
}

#[test]
fn each_flag_turns_its_feature_on_and_only_its_flag_does() {
    let Some(context) = common::gpu() else {
        return;
    };
    let mut renderer = Renderer::new(context);
    let mut world = cornell_with_every_feature();
    let all = render(&mut renderer, &mut world, PipelineChoice::AllFeatures);
    let needed = scene_features(&world);
    let resampling = PipelineFeatures::RESTIR_DI;
    assert_eq!(
        needed,
        PipelineFeatures::ALL.without(resampling),
        "{:?}",
        needed.names()
    );
    let exact = render(&mut renderer, &mut world, PipelineChoice::Exactly(needed));
    let e = rel_mse(&exact, &all);
    eprintln!("every feature: exact against all features: relMSE {e:.3e}");
    assert!(e <= ROUNDING, "{e:.3e}");
    for flag in PipelineFeatures::FLAGS {
        if flag.bit == resampling {
            continue;
        }
        let without = PipelineChoice::Exactly(needed.without(flag.bit));
        let e = rel_mse(&render(&mut renderer, &mut world, without), &all);
        eprintln!("without {}: relMSE {e:.3e}", flag.name);
        assert!(e > MISSING, "{} off changes nothing: {e:.3e}", flag.name);
    }
    let mut realtime = settings(PipelineChoice::Exactly(needed.with(resampling)));
    realtime.frame.mode = RenderMode::Realtime;
    realtime.frame.restir.direct = true;
    let resampled = renderer.render(&mut world, &realtime).unwrap().hdr;
    realtime.frame.pipeline = PipelineChoice::Exactly(needed);
    let without = renderer.render(&mut world, &realtime).unwrap().hdr;
    let e = rel_mse(&without, &resampled);
    eprintln!("without FEATURE_RESTIR_DI: relMSE {e:.3e}");
    assert!(
        e > MISSING,
        "FEATURE_RESTIR_DI off changes nothing: {e:.3e}"
    );
}

/// An edit that adds a feature does not stall a renderer that compiles in the background: the
/// frame after the edit renders at once with the pipeline in use, and a later frame switches to
/// the one compiled for the new features.
#[test]
fn a_new_feature_compiles_in_the_background_while_the_old_pipeline_renders() {
    let Some(context) = common::gpu() else {
        return;
    };
    let mut renderer = Renderer::new(context);
    renderer.compile_in_background(true);
    let mut world = cornell();
    let frame = settings(PipelineChoice::Specialized);
    renderer.accumulate(&mut world, &frame, 1).unwrap();
    let before = scene_features(&world);
    assert_eq!(renderer.frame().unwrap().features(), Some(before));
    let plain = std::time::Instant::now();
    renderer.accumulate(&mut world, &frame, 1).unwrap();
    let plain = plain.elapsed();
    mask_tall_block(&mut world);
    let edited = std::time::Instant::now();
    renderer.accumulate(&mut world, &frame, 1).unwrap();
    let edited = edited.elapsed();
    let after = scene_features(&world);
    assert_eq!(after, before.with(PipelineFeatures::ALPHA_MASKS));
    assert_eq!(renderer.frame().unwrap().features(), Some(before));
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    let mut frames = 1;
    while renderer.frame().unwrap().features() != Some(after) {
        assert!(std::time::Instant::now() < deadline, "never switched");
        renderer.accumulate(&mut world, &frame, 1).unwrap();
        frames += 1;
    }
    eprintln!(
        "frame before the edit {plain:?}, the edit's frame {edited:?}; switched to the new \
         features after {frames} frames"
    );
    // The pipeline it switched to is the exact one: a fresh render with it matches a fresh
    // renderer's, which compiles before its first frame.
    let switched = renderer.render(&mut world, &frame).unwrap();
    let mut fresh_world = cornell();
    mask_tall_block(&mut fresh_world);
    let mut fresh = Renderer::new(common::gpu().unwrap());
    let compiled_first = std::time::Instant::now();
    let exact = fresh.render(&mut fresh_world, &frame).unwrap();
    eprintln!(
        "a fresh renderer's first 2 frames (compiling before them): {:?}",
        compiled_first.elapsed()
    );
    let e = rel_mse(&switched.hdr, &exact.hdr);
    assert!(e <= ROUNDING, "{e:.3e}");
}

/// A new output size keeps the compiled pipelines (a window resize recompiles nothing), and the
/// resized frame is the image a fresh renderer gives at that size.
#[test]
fn a_resize_keeps_the_compiled_pipelines() {
    let Some(context) = common::gpu() else {
        return;
    };
    let mut renderer = Renderer::new(context);
    let mut world = cornell();
    let small = settings(PipelineChoice::Specialized);
    renderer.render(&mut world, &small).unwrap();
    let builds = renderer.frame().unwrap().pipeline_builds();
    assert_eq!(builds, 3, "gbuffer, direct and indirect");
    let large = RenderSettings {
        width: 40,
        height: 24,
        ..small
    };
    let resized = renderer.render(&mut world, &large).unwrap();
    assert_eq!(renderer.frame().unwrap().pipeline_builds(), builds);
    let fresh = Renderer::new(common::gpu().unwrap())
        .render(&mut cornell(), &large)
        .unwrap();
    let e = rel_mse(&resized.hdr, &fresh.hdr);
    assert!(e <= ROUNDING, "{e:.3e}");
}
