//! KHR_materials_volume in the CPU reference and on the GPU, against closed forms and against
//! each other:
//!
//! - a tinted glass slab seen face-on under a white sky reads R + T^2 a / (1 - R a) per channel
//!   (R = 0.04 and T = 0.96 at normal incidence, a the slab's Beer-Lambert transmittance): the
//!   light reflected by the front face, plus what crosses the slab after any number of inner
//!   reflections;
//! - a ray entering a glass slab at 45 degrees is bent to asin(sin 45 / 1.5) inside, so it
//!   leaves the slab shifted and lands on an emitter that a straight ray misses: it reads
//!   T(45)^2 times the emitter's radiance;
//! - glass spheres, smooth and rough, clear and tinted, over a floor: the GPU reference mode
//!   agrees with the CPU within three times their combined noise, and the realtime frame
//!   within relMSE 0.05 (its denoiser blurs).

mod common;
mod hard_cases_common;

use bevy_ecs::prelude::World;
use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_reference::PathSettings;
use chiaro_scene::builtin::shapes::{cuboid, floor, icosphere, quad};
use chiaro_scene::{
    Camera, Material, Node, Projection, SceneBuilder, SceneFeatures, Transform, Volume,
};
use glam::Vec3;
use hard_cases_common::{cpu_reference, gpu_modes_match_the_cpu, mode, settings};

/// Clear glass of IOR 1.5 (a volume) with this Beer-Lambert attenuation and roughness.
fn glass(name: &str, roughness: f32, volume: Volume) -> Material {
    Material {
        transmission: 1.0,
        volume: Some(volume),
        ..Material::diffuse(name, Vec3::ONE, roughness)
    }
}

/// An orthographic camera at `eye` looking at the origin, `half` scene units across.
fn orthographic(b: &mut SceneBuilder, eye: Vec3, half: f32) {
    b.add_node(Node {
        name: Some("camera".into()),
        transform: Transform::looking_at(eye, Vec3::ZERO, Vec3::Y),
        camera: Some(Camera {
            projection: Projection::Orthographic {
                xmag: half,
                ymag: half,
                znear: 0.0,
                zfar: 100.0,
            },
        }),
        ..Node::default()
    });
}

/// The mean of each channel.
fn channel_means(image: &[Vec3]) -> Vec3 {
    image.iter().copied().sum::<Vec3>() / image.len() as f32
}

/// The GPU's image in reference mode (`frames` frames of 4 paths) and in the realtime mode,
/// `size` x `size`.
fn gpu_images(world: &mut World, size: u32, frames: u32) -> Option<[Vec<Vec3>; 2]> {
    let gpu = common::gpu()?;
    let mut renderer = Renderer::new(gpu);
    let reference = FrameSettings {
        spp: 4,
        ..mode(RenderMode::Reference)
    };
    let a = renderer
        .render(world, &settings(size, frames, 1, reference))
        .unwrap();
    let features = *world.resource::<SceneFeatures>();
    assert!(features.volumes, "the scene's features: {features:?}");
    let b = renderer
        .render(world, &settings(size, 16, 1, mode(RenderMode::Realtime)))
        .unwrap();
    Some([a.hdr, b.hdr])
}

/// Beer-Lambert through a slab one unit thick whose attenuation colour at one unit is
/// (0.5, 0.25, 1), seen face-on under a white sky: per channel, within 1% in the CPU
/// reference and the GPU's reference mode, 2% in the realtime frame.
#[test]
fn a_tinted_slab_attenuates_by_beer_lambert() {
    let color = Vec3::new(0.5, 0.25, 1.0);
    let mut b = SceneBuilder::new("tinted slab");
    let slab = b.add_material(glass(
        "tinted",
        0.0,
        Volume {
            attenuation_color: color,
            attenuation_distance: 1.0,
        },
    ));
    let mesh = b
        .add_mesh(
            "mesh",
            "slab",
            cuboid(Vec3::new(-20.0, -20.0, -1.0), Vec3::new(20.0, 20.0, 0.0)),
        )
        .unwrap()
        .unwrap();
    b.add_instance("slab", mesh, slab, Transform::IDENTITY);
    orthographic(&mut b, Vec3::new(0.0, 0.0, 5.0), 1.0);
    b.set_environment(chiaro_scene::Environment::constant(Vec3::ONE));
    let mut world = World::new();
    b.spawn(&mut world);

    let (r, t) = (0.04f32, 0.96f32);
    let expected = Vec3::ONE * r + color * (t * t) / (Vec3::ONE - color * r);
    let cpu = channel_means(&cpu_reference(&mut world, 8, 512, PathSettings::default()).image);
    eprintln!("expected {expected}, CPU {cpu}");
    assert!(
        ((cpu - expected) / expected).abs().max_element() < 0.01,
        "CPU {cpu} against {expected}"
    );
    let Some([reference, realtime]) = gpu_images(&mut world, 8, 64) else {
        return;
    };
    let (reference, realtime) = (channel_means(&reference), channel_means(&realtime));
    eprintln!("GPU reference mode {reference}, realtime {realtime}");
    assert!(((reference - expected) / expected).abs().max_element() < 0.01);
    assert!(((realtime - expected) / expected).abs().max_element() < 0.02);
}

/// A ray at 45 degrees through a slab of IOR 1.5 (y from -1 to 0) lands at x = 1.53 on the
/// floor at y = -2, where an emitter strip lies (x from 1.3 to 1.75); a ray that went straight
/// through would land at x = 2, off the strip. It reads T(45)^2 = 0.9176 of the strip's
/// radiance 1 (within 3%), and 0 when the slab is thin-walled.
#[test]
fn refraction_bends_rays_by_snells_law() {
    let scene = |volume: Option<Volume>| {
        let mut b = SceneBuilder::new("refraction");
        let slab = b.add_material(Material {
            volume,
            ..glass("glass", 0.0, Volume::default())
        });
        let mesh = b
            .add_mesh(
                "mesh",
                "slab",
                cuboid(Vec3::new(-50.0, -1.0, -50.0), Vec3::new(50.0, 0.0, 50.0)),
            )
            .unwrap()
            .unwrap();
        b.add_instance("slab", mesh, slab, Transform::IDENTITY);
        let strip = b.add_material(Material::emitter("strip", Vec3::ONE));
        let corners = [(1.3, -1.0), (1.75, -1.0), (1.75, 1.0), (1.3, 1.0)]
            .map(|(x, z)| Vec3::new(x, -2.0, z));
        let mesh = b
            .add_mesh("strip mesh", "strip", quad(corners, Vec3::Y))
            .unwrap()
            .unwrap();
        b.add_instance("strip", mesh, strip, Transform::IDENTITY);
        orthographic(&mut b, Vec3::new(-3.0, 3.0, 0.0), 0.01);
        let mut world = World::new();
        b.spawn(&mut world);
        world
    };
    let f = 0.04 + 0.96 * (1.0 - std::f32::consts::FRAC_1_SQRT_2).powi(5);
    let expected = (1.0 - f) * (1.0 - f);
    let mut world = scene(Some(Volume::default()));
    let cpu = channel_means(&cpu_reference(&mut world, 2, 4096, PathSettings::default()).image);
    eprintln!("expected {expected}, CPU {cpu}");
    assert!(
        (cpu / expected - Vec3::ONE).abs().max_element() < 0.03,
        "{cpu}"
    );
    let mut thin = scene(None);
    let straight = channel_means(&cpu_reference(&mut thin, 2, 256, PathSettings::default()).image);
    assert!(straight.max_element() < 0.01, "thin-walled: {straight}");
    let Some([reference, _]) = gpu_images(&mut world, 2, 1024) else {
        return;
    };
    let reference = channel_means(&reference);
    eprintln!("GPU reference mode {reference}");
    assert!(
        (reference / expected - Vec3::ONE).abs().max_element() < 0.03,
        "{reference}"
    );
}

/// Smooth clear glass, rough glass and smooth tinted glass spheres over a grey floor under a
/// white sky: the GPU's reference mode against the CPU, relMSE over the covered pixels within
/// three times the combined noise.
#[test]
fn glass_spheres_match_the_cpu_reference() {
    let mut b = SceneBuilder::new("glass spheres");
    let sphere = b
        .add_mesh("mesh", "sphere", icosphere(4, false))
        .unwrap()
        .unwrap();
    let tint = Volume {
        attenuation_color: Vec3::new(0.9, 0.5, 0.2),
        attenuation_distance: 0.5,
    };
    for (x, material) in [
        (-1.1, glass("clear", 0.0, Volume::default())),
        (0.0, glass("rough", 0.35, Volume::default())),
        (1.1, glass("tinted", 0.0, tint)),
    ] {
        let id = b.add_material(material);
        b.add_instance(
            "sphere",
            sphere,
            id,
            Transform::from_translation(Vec3::new(x, 0.0, 0.0)).with_scale(Vec3::splat(0.5)),
        );
    }
    let grey = b.add_material(Material::diffuse("floor", Vec3::splat(0.5), 0.8));
    let mesh = b
        .add_mesh("floor mesh", "floor", floor(20.0))
        .unwrap()
        .unwrap();
    b.add_instance(
        "floor",
        mesh,
        grey,
        Transform::from_translation(Vec3::new(0.0, -0.5, 0.0)),
    );
    let mut world = common::spawn_under_white_sky(b, Vec3::new(0.0, 1.5, 4.5));
    let size = 40;
    let cpu = cpu_reference(&mut world, size, 256, PathSettings::default());
    let Some(gpu) = common::gpu() else { return };
    gpu_modes_match_the_cpu(&mut Renderer::new(gpu), &mut world, &cpu, size, 64);
}
