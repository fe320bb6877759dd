//! lib/light_tree.wgsl against chiaro_shading::light_tree on random light sets and random
//! queries made in Rust: the light a walk picks from (point, normal, u), the probability it
//! reports, and the probability the leaf-to-root re-walk gives a random light.
//!
//! The nodes are the GPU scene's own: two trees (one playing the area tree, one the punctual
//! tree) flattened and combined into one buffer by `gpu_scene::light_trees`, read through
//! scene_bindings.wgsl's hook, so the offsets of the second tree are checked too. Light sets
//! mix one- and two-sided triangles, point and spot lights over a 20-unit box; query points
//! lie in a 30-unit box (some inside the lights' boxes), a fifth with no normal.
//!
//! What must hold: the GPU's pick reports the probability its own re-walk gives (within
//! [`SELF_TOL`]: MIS relies on it); the same light as the CPU's picked for all but
//! [`MAX_PICK_MISMATCH`] of the queries (a u within rounding of a child's probability may go
//! either way: the GPU's atan2, sqrt and cos are not the CPU's to the last bit); where the
//! same, its probability, and the re-walked probability of a random light, within [`REL_TOL`]
//! relative of the CPU's for all but [`MAX_PMF_MISMATCH`] (the angles' rounding is amplified
//! near a cone's edge, and a bound that crosses an edge by a rounding flips a child's
//! importance to or from zero). Measured on lavapipe, per set of 8,000 queries: at most 2
//! picks differ and at most 17 of the 16,000 probabilities beyond 1e-3 (most under 1e-5);
//! pick against re-walk within 3.7e-7. (With WGSL's asin, whose lavapipe version errs by
//! 4e-4, half the probabilities differed by over 1e-5 and up to 73 picks per set.)

mod common;
mod kernel;

use bytemuck::{Pod, Zeroable};
use chiaro_gpu::gpu_scene::light_trees::{FlatTree, combine};
use chiaro_shading::light_tree::{LightBounds, LightTree};
use chiaro_shading::rng::Pcg32;
use chiaro_shading::sampling::uniform_sphere;
use glam::Vec3;
use kernel::{Input, Kernel, Output};

/// Queries per light set.
const QUERIES: usize = 8_000;
/// Relative bound on a probability against the CPU's.
const REL_TOL: f32 = 1e-3;
/// Relative bound between the probability a GPU pick reports and the GPU's re-walk of it (the
/// same arithmetic, multiplied in the other order), which MIS needs to agree.
const SELF_TOL: f32 = 1e-5;
/// Most queries whose picks may differ.
const MAX_PICK_MISMATCH: usize = QUERIES / 1000;
/// Most probabilities (picked and re-walked) that may differ beyond [`REL_TOL`].
const MAX_PMF_MISMATCH: usize = QUERIES / 200;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct Query {
    p: [f32; 3],
    u: f32,
    n: [f32; 3],
    root: u32,
    leaf: u32,
    leaf_base: u32,
    pad: [u32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, Default)]
struct Answer {
    light: u32,
    pick_pmf: f32,
    pmf: f32,
    rewalk: f32,
}

const KERNEL: &str = r#"
#import lib/scene_bindings.wgsl
#import lib/light_tree.wgsl

struct Query {
    p: vec3<f32>,
    u: f32,
    n: vec3<f32>,
    root: u32,
    leaf: u32,
    leaf_base: u32,
}

struct Answer {
    light: u32,
    pick_pmf: f32,
    pmf: f32,
    rewalk: f32,
}

@group(1) @binding(0) var<storage, read> queries: array<Query>;
@group(1) @binding(1) var<storage, read_write> answers: array<Answer>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&queries) {
        return;
    }
    let q = queries[i];
    let pick = light_tree_pick(q.root, q.p, q.n, q.u);
    let rewalk = light_tree_pmf(q.leaf_base + pick.light, q.p, q.n);
    answers[i] = Answer(pick.light, pick.pmf, light_tree_pmf(q.leaf, q.p, q.n), rewalk);
}
"#;

fn random_unit(rng: &mut Pcg32) -> Vec3 {
    uniform_sphere(rng.next_vec2())
}

/// Triangles (one- and two-sided), points and spots spread over a 20-unit box.
fn random_lights(rng: &mut Pcg32, n: usize) -> Vec<LightBounds> {
    (0..n)
        .map(|i| {
            let at = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 20.0 - 10.0;
            let power = 0.1 + 10.0 * rng.next_f32();
            match i % 4 {
                0 | 1 => {
                    let (a, b) = (random_unit(rng) * 0.5, random_unit(rng) * 0.5);
                    LightBounds::triangle([at, at + a, at + b], power, i % 8 == 1)
                }
                2 => LightBounds::point(at, power),
                _ => LightBounds::spot(at, random_unit(rng), 0.2 + rng.next_f32(), power),
            }
        })
        .collect()
}

fn relative(a: f32, b: f32) -> f32 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-30)
}

#[test]
fn gpu_walks_match_the_cpu_tree() {
    let Some(gpu) = common::gpu() else { return };
    let kernel = Kernel::new(&gpu, "light tree parity", KERNEL);
    let mut rng = Pcg32::new(8, 3);
    let mut checked = 0;
    let mut worst = 0.0f32;
    let mut worst_self = 0.0f32;
    for (area_n, punctual_n) in [(1, 2), (3, 17), (64, 5), (256, 256), (512, 9), (2, 1000)] {
        let sets = [
            random_lights(&mut rng, area_n),
            random_lights(&mut rng, punctual_n),
        ];
        let trees = sets.each_ref().map(|s| LightTree::build(s).unwrap());
        let flat = sets
            .each_ref()
            .map(|s| FlatTree::build(&s.iter().copied().map(Some).collect::<Vec<_>>()));
        let (nodes, area_root, punctual_root) = combine(&flat[0], &flat[1]);
        let roots = [area_root, punctual_root];
        // Node of each tree's light 0.
        let leaf_bases = [0, 1].map(|t| roots[t] + flat[t].leaf(0));
        let mut expected = Vec::new();
        let queries: Vec<Query> = (0..QUERIES)
            .map(|i| {
                let t = i % 2;
                let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 30.0 - 15.0;
                let n = if rng.next_f32() < 0.2 {
                    Vec3::ZERO
                } else {
                    random_unit(&mut rng)
                };
                let u = rng.next_f32();
                let light = (rng.next_u32() as usize) % sets[t].len();
                let (picked, pick_pmf) = trees[t].pick(p, n, u);
                expected.push((t, picked, pick_pmf, trees[t].pmf(light, p, n)));
                Query {
                    p: p.to_array(),
                    u,
                    n: n.to_array(),
                    root: roots[t],
                    leaf: leaf_bases[t] + light as u32,
                    leaf_base: leaf_bases[t],
                    pad: [0; 2],
                }
            })
            .collect();
        let bytes = kernel.run_with_texels(
            &gpu,
            &[Input {
                group: 1,
                binding: 0,
                data: bytemuck::cast_slice(&queries),
            }],
            &[Input {
                group: 0,
                binding: 20,
                data: bytemuck::cast_slice(&nodes),
            }],
            &Output {
                group: 1,
                binding: 1,
                size: (QUERIES * size_of::<Answer>()) as u64,
            },
            QUERIES as u32,
        );
        let answers: Vec<Answer> = bytemuck::pod_collect_to_vec(&bytes);
        let (mut pick_mismatch, mut pmf_mismatch) = (0, 0);
        for (a, &(t, light, pick_pmf, pmf)) in answers.iter().zip(&expected) {
            assert!(a.pick_pmf.is_finite() && a.pmf.is_finite(), "{a:?}");
            assert!((a.light as usize) < sets[t].len(), "{a:?}");
            let e = relative(a.rewalk, a.pick_pmf);
            assert!(e <= SELF_TOL, "re-walk {} vs pick {}", a.rewalk, a.pick_pmf);
            worst_self = worst_self.max(e);
            if a.light as usize == light {
                let e = relative(a.pick_pmf, pick_pmf);
                if e > REL_TOL {
                    pmf_mismatch += 1;
                } else {
                    worst = worst.max(e);
                }
            } else {
                pick_mismatch += 1;
            }
            let e = relative(a.pmf, pmf);
            if e > REL_TOL {
                pmf_mismatch += 1;
            } else {
                worst = worst.max(e);
            }
        }
        eprintln!(
            "{area_n} + {punctual_n} lights: {pick_mismatch} pick and {pmf_mismatch} pmf \
             mismatches of {QUERIES}"
        );
        assert!(
            pick_mismatch <= MAX_PICK_MISMATCH,
            "{pick_mismatch} picks differ"
        );
        assert!(
            pmf_mismatch <= MAX_PMF_MISMATCH,
            "{pmf_mismatch} pmfs differ"
        );
        checked += QUERIES;
    }
    eprintln!(
        "{checked} queries, largest relative error {worst:e} against the CPU, {worst_self:e} \
         between the GPU's pick and its re-walk"
    );
}
