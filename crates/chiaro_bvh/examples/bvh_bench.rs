//! chiaro_bvh benchmark: BLAS build speed and size, TLAS build and update times against instance
//! count, traversal rays per second, and chiaro's robust CWBVH traversal against obvhs's own CWBVH
//! and BVH2 traversals.
//!
//! ```text
//! cargo run --release -p chiaro_bvh --example bvh_bench
//! ```

use std::time::{Duration, Instant};

use bevy_ecs::prelude::*;
use chiaro_bvh::{Blas, BvhStats, Ray, SceneBvh, add_bvh_systems, offset_ray_origin};
use chiaro_scene::builtin::shapes::icosphere;
use chiaro_scene::{
    ActiveCamera, Camera, GlobalTransform, MaterialId, Mesh, MeshData, MeshInstance, Meshes,
    Projection, Transform, load_scene, propagate_transforms,
};
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;

/// SplitMix64, for reproducible rays.
struct Rng(u64);

impl Rng {
    fn f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    fn unit_vector(&mut self) -> Vec3 {
        let z = self.f32() * 2.0 - 1.0;
        let phi = self.f32() * std::f32::consts::TAU;
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn time<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let start = Instant::now();
    let out = f();
    (out, start.elapsed())
}

fn main() {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!(
        "chiaro_bvh benchmark, single-threaded unless stated ({threads} hardware threads); times are the best of {RUNS} runs, medians where stated\n"
    );
    blas_builds();
    tlas_scaling();
    traversal();
    obvhs_comparison();
}

/// A height-field grid of `2 * n * n` triangles.
fn grid(n: u32) -> MeshData {
    let positions = (0..=n)
        .flat_map(|y| {
            (0..=n).map(move |x| {
                let (fx, fy) = (x as f32, y as f32);
                Vec3::new(fx, (fx * 0.05).sin() * (fy * 0.07).cos() * 20.0, fy)
            })
        })
        .collect();
    let indices = (0..n)
        .flat_map(|y| {
            (0..n).flat_map(move |x| {
                let i = y * (n + 1) + x;
                [i, i + 1, i + n + 2, i, i + n + 2, i + n + 1]
            })
        })
        .collect();
    MeshData {
        positions,
        indices: Some(indices),
        ..MeshData::default()
    }
}

fn blas_builds() {
    println!(
        "== BLAS builds (obvhs PLOC medium + reinsertion, converted to CWBVH, <= 3 triangles per leaf) =="
    );
    println!(
        "{:<34} {:>10} {:>10} {:>11} {:>9} {:>6} {:>8}",
        "mesh", "triangles", "build ms", "ms / M tri", "B / tri", "depth", "builder"
    );
    let copies = MeshData {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        indices: Some((0..100_000).flat_map(|_| [0, 1, 2]).collect()),
        ..MeshData::default()
    };
    let meshes = [
        ("icosphere level 6", icosphere(6, false)),
        ("icosphere level 8", icosphere(8, false)),
        ("height-field grid 708 x 708", grid(708)),
        ("100k copies of one triangle", copies),
    ];
    for (name, data) in meshes {
        let mesh = Mesh::new(name, data).unwrap().0;
        let (blas, t) = best_time(|| Blas::build(&mesh));
        let tris = blas.triangle_count();
        println!(
            "{:<34} {:>10} {:>10.1} {:>11.1} {:>9.1} {:>6} {:>8?}",
            name,
            tris,
            ms(t),
            ms(t) / (tris as f64 / 1e6),
            blas.memory_bytes() as f64 / tris as f64,
            blas.depth(),
            blas.builder()
        );
    }
    println!(
        "(bytes per triangle: 80-byte CWBVH nodes + 48-byte triangle records + 4-byte triangle-to-slot map; depth in CWBVH levels)\n"
    );
}

fn schedule() -> Schedule {
    let mut s = Schedule::default();
    add_bvh_systems(&mut s);
    s
}

fn tlas_scaling() {
    println!("== TLAS: builtin:instances?n=N (one 80-triangle sphere mesh, N instances) ==");
    println!(
        "{:>7} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}",
        "N", "build ms", "obvhs ms", "move µs", "far move µs", "frame ms", "add ms", "SAH cost"
    );
    for n in [1_000usize, 10_000, 100_000] {
        let mut world = World::new();
        load_scene(&mut world, &format!("builtin:instances?n={n}")).unwrap();
        let mut schedule = schedule();
        schedule.run(&mut world);

        // Full TLAS build over the existing records (binned SAH), median of 5.
        let builds: Vec<f64> = (0..5)
            .map(|_| {
                let mut bvh = world.resource_mut::<SceneBvh>();
                ms(time(|| bvh.rebuild_tlas()).1)
            })
            .collect();
        let cost = world.resource::<SceneBvh>().tlas_cost();

        // The same boxes through obvhs's PLOC (medium preset), for reference.
        let boxes: Vec<obvhs::aabb::Aabb> = {
            let bvh = world.resource::<SceneBvh>();
            bvh.instances()
                .iter()
                .map(|r| {
                    let b = bvh.blas(r.mesh).unwrap().bounds().transformed(&r.world);
                    obvhs::aabb::Aabb::new(b.min.into(), b.max.into())
                })
                .collect()
        };
        let obvhs_ms = ms(best_time(|| {
            obvhs::bvh2::builder::build_bvh2(
                &boxes,
                BvhBuildParams::medium_build(),
                &mut Duration::default(),
            )
        })
        .1);

        // Moving one instance: the system's own time (change scan, checks, re-insertion) and
        // the whole frame (transform propagation over every entity + the system).
        let entities: Vec<Entity> = world
            .resource::<SceneBvh>()
            .instances()
            .iter()
            .map(|r| r.entity)
            .collect();
        let mut rng = Rng(n as u64);
        let mut system_us = Vec::new();
        let mut far_us = Vec::new();
        let mut frame_ms = Vec::new();
        for k in 0..41 {
            let e = entities[(rng.f32() * entities.len() as f32) as usize % entities.len()];
            let mut t = world.get_mut::<Transform>(e).unwrap();
            if k % 2 == 0 {
                t.translation.x += 0.3;
            } else {
                t.translation.x = -t.translation.x;
                t.translation.z = -t.translation.z;
            }
            let before = world.resource::<BvhStats>().clone();
            let frame = time(|| schedule.run(&mut world)).1;
            let after = world.resource::<BvhStats>();
            assert_eq!(
                after.tlas_builds, before.tlas_builds,
                "a move must not rebuild"
            );
            assert_eq!(after.tlas_updates, before.tlas_updates + 1);
            let us = after.last_work_seconds * 1e6;
            if k % 2 == 0 {
                system_us.push(us);
            } else {
                far_us.push(us);
            }
            frame_ms.push(ms(frame));
        }
        // Adding one instance rebuilds the TLAS (gather, check, sort and build).
        let mesh = world.resource::<SceneBvh>().instances()[0].mesh;
        world.spawn((
            MeshInstance {
                mesh,
                material: MaterialId(0),
            },
            Transform::from_translation(Vec3::new(0.0, 3.0, 0.0)),
        ));
        schedule.run(&mut world);
        let add_ms = world.resource::<BvhStats>().last_work_seconds * 1e3;
        println!(
            "{:>7} {:>12.2} {:>12.2} {:>12.1} {:>12.1} {:>12.2} {:>12.2} {:>12.1}",
            n,
            median(builds),
            obvhs_ms,
            median(system_us),
            median(far_us),
            median(frame_ms),
            add_ms,
            cost
        );
    }
    coincident();
    println!(
        "(build: SceneBvh::rebuild_tlas; move: update_scene_bvh's own time to move one instance by 0.3, \
         far move: to the mirrored grid position, median of 20 each; frame: propagate_transforms + \
         update_scene_bvh; add: spawning one instance, a full rebuild through the system)\n"
    );
}

/// 40,000 instances of one sphere, all at the origin: obvhs's PLOC would take about a minute.
fn coincident() {
    let mut world = World::new();
    let mesh = world
        .get_resource_or_init::<Meshes>()
        .add(Mesh::new("sphere", icosphere(1, false)).unwrap().0);
    let instance = MeshInstance {
        mesh,
        material: MaterialId(0),
    };
    world.spawn_batch((0..40_000).map(|_| (instance, Transform::IDENTITY)));
    let mut schedule = schedule();
    let first = time(|| schedule.run(&mut world)).1;
    let builds: Vec<f64> = (0..5)
        .map(|_| {
            let mut bvh = world.resource_mut::<SceneBvh>();
            ms(time(|| bvh.rebuild_tlas()).1)
        })
        .collect();
    let entities: Vec<Entity> = world
        .resource::<SceneBvh>()
        .instances()
        .iter()
        .map(|r| r.entity)
        .collect();
    let mut moves = Vec::new();
    for k in 0..21 {
        world
            .get_mut::<Transform>(entities[k * 1000])
            .unwrap()
            .translation
            .x += 0.3;
        schedule.run(&mut world);
        moves.push(world.resource::<BvhStats>().last_work_seconds * 1e6);
    }
    println!(
        "{:>7} {:>12.2} {:>12} {:>12.1} {:>12} {:>12} {:>12} {:>12.1}   <- 40,000 at the origin (first system run {:.1} ms)",
        "40000",
        median(builds),
        "(~60 s)",
        median(moves),
        "",
        "",
        "",
        world.resource::<SceneBvh>().tlas_cost(),
        ms(first)
    );
}

/// Perspective camera rays of the world's active camera, `side` x `side`.
fn camera_rays(world: &mut World, side: u32) -> Vec<Ray> {
    world.run_system_once_with_propagate();
    let camera = world.resource::<ActiveCamera>().0;
    let global = *world.get::<GlobalTransform>(camera).unwrap();
    let yfov = match world.get::<Camera>(camera).unwrap().projection {
        Projection::Perspective { yfov, .. } => yfov,
        Projection::Orthographic { .. } => 1.0,
    };
    let tan = (yfov * 0.5).tan();
    let mut rays = Vec::with_capacity((side * side) as usize);
    for y in 0..side {
        for x in 0..side {
            let u = (x as f32 + 0.5) / side as f32 * 2.0 - 1.0;
            let v = 1.0 - (y as f32 + 0.5) / side as f32 * 2.0;
            let d = global.transform_vector(Vec3::new(u * tan, v * tan, -1.0));
            rays.push(Ray::new(global.translation(), d.normalize()));
        }
    }
    rays
}

trait Propagate {
    fn run_system_once_with_propagate(&mut self);
}

impl Propagate for World {
    fn run_system_once_with_propagate(&mut self) {
        use bevy_ecs::system::RunSystemOnce;
        self.run_system_once(propagate_transforms).unwrap();
    }
}

/// Timed runs per figure; the best is reported (the machine may be shared).
const RUNS: usize = 3;

/// Rays per second of `f` over `rays`, one thread, best of [`RUNS`].
fn rate(rays: &[Ray], f: impl Fn(&Ray) -> bool) -> (f64, usize) {
    let mut best = (0.0f64, 0);
    for _ in 0..RUNS {
        let start = Instant::now();
        let hits = rays.iter().filter(|r| f(r)).count();
        let r = rays.len() as f64 / start.elapsed().as_secs_f64();
        if r > best.0 {
            best = (r, hits);
        }
    }
    best
}

/// Rays per second of `f` over `rays`, all threads, best of [`RUNS`].
fn rate_parallel(rays: &[Ray], f: impl Fn(&Ray) -> bool + Sync) -> f64 {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut best = 0.0f64;
    for _ in 0..RUNS {
        let start = Instant::now();
        std::thread::scope(|s| {
            for part in rays.chunks(rays.len().div_ceil(threads)) {
                let f = &f;
                s.spawn(move || part.iter().filter(|r| f(r)).count());
            }
        });
        best = best.max(rays.len() as f64 / start.elapsed().as_secs_f64());
    }
    best
}

/// The shortest of [`RUNS`] timings of `f`, and its last result.
fn best_time<T>(mut f: impl FnMut() -> T) -> (T, Duration) {
    let (mut out, mut best) = time(&mut f);
    for _ in 1..RUNS {
        let (o, t) = time(&mut f);
        out = o;
        best = best.min(t);
    }
    (out, best)
}

fn traversal() {
    println!(
        "== Traversal (Mrays/s; camera rays 512 x 512, then per hit one diffuse bounce and one shadow ray towards a sun) =="
    );
    println!(
        "{:<34} {:>10} {:>9} {:>9} {:>9} {:>9} {:>12}",
        "scene", "triangles", "primary", "bounce", "shadow", "bounce", "bounce"
    );
    println!(
        "{:<34} {:>10} {:>9} {:>9} {:>9} {:>9} {:>12}",
        "", "", "closest", "closest", "any", "hit %", "all threads"
    );
    let scenes = [
        "builtin:cornell",
        "builtin:hard-cases?case=spheres",
        "builtin:instances?n=10000",
        "builtin:hard-cases",
    ];
    for spec in scenes {
        let mut world = World::new();
        load_scene(&mut world, spec).unwrap();
        let bvh = SceneBvh::build(&mut world);
        let triangles: usize = bvh
            .instances()
            .iter()
            .map(|r| bvh.blas(r.mesh).unwrap().triangle_count())
            .sum();
        let primary = camera_rays(&mut world, 512);
        let (primary_rate, _) = rate(&primary, |r| bvh.closest_hit(r).is_some());
        let mut rng = Rng(1);
        let sun = Vec3::new(0.3, 1.0, 0.5).normalize();
        let (mut bounce, mut shadow) = (Vec::new(), Vec::new());
        for r in &primary {
            let Some(hit) = bvh.closest_hit(r) else {
                continue;
            };
            let p = bvh.hit_point(&hit).unwrap();
            let n = bvh.geometric_normal(&hit).unwrap();
            let n = if n.dot(r.direction) < 0.0 { n } else { -n };
            let o = offset_ray_origin(p, n);
            let d = (n + rng.unit_vector()).normalize_or(n);
            bounce.push(Ray::new(o, d));
            shadow.push(Ray::new(
                offset_ray_origin(p, if n.dot(sun) > 0.0 { n } else { -n }),
                sun,
            ));
        }
        let (bounce_rate, bounce_hits) = rate(&bounce, |r| bvh.closest_hit(r).is_some());
        let (shadow_rate, _) = rate(&shadow, |r| bvh.any_hit(r));
        let parallel = rate_parallel(&bounce, |r| bvh.closest_hit(r).is_some());
        println!(
            "{:<34} {:>10} {:>9.2} {:>9.2} {:>9.2} {:>9.0} {:>12.2}",
            spec,
            triangles,
            primary_rate / 1e6,
            bounce_rate / 1e6,
            shadow_rate / 1e6,
            100.0 * bounce_hits as f64 / bounce.len().max(1) as f64,
            parallel / 1e6
        );
    }
    println!();
}

fn obvhs_comparison() {
    println!("== One mesh, three traversals, same watertight triangle test ==");
    let mesh = Mesh::new("sphere", icosphere(7, false)).unwrap().0;
    let mut world = World::new();
    let id = world.get_resource_or_init::<Meshes>().add(mesh.clone());
    world.spawn((
        MeshInstance {
            mesh: id,
            material: MaterialId(0),
        },
        Transform::IDENTITY,
    ));
    let bvh = SceneBvh::build(&mut world);
    let tris: Vec<obvhs::triangle::Triangle> = mesh
        .indices()
        .chunks_exact(3)
        .map(|i| {
            let p = |k: usize| Vec3A::from(mesh.positions()[i[k] as usize]);
            obvhs::triangle::Triangle {
                v0: p(0),
                v1: p(1),
                v2: p(2),
            }
        })
        .collect();
    let params = BvhBuildParams::medium_build();
    let (cwbvh, cw_build) = best_time(|| {
        obvhs::cwbvh::builder::build_cwbvh_from_tris(&tris, params, &mut Duration::default())
    });
    let (bvh2, b2_build) = best_time(|| {
        obvhs::bvh2::builder::build_bvh2_from_tris(
            &tris,
            BvhBuildParams {
                max_prims_per_leaf: 4,
                ..params
            },
            &mut Duration::default(),
        )
    });

    // Incoherent rays from a box around the sphere, and axis-parallel ones from 1e5 away.
    let mut rng = Rng(3);
    let random: Vec<Ray> = (0..300_000)
        .map(|_| {
            let o = (Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 2.0 - 1.0) * 2.0;
            Ray::new(o, rng.unit_vector())
        })
        .collect();
    let axis: Vec<Ray> = (0..100_000)
        .map(|k| {
            let mut d = Vec3::ZERO;
            d[k % 3] = if k % 2 == 0 { 1.0 } else { -1.0 };
            let mut o = (Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 2.0 - 1.0) * 0.99;
            o[k % 3] = -d[k % 3] * 1e5;
            Ray::new(o, d)
        })
        .collect();
    let wt = |r: &Ray| chiaro_bvh::watertight::WatertightRay::new(r.origin, r.direction);
    let obvhs_ray =
        |r: &Ray| obvhs::ray::Ray::new(r.origin.into(), r.direction.into(), r.t_min, r.t_max);
    let tri_t = |w: &chiaro_bvh::watertight::WatertightRay,
                 t: &obvhs::triangle::Triangle,
                 ray: &obvhs::ray::Ray| {
        w.intersect(t.v0.into(), t.v1.into(), t.v2.into(), ray.tmin, ray.tmax)
            .map_or(f32::INFINITY, |h| h.t)
    };
    let ours = |r: &Ray| bvh.closest_hit(r).map(|h| h.t);
    let cw = |r: &Ray| {
        let w = wt(r);
        let mut hit = obvhs::ray::RayHit::none();
        cwbvh
            .ray_traverse(obvhs_ray(r), &mut hit, |ray, id| {
                tri_t(&w, &tris[cwbvh.primitive_indices[id] as usize], ray)
            })
            .then_some(hit.t)
    };
    let b2 = |r: &Ray| {
        let w = wt(r);
        let mut hit = obvhs::ray::RayHit::none();
        bvh2.ray_traverse(obvhs_ray(r), &mut hit, |ray, id| {
            tri_t(&w, &tris[bvh2.primitive_indices[id] as usize], ray)
        })
        .then_some(hit.t)
    };
    println!(
        "icosphere level 7: {} triangles; builds: chiaro BLAS {:.1} ms, obvhs CWBVH {:.1} ms, obvhs BVH2 {:.1} ms",
        tris.len(),
        ms(best_time(|| Blas::build(&mesh)).1),
        ms(cw_build),
        ms(b2_build)
    );
    println!(
        "{:<38} {:>14} {:>22} {:>22}",
        "traversal", "random Mrays/s", "random: lost hits", "axis-parallel: lost"
    );
    let reference_random: Vec<Option<f32>> = random.iter().map(ours).collect();
    let reference_axis: Vec<Option<f32>> = axis.iter().map(ours).collect();
    type Trace<'a> = &'a dyn Fn(&Ray) -> Option<f32>;
    let runs: [(&str, Trace); 3] = [
        ("chiaro CWBVH (robust, via the TLAS)", &ours),
        ("obvhs CWBVH ray_traverse", &cw),
        ("obvhs BVH2 ray_traverse", &b2),
    ];
    for (name, f) in runs {
        let (r, _) = rate(&random, |ray| f(ray).is_some());
        let lost = |rays: &[Ray], reference: &[Option<f32>]| {
            rays.iter()
                .zip(reference)
                .filter(|(ray, want)| want.is_some() && f(ray).is_none())
                .count()
        };
        println!(
            "{:<38} {:>14.2} {:>15} of {:>4}k {:>15} of {:>4}k",
            name,
            r / 1e6,
            lost(&random, &reference_random),
            random.len() / 1000,
            lost(&axis, &reference_axis),
            axis.len() / 1000
        );
    }
}
