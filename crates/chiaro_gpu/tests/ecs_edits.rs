//! Editing through ECS: on the Cornell box (48x48, reference mode, 4 paths per pixel per frame,
//! accumulating), four edits made to the rendered World's components one after another: the red
//! wall's material turns blue (`Materials`), the tall block moves (its `Transform`), a point
//! light is spawned (`Light` + `Transform`), then despawned.
//!
//! After each edit the renderer's next frames restart the mean and converge to the edited
//! scene: relMSE (linear HDR, mean((x-y)^2/(y^2+0.01)) over pixels and channels) between the
//! in-place image (16 frames after the edit) and a fresh render of a new World built with the
//! edits applied from the start (32 frames, another seed) is under `CONVERGED` (2.5e-2), while
//! the image from before the edit is at least `CHANGED` (5e-2) from that reference, so a missed
//! or unapplied edit fails. Measured on lavapipe (recolour, move, add light, remove light; the
//! reference of the removal is the fresh scene without the light): converged 5.7e-3, 5.8e-3,
//! 1.2e-2, 6.4e-3; before the edit 6.8e-1, 6.9e-2, 2.1e-1, 2.85.
//!
//! Counters: the frame after the colour edit writes one material record and nothing else; after
//! the move, the instance record and TLAS nodes (and the frame after, that instance's previous
//! transform), with one TLAS update and no BLAS or TLAS build, and no vertices, indices or BLAS
//! data; after adding or removing the light, the light table and the scene info only, with no
//! BVH work; every other frame writes nothing.

mod common;

use bevy_ecs::prelude::*;
use chiaro_bvh::{BvhStats, GpuInstance};
use chiaro_gpu::UploadStats;
use chiaro_gpu::gpu_scene::GpuMaterial;
use chiaro_gpu::{FrameSettings, GpuScene, RenderMode, RenderOutput, RenderSettings, Renderer};
use chiaro_scene::{Light, LightKind, Name, Transform, load_scene};
use glam::Vec3;

const SIZE: u32 = 48;
/// Paths per pixel per frame.
const SPP: u32 = 4;
/// Frames accumulated after each edit.
const FRAMES: u32 = 16;
/// Frames of each fresh reference.
const REFERENCE_FRAMES: u32 = 32;
/// Largest relMSE between the edited image and the fresh reference.
const CONVERGED: f64 = 2.5e-2;
/// Least relMSE between the image from before an edit and the edited scene's reference.
const CHANGED: f64 = 5e-2;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Edit {
    Recolour,
    Move,
    AddLight,
    RemoveLight,
}

const EDITS: [Edit; 4] = [
    Edit::Recolour,
    Edit::Move,
    Edit::AddLight,
    Edit::RemoveLight,
];

fn named(world: &mut World, name: &str) -> Entity {
    let mut query = world.query::<(Entity, &Name)>();
    query
        .iter(world)
        .find(|(_, n)| n.as_str() == name)
        .map(|(e, _)| e)
        .unwrap_or_else(|| panic!("no entity named {name:?}"))
}

fn apply(world: &mut World, edit: Edit) {
    match edit {
        Edit::Recolour => common::recolour_red_wall(world),
        Edit::Move => {
            let block = named(world, "tall block");
            world.get_mut::<Transform>(block).unwrap().translation += Vec3::new(-0.05, 0.15, 0.08);
        }
        Edit::AddLight => {
            world.spawn((
                Name::new("added light"),
                Light {
                    kind: LightKind::Point,
                    color: Vec3::new(0.3, 0.5, 1.0),
                    intensity: 0.1,
                    range: None,
                },
                Transform::from_translation(Vec3::new(0.15, 0.45, 0.15)),
            ));
        }
        Edit::RemoveLight => {
            let light = named(world, "added light");
            world.despawn(light);
        }
    }
}

/// The Cornell box with `edits` applied before anything was rendered.
fn scene(edits: &[Edit]) -> World {
    let mut world = World::new();
    load_scene(&mut world, "builtin:cornell").unwrap();
    for edit in edits {
        apply(&mut world, *edit);
    }
    world
}

fn settings(seed: u64) -> RenderSettings {
    RenderSettings {
        width: SIZE,
        height: SIZE,
        frames: FRAMES,
        seed,
        frame: FrameSettings {
            mode: RenderMode::Reference,
            spp: SPP,
            ..FrameSettings::default()
        },
    }
}

fn uploads(world: &World) -> (UploadStats, u64) {
    let scene = world.resource::<GpuScene>();
    (scene.last.clone(), scene.total.bytes)
}

/// Checks what the frame right after `edit` (and the one after it) uploaded and built.
fn check_edit_counters(edit: Edit, first: &UploadStats, second: &UploadStats, bvh: [&BvhStats; 2]) {
    let [before, after] = bvh;
    let material = size_of::<GpuMaterial>() as u64;
    match edit {
        Edit::Recolour => {
            assert_eq!(first.written(), ["scene materials"], "{first:?}");
            assert_eq!(first.bytes, material, "one material record: {first:?}");
        }
        Edit::Move => {
            assert_eq!(
                first.written(),
                [
                    "scene instance texels",
                    "scene instances",
                    "scene tlas nodes"
                ],
                "{first:?}"
            );
            // The moved instance's record, in the shading passes' buffer and in the
            // traversal's texel array.
            for copy in ["scene instances", "scene instance texels"] {
                assert_eq!(
                    first.bytes_of(copy),
                    size_of::<GpuInstance>() as u64,
                    "{copy}"
                );
            }
            assert_eq!(second.written(), ["scene instance extras"], "{second:?}");
            assert_eq!(second.bytes, 64, "one previous transform: {second:?}");
        }
        Edit::AddLight | Edit::RemoveLight => {
            let mut written = first.written();
            written.retain(|b| *b != "scene lights");
            assert_eq!(written, ["scene info"], "{first:?}");
        }
    }
    if edit != Edit::Move {
        assert_eq!(
            second.bytes, 0,
            "{edit:?}: the frame after wrote {second:?}"
        );
    }
    assert_eq!(
        after.blas_builds, before.blas_builds,
        "{edit:?}: BLAS built"
    );
    assert_eq!(
        after.tlas_builds, before.tlas_builds,
        "{edit:?}: TLAS rebuilt"
    );
    let updates = u64::from(edit == Edit::Move);
    assert_eq!(
        after.tlas_updates - before.tlas_updates,
        updates,
        "{edit:?}"
    );
}

#[test]
fn edits_through_ecs_converge_and_upload_only_what_changed() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let live_settings = settings(1);
    let mut world = scene(&[]);
    let mut before = renderer.render(&mut world, &live_settings).unwrap();
    assert_eq!(
        uploads(&world).0.bytes,
        0,
        "a frame without edits writes nothing"
    );

    // The edits, in place, one after another.
    let mut edited: Vec<(RenderOutput, RenderOutput)> = Vec::new();
    for edit in EDITS {
        let bvh_before = world.resource::<BvhStats>().clone();
        apply(&mut world, edit);
        renderer.accumulate(&mut world, &live_settings, 1).unwrap();
        let (first, _) = uploads(&world);
        renderer.accumulate(&mut world, &live_settings, 1).unwrap();
        let (second, total) = uploads(&world);
        check_edit_counters(
            edit,
            &first,
            &second,
            [&bvh_before, world.resource::<BvhStats>()],
        );
        renderer
            .accumulate(&mut world, &live_settings, FRAMES - 2)
            .unwrap();
        assert_eq!(
            uploads(&world).1,
            total,
            "{edit:?}: frames without edits wrote"
        );
        let image = renderer.read(&live_settings).unwrap();
        // The mean restarts once, at the edit: the previous transforms that catch up the frame
        // after a move feed motion vectors only and do not restart it again.
        assert_eq!(image.frames, FRAMES, "{edit:?}: {} frames", image.frames);
        edited.push((before, image.clone()));
        before = image;
    }

    // Fresh references of the edited scenes, each a new World with its edits from the start.
    let reference_settings = RenderSettings {
        frames: REFERENCE_FRAMES,
        ..settings(2)
    };
    let mut references = Vec::new();
    for k in 0..3 {
        let mut fresh = scene(&EDITS[..=k]);
        references.push(renderer.render(&mut fresh, &reference_settings).unwrap());
    }
    // Removing the light leaves the scene as it was before the light came.
    references.push(references[1].clone());

    let mut measured = Vec::new();
    for ((edit, (before, after)), reference) in EDITS.iter().zip(&edited).zip(&references) {
        assert!(after.hdr.iter().all(|p| p.is_finite()), "{edit:?}");
        let converged = common::rel_mse(&after.hdr, &reference.hdr);
        let changed = common::rel_mse(&before.hdr, &reference.hdr);
        eprintln!(
            "{edit:?}: relMSE to the fresh reference {converged:.3e}, before the edit {changed:.3e}"
        );
        measured.push((edit, converged, changed));
    }
    for (edit, converged, changed) in measured {
        assert!(converged < CONVERGED, "{edit:?}: {converged}");
        assert!(changed > CHANGED, "{edit:?}: {changed}");
    }
}
