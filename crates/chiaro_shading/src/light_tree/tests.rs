use super::*;
use crate::rng::Pcg32;
use crate::test_util::chi_square_test;

fn random_unit(rng: &mut Pcg32) -> Vec3 {
    loop {
        let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
        if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// A mix of triangles (one- and two-sided), points and spots spread over a 20-unit box.
fn random_lights(rng: &mut Pcg32, n: usize) -> Vec<LightBounds> {
    (0..n)
        .map(|i| {
            let at = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 20.0 - 10.0;
            let power = 0.1 + 10.0 * rng.next_f32();
            match i % 4 {
                0 | 1 => {
                    let (a, b) = (random_unit(rng) * 0.3, random_unit(rng) * 0.3);
                    LightBounds::triangle([at, at + a, at + b], power, i % 8 == 1)
                }
                2 => LightBounds::point(at, power),
                _ => LightBounds::spot(at, random_unit(rng), 0.2 + rng.next_f32(), power),
            }
        })
        .collect()
}

#[test]
fn probabilities_sum_to_one_and_pick_reports_them() {
    let mut rng = Pcg32::new(3, 1);
    for n in [1, 2, 3, 7, 64, 301] {
        let lights = random_lights(&mut rng, n);
        let tree = LightTree::build(&lights).unwrap();
        assert_eq!(tree.len(), n);
        for _ in 0..20 {
            let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 30.0 - 15.0;
            let normal = if rng.next_f32() < 0.2 {
                Vec3::ZERO
            } else {
                random_unit(&mut rng)
            };
            let total: f64 = (0..n).map(|i| f64::from(tree.pmf(i, p, normal))).sum();
            assert!((total - 1.0).abs() < 1e-4, "{n} lights: sum {total}");
            for _ in 0..10 {
                let (light, pmf) = tree.pick(p, normal, rng.next_f32());
                let again = tree.pmf(light, p, normal);
                assert!(
                    pmf > 0.0 && (pmf - again).abs() <= 1e-6 * again,
                    "{pmf} vs {again}"
                );
            }
        }
    }
}

#[test]
fn picks_follow_the_probabilities() {
    let mut rng = Pcg32::new(9, 2);
    let lights = random_lights(&mut rng, 40);
    let tree = LightTree::build(&lights).unwrap();
    let points = [
        (Vec3::ZERO, Vec3::Y),
        (
            Vec3::new(9.0, -9.0, 2.0),
            Vec3::new(-1.0, 1.0, 0.0).normalize(),
        ),
        (Vec3::new(0.0, 30.0, 0.0), Vec3::ZERO),
    ];
    let samples = 200_000;
    for (p, n) in points {
        let mut observed = vec![0.0; lights.len()];
        for _ in 0..samples {
            observed[tree.pick(p, n, rng.next_f32()).0] += 1.0;
        }
        let expected: Vec<f64> = (0..lights.len())
            .map(|i| f64::from(tree.pmf(i, p, n)) * samples as f64)
            .collect();
        chi_square_test(&observed, &expected, points.len()).unwrap();
    }
}

#[test]
fn every_light_keeps_a_chance_and_the_bound_favours_the_lights_that_matter() {
    let near = LightBounds::triangle(
        [
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.1, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.1),
        ],
        1.0,
        false,
    );
    // The same triangle, far away, and one close by facing away from the point.
    let far = LightBounds {
        min: near.min + Vec3::new(0.0, 10.0, 0.0),
        max: near.max + Vec3::new(0.0, 10.0, 0.0),
        ..near
    };
    let facing_away = LightBounds {
        min: near.min - Vec3::new(0.0, 2.0, 0.0),
        max: near.max - Vec3::new(0.0, 2.0, 0.0),
        axis: -near.axis,
        ..near
    };
    // The near triangle's normal: (v1 - v0) x (v2 - v0) = +x by +z = -y, pointing down to p.
    assert!(near.axis.abs_diff_eq(Vec3::NEG_Y, 1e-6));
    let tree = LightTree::build(&[near, far, facing_away]).unwrap();
    let (p, n) = (Vec3::ZERO, Vec3::Y);
    let [p_near, p_far, p_away] = [0, 1, 2].map(|i| tree.pmf(i, p, n));
    assert!(p_near > 0.9, "{p_near} {p_far} {p_away}");
    assert!(p_far > 0.0 && p_far < 0.05 && p_away > 0.0 && p_away < UNIFORM_SHARE);
    // Below the surface: the near light is behind the receiver's horizon.
    let p_below = tree.pmf(0, p, Vec3::NEG_Y);
    assert!(p_below < 0.02, "{p_below}");
}

#[test]
fn cone_union_holds_both_cones() {
    let mut rng = Pcg32::new(5, 5);
    for _ in 0..10_000 {
        let cone = |rng: &mut Pcg32| LightBounds {
            axis: random_unit(rng),
            theta_o: rng.next_f32() * PI,
            theta_e: rng.next_f32() * PI / 2.0,
            ..LightBounds::point(Vec3::ZERO, 1.0)
        };
        let (a, b) = (cone(&mut rng), cone(&mut rng));
        let (axis, theta_o, theta_e) = union_cone(&a, &b);
        assert!((axis.length() - 1.0).abs() < 1e-4);
        assert!(theta_e >= a.theta_e.max(b.theta_e));
        for c in [a, b] {
            let needed = angle_between(axis, c.axis) + c.theta_o;
            assert!(
                theta_o >= needed.min(PI) - 1e-4,
                "union {theta_o} around {axis} misses {c:?}: needs {needed}"
            );
        }
    }
}

#[test]
fn degenerate_input_is_safe() {
    assert!(LightTree::build(&[]).is_none());
    // Coincident lights, zero power, a point exactly at a light.
    let point = LightBounds::point(Vec3::ONE, 1.0);
    let dark = LightBounds::point(Vec3::ONE, 0.0);
    let tree = LightTree::build(&[point, point, dark, point]).unwrap();
    let total: f32 = (0..4).map(|i| tree.pmf(i, Vec3::ONE, Vec3::Y)).sum();
    assert!((total - 1.0).abs() < 1e-5);
    assert!(tree.pmf(2, Vec3::ZERO, Vec3::Y) > 0.0);
    let (light, pmf) = tree.pick(Vec3::ONE, Vec3::Y, 0.999_999_9);
    assert!(light < 4 && pmf.is_finite() && pmf > 0.0);
}

#[test]
fn the_flat_tree_links_up_and_down() {
    let mut rng = Pcg32::new(11, 2);
    for n in [1, 2, 5, 64] {
        let lights = random_lights(&mut rng, n);
        let tree = LightTree::build(&lights).unwrap();
        let nodes = tree.nodes();
        assert_eq!(nodes.len(), 2 * n - 1);
        assert_eq!(nodes[0].parent, NO_PARENT);
        for (light, &leaf) in tree.leaves().iter().enumerate() {
            let node = nodes[leaf as usize];
            assert!(node.leaf && node.first as usize == light);
            assert_eq!(node.bounds, lights[light]);
        }
        for (i, node) in nodes.iter().enumerate().filter(|(_, n)| !n.leaf) {
            let first = node.first as usize;
            assert!(first > i);
            assert_eq!(nodes[first].parent as usize, i);
            assert_eq!(nodes[first + 1].parent as usize, i);
        }
    }
}

/// The depth of `node` in `tree`: its parent links up to the root.
fn depth(tree: &LightTree, mut node: usize) -> usize {
    let mut levels = 0;
    while tree.nodes()[node].parent != NO_PARENT {
        node = tree.nodes()[node].parent as usize;
        levels += 1;
    }
    levels
}

#[test]
fn far_apart_clusters_get_subtrees_of_their_own() {
    // Three lights by the origin and two 1e5 away (hard-cases' far copy): the root cuts
    // between the clusters (the median cut would put the third near light with the far ones),
    // so a point by the origin weighs the far ones by their distance, not by their power alone
    // inside a box that holds both clusters.
    let near = [0.0, 1.0, 2.0].map(|x| Vec3::new(x, 0.0, 0.0));
    let far = [1e5, 1e5 + 1.0].map(|x| Vec3::new(x, 0.0, 0.0));
    let lights: Vec<LightBounds> = near
        .iter()
        .chain(&far)
        .map(|&p| LightBounds::point(p, 100.0))
        .collect();
    let tree = LightTree::build(&lights).unwrap();
    let root = tree.nodes()[0];
    let first = tree.nodes()[root.first as usize].bounds;
    let second = tree.nodes()[root.first as usize + 1].bounds;
    let (lo, hi) = if first.max.x < second.min.x {
        (first, second)
    } else {
        (second, first)
    };
    assert!(lo.max.x <= 2.0 && hi.min.x >= 1e5, "{lo:?} {hi:?}");
    let p = Vec3::new(0.5, 1.0, 0.0);
    let near_share: f32 = (0..3).map(|i| tree.pmf(i, p, Vec3::ZERO)).sum();
    assert!(near_share > 0.98, "{near_share}");
}

#[test]
fn the_depth_stays_within_the_gpu_walks_bound() {
    // Lights along a row at distances growing fourfold from one to the next: the heuristic
    // alone cuts near the far end level after level (depth 39 here, measured, against a bound
    // of 30); below SAH_LEVELS the cuts are at the median.
    let n = 60;
    let lights: Vec<LightBounds> = (0..n)
        .map(|i| LightBounds::point(Vec3::new(4f32.powi(i as i32), 0.0, 0.0), 1.0))
        .collect();
    let tree = LightTree::build(&lights).unwrap();
    let deepest = tree
        .leaves()
        .iter()
        .map(|&leaf| depth(&tree, leaf as usize))
        .max()
        .unwrap();
    let bound = SAH_LEVELS + (n as f32).log2().ceil() as usize;
    assert!(deepest <= bound, "depth {deepest}, bound {bound}");
    let total: f32 = (0..n)
        .map(|i| tree.pmf(i, Vec3::new(3.0, 1.0, 0.0), Vec3::Y))
        .sum();
    assert!((total - 1.0).abs() < 1e-4, "{total}");
}
