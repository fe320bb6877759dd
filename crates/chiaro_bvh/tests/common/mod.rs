//! Shared test helpers: a deterministic generator, ray families, and the BVH-versus-brute-force
//! comparison.
#![allow(dead_code)]

use bevy_ecs::prelude::*;
use chiaro_bvh::{Hit, Ray, SceneBvh};
use chiaro_scene::{MaterialId, Mesh, MeshData, MeshId, MeshInstance, Meshes, Transform};
use glam::Vec3;

/// SplitMix64.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn f32(&mut self) -> f32 {
        (self.u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.u64() % n as u64) as usize
    }

    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    pub fn unit_vector(&mut self) -> Vec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f32::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    pub fn in_box(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        Vec3::new(
            self.range(lo.x, hi.x),
            self.range(lo.y, hi.y),
            self.range(lo.z, hi.z),
        )
    }
}

/// Rays per scene: `CHIARO_BVH_RAYS` if set, else `release` in optimised builds and `debug`
/// in debug builds (the crate under test is not optimised there).
pub fn ray_count(release: usize, debug: usize) -> usize {
    std::env::var("CHIARO_BVH_RAYS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(if cfg!(debug_assertions) {
            debug
        } else {
            release
        })
}

/// Every world-space triangle of the BVH, as (instance, triangle, vertices).
pub fn world_triangles(bvh: &SceneBvh) -> Vec<(u32, u32, [Vec3; 3])> {
    let mut out = Vec::new();
    for (i, record) in bvh.instances().iter().enumerate() {
        let blas = bvh.blas(record.mesh).unwrap();
        for t in blas.triangles() {
            out.push((
                i as u32,
                t.triangle,
                bvh.world_triangle(i as u32, t.triangle).unwrap(),
            ));
        }
    }
    out
}

/// A mixed family of rays over a scene: random, axis-parallel (some lying exactly in the
/// planes of vertices), from 1e5 units away, aimed exactly at vertices and edges, and
/// segments with finite intervals.
pub fn scene_rays(bvh: &SceneBvh, count: usize, seed: u64) -> Vec<Ray> {
    let tris = world_triangles(bvh);
    assert!(!tris.is_empty());
    let bounds = bvh.bounds();
    let (lo, hi) = (
        bounds.min - bounds.size() * 0.1 - 1e-3,
        bounds.max + bounds.size() * 0.1 + 1e-3,
    );
    let mut rng = Rng::new(seed);
    let mut rays = Vec::with_capacity(count);
    while rays.len() < count {
        let (_, _, v) = tris[rng.below(tris.len())];
        let kind = rng.below(10);
        let ray = match kind {
            // Random origin and direction.
            0 | 1 => Ray::new(rng.in_box(lo, hi), rng.unit_vector()),
            // Axis-parallel, the two other coordinates copied from a vertex (the ray lies in
            // planes of boxes and of axis-aligned faces) or random.
            2 | 3 => {
                let axis = rng.below(3);
                let sign = if rng.f32() < 0.5 { -1.0 } else { 1.0 };
                let mut d = Vec3::ZERO;
                d[axis] = sign;
                let mut o = rng.in_box(lo, hi);
                if kind == 2 {
                    let p = v[rng.below(3)];
                    for k in 0..3 {
                        if k != axis {
                            o[k] = p[k];
                        }
                    }
                }
                Ray::new(o, d)
            }
            // From 1e5 units away at a point inside a triangle.
            4 | 5 => {
                let (a, b) = (rng.f32(), rng.f32());
                let (a, b) = if a + b > 1.0 {
                    (1.0 - a, 1.0 - b)
                } else {
                    (a, b)
                };
                let target = v[0] + (v[1] - v[0]) * a + (v[2] - v[0]) * b;
                let origin = bounds.center() + rng.unit_vector() * 1e5;
                Ray::new(origin, target - origin)
            }
            // Exactly at a vertex or an edge point, from near or far.
            6 | 7 => {
                let k = rng.below(3);
                let target = if rng.f32() < 0.5 {
                    v[k]
                } else {
                    v[k].lerp(
                        v[(k + 1) % 3],
                        if rng.f32() < 0.5 { 0.5 } else { rng.f32() },
                    )
                };
                let origin = if kind == 6 {
                    rng.in_box(lo, hi)
                } else {
                    target + rng.unit_vector() * 10f32.powf(rng.range(0.0, 5.0))
                };
                Ray::new(origin, target - origin)
            }
            // Segments: finite interval, unnormalised direction, t_min > 0.
            _ => {
                let o = rng.in_box(lo, hi);
                let d = rng.unit_vector() * 10f32.powf(rng.range(-3.0, 3.0));
                let t_min = rng.range(0.0, 0.2) / d.length();
                let t_max = t_min + rng.range(0.0, 1.0) * bounds.size().length() / d.length();
                Ray::new(o, d).with_interval(t_min, t_max)
            }
        };
        if ray.is_valid() {
            rays.push(ray);
        }
    }
    rays
}

/// Mismatches found by [`compare`].
#[derive(Debug, Default)]
pub struct Report {
    pub rays: usize,
    pub hits: usize,
    /// Rays with at least one mismatch.
    pub failed_rays: usize,
    /// The first few mismatches.
    pub examples: Vec<String>,
}

fn same_closest(bvh: Option<Hit>, reference: Option<Hit>) -> bool {
    match (bvh, reference) {
        (None, None) => true,
        // Equal t; the triangle may differ only on an exact tie (a shared edge or vertex).
        (Some(a), Some(b)) => a.t == b.t,
        _ => false,
    }
}

/// Checks closest-hit and any-hit (plain, filtered, and clipped just before the nearest hit)
/// against brute force on `rays`, on all available cores.
pub fn compare(bvh: &SceneBvh, rays: &[Ray]) -> Report {
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(8);
    let chunk = rays.len().div_ceil(threads).max(1);
    let reports: Vec<Report> = std::thread::scope(|s| {
        let handles: Vec<_> = rays
            .chunks(chunk)
            .map(|part| s.spawn(move || compare_serial(bvh, part)))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut total = Report::default();
    for r in reports {
        total.rays += r.rays;
        total.hits += r.hits;
        total.failed_rays += r.failed_rays;
        total.examples.extend(r.examples);
    }
    total
}

fn compare_serial(bvh: &SceneBvh, rays: &[Ray]) -> Report {
    let mut report = Report::default();
    // Alpha-mask stand-in: odd triangles have holes.
    let accept = |h: &Hit| h.triangle.is_multiple_of(2);
    for ray in rays {
        report.rays += 1;
        let all = bvh.all_hits_brute_force(ray);
        let reference = all
            .iter()
            .copied()
            .reduce(|a, b| if b.t < a.t { b } else { a });
        let filtered = all
            .iter()
            .copied()
            .filter(accept)
            .reduce(|a, b| if b.t < a.t { b } else { a });
        let closest = bvh.closest_hit(ray);
        report.hits += usize::from(reference.is_some());
        let mut failures = Vec::new();
        let mut fail = |what: &str| {
            failures.push(format!(
                "{what}: {ray:?} bvh {closest:?} brute {reference:?}"
            ))
        };
        if !same_closest(closest, reference) {
            fail("closest");
        }
        if let Some(h) = closest
            && !all.contains(&h)
        {
            fail("closest hit not a brute-force hit");
        }
        if bvh.any_hit(ray) != reference.is_some() {
            fail("any");
        }
        if !same_closest(bvh.closest_hit_with(ray, &accept), filtered) {
            fail("closest_with");
        }
        if bvh.any_hit_with(ray, &accept) != filtered.is_some() {
            fail("any_with");
        }
        if let Some(h) = reference {
            // The open interval excludes the nearest hit itself.
            let clipped = ray.with_interval(ray.t_min, h.t);
            let expected = all.iter().any(|g| g.t < h.t);
            if bvh.any_hit(&clipped) != expected {
                fail("any clipped at the nearest hit");
            }
        }
        if !failures.is_empty() {
            report.failed_rays += 1;
            if report.examples.len() < 10 {
                report.examples.extend(failures);
            }
        }
    }
    report
}

/// Asserts a clean report with at least `min_hit_fraction` of rays hitting.
pub fn assert_agrees(name: &str, report: &Report, min_hit_fraction: f64) {
    assert!(
        report.failed_rays == 0,
        "{name}: {} of {} rays disagree, e.g.\n{}",
        report.failed_rays,
        report.rays,
        report.examples.join("\n")
    );
    let fraction = report.hits as f64 / report.rays as f64;
    assert!(
        fraction >= min_hit_fraction,
        "{name}: only {fraction:.3} of rays hit"
    );
    eprintln!(
        "{name}: {} rays agree with brute force ({} hits)",
        report.rays, report.hits
    );
}

/// Adds a mesh to the world's `Meshes` (creating it).
pub fn add_mesh(world: &mut World, data: MeshData) -> MeshId {
    let mesh = Mesh::new("test mesh", data).unwrap().0;
    world.get_resource_or_init::<Meshes>().add(mesh)
}

/// Spawns an instance of `mesh`.
pub fn spawn_instance(world: &mut World, mesh: MeshId, transform: Transform) -> Entity {
    world
        .spawn((
            MeshInstance {
                mesh,
                material: MaterialId(0),
            },
            transform,
        ))
        .id()
}

/// A single triangle's mesh data.
pub fn triangle_data(v: [Vec3; 3]) -> MeshData {
    MeshData {
        positions: v.to_vec(),
        ..MeshData::default()
    }
}
