use super::*;

/// The first Sobol dimension of point `index` as a 32-bit fraction: the van der Corput radical
/// inverse, the index's bits reversed.
fn sobol_first(index: u32) -> u32 {
    index.reverse_bits()
}

/// The nested uniform scramble of the 32-bit fraction `x`.
fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    scramble_reversed(x.reverse_bits(), seed)
}

/// The second Sobol dimension of point `index` as a 32-bit fraction.
fn sobol_second(index: u32) -> u32 {
    sobol_second_reversed(index).reverse_bits()
}

/// The points of sample `index`'s `draws`-th two-number draw (after `draws` earlier ones).
fn vec2_draw(sampler: &mut OwenSobol, index: u32, draws: usize) -> Vec2 {
    sampler.start_sample(index);
    for _ in 0..draws {
        sampler.next_vec2();
    }
    sampler.next_vec2()
}

#[test]
fn the_unscrambled_points_are_sobol_s() {
    let points: Vec<(f32, f32)> = (0..8)
        .map(|i| (to_unit(sobol_first(i)), to_unit(sobol_second(i))))
        .collect();
    let expected = [
        (0.0, 0.0),
        (0.5, 0.5),
        (0.25, 0.75),
        (0.75, 0.25),
        (0.125, 0.625),
        (0.625, 0.125),
        (0.375, 0.375),
        (0.875, 0.875),
    ];
    assert_eq!(points, expected);
}

#[test]
fn the_scramble_is_nested() {
    // Two fractions agreeing on their top k bits still agree on them after the scramble, and
    // differing values stay different (a permutation).
    let mut rng = chiaro_shading::rng::Pcg32::new(1, 2);
    for _ in 0..10_000 {
        let (a, seed, k) = (rng.next_u32(), rng.next_u32(), rng.next_u32() % 32);
        let b = a ^ (rng.next_u32() >> k).max(1);
        let (sa, sb) = (
            nested_uniform_scramble(a, seed),
            nested_uniform_scramble(b, seed),
        );
        assert_ne!(sa, sb);
        let top = |x: u32| x.checked_shr(32 - k).unwrap_or(0);
        assert_eq!(top(sa), top(sb), "{a:#x} {b:#x} seed {seed:#x} k {k}");
    }
}

#[test]
fn the_first_power_of_two_samples_of_a_draw_are_a_net() {
    // (0, m, 2)-net: each of the 2^m boxes of 2^-a by 2^-(m-a) holds exactly one point.
    for (seed, pixel, draws) in [(0, 0, 0), (7, 12_345, 1), (3, 99, 5)] {
        let mut sampler = OwenSobol::new(seed, pixel, 1);
        for m in 0..=8u32 {
            let n = 1u32 << m;
            let points: Vec<Vec2> = (0..n).map(|i| vec2_draw(&mut sampler, i, draws)).collect();
            for a in 0..=m {
                let (cols, rows) = (1u32 << a, 1u32 << (m - a));
                let mut count = vec![0u32; n as usize];
                for p in &points {
                    let (cx, cy) = ((p.x * cols as f32) as u32, (p.y * rows as f32) as u32);
                    count[(cy * cols + cx) as usize] += 1;
                }
                assert!(
                    count.iter().all(|&c| c == 1),
                    "seed {seed}, pixel {pixel}, draw {draws}: {n} points in {cols}x{rows} boxes"
                );
            }
        }
    }
}

#[test]
fn the_first_power_of_two_samples_of_a_one_number_draw_are_stratified() {
    let mut sampler = OwenSobol::new(5, 77, 0);
    for m in 0..=10u32 {
        let n = 1u32 << m;
        let mut count = vec![0u32; n as usize];
        for i in 0..n {
            sampler.start_sample(i);
            sampler.next_vec2();
            let x = sampler.next_f32();
            count[(x * n as f32) as usize] += 1;
        }
        assert!(count.iter().all(|&c| c == 1), "{n} numbers");
    }
}

#[test]
fn a_sample_is_uniform_over_the_pixels() {
    // Owen scrambling makes each point uniformly distributed: sample 0 of a draw over 16384
    // pixels, in 16 x 16 boxes, passes a chi-square test (255 degrees of freedom; 99.9% point
    // 330).
    let n = 16_384;
    let mut count = [0f64; 256];
    for pixel in 0..n {
        let p = vec2_draw(&mut OwenSobol::new(3, pixel, 0), 0, 2);
        count[(p.y * 16.0) as usize * 16 + (p.x * 16.0) as usize] += 1.0;
    }
    let expected = n as f64 / 256.0;
    let chi2: f64 = count
        .iter()
        .map(|c| (c - expected).powi(2) / expected)
        .sum();
    assert!(chi2 < 330.0, "chi-square {chi2}");
}

#[test]
fn draws_are_not_correlated_with_each_other() {
    // Each draw takes the points in an order of its own: over a pixel's 1024 samples the first
    // numbers of two draws have a correlation near zero (its standard error is 1/32).
    let mut sampler = OwenSobol::new(11, 4, 0);
    let pairs: Vec<(f64, f64)> = (0..1024)
        .map(|i| {
            sampler.start_sample(i);
            let a = sampler.next_vec2().x as f64;
            (a, sampler.next_vec2().x as f64)
        })
        .collect();
    let mean = |f: &dyn Fn(&(f64, f64)) -> f64| pairs.iter().map(f).sum::<f64>() / 1024.0;
    let (ma, mb) = (mean(&|p| p.0), mean(&|p| p.1));
    let covariance = mean(&|p| (p.0 - ma) * (p.1 - mb));
    let correlation =
        covariance / (mean(&|p| (p.0 - ma).powi(2)) * mean(&|p| (p.1 - mb).powi(2))).sqrt();
    assert!(correlation.abs() < 0.15, "correlation {correlation}");
}

#[test]
fn halves_and_pixels_differ_and_a_seed_repeats() {
    let first = |seed, pixel, half| vec2_draw(&mut OwenSobol::new(seed, pixel, half), 3, 1);
    assert_eq!(first(1, 2, 0), first(1, 2, 0));
    assert_ne!(first(1, 2, 0), first(1, 2, 1));
    assert_ne!(first(1, 2, 0), first(1, 3, 0));
    assert_ne!(first(1, 2, 0), first(2, 2, 0));
}

#[test]
fn a_stream_reads_the_same_numbers_whatever_came_before() {
    let light = |camera_draws: usize| {
        let mut sampler = OwenSobol::new(9, 8, 0);
        sampler.start_sample(5);
        for _ in 0..camera_draws {
            sampler.next_f32();
        }
        sampler.start_stream(Stream::Light);
        (sampler.next_f32(), sampler.next_vec2())
    };
    assert_eq!(light(0), light(7));
}

#[test]
fn the_shuffled_coordinate_is_the_radical_inverse_of_the_shuffled_index() {
    let mut rng = chiaro_shading::rng::Pcg32::new(5, 6);
    let mut sampler = OwenSobol::new(1, 2, 0);
    for _ in 0..1000 {
        let (index, seed) = (rng.next_u32(), rng.next_u32());
        sampler.start_sample(index);
        assert_eq!(
            sampler.shuffled_first(seed),
            sobol_first(nested_uniform_scramble(index, seed))
        );
    }
}

#[test]
fn a_choice_and_its_pair_are_a_three_dimensional_net() {
    // The first three Sobol dimensions are a (1, 3)-sequence: 2^m points put exactly two in each
    // box of 2^-a by 2^-b by 2^-c with a + b + c = m - 1, scrambled or not.
    let mut sampler = OwenSobol::new(2, 31, 0);
    for m in 1..=8u32 {
        let n = 1u32 << m;
        let points: Vec<(f32, Vec2)> = (0..n)
            .map(|i| {
                sampler.start_sample(i);
                sampler.next_f32();
                sampler.next_choice_and_vec2()
            })
            .collect();
        for a in 0..m {
            for b in 0..m - a {
                let c = m - 1 - a - b;
                let (na, nb, nc) = (1u32 << a, 1u32 << b, 1u32 << c);
                let mut count = vec![0u32; (na * nb * nc) as usize];
                for (choice, p) in &points {
                    let cell = ((choice * na as f32) as u32 * nb + (p.x * nb as f32) as u32) * nc
                        + (p.y * nc as f32) as u32;
                    count[cell as usize] += 1;
                }
                assert!(
                    count.iter().all(|&k| k == 2),
                    "{n} points in {na}x{nb}x{nc} boxes"
                );
            }
        }
    }
}
