//! Brute-force ray queries: every triangle of every instance, through the same object-space ray
//! and the same watertight test as traversal. The reference the BVH is tested against; far too
//! slow for rendering.

use glam::Vec2;

use crate::object_ray::ObjectRay;
use crate::ray::{Hit, Ray};
use crate::scene_bvh::SceneBvh;

impl SceneBvh {
    /// Every hit of `ray` in `(t_min, t_max)`, in instance then triangle-storage order, found
    /// without the TLAS or any BLAS tree.
    pub fn all_hits_brute_force(&self, ray: &Ray) -> Vec<Hit> {
        let mut hits = Vec::new();
        if !ray.is_valid() || ray.t_min >= ray.t_max {
            return hits;
        }
        for (index, record) in self.instances().iter().enumerate() {
            let Some(blas) = self.blas(record.mesh) else {
                continue;
            };
            let Some(object_ray) = ObjectRay::from_world(ray, &record.inverse) else {
                continue;
            };
            for tri in blas.triangles() {
                let [v0, v1, v2] = tri.vertices();
                if let Some(h) = object_ray
                    .watertight
                    .intersect(v0, v1, v2, ray.t_min, ray.t_max)
                {
                    hits.push(Hit {
                        t: h.t,
                        instance: index as u32,
                        triangle: tri.triangle,
                        barycentrics: Vec2::new(h.b1, h.b2),
                    });
                }
            }
        }
        hits
    }

    /// The nearest hit by brute force (the first found among equally near ones).
    pub fn closest_hit_brute_force(&self, ray: &Ray) -> Option<Hit> {
        self.all_hits_brute_force(ray)
            .into_iter()
            .reduce(|best, h| if h.t < best.t { h } else { best })
    }

    /// Whether anything is hit, by brute force.
    pub fn any_hit_brute_force(&self, ray: &Ray) -> bool {
        !self.all_hits_brute_force(ray).is_empty()
    }
}
