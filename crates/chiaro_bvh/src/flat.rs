//! [`FlatBvh`]: every instance of a scene that will not change under one BVH, for a renderer
//! that traces many rays through a still scene (the CPU reference).
//!
//! [`SceneBvh`] traverses a TLAS and, for each instance a ray's box test lets through, carries
//! the ray into the instance's object space and prepares it for that BLAS; where instance boxes
//! overlap (the Cornell box's walls and blocks: 8 instances, 32 triangles) a ray pays that
//! several times. Here a ray is prepared once and meets one tree. Hits are reported in the scene's terms (instance index and the triangle's
//! index in its mesh, barycentrics in the mesh's vertex order).
//!
//! Measured with `chiaro reference builtin:NAME --size 128x128 --spp 32`, three seeds, 2-core VM,
//! paths a second through the TLAS against flattened (means): Cornell 0.64 M -> 0.78 M (+21%),
//! door +24%, caustic +40%, lamp +14%; many-lights (273 instances) and the walkthrough (151
//! instances, 1.3 million triangles) within the runs' 10% spread either way. Where flattening
//! does not pay, the scene keeps the TLAS ([`FlatBvh::build`] returns `None`):
//! - **instancing**: more than [`FLAT_MAX_INSTANCING`] times the triangles its meshes store.
//!   Flattening multiplies memory there, and 1025 instanced cubes traced 19% fewer paths a
//!   second flattened;
//! - **a far outlier**: the scene's largest coordinate more than [`FLAT_MAX_SPREAD`] times the
//!   median instance's. Every box of one tree is padded by 16 ulps of its largest coordinate
//!   ([`crate::slab`]); `builtin:hard-cases`, with one copy 1e5 units away, traced 21 times
//!   fewer paths flattened, its spheres' small triangles all inside each other's padded boxes.
//!
//! Instances with the identity matrix (object space is world space) give bit-identical hits;
//! others' vertices are carried to world space once, so their hits differ from [`SceneBvh`]'s
//! by that rounding (tested: the same triangle, `t` within 1e-4 relative).

use chiaro_scene::Aabb;
use glam::{Affine3A, Vec2};

use crate::blas::{Blas, Candidate};
use crate::layout::BvhTriangle;
use crate::object_ray::ObjectRay;
use crate::query::CandidateHits;
use crate::ray::{Hit, Ray};
use crate::scene_bvh::SceneBvh;

/// Most world-space triangles [`FlatBvh::build`] takes (48 bytes each plus about 40 bytes of
/// nodes): 2^21, about 180 MB.
pub const FLAT_MAX_TRIANGLES: usize = 1 << 21;

/// Most world-space triangles a flattened scene may have per triangle its meshes store.
pub const FLAT_MAX_INSTANCING: usize = 2;

/// Largest ratio of the scene's largest absolute coordinate to the median instance's that is
/// flattened (the box pad grows with the former).
pub const FLAT_MAX_SPREAD: f32 = 64.0;

/// A still scene's triangles in world space under one BVH (see the module docs).
#[derive(Clone, Debug)]
pub struct FlatBvh {
    blas: Blas,
    /// Instance and mesh triangle of each flat triangle index.
    origins: Vec<(u32, u32)>,
}

/// The largest absolute coordinate of `b` (0 when empty).
fn magnitude(b: Aabb) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    b.min.abs().max(b.max.abs()).max_element()
}

impl FlatBvh {
    /// Flattens `scene` as it is now; `None` when its instances hold more than
    /// `max_triangles` triangles in all, or where the TLAS serves it better (instancing, a far
    /// outlier: see the module docs). Triangles whose world-space vertices are not finite are
    /// left out.
    pub fn build(scene: &SceneBvh, max_triangles: usize) -> Option<Self> {
        let total: usize = scene
            .instances()
            .iter()
            .map(|r| scene.blas(r.mesh).map_or(0, Blas::triangle_count))
            .sum();
        let stored: usize = scene.blases().map(|(_, b)| b.triangle_count()).sum();
        if total > max_triangles || total > FLAT_MAX_INSTANCING * stored {
            return None;
        }
        let mut magnitudes: Vec<f32> = scene.bounds.iter().map(|b| magnitude(b.bounds)).collect();
        if !magnitudes.is_empty() {
            let middle = magnitudes.len() / 2;
            let median = *magnitudes.select_nth_unstable_by(middle, f32::total_cmp).1;
            if magnitude(scene.bounds()) > FLAT_MAX_SPREAD * median {
                return None;
            }
        }
        let mut triangles = Vec::with_capacity(total);
        let mut origins = Vec::with_capacity(total);
        for (instance, record) in scene.instances().iter().enumerate() {
            let Some(blas) = scene.blas(record.mesh) else {
                continue;
            };
            let identity = record.world == Affine3A::IDENTITY;
            for t in blas.triangles() {
                let v = if identity {
                    t.vertices()
                } else {
                    t.vertices().map(|p| record.world.transform_point3(p))
                };
                if v.iter().all(|p| p.is_finite()) {
                    triangles.push(BvhTriangle::new(v, origins.len() as u32));
                    origins.push((instance as u32, t.triangle));
                }
            }
        }
        let blas = Blas::from_triangles(&triangles, origins.len());
        Some(Self { blas, origins })
    }

    /// World-space triangles in the tree.
    pub fn triangle_count(&self) -> usize {
        self.origins.len()
    }

    /// The nearest hit of `ray`, as [`SceneBvh::closest_hit`].
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        self.nearest_accepted(ray, |_| true)
    }

    /// The nearest hit that `accept` takes, as [`SceneBvh::closest_hit_with`].
    pub fn closest_hit_with(&self, ray: &Ray, accept: &dyn Fn(&Hit) -> bool) -> Option<Hit> {
        self.nearest_accepted(ray, accept)
    }

    /// True if anything is hit, as [`SceneBvh::any_hit`].
    pub fn any_hit(&self, ray: &Ray) -> bool {
        self.any_accepted(ray, |_| true)
    }

    /// True if anything `accept` takes is hit, as [`SceneBvh::any_hit_with`].
    pub fn any_hit_with(&self, ray: &Ray, accept: &dyn Fn(&Hit) -> bool) -> bool {
        self.any_accepted(ray, accept)
    }
}

impl CandidateHits for FlatBvh {
    fn offer(&self, ray: &Ray, on_hit: &mut impl FnMut(Hit) -> Candidate) -> bool {
        if !ray.is_valid() || ray.t_min >= ray.t_max {
            return false;
        }
        let Some(world_ray) = ObjectRay::new(ray.origin, ray.direction) else {
            return false;
        };
        let mut t_max = ray.t_max;
        self.blas
            .traverse(&world_ray, ray.t_min, &mut t_max, &mut |flat, h| {
                let (instance, triangle) = self.origins[flat as usize];
                on_hit(Hit {
                    t: h.t,
                    instance,
                    triangle,
                    barycentrics: Vec2::new(h.b1, h.b2),
                })
            })
    }
}

#[cfg(test)]
mod tests {
    use bevy_ecs::prelude::*;
    use chiaro_scene::{MaterialId, Mesh, MeshInstance, Meshes, Transform};
    use glam::Vec3;

    use super::*;

    fn scene(name: &str) -> SceneBvh {
        let mut world = World::new();
        chiaro_scene::load_scene(&mut world, name).unwrap();
        SceneBvh::build(&mut world)
    }

    /// Rays from points spread over the scene's bounds in directions spread over the sphere.
    fn rays(bvh: &SceneBvh, count: usize) -> Vec<Ray> {
        let b = bvh.bounds();
        (0..count)
            .map(|i| {
                let f = |k: f32| (i as f32 * k).fract();
                let origin = b.min + (b.max - b.min) * Vec3::new(f(0.618), f(0.414), f(0.732));
                let z = 2.0 * f(0.5772) - 1.0;
                let phi = std::f32::consts::TAU * f(0.3071);
                let r = (1.0 - z * z).sqrt();
                Ray::new(origin, Vec3::new(r * phi.cos(), r * phi.sin(), z))
            })
            .collect()
    }

    #[test]
    fn identity_instances_give_the_scene_bvhs_hits_exactly() {
        let bvh = scene("builtin:cornell");
        let flat = FlatBvh::build(&bvh, FLAT_MAX_TRIANGLES).unwrap();
        assert_eq!(flat.triangle_count(), 32);
        let mut hits = 0;
        for ray in rays(&bvh, 4000) {
            let expected = bvh.closest_hit(&ray);
            assert_eq!(flat.closest_hit(&ray), expected, "{ray:?}");
            hits += usize::from(expected.is_some());
            let shadow = ray.with_interval(0.0, 0.3);
            assert_eq!(flat.any_hit(&shadow), bvh.any_hit(&shadow), "{shadow:?}");
        }
        assert!(hits > 2000, "{hits} of 4000 rays hit");
    }

    #[test]
    fn instancing_and_a_far_outlier_keep_the_tlas() {
        // 1025 instances of two meshes; five times the stored triangles, one copy 1e5 away.
        assert!(FlatBvh::build(&scene("builtin:instances"), FLAT_MAX_TRIANGLES).is_none());
        assert!(FlatBvh::build(&scene("builtin:hard-cases"), FLAT_MAX_TRIANGLES).is_none());
    }

    /// Three meshes of one sphere each (no instancing), two near the origin and one at `far`
    /// along X.
    fn spheres(far: f32) -> SceneBvh {
        let mut world = World::new();
        let mut meshes = Meshes::default();
        for (k, x) in [0.0, 3.0, far].into_iter().enumerate() {
            let data = chiaro_scene::builtin::shapes::icosphere(2, false);
            let mesh = meshes.add(Mesh::new(format!("ball {k}"), data).unwrap().0);
            world.spawn((
                MeshInstance {
                    mesh,
                    material: MaterialId(0),
                },
                Transform::from_translation(Vec3::new(x, 0.0, 0.0)),
            ));
        }
        world.insert_resource(meshes);
        SceneBvh::build(&mut world)
    }

    #[test]
    fn a_far_outlier_keeps_the_tlas() {
        // Median instance magnitude 4 (the sphere at 3, radius 1): 64 times that is 256.
        assert!(FlatBvh::build(&spheres(200.0), FLAT_MAX_TRIANGLES).is_some());
        assert!(FlatBvh::build(&spheres(300.0), FLAT_MAX_TRIANGLES).is_none());
    }

    #[test]
    fn transformed_instances_give_the_same_surfaces() {
        let bvh = scene("builtin:walkthrough");
        assert!(
            bvh.instances()
                .iter()
                .any(|r| r.world != Affine3A::IDENTITY)
        );
        let flat = FlatBvh::build(&bvh, FLAT_MAX_TRIANGLES).unwrap();
        let (mut same, mut hits) = (0, 0);
        for ray in rays(&bvh, 2000) {
            let expected = bvh.closest_hit(&ray);
            let got = flat.closest_hit(&ray);
            assert_eq!(got.is_some(), expected.is_some(), "{ray:?}");
            if let (Some(g), Some(e)) = (got, expected) {
                hits += 1;
                assert!((g.t - e.t).abs() <= 1e-4 * e.t.max(1.0), "{g:?} {e:?}");
                same += usize::from((g.instance, g.triangle) == (e.instance, e.triangle));
            }
        }
        assert!(hits > 1000, "{hits} of 2000 rays hit");
        // Only a ray through a shared edge may name the neighbouring triangle.
        assert!(
            same * 100 >= hits * 99,
            "{same} of {hits} hits on the same triangle"
        );
    }

    #[test]
    fn too_many_triangles_keep_the_tlas() {
        let bvh = scene("builtin:cornell");
        assert!(FlatBvh::build(&bvh, 31).is_none());
        assert!(FlatBvh::build(&bvh, 32).is_some());
    }

    #[test]
    fn invalid_rays_hit_nothing() {
        let bvh = scene("builtin:cornell");
        let flat = FlatBvh::build(&bvh, FLAT_MAX_TRIANGLES).unwrap();
        let center = bvh.bounds().center();
        for ray in [
            Ray::new(center, Vec3::ZERO),
            Ray::new(Vec3::NAN, Vec3::Y),
            Ray::new(center, Vec3::Y).with_interval(1.0, 0.5),
        ] {
            assert_eq!(flat.closest_hit(&ray), None);
            assert!(!flat.any_hit(&ray));
        }
    }
}
