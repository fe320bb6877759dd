//! Applying instance changes to a [`SceneBvh`]: re-insert or refit what moved, rebuild the TLAS
//! only when its membership changed or updates have degraded it.

use bevy_ecs::entity::Entity;
use chiaro_scene::MeshInstance;
use glam::Affine3A;

use crate::instance::{InstanceRejection, prepare_instance};
use crate::scene_bvh::SceneBvh;
use crate::tlas::Tlas;

/// An instance as the ECS has it: entity, what it draws, its world matrix.
pub(crate) type InstanceItem = (Entity, MeshInstance, Affine3A);

/// What [`SceneBvh::apply_changes`] did to the TLAS.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TlasWork {
    /// Nothing.
    None,
    /// Records or boxes were updated in place (re-insertion or refit).
    Updated,
    /// The TLAS was rebuilt.
    Rebuilt,
}

impl SceneBvh {
    /// Applies `changed` instances (added, moved or edited) and `removed` entities (which no
    /// longer have a `MeshInstance`). `new_blases` says BLASes were just built, which may let
    /// left-out instances in. `all` lists every instance; it is called only for a rebuild.
    pub(crate) fn apply_changes(
        &mut self,
        changed: Vec<InstanceItem>,
        removed: Vec<Entity>,
        new_blases: bool,
        all: impl FnOnce() -> Vec<InstanceItem>,
    ) -> TlasWork {
        let mut rebuild = false;
        for entity in removed {
            rebuild |= self.index_of.contains_key(&entity);
            self.left_out.remove(&entity);
        }
        if new_blases {
            rebuild |= self.left_out.values().any(|why| match why {
                InstanceRejection::MissingMesh(mesh) => {
                    self.blas(*mesh).is_some_and(|b| b.triangle_count() > 0)
                }
                _ => false,
            });
        }
        let mut moved = Vec::new();
        let mut edited = false;
        for (entity, mi, world) in changed {
            if rebuild {
                break;
            }
            let prepared =
                prepare_instance(entity, mi.mesh, mi.material, world, self.blas(mi.mesh));
            match (self.index_of.get(&entity).copied(), prepared) {
                (Some(index), Ok((record, bounds))) => {
                    let i = index as usize;
                    if self.bounds[i] != bounds {
                        self.bounds[i] = bounds;
                        moved.push(index);
                    }
                    if self.instances[i] != record {
                        self.instances[i] = record;
                        edited = true;
                    }
                }
                // In the TLAS but no longer traceable, or newly traceable, or new.
                (Some(_), Err(_)) | (None, Ok(_)) => rebuild = true,
                (None, Err(why)) => {
                    if self.left_out.get(&entity) != Some(&why) {
                        log::warn!("instance {entity} left out of the BVH: {why}");
                    }
                    self.left_out.insert(entity, why);
                }
            }
        }
        if rebuild {
            self.rebuild_instances(all());
            return TlasWork::Rebuilt;
        }
        if moved.is_empty() {
            return if edited {
                TlasWork::Updated
            } else {
                TlasWork::None
            };
        }
        if moved.len() > self.instances.len() / 8 {
            self.tlas.refit_all(&self.bounds);
        } else {
            for index in moved {
                self.tlas
                    .reinsert_instance(index, &self.bounds[index as usize]);
            }
        }
        if self.tlas.degraded() {
            self.tlas = Tlas::build(&self.bounds);
            return TlasWork::Rebuilt;
        }
        TlasWork::Updated
    }
}
