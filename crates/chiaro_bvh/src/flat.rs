//! [`FlatBvh`]: every instance of a scene that will not change, its triangles carried into world
//! space and put under one BVH, for a renderer that traces many rays through a still scene (the
//! CPU reference).
//!
//! [`SceneBvh`] traverses a TLAS and, for each instance a ray's box test lets through, carries
//! the ray into the instance's object space and prepares it for that BLAS. On a scene of a few
//! small meshes (the Cornell box: 8 instances, 32 triangles) that per-instance work, and the
//! overlap of instance boxes, cost more than the triangle tests. Here a ray is prepared once and
//! meets one tree. Hits are reported in the scene's terms (instance index and the triangle's
//! index in its mesh, barycentrics in the mesh's vertex order), so a caller sees the same
//! [`Hit`]s; instances with an identity matrix give bit-identical ones, others differ by the
//! rounding of their vertices' transform.

use glam::Vec2;

use crate::blas::{Blas, Candidate};
use crate::layout::BvhTriangle;
use crate::object_ray::ObjectRay;
use crate::ray::{Hit, Ray};
use crate::scene_bvh::SceneBvh;

/// Most world-space triangles [`FlatBvh::build`] takes (48 bytes each plus about 40 bytes of
/// nodes): 2^21, about 180 MB. A scene with more (typically heavy instancing) keeps its TLAS.
pub const FLAT_MAX_TRIANGLES: usize = 1 << 21;

/// A still scene's triangles in world space under one BVH (see the module docs).
#[derive(Clone, Debug)]
pub struct FlatBvh {
    blas: Blas,
    /// Instance and mesh triangle of each flat triangle index.
    origins: Vec<(u32, u32)>,
}

impl FlatBvh {
    /// Flattens `scene` as it is now; `None` when it has more than `max_triangles` triangles
    /// over all its instances. Triangles whose world-space vertices are not finite are left out,
    /// as [`SceneBvh`] leaves them out.
    pub fn build(scene: &SceneBvh, max_triangles: usize) -> Option<Self> {
        let total: usize = scene
            .instances()
            .iter()
            .map(|r| scene.blas(r.mesh).map_or(0, Blas::triangle_count))
            .sum();
        if total > max_triangles {
            return None;
        }
        let mut triangles = Vec::with_capacity(total);
        let mut origins = Vec::with_capacity(total);
        for (instance, record) in scene.instances().iter().enumerate() {
            let Some(blas) = scene.blas(record.mesh) else {
                continue;
            };
            for t in blas.triangles() {
                let v = t.vertices().map(|p| record.world.transform_point3(p));
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
        self.closest_hit_filtered(ray, |_| true)
    }

    /// The nearest hit that `accept` takes, as [`SceneBvh::closest_hit_with`].
    pub fn closest_hit_with(&self, ray: &Ray, accept: &dyn Fn(&Hit) -> bool) -> Option<Hit> {
        self.closest_hit_filtered(ray, accept)
    }

    /// True if anything is hit, as [`SceneBvh::any_hit`].
    pub fn any_hit(&self, ray: &Ray) -> bool {
        self.any_hit_filtered(ray, |_| true)
    }

    /// True if anything `accept` takes is hit, as [`SceneBvh::any_hit_with`].
    pub fn any_hit_with(&self, ray: &Ray, accept: &dyn Fn(&Hit) -> bool) -> bool {
        self.any_hit_filtered(ray, accept)
    }

    fn closest_hit_filtered(&self, ray: &Ray, accept: impl Fn(&Hit) -> bool) -> Option<Hit> {
        let mut best = None;
        self.traverse(ray, &mut |hit| {
            if accept(&hit) {
                best = Some(hit);
                Candidate::Accept
            } else {
                Candidate::Reject
            }
        });
        best
    }

    fn any_hit_filtered(&self, ray: &Ray, accept: impl Fn(&Hit) -> bool) -> bool {
        self.traverse(ray, &mut |hit| {
            if accept(&hit) {
                Candidate::Stop
            } else {
                Candidate::Reject
            }
        })
    }

    /// Visits the candidates along `ray` as scene hits; true when `on_hit` stopped it.
    fn traverse(&self, ray: &Ray, on_hit: &mut impl FnMut(Hit) -> Candidate) -> bool {
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
    fn transformed_instances_give_the_same_surfaces() {
        let bvh = scene("builtin:instances");
        let flat = FlatBvh::build(&bvh, FLAT_MAX_TRIANGLES).unwrap();
        let (mut same, mut hits) = (0, 0);
        for ray in rays(&bvh, 4000) {
            let expected = bvh.closest_hit(&ray);
            let got = flat.closest_hit(&ray);
            assert_eq!(got.is_some(), expected.is_some(), "{ray:?}");
            if let (Some(g), Some(e)) = (got, expected) {
                hits += 1;
                assert!((g.t - e.t).abs() <= 1e-4 * e.t.max(1.0), "{g:?} {e:?}");
                same += usize::from((g.instance, g.triangle) == (e.instance, e.triangle));
            }
        }
        assert!(hits > 1000, "{hits} of 4000 rays hit");
        // Only rays through a shared edge may name the neighbouring triangle.
        assert!(
            same * 1000 >= hits * 998,
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
