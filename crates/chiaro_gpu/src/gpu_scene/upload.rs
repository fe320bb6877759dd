//! [`upload_gpu_scene`]: the system that keeps [`GpuScene`] in step with the world, rebuilding
//! on the CPU only the tables whose sources changed and writing only their differing ranges.

use bevy_ecs::prelude::*;
use chiaro_bvh::{GpuBvhBuffers, SceneBvh, TlasNode};
use chiaro_scene::{Environment, GlobalTransform, Light, Materials, Meshes, Textures};
use rayon::prelude::*;

use super::layout::{self, GpuInstanceExtra};
use super::light_trees::{self, FlatTree};
use super::{GpuScene, UploadStats, back_faces, gather, raster};

/// Writes `$data` into the mirror `$field`, noting a reallocation.
macro_rules! put {
    ($scene:ident, $stats:ident, $realloc:ident, $field:ident, $data:expr) => {{
        let (d, q) = ($scene.device.clone(), $scene.queue.clone());
        $realloc |= $scene.$field.update(&d, &q, $data, &mut $stats);
    }};
}

/// Writes `$data` into the texel array `$field`, noting a reallocation; an array too large for
/// the device keeps its old contents and reports it ([`GpuScene::overflow`]).
macro_rules! put_texels {
    ($scene:ident, $stats:ident, $realloc:ident, $field:ident, $data:expr) => {{
        let (d, q) = ($scene.device.clone(), $scene.queue.clone());
        $realloc |= $scene
            .$field
            .update(&d, &q, $data, &mut $stats)
            .unwrap_or(false);
    }};
}

/// Brings [`GpuScene`] in step with the world: each buffer whose source changed is rebuilt on
/// the CPU and only its differing ranges are written; [`GpuScene::last`] counts what this run
/// wrote. Runs after `chiaro_bvh::update_scene_bvh` (see
/// [`add_gpu_scene_systems`](super::add_gpu_scene_systems)).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn upload_gpu_scene(
    scene: Option<ResMut<GpuScene>>,
    bvh: Option<Res<SceneBvh>>,
    meshes: Option<Res<Meshes>>,
    materials: Option<Res<Materials>>,
    textures: Option<Res<Textures>>,
    environment: Option<Res<Environment>>,
    lights: Query<(&Light, &GlobalTransform)>,
    changed_lights: Query<(), (With<Light>, Or<(Changed<Light>, Changed<GlobalTransform>)>)>,
    mut removed_lights: RemovedComponents<Light>,
) {
    let (Some(mut scene), Some(bvh)) = (scene, bvh) else {
        return;
    };
    let start = std::time::Instant::now();
    let scene = scene.bypass_change_detection();
    let fresh = !scene.uploaded;
    let mut stats = UploadStats::default();
    let mut realloc = fresh;
    let default_env = Environment::default();
    let environment_ref = environment.as_deref().unwrap_or(&default_env);
    let empty_meshes = Meshes::default();
    let meshes_ref = meshes.as_deref().unwrap_or(&empty_meshes);
    let empty_materials = Materials::default();
    let materials_ref = materials.as_deref().unwrap_or(&empty_materials);

    let bvh_changed = fresh || bvh.is_changed();
    if bvh_changed {
        // Instances that only moved leave the BLAS part as it was: not gathered again.
        let placement = GpuBvhBuffers::blas_placement(&bvh);
        let blases_changed = fresh || placement != scene.blas_placement;
        let mut flat = if blases_changed {
            GpuBvhBuffers::from_scene(&bvh)
        } else {
            GpuBvhBuffers::without_blases(&bvh)
        };
        if flat.tlas_nodes.is_empty() {
            flat.tlas_nodes.push(TlasNode {
                child: chiaro_bvh::TLAS_LEAF_BIT | 0x7fff_ffff,
                ..TlasNode::default()
            });
        }
        if blases_changed {
            put_texels!(scene, stats, realloc, blas_nodes, &flat.blas_nodes);
            put_texels!(scene, stats, realloc, triangles, &flat.triangles);
            scene.blas_placement = placement;
        }
        put_texels!(scene, stats, realloc, tlas_nodes, &flat.tlas_nodes);
        put_texels!(scene, stats, realloc, instance_texels, &flat.instances);
        put!(scene, stats, realloc, instances, &flat.instances);
        scene.mesh_runs = gather::mesh_runs(flat.instances.iter().map(|i| i.mesh));
    }
    let meshes_changed = fresh || meshes.as_ref().is_some_and(|m| m.is_changed());
    if meshes_changed {
        let (vertices, indices, table) = gather::meshes(meshes_ref);
        let (raster_scene_vertices, raster_indices) =
            raster::raster_lists(&indices, vertices.len(), &table);
        let raster_vertices = raster::raster_vertices(
            (&raster_scene_vertices, &raster_indices),
            &indices,
            &table,
            &vertices,
        );
        put_texels!(scene, stats, realloc, vertices, &vertices);
        put_texels!(
            scene,
            stats,
            realloc,
            indices,
            &gather::four_to_a_texel(&indices)
        );
        put!(scene, stats, realloc, raster_vertices, &raster_vertices);
        put!(scene, stats, realloc, raster_indices, &raster_indices);
        put!(scene, stats, realloc, meshes, &table);
        let all: Vec<&chiaro_scene::Mesh> = meshes_ref.iter().map(|(_, mesh)| mesh).collect();
        scene.closed_bounds = all
            .par_iter()
            .map(|mesh| back_faces::closed_bounds(mesh.positions(), mesh.indices()))
            .collect();
    }
    let materials_changed = fresh || materials.as_ref().is_some_and(|m| m.is_changed());
    if materials_changed {
        put_texels!(
            scene,
            stats,
            realloc,
            materials,
            &gather::materials(materials_ref)
        );
    }
    if bvh_changed || meshes_changed || materials_changed {
        let materials = scene.materials.contents();
        let boxes = scene.instances.contents().iter().map(|instance| {
            // A mask's holes and a blend's coverage show the back faces behind.
            let see_through = layout::MATERIAL_ALPHA_MASK | layout::MATERIAL_ALPHA_BLEND;
            let alpha_masked = materials
                .get(instance.material as usize)
                .is_none_or(|material| material.flags & see_through != 0);
            let bounds = scene
                .closed_bounds
                .get(instance.mesh as usize)
                .copied()
                .flatten();
            back_faces::cullable_box(bounds, &instance.object_to_world, alpha_masked)
        });
        scene.cullable_boxes = boxes.collect();
    }
    let textures_changed = fresh || textures.as_ref().is_some_and(|t| t.is_changed());
    if textures_changed {
        let (texels, table) = textures
            .as_deref()
            .map(gather::textures)
            .unwrap_or_default();
        put!(scene, stats, realloc, texels, &texels);
        put!(scene, stats, realloc, textures, &table);
    }
    let env_changed = fresh || environment.as_ref().is_some_and(|e| e.is_changed());
    let mut info = scene.info;
    if env_changed {
        let (texels, table) = gather::environment(environment_ref, &mut info);
        put_texels!(scene, stats, realloc, env_texels, &texels);
        put_texels!(scene, stats, realloc, env_table, &table);
    }
    let lights_edited = fresh || !changed_lights.is_empty() || removed_lights.read().count() > 0;
    // The table also follows the scene's radius (a directional light's power); the tree, only
    // the lights themselves.
    let lights_changed = lights_edited || bvh_changed;
    if lights_changed {
        let radius = gather::scene_radius(&bvh);
        let (table, bounds, directional_share) = gather::lights(lights.iter(), radius);
        // A radius of 0 leaves directional lights out of the table: its indices then move.
        let reindexed = table.len() as u32 != info.light_count;
        info.light_count = table.len() as u32;
        info.directional_share = directional_share;
        if lights_edited || reindexed {
            scene.punctual_tree = if table.len() > layout::ALL_PUNCTUAL_LIGHTS_MAX as usize {
                FlatTree::build(&bounds)
            } else {
                FlatTree::default()
            };
        }
        put_texels!(scene, stats, realloc, lights, &table);
    }
    let area_changed = bvh_changed || materials_changed || env_changed;
    if area_changed {
        let (table, first, env_pmf, bounds) =
            gather::area_lights(&bvh, meshes_ref, materials_ref, environment_ref);
        info.area_count = table.len() as u32;
        info.env_pmf = env_pmf;
        scene.area_first = first;
        scene.area_tree = if bounds.len() > layout::AREA_LIGHTS_BY_POWER_MAX {
            let bounds: Vec<_> = bounds.into_iter().map(Some).collect();
            FlatTree::build(&bounds)
        } else {
            FlatTree::default()
        };
        put_texels!(scene, stats, realloc, area_lights, &table);
    }
    if fresh || lights_changed || area_changed {
        let (nodes, area_root, punctual_root) =
            light_trees::combine(&scene.area_tree, &scene.punctual_tree);
        info.area_tree = area_root;
        info.punctual_tree = punctual_root;
        info.area_leaves = scene.area_tree.leaf(0);
        put_texels!(scene, stats, realloc, light_tree, &nodes);
    }
    // The per-instance extras change when the BVH or the area lights do, and once more the
    // frame after an instance moved (its previous transform catches up); otherwise this
    // per-frame system does no per-instance work.
    scene.content_changed =
        bvh_changed || meshes_changed || textures_changed || lights_changed || area_changed;
    if area_changed || scene.motion_pending {
        write_instance_extras(scene, bvh_changed, &mut stats, &mut realloc);
        scene.motion_pending = bvh_changed;
    }
    info.instance_count = scene.instances.contents().len() as u32;
    scene.info = info;
    put!(scene, stats, realloc, info_buffer, &[info]);

    if realloc {
        scene.remake_bind_group();
    }
    scene.uploaded = true;
    scene.total.bytes += stats.bytes;
    scene.total.writes += stats.writes;
    scene.total.allocations += stats.allocations;
    for (label, bytes) in &stats.per_buffer {
        *scene.total.per_buffer.entry(label).or_default() += bytes;
    }
    scene.last = stats;
    scene.last_seconds = start.elapsed().as_secs_f64();
}

/// Rebuilds the per-instance extras: the previous frame's transforms (what was current at the
/// last rebuild), the area-light table offsets and the mirroring flags.
fn write_instance_extras(
    scene: &mut GpuScene,
    bvh_changed: bool,
    stats: &mut UploadStats,
    realloc: &mut bool,
) {
    let previous = std::mem::take(&mut scene.current_transforms);
    scene.current_transforms = if bvh_changed {
        scene
            .instances
            .contents()
            .iter()
            .map(|i| i.object_to_world)
            .collect()
    } else {
        previous.clone()
    };
    let extras: Vec<GpuInstanceExtra> = scene
        .instances
        .contents()
        .iter()
        .enumerate()
        .map(|(i, inst)| {
            let m = inst.object_to_world;
            let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
            GpuInstanceExtra {
                previous_object_to_world: previous.get(i).copied().unwrap_or(m),
                area_first: scene.area_first.get(i).copied().unwrap_or(layout::NO_INDEX),
                mirrored: u32::from(det < 0.0),
                pad0: 0,
                pad1: 0,
            }
        })
        .collect();
    let (d, q) = (scene.device.clone(), scene.queue.clone());
    *realloc |= scene.instance_extras.update(&d, &q, &extras, stats);
}
