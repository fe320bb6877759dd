//! [`SceneBvh`]: every mesh's BLAS and the TLAS over the instances, and the ray queries.

use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};

use bevy_ecs::prelude::*;
use bevy_ecs::system::RunSystemOnce;
use chiaro_scene::{
    Aabb, GlobalTransform, Mesh, MeshId, MeshInstance, Meshes, propagate_transforms,
};
use glam::{Affine3A, Vec2, Vec3};

use crate::blas::{Blas, Candidate};
use crate::instance::{InstanceBounds, InstanceRecord, InstanceRejection};
use crate::object_ray::ObjectRay;
use crate::query::CandidateHits;
use crate::ray::{Hit, Ray};
use crate::tlas::Tlas;

/// The scene's ray-tracing acceleration structure: a BLAS per mesh (shared by all its instances)
/// and a TLAS over the instances.
///
/// Build it once with [`SceneBvh::build`], or keep it current every frame with
/// [`crate::update_scene_bvh`], which rebuilds only what changed. Queries take `&self` and the
/// type is `Sync`: trace from as many threads as you like.
#[derive(Resource, Default, Debug)]
pub struct SceneBvh {
    /// BLAS of each mesh id (by index); `None` until built.
    pub(crate) blases: Vec<Option<Blas>>,
    pub(crate) instances: Vec<InstanceRecord>,
    pub(crate) bounds: Vec<InstanceBounds>,
    pub(crate) tlas: Tlas,
    /// Instance index of each entity in the TLAS.
    pub(crate) index_of: HashMap<Entity, u32>,
    /// Entities with a `MeshInstance` left out of the TLAS, and why.
    pub(crate) left_out: HashMap<Entity, InstanceRejection>,
}

impl SceneBvh {
    /// Builds the BVH of `world` as it is now: propagates transforms (runs
    /// [`propagate_transforms`]), builds a BLAS for every mesh in [`Meshes`], and the TLAS over
    /// every entity with a [`MeshInstance`]. Instances that cannot be traced (see
    /// [`InstanceRejection`]) are left out with a logged warning.
    pub fn build(world: &mut World) -> Self {
        if let Err(e) = world.run_system_once(propagate_transforms) {
            log::error!("propagating transforms before the BVH build failed: {e}");
        }
        let mut bvh = Self::default();
        if let Some(meshes) = world.get_resource::<Meshes>() {
            bvh.sync_blases(meshes);
        }
        let mut query = world.query::<(Entity, &MeshInstance, &GlobalTransform)>();
        let items = query
            .iter(world)
            .map(|(e, mi, gt)| (e, *mi, gt.0))
            .collect();
        bvh.rebuild_instances(items);
        bvh
    }

    /// Brings the BLASes in line with `meshes`: builds one for every mesh without, rebuilds those
    /// whose mesh no longer matches their fingerprint, drops those of ids past the end. Returns
    /// how many were built and whether any existing one was replaced or dropped (the TLAS must
    /// then be rebuilt).
    pub(crate) fn sync_blases(&mut self, meshes: &Meshes) -> (u64, bool) {
        let mut replaced = false;
        if self.blases.len() > meshes.len() {
            self.blases.truncate(meshes.len());
            replaced = true;
        }
        self.blases.resize_with(meshes.len(), || None);
        let mut todo = Vec::new();
        for (id, mesh) in meshes.iter() {
            match &self.blases[id.0 as usize] {
                None => todo.push((id, mesh)),
                Some(b) if b.fingerprint() != Blas::fingerprint_of(mesh) => {
                    replaced = true;
                    todo.push((id, mesh));
                }
                Some(_) => {}
            }
        }
        for (id, blas) in build_blases(&todo) {
            self.blases[id.0 as usize] = Some(blas);
        }
        (todo.len() as u64, replaced)
    }

    /// The BLAS of `mesh`, if built.
    pub fn blas(&self, mesh: MeshId) -> Option<&Blas> {
        self.blases.get(mesh.0 as usize)?.as_ref()
    }

    /// Every built BLAS with its mesh id.
    pub fn blases(&self) -> impl Iterator<Item = (MeshId, &Blas)> {
        self.blases
            .iter()
            .enumerate()
            .filter_map(|(i, b)| Some((MeshId(i as u32), b.as_ref()?)))
    }

    /// The instances in the TLAS; [`Hit::instance`] indexes this slice. Sorted by entity.
    pub fn instances(&self) -> &[InstanceRecord] {
        &self.instances
    }

    /// The instance index of `entity`, if it is in the TLAS.
    pub fn instance_of(&self, entity: Entity) -> Option<u32> {
        self.index_of.get(&entity).copied()
    }

    /// Entities with a [`MeshInstance`] that are not in the TLAS, and why.
    pub fn left_out(&self) -> impl Iterator<Item = (Entity, InstanceRejection)> + '_ {
        self.left_out.iter().map(|(e, r)| (*e, *r))
    }

    /// World bounds of all instances (each grown by its robustness pad); empty without any.
    pub fn bounds(&self) -> Aabb {
        self.bounds
            .iter()
            .fold(Aabb::EMPTY, |b, i| b.union(i.bounds))
    }

    /// Bytes of traversal data: every BLAS, the TLAS nodes and the instance records.
    pub fn memory_bytes(&self) -> usize {
        self.blases().map(|(_, b)| b.memory_bytes()).sum::<usize>()
            + std::mem::size_of_val(self.tlas.nodes.as_slice())
            + std::mem::size_of_val(self.instances.as_slice())
    }

    /// The nearest hit of `ray` in `(t_min, t_max)`, or `None` (also for an invalid ray, see
    /// [`Ray::is_valid`]).
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        self.nearest_accepted(ray, |_| true)
    }

    /// Like [`SceneBvh::closest_hit`], but a candidate hit for which `accept` returns false is
    /// ignored, as if the triangle had a hole there (alpha masking). `accept` is called only for
    /// candidates nearer than the best accepted so far, in no particular order.
    pub fn closest_hit_with(&self, ray: &Ray, accept: &dyn Fn(&Hit) -> bool) -> Option<Hit> {
        self.nearest_accepted(ray, accept)
    }

    /// True if anything is hit in `(t_min, t_max)` (an occlusion test); stops at the first
    /// occluder found, which need not be the nearest. False for an invalid ray.
    pub fn any_hit(&self, ray: &Ray) -> bool {
        self.any_accepted(ray, |_| true)
    }

    /// Like [`SceneBvh::any_hit`], but candidates that `accept` rejects do not occlude.
    pub fn any_hit_with(&self, ray: &Ray, accept: &dyn Fn(&Hit) -> bool) -> bool {
        self.any_accepted(ray, accept)
    }

    /// Traverses one instance's BLAS; returns true when `on_hit` stopped it.
    #[inline]
    fn trace_instance(
        &self,
        ray: &Ray,
        instance: u32,
        t_max: &mut f32,
        on_hit: &mut impl FnMut(Hit) -> Candidate,
    ) -> bool {
        let record = &self.instances[instance as usize];
        let Some(blas) = self.blas(record.mesh) else {
            return false;
        };
        let Some(object_ray) = ObjectRay::from_world(ray, &record.inverse) else {
            return false;
        };
        blas.traverse(&object_ray, ray.t_min, t_max, &mut |triangle, h| {
            on_hit(Hit {
                t: h.t,
                instance,
                triangle,
                barycentrics: Vec2::new(h.b1, h.b2),
            })
        })
    }

    /// The world-space vertices of `triangle` of instance `instance`.
    pub fn world_triangle(&self, instance: u32, triangle: u32) -> Option<[Vec3; 3]> {
        let record = self.instances.get(instance as usize)?;
        let v = self.blas(record.mesh)?.triangle(triangle)?;
        Some(v.map(|p| record.world.transform_point3(p)))
    }

    /// The world-space point of `hit`, interpolated from the triangle's vertices with its
    /// barycentrics. Prefer it to `ray.at(hit.t)` as the base of [`crate::offset_ray_origin`]:
    /// its error is relative to the point's own coordinates, not to the ray's length.
    pub fn hit_point(&self, hit: &Hit) -> Option<Vec3> {
        let record = self.instances.get(hit.instance as usize)?;
        let [a, b, c] = self.blas(record.mesh)?.triangle(hit.triangle)?;
        let w = hit.weights();
        Some(record.world.transform_point3(a * w.x + b * w.y + c * w.z))
    }

    /// The unit world-space geometric normal of `hit`'s triangle, on the side of its
    /// counter-clockwise front face (`(v1 - v0) x (v2 - v0)` in world space).
    pub fn geometric_normal(&self, hit: &Hit) -> Option<Vec3> {
        let [a, b, c] = self.world_triangle(hit.instance, hit.triangle)?;
        (b - a).cross(c - a).try_normalize()
    }

    /// Rebuilds the TLAS tree over the current instances (same records and indices, fresh
    /// binned-SAH tree), as [`crate::update_scene_bvh`] does when updates have degraded it.
    pub fn rebuild_tlas(&mut self) {
        self.tlas = Tlas::build(&self.bounds);
    }

    /// SAH cost of the TLAS: summed inner-node area over the root's (the expected number of
    /// inner nodes a ray through the root visits). Updates that degrade the tree raise it.
    pub fn tlas_cost(&self) -> f64 {
        self.tlas.cost()
    }

    /// Rebuilds the TLAS over `items` (entity, instance, world matrix), re-checking each.
    pub(crate) fn rebuild_instances(&mut self, mut items: Vec<(Entity, MeshInstance, Affine3A)>) {
        items.sort_by_key(|(e, _, _)| *e);
        let previous = std::mem::take(&mut self.left_out);
        self.instances.clear();
        self.bounds.clear();
        self.index_of.clear();
        for (entity, mi, world) in items {
            let blas = self.blas(mi.mesh);
            match crate::instance::prepare_instance(entity, mi.mesh, mi.material, world, blas) {
                Ok((record, bounds)) => {
                    self.index_of.insert(entity, self.instances.len() as u32);
                    self.instances.push(record);
                    self.bounds.push(bounds);
                }
                Err(why) => {
                    if previous.get(&entity) != Some(&why) {
                        log::warn!("instance {entity} left out of the BVH: {why}");
                    }
                    self.left_out.insert(entity, why);
                }
            }
        }
        self.tlas = Tlas::build(&self.bounds);
    }
}

impl CandidateHits for SceneBvh {
    fn offer(&self, ray: &Ray, on_hit: &mut impl FnMut(Hit) -> Candidate) -> bool {
        if !ray.is_valid() || ray.t_min >= ray.t_max {
            return false;
        }
        let mut t_max = ray.t_max;
        self.tlas.traverse(ray, &mut t_max, &mut |instance, t_max| {
            self.trace_instance(ray, instance, t_max, on_hit)
        })
    }
}

/// Builds the BLASes of `meshes`, on as many threads as there are cores when there is more
/// than one mesh (each BLAS build is single-threaded).
fn build_blases(meshes: &[(MeshId, &Mesh)]) -> Vec<(MeshId, Blas)> {
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(meshes.len());
    if threads <= 1 {
        return meshes.iter().map(|(id, m)| (*id, Blas::build(m))).collect();
    }
    // Largest first, handed out one at a time, so a big mesh does not finish last alone.
    let mut order: Vec<usize> = (0..meshes.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(meshes[i].1.triangle_count()));
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut built = Vec::new();
                    while let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
                        let (id, mesh) = meshes[i];
                        built.push((id, Blas::build(mesh)));
                    }
                    built
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a BLAS build panicked"))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_bvh_is_send_and_sync() {
        fn check<T: Send + Sync>() {}
        check::<SceneBvh>();
    }

    #[test]
    fn cornell_box_is_closed_from_inside() {
        let mut world = World::new();
        chiaro_scene::load_scene(&mut world, "builtin:cornell").unwrap();
        let bvh = SceneBvh::build(&mut world);
        let center = bvh.bounds().center();
        let mut hits = 0;
        for i in 0..200 {
            let a = i as f32 * 0.731;
            let dir = Vec3::new(a.cos(), (a * 1.7).sin(), a.sin());
            let hit = bvh.closest_hit(&Ray::new(center, dir));
            // The camera wall of the Cornell box is open: rays toward it may escape.
            hits += usize::from(hit.is_some());
            if let Some(h) = hit {
                let p = bvh.hit_point(&h).unwrap();
                assert!((p - (center + dir * h.t)).length() < 1e-3);
            }
        }
        assert!(hits > 100, "{hits}");
    }
}
