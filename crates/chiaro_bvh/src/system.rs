//! The ECS side: [`update_scene_bvh`] keeps the [`SceneBvh`] resource in step with the World,
//! doing only the work that changes call for, and counts it in [`BvhStats`].

use std::time::Instant;

use bevy_ecs::prelude::*;
use chiaro_scene::{GlobalTransform, MeshInstance, Meshes, propagate_transforms};

use crate::scene_bvh::SceneBvh;
use crate::update::{InstanceItem, TlasWork};

/// What the BVH systems have done, cumulatively, and how the scene stands.
#[derive(Resource, Default, Debug, Clone, PartialEq)]
pub struct BvhStats {
    /// BLASes built (one per mesh id, ever).
    pub blas_builds: u64,
    /// Full TLAS builds (instances added or removed, a moved instance's mesh or validity
    /// changed, or updates degraded the tree).
    pub tlas_builds: u64,
    /// In-place TLAS updates (instances moved or their `MeshInstance` edited: re-insertion, or
    /// one refit pass when more than an eighth moved).
    pub tlas_updates: u64,
    /// Instances in the TLAS after the last change.
    pub instances: u64,
    /// Entities with a `MeshInstance` left out of the TLAS after the last change (see
    /// [`crate::InstanceRejection`]); their warnings are logged once per reason.
    pub left_out_instances: u64,
    /// Wall-clock seconds the last run that did any work took.
    pub last_work_seconds: f64,
}

/// Keeps [`SceneBvh`] current; run it after [`propagate_transforms`] (see [`add_bvh_systems`]).
///
/// - When [`Meshes`] changed, builds a BLAS for each mesh id that has none yet, and rebuilds
///   the BLAS of a mesh that no longer matches it (a replaced `Meshes` store, or a mesh replaced
///   in place; see [`crate::Blas::fingerprint`] for what is compared), then rebuilds the TLAS.
/// - When an instance was added or removed, or became traceable or untraceable, rebuilds the
///   TLAS; when instances only moved (`Changed<GlobalTransform>`) or had their `MeshInstance`
///   edited, updates records and re-inserts the moved ones (or refits, when many moved).
/// - When nothing changed, does nothing and counts nothing.
///
/// Creates the [`SceneBvh`] and [`BvhStats`] resources (through `Commands`) when they are
/// missing, building everything in that first run.
#[allow(clippy::type_complexity)]
pub fn update_scene_bvh(
    mut commands: Commands,
    bvh: Option<ResMut<SceneBvh>>,
    stats: Option<ResMut<BvhStats>>,
    meshes: Option<Res<Meshes>>,
    changed: Query<
        (Entity, &MeshInstance, &GlobalTransform),
        Or<(Changed<GlobalTransform>, Changed<MeshInstance>)>,
    >,
    all: Query<(Entity, &MeshInstance, &GlobalTransform)>,
    mut removed: RemovedComponents<MeshInstance>,
) {
    let start = Instant::now();
    let item =
        |(e, mi, gt): (Entity, &MeshInstance, &GlobalTransform)| -> InstanceItem { (e, *mi, gt.0) };
    let fresh = bvh.is_none();
    let mut bvh = bvh;
    let mut created = SceneBvh::default();
    let target: &mut SceneBvh = match bvh.as_mut() {
        Some(b) => b.bypass_change_detection(),
        None => &mut created,
    };

    let (built, replaced) = match &meshes {
        Some(m) if fresh || m.is_changed() => target.sync_blases(m),
        _ => (0, false),
    };
    let removed: Vec<Entity> = removed.read().filter(|e| !all.contains(*e)).collect();
    let work = if fresh || replaced {
        target.rebuild_instances(all.iter().map(item).collect());
        TlasWork::Rebuilt
    } else {
        let changed = changed.iter().map(item).collect();
        target.apply_changes(changed, removed, built > 0, || {
            all.iter().map(item).collect()
        })
    };

    let did_work = built > 0 || work != TlasWork::None;
    let instances = target.instances().len() as u64;
    let left_out = target.left_out.len() as u64;
    if let Some(b) = bvh.as_mut()
        && did_work
    {
        b.set_changed();
    }
    if fresh {
        commands.insert_resource(created);
    }
    let mut created_stats = BvhStats::default();
    let mut stats = stats;
    let s: &mut BvhStats = match stats.as_mut() {
        Some(s) => s.bypass_change_detection(),
        None => &mut created_stats,
    };
    let before = s.clone();
    s.blas_builds += built;
    match work {
        TlasWork::None => {}
        TlasWork::Updated => s.tlas_updates += 1,
        TlasWork::Rebuilt => s.tlas_builds += 1,
    }
    if did_work {
        s.last_work_seconds = start.elapsed().as_secs_f64();
    }
    // Gauges: kept current even when no work was done (an instance left out on arrival).
    s.instances = instances;
    s.left_out_instances = left_out;
    let stats_changed = *s != before;
    match stats.as_mut() {
        Some(s) if stats_changed => s.set_changed(),
        Some(_) => {}
        None => commands.insert_resource(created_stats),
    }
}

/// Adds [`propagate_transforms`] and then [`update_scene_bvh`] to `schedule`.
pub fn add_bvh_systems(schedule: &mut Schedule) {
    schedule.add_systems((propagate_transforms, update_scene_bvh).chain());
}
