//! Material extensions on the GPU against the CPU reference: clear-coated spheres (a rough coat
//! and a mirror coat over coloured bases), a KHR_materials_specular sphere (tinted, half
//! strength), a thin-walled transmissive one (KHR_materials_transmission) and a sheen over a dark
//! base (KHR_materials_sheen) under a white sky. The GPU reference mode must agree with the CPU reference within
//! three times the two images' combined noise (relMSE over the spheres' pixels), and the
//! realtime frame within 0.05 (its denoiser blurs). The clearcoat pipeline feature is on only
//! for this scene: the coat code is compiled in when a used material has one.

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_reference::PathSettings;
use chiaro_scene::builtin::shapes::icosphere;
use chiaro_scene::{Material, SceneBuilder, SceneFeatures, Transform};
use glam::Vec3;
use hard_cases_common::{cpu_reference, gpu_modes_match_the_cpu, mode, settings};

fn spheres() -> World {
    let mut b = SceneBuilder::new("material extensions");
    let mesh = b
        .add_mesh("mesh", "sphere", icosphere(4, false))
        .unwrap()
        .unwrap();
    let rough_coat = Material {
        clearcoat: 1.0,
        clearcoat_roughness: 0.3,
        ..Material::diffuse("rough coat", Vec3::new(0.8, 0.1, 0.1), 0.6)
    };
    let mirror_coat = Material {
        clearcoat: 0.8,
        clearcoat_roughness: 0.0,
        metallic: 1.0,
        ..Material::diffuse("mirror coat", Vec3::new(0.9, 0.7, 0.3), 0.5)
    };
    let specular = Material {
        specular: 0.5,
        specular_color: Vec3::new(2.0, 1.0, 0.5),
        ..Material::diffuse("tinted specular", Vec3::new(0.2, 0.4, 0.8), 0.3)
    };
    let glass = Material {
        transmission: 0.9,
        ..Material::diffuse("rough glass", Vec3::new(0.9, 0.95, 1.0), 0.25)
    };
    let velvet = Material {
        sheen_color: Vec3::new(0.9, 0.5, 0.7),
        sheen_roughness: 0.5,
        ..Material::diffuse("velvet", Vec3::new(0.2, 0.05, 0.1), 0.8)
    };
    for (x, material) in [
        (-2.2, rough_coat),
        (-1.1, mirror_coat),
        (0.0, specular),
        (1.1, glass),
        (2.2, velvet),
    ] {
        let id = b.add_material(material);
        b.add_instance(
            "sphere",
            mesh,
            id,
            Transform::from_translation(Vec3::new(x, 0.0, 0.0)).with_scale(Vec3::splat(0.5)),
        );
    }
    common::spawn_under_white_sky(b, Vec3::new(0.0, 1.0, 7.0))
}

#[test]
fn coats_specular_tints_and_glass_match_the_cpu_reference() {
    let Some(gpu) = common::gpu() else { return };
    let size = 48;
    let mut world = spheres();
    let cpu = cpu_reference(&mut world, size, 256, PathSettings::default());
    let mut renderer = Renderer::new(gpu);
    gpu_modes_match_the_cpu(&mut renderer, &mut world, &cpu, size, 48);
    let features = *world.resource::<SceneFeatures>();
    assert!(
        features.clearcoat && features.transmission && features.sheen,
        "the scene's features: {features:?}"
    );
}

/// A clear, smooth, thin-walled pane filling the view under a white sky of radiance 1: what it
/// does not reflect (F) it passes straight through (1 - F), so every pixel's exact value is 1,
/// in the CPU reference and every GPU mode (mean within 1%).
#[test]
fn a_clear_pane_under_a_white_sky_reads_one() {
    let mut b = SceneBuilder::new("clear pane");
    let pane = b.add_material(Material {
        transmission: 1.0,
        ..Material::diffuse("pane", Vec3::ONE, 0.0)
    });
    let mesh = b
        .add_mesh("mesh", "pane", chiaro_scene::builtin::shapes::floor(50.0))
        .unwrap()
        .unwrap();
    b.add_instance(
        "pane",
        mesh,
        pane,
        Transform::IDENTITY.with_rotation(glam::Quat::from_rotation_x(std::f32::consts::FRAC_PI_2)),
    );
    let mut world = common::spawn_under_white_sky(b, Vec3::new(0.3, 0.4, 3.0));
    let mean = |image: &[Vec3]| {
        image
            .iter()
            .map(|p| f64::from(p.x + p.y + p.z))
            .sum::<f64>()
            / (3 * image.len()) as f64
    };
    let cpu = cpu_reference(&mut world, 16, 64, PathSettings::default());
    eprintln!("CPU reference: mean {:.4}", mean(&cpu.image));
    assert!((mean(&cpu.image) - 1.0).abs() < 0.01);
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    for frame in [
        FrameSettings {
            spp: 4,
            ..mode(RenderMode::Reference)
        },
        mode(RenderMode::Realtime),
    ] {
        let out = renderer
            .render(&mut world, &settings(16, 16, 1, frame))
            .unwrap();
        eprintln!("{:?}: mean {:.4}", frame.mode, mean(&out.hdr));
        assert!((mean(&out.hdr) - 1.0).abs() < 0.01, "{:?}", frame.mode);
    }
}
