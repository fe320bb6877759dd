//! lib/bvh.wgsl against chiaro_bvh's CPU traversal: for 100k random rays per scene, the GPU's
//! closest hit (distance, instance, triangle, barycentrics) and any-hit answer equal
//! SceneBvh::closest_hit / any_hit, with and without an alpha-mask hook that rejects every odd
//! triangle on both sides.
//!
//! Scenes: builtin:cornell, builtin:instances?n=64, builtin:hard-cases (far copies, a tiny
//! cube on a huge box, coplanar quads, grazing planes) and the shared MetalRoughSpheresNoTextures
//! model.
//!
//! Rays: half are aimed at random points of random triangles (a tenth of those at points of
//! their edges and vertices), from random origins around the scene and near the target; a
//! quarter are random rays through the scene's bounds; a quarter are shadow segments between
//! two points on surfaces (t in (0, 1)). Every other ray has the odd-triangle mask on.
//!
//! Agreement: same instance and triangle, hit points within [`T_REL`] of the coordinates' scale
//! (a few ulps; the GPU may fuse multiply-adds the CPU rounds twice), barycentrics within
//! [`BARY_TOL`]. A disagreement is allowed only for a ray within float tolerance of an edge
//! (the smallest barycentric weight of the CPU's or the GPU's hit below [`EDGE_TOL`]), or
//! between two hits at the same distance (within [`T_REL`]: a shared edge or a coplanar
//! overlap), or for an any-hit segment ending within [`T_REL`] of a surface; such rays are
//! counted and must be at most [`MAX_MISMATCH_FRACTION`] of all.

mod common;
mod kernel;

use std::time::Instant;

use bevy_ecs::world::World;
use bytemuck::{Pod, Zeroable};
use chiaro_bvh::{GpuBvhBuffers, Hit, Ray, SceneBvh};
use chiaro_shading::rng::Pcg32;
use chiaro_shading::sampling::uniform_sphere;
use glam::{Vec2, Vec3};
use kernel::{Input, Kernel, Output};

/// Rays per scene.
const RAYS: usize = 100_000;
/// Tolerance on hit distances: the two hit points may be this far apart relative to the largest
/// coordinate of the ray's origin and hit point (a few ulps of them).
const T_REL: f32 = 1e-6;
/// Absolute tolerance on barycentrics of the same triangle.
const BARY_TOL: f32 = 1e-4;
/// A hit whose smallest barycentric weight is below this is "on an edge".
const EDGE_TOL: f32 = 1e-5;
/// Most rays (fraction of all) whose answers may differ, all at edges or ties.
const MAX_MISMATCH_FRACTION: f64 = 1e-3;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct TestRay {
    origin: [f32; 3],
    t_min: f32,
    direction: [f32; 3],
    t_max: f32,
    mask_odd: u32,
    pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct TestHit {
    t: f32,
    instance: u32,
    triangle: u32,
    occluded: u32,
    barycentrics: [f32; 2],
    pad: [f32; 2],
}

const KERNEL: &str = r#"
#import lib/bvh.wgsl

struct TestRay {
    origin: vec3<f32>,
    t_min: f32,
    direction: vec3<f32>,
    t_max: f32,
    mask_odd: u32,
}

struct TestHit {
    t: f32,
    instance: u32,
    triangle: u32,
    occluded: u32,
    barycentrics: vec2<f32>,
    pad: vec2<f32>,
}

@group(1) @binding(0) var<storage, read> rays: array<TestRay>;
@group(1) @binding(1) var<storage, read_write> hits: array<TestHit>;

var<private> mask_odd: bool;

// The test's alpha mask: with mask_odd, every odd triangle is a hole.
fn hit_accepted(ray: Ray, instance: u32, triangle: u32, barycentrics: vec2<f32>) -> bool {
    return !mask_odd || (triangle & 1u) == 0u;
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&rays) {
        return;
    }
    let r = rays[i];
    mask_odd = r.mask_odd != 0u;
    let ray = Ray(r.origin, r.t_min, r.direction);
    let h = trace_closest(ray, r.t_max);
    var out: TestHit;
    out.t = h.t;
    out.instance = h.instance;
    out.triangle = h.triangle;
    out.barycentrics = h.barycentrics;
    out.occluded = select(0u, 1u, trace_any(ray, r.t_max));
    hits[i] = out;
}
"#;

/// A scene's BVH with a way to pick random surface points.
struct Scene {
    name: String,
    bvh: SceneBvh,
    /// (instance, triangle) of every triangle of every instance.
    triangles: Vec<(u32, u32)>,
}

impl Scene {
    fn load(name: &str) -> Self {
        let mut world = World::new();
        chiaro_scene::load_scene(&mut world, name).unwrap_or_else(|e| panic!("{name}: {e}"));
        let bvh = SceneBvh::build(&mut world);
        let mut triangles = Vec::new();
        for (i, record) in bvh.instances().iter().enumerate() {
            let count = bvh.blas(record.mesh).map_or(0, |b| b.triangle_count());
            triangles.extend((0..count as u32).map(|t| (i as u32, t)));
        }
        Self {
            name: name.to_owned(),
            bvh,
            triangles,
        }
    }

    /// A random point on a random triangle; with `on_edge`, on one of its edges or vertices.
    fn surface_point(&self, rng: &mut Pcg32, on_edge: bool) -> Vec3 {
        let (instance, triangle) = self.triangles[(rng.next_u32() as usize) % self.triangles.len()];
        let [a, b, c] = self.bvh.world_triangle(instance, triangle).unwrap();
        let (mut b1, mut b2) = chiaro_shading::sampling::uniform_triangle(rng.next_vec2());
        if on_edge {
            match rng.next_u32() % 4 {
                0 => b1 = 0.0,
                1 => b2 = 0.0,
                2 => b2 = 1.0 - b1,
                _ => (b1, b2) = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)][(rng.next_u32() % 3) as usize],
            }
        }
        a + (b - a) * b1 + (c - a) * b2
    }

    fn random_ray(&self, rng: &mut Pcg32, index: usize) -> TestRay {
        let bounds = self.bvh.bounds();
        let center = bounds.center();
        let extent = (bounds.max - bounds.min).max_element();
        let in_bounds = |rng: &mut Pcg32| {
            let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            bounds.min + (bounds.max - bounds.min) * u
        };
        let (origin, direction, t_max) = match index % 4 {
            0 | 1 => {
                let on_edge = rng.next_f32() < 0.1;
                let target = self.surface_point(rng, on_edge);
                let origin = if rng.next_f32() < 0.5 {
                    center + uniform_sphere(rng.next_vec2()) * extent * rng.next_f32()
                } else {
                    target + uniform_sphere(rng.next_vec2()) * extent * 1e-3 * rng.next_f32()
                };
                (origin, target - origin, f32::INFINITY)
            }
            2 => (
                in_bounds(rng),
                uniform_sphere(rng.next_vec2()),
                f32::INFINITY,
            ),
            _ => {
                let from = self.surface_point(rng, false);
                let to = self.surface_point(rng, false);
                (from, to - from, 1.0)
            }
        };
        TestRay {
            origin: origin.to_array(),
            t_min: if index % 4 == 3 { 1e-4 } else { 0.0 },
            direction: direction.to_array(),
            t_max,
            mask_odd: ((index / 4) % 2) as u32,
            pad: [0; 3],
        }
    }
}

fn min_weight(b: Vec2) -> f32 {
    (1.0 - b.x - b.y).min(b.x).min(b.y)
}

#[derive(Default, Debug)]
struct Tally {
    hits: usize,
    occluded: usize,
    closest_mismatch: usize,
    any_mismatch: usize,
    worst_t: f32,
    worst_bary: f32,
}

/// Returns an error with the message unless the condition holds.
macro_rules! ensure {
    ($cond:expr, $($fmt:tt)+) => {
        let holds: bool = $cond;
        if !holds {
            return Err(format!($($fmt)+));
        }
    };
}

/// The ray as chiaro_bvh takes it.
fn cpu_ray(r: &TestRay) -> Ray {
    Ray::new(Vec3::from_array(r.origin), Vec3::from_array(r.direction))
        .with_interval(r.t_min, r.t_max)
}

/// The CPU's closest hit and any-hit answer for `r`, with the test's mask.
fn cpu_answers(scene: &Scene, r: &TestRay) -> (Option<Hit>, bool) {
    let ray = cpu_ray(r);
    let accept = |h: &Hit| r.mask_odd == 0 || h.triangle.is_multiple_of(2);
    (
        scene.bvh.closest_hit_with(&ray, &accept),
        scene.bvh.any_hit_with(&ray, &accept),
    )
}

/// The CPU answers for every ray, on every core (the test's own code is not optimised).
fn cpu_answers_parallel(scene: &Scene, rays: &[TestRay]) -> Vec<(Option<Hit>, bool)> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = rays.len().div_ceil(threads).max(1);
    std::thread::scope(|s| {
        let workers: Vec<_> = rays
            .chunks(chunk)
            .map(|part| {
                s.spawn(move || {
                    part.iter()
                        .map(|r| cpu_answers(scene, r))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a CPU tracing thread panicked"))
            .collect()
    })
}

fn compare(
    scene: &Scene,
    r: &TestRay,
    g: &TestHit,
    (cpu, cpu_any): (Option<Hit>, bool),
    tally: &mut Tally,
) -> Result<(), String> {
    let ray = cpu_ray(r);
    let gpu = (g.instance != u32::MAX).then(|| Hit {
        t: g.t,
        instance: g.instance,
        triangle: g.triangle,
        barycentrics: Vec2::from_array(g.barycentrics),
    });
    let at_edge = |h: &Option<Hit>| h.is_some_and(|h| min_weight(h.barycentrics) < EDGE_TOL);
    let tie = |a: &Option<Hit>, b: &Option<Hit>| match (a, b) {
        (Some(a), Some(b)) => (a.t - b.t).abs() <= T_REL * a.t.abs().max(b.t.abs()),
        _ => false,
    };
    tally.hits += usize::from(cpu.is_some());
    tally.occluded += usize::from(cpu_any);
    match (&cpu, &gpu) {
        (Some(c), Some(h)) if (c.instance, c.triangle) == (h.instance, h.triangle) => {
            // The hit points' distance, relative to the coordinates involved: t itself carries
            // the error of the origin's coordinates divided by the direction's length.
            let d = (c.t - h.t).abs() * ray.direction.abs().max_element();
            let scale = ray
                .origin
                .abs()
                .max_element()
                .max(ray.at(c.t).abs().max_element());
            let e = d / scale.max(f32::MIN_POSITIVE);
            ensure!(
                e <= T_REL,
                "{}: t {} vs {} ({e}) for {r:?}",
                scene.name,
                h.t,
                c.t
            );
            tally.worst_t = tally.worst_t.max(e);
            let e = (c.barycentrics - h.barycentrics).abs().max_element();
            ensure!(e <= BARY_TOL, "{}: barycentrics {h:?} vs {c:?}", scene.name);
            tally.worst_bary = tally.worst_bary.max(e);
        }
        (None, None) => {}
        _ => {
            ensure!(
                at_edge(&cpu) || at_edge(&gpu) || tie(&cpu, &gpu),
                "{}: closest hit differs away from any edge for {r:?}: cpu {cpu:?}, gpu {gpu:?}",
                scene.name
            );
            tally.closest_mismatch += 1;
        }
    }
    let gpu_any = g.occluded != 0;
    if gpu_any != cpu_any {
        let ends_at_surface = cpu
            .or(gpu)
            .is_some_and(|h| (h.t - r.t_max).abs() <= T_REL * r.t_max.abs());
        ensure!(
            at_edge(&cpu) || at_edge(&gpu) || ends_at_surface,
            "{}: any-hit {gpu_any} vs {cpu_any} away from any edge for {r:?}: cpu {cpu:?}, gpu {gpu:?}",
            scene.name
        );
        tally.any_mismatch += 1;
    }
    Ok(())
}

fn check_scene(gpu: &chiaro_gpu::GpuContext, kernel: &Kernel, name: &str) {
    let start = Instant::now();
    let scene = Scene::load(name);
    let buffers = GpuBvhBuffers::from_scene(&scene.bvh);
    let mut rng = Pcg32::new(0x7a5e, name.len() as u64);
    let rays: Vec<TestRay> = (0..RAYS).map(|i| scene.random_ray(&mut rng, i)).collect();
    let t = Instant::now();
    let texel = |binding, data| Input {
        group: 0,
        binding,
        data,
    };
    let bytes = kernel.run_with_texels(
        gpu,
        &[
            Input {
                group: 0,
                binding: 3,
                data: bytemuck::cast_slice(&buffers.instances),
            },
            Input {
                group: 1,
                binding: 0,
                data: bytemuck::cast_slice(&rays),
            },
        ],
        &[
            texel(0, bytemuck::cast_slice(&buffers.blas_nodes)),
            texel(1, bytemuck::cast_slice(&buffers.triangles)),
            texel(2, bytemuck::cast_slice(&buffers.tlas_nodes)),
            texel(4, bytemuck::cast_slice(&buffers.instances)),
        ],
        &Output {
            group: 1,
            binding: 1,
            size: (RAYS * size_of::<TestHit>()) as u64,
        },
        RAYS as u32,
    );
    let gpu_seconds = t.elapsed().as_secs_f64();
    let hits: &[TestHit] = bytemuck::cast_slice(&bytes);
    let mut tally = Tally::default();
    let mut failures = 0;
    let answers = cpu_answers_parallel(&scene, &rays);
    for ((r, g), answer) in rays.iter().zip(hits).zip(answers) {
        if let Err(e) = compare(&scene, r, g, answer, &mut tally) {
            if failures < 10 {
                eprintln!("{e}");
            }
            failures += 1;
        }
    }
    eprintln!(
        "{name}: {} triangles, {RAYS} rays ({:.1} s, GPU {gpu_seconds:.1} s): {tally:?}",
        scene.triangles.len(),
        start.elapsed().as_secs_f64()
    );
    assert_eq!(failures, 0, "{name}: {failures} of {RAYS} rays disagree");
    let bound = (MAX_MISMATCH_FRACTION * RAYS as f64) as usize;
    assert!(
        tally.closest_mismatch <= bound && tally.any_mismatch <= bound,
        "{name}: {tally:?}"
    );
    // The rays exercise both answers.
    assert!(
        tally.hits > RAYS / 4 && tally.hits < RAYS,
        "{name}: {tally:?}"
    );
    assert!(tally.occluded > RAYS / 10, "{name}: {tally:?}");
}

#[test]
fn wgsl_traversal_matches_the_cpu_on_random_rays() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let kernel = Kernel::new(&gpu, "traversal parity", KERNEL);
    // A real model too: spheres of shared edges, from the test data beside the checkout.
    let shared = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/scenes/MetalRoughSpheresNoTextures.glb");
    assert!(
        shared.is_file(),
        "{} is missing: this test needs the shared test data folder (../shared/scenes) beside the checkout",
        shared.display()
    );
    for name in [
        "builtin:cornell",
        "builtin:instances?n=64",
        "builtin:hard-cases",
        shared.to_str().expect("a UTF-8 path"),
    ] {
        check_scene(&gpu, &kernel, name);
    }
}
