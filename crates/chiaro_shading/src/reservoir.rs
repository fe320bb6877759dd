//! Weighted reservoir sampling for resampled importance sampling (RIS) and its reuse across
//! pixels and frames, as ReSTIR does it (Bitterli et al., "Spatiotemporal Reservoir Resampling
//! for Real-Time Ray Tracing with Dynamic Direct Lighting", SIGGRAPH 2020, algorithms 1 to 4;
//! Talbot et al., "Importance Resampling for Global Illumination", EGSR 2005, for RIS).
//!
//! A reservoir streams candidates x_i, each with a resampling weight w_i, and keeps one, x_i
//! with probability w_i / sum w. For candidates drawn from a source pdf p, w_i = p_hat(x_i) /
//! p(x_i) for a target function p_hat, and f(y) W with the contribution weight
//! W = sum w / (M p_hat(y)) is an unbiased estimate of the integral of f wherever p_hat > 0
//! covers f's support.
//!
//! Reuse merges reservoirs of other pixels (or of the last frame): each enters with the
//! weight p_hat_here(y_j) W_j M_j. Normalising the sum by the total count M (`1/M`) is biased
//! where the other domains cannot produce every sample this one can (another surface's
//! hemisphere, another visibility); normalising by Z, the counts of only those domains whose
//! target is nonzero at the sample kept, is unbiased (Bitterli et al., section 4.3).
//!
//! `shaders/lib/reservoir.wgsl` mirrors this for the GPU's direct light.

/// A reservoir holding at most one sample of type `S`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reservoir<S> {
    /// The sample kept, if any candidate had a positive weight.
    pub sample: Option<S>,
    /// The sum of the candidates' resampling weights.
    pub weight_sum: f32,
    /// Candidates seen (M), a merged reservoir's counting as many as it saw.
    pub count: u32,
    /// The contribution weight W set by [`Reservoir::finish`] (0 before, or with no sample).
    pub contribution_weight: f32,
}

impl<S> Default for Reservoir<S> {
    fn default() -> Self {
        Self {
            sample: None,
            weight_sum: 0.0,
            count: 0,
            contribution_weight: 0.0,
        }
    }
}

impl<S: Copy> Reservoir<S> {
    /// An empty reservoir.
    pub fn new() -> Self {
        Self::default()
    }

    /// Streams `count` candidates' worth of `sample` with resampling weight `weight`, keeping
    /// it with probability `weight / weight_sum` decided by `u` in [0, 1). A weight that is
    /// not finite and positive counts the candidates but can never be kept nor change the
    /// sum, so a NaN or an infinity does not spread. Returns whether `sample` was kept.
    pub fn stream(&mut self, sample: S, weight: f32, count: u32, u: f32) -> bool {
        self.count += count;
        if !(weight > 0.0 && weight.is_finite()) {
            return false;
        }
        self.weight_sum += weight;
        let kept = u * self.weight_sum < weight;
        if kept {
            self.sample = Some(sample);
        }
        kept
    }

    /// Streams one candidate (RIS: weight = p_hat(x) / p(x)).
    pub fn update(&mut self, sample: S, weight: f32, u: f32) -> bool {
        self.stream(sample, weight, 1, u)
    }

    /// Merges `other`, whose sample's target function here is `target_here`: it enters with
    /// weight `target_here * W * M` and adds its count. Returns whether its sample was kept.
    pub fn merge(&mut self, other: &Reservoir<S>, target_here: f32, u: f32) -> bool {
        match other.sample {
            Some(sample) => {
                let weight = target_here * other.contribution_weight * other.count as f32;
                self.stream(sample, weight, other.count, u)
            }
            None => {
                self.count += other.count;
                false
            }
        }
    }

    /// Sets the contribution weight W = weight_sum / (normaliser * p_hat(y)) for the kept
    /// sample's target `target` here: `normaliser` is the count M (biased under reuse across
    /// domains) or Z, the counts of the domains that could have produced the sample
    /// (unbiased). W is 0 with no sample, a zero target or a zero normaliser.
    pub fn finish(&mut self, target: f32, normaliser: u32) {
        self.contribution_weight = if self.sample.is_some() && target > 0.0 && normaliser > 0 {
            self.weight_sum / (normaliser as f32 * target)
        } else {
            0.0
        };
    }

    /// Caps the count at `cap` (the history cap of temporal reuse), scaling the weight sum
    /// with it so that W stays the same.
    pub fn cap_count(&mut self, cap: u32) {
        if self.count > cap {
            self.weight_sum *= cap as f32 / self.count as f32;
            self.count = cap;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;

    /// Mean and standard error of `n` draws of `estimate`.
    fn mean_and_error(n: u32, mut estimate: impl FnMut() -> f64) -> (f64, f64) {
        let (mut sum, mut squares) = (0.0, 0.0);
        for _ in 0..n {
            let x = estimate();
            sum += x;
            squares += x * x;
        }
        let mean = sum / f64::from(n);
        let variance = (squares / f64::from(n) - mean * mean).max(0.0);
        (mean, (variance / f64::from(n)).sqrt())
    }

    /// One RIS reservoir over `candidates` uniform draws on [0, 1) for `target`, finished
    /// with its own count.
    fn ris(rng: &mut Pcg32, candidates: u32, target: impl Fn(f32) -> f32) -> Reservoir<f32> {
        let mut r = Reservoir::new();
        for _ in 0..candidates {
            let x = rng.next_f32();
            r.update(x, target(x), rng.next_f32());
        }
        let t = r.sample.map_or(0.0, &target);
        r.finish(t, r.count);
        r
    }

    #[test]
    fn keeps_each_candidate_in_proportion_to_its_weight() {
        let weights = [1.0, 2.0, 3.0, 4.0];
        let mut rng = Pcg32::new(7, 1);
        let mut kept = [0u32; 4];
        let n = 40_000;
        for _ in 0..n {
            let mut r = Reservoir::new();
            for (i, w) in weights.iter().enumerate() {
                r.update(i, *w, rng.next_f32());
            }
            kept[r.sample.unwrap()] += 1;
        }
        for (i, w) in weights.iter().enumerate() {
            let expected = w / 10.0;
            let got = kept[i] as f32 / n as f32;
            // The binomial's standard error is at most 0.0025 here.
            assert!(
                (got - expected).abs() < 0.01,
                "candidate {i}: {got} vs {expected}"
            );
        }
    }

    #[test]
    fn resampled_estimate_is_unbiased_and_beats_its_source() {
        let f = |x: f32| x * x * x + 0.01;
        let exact = 0.25 + 0.01;
        let mut rng = Pcg32::new(3, 9);
        // Target x^3 + 0.01 is f itself: the more candidates, the closer to f / integral.
        let (mean, error) = mean_and_error(100_000, || {
            let r = ris(&mut rng, 8, f);
            f64::from(r.sample.map_or(0.0, |y| f(y) * r.contribution_weight))
        });
        assert!(
            (mean - exact).abs() < 4.0 * error,
            "{mean} vs {exact} (+- {error})"
        );
        let (plain, plain_error) = mean_and_error(100_000, || f64::from(f(rng.next_f32())));
        assert!((plain - exact).abs() < 4.0 * plain_error);
        assert!(
            error < 0.5 * plain_error,
            "RIS {error} vs uniform {plain_error}"
        );
    }

    #[test]
    fn merged_reservoirs_estimate_what_their_candidates_would() {
        let f = |x: f32| (6.0 * x).sin().abs() + 0.05;
        // Its integral over [0, 1), by the midpoint rule.
        let quadrature: f64 = (0..100_000)
            .map(|i| f64::from(f((i as f32 + 0.5) / 100_000.0)))
            .sum::<f64>()
            / 100_000.0;
        let mut rng = Pcg32::new(5, 2);
        let (mean, error) = mean_and_error(50_000, || {
            let mut merged = Reservoir::new();
            for _ in 0..4 {
                let other = ris(&mut rng, 2, f);
                let t = other.sample.map_or(0.0, f);
                merged.merge(&other, t, rng.next_f32());
            }
            assert_eq!(merged.count, 8);
            let t = merged.sample.map_or(0.0, f);
            merged.finish(t, merged.count);
            f64::from(
                merged
                    .sample
                    .map_or(0.0, |y| f(y) * merged.contribution_weight),
            )
        });
        assert!(
            (mean - quadrature).abs() < 4.0 * error,
            "{mean} vs {quadrature} (+- {error})"
        );
    }

    #[test]
    fn normalising_by_z_is_unbiased_where_normalising_by_m_is_not() {
        // This pixel's target covers [0, 1); the neighbour's only [0, 0.5) (another surface
        // that cannot see half of what this one sees).
        let here = |x: f32| x + 0.1;
        let neighbour = |x: f32| if x < 0.5 { 1.0 } else { 0.0 };
        let f = here;
        let exact = 0.5 + 0.1;
        let mut rng = Pcg32::new(11, 4);
        let estimate = |unbiased: bool, rng: &mut Pcg32| {
            let own = ris(rng, 4, here);
            let other = ris(rng, 4, neighbour);
            let mut merged = Reservoir::new();
            for r in [&own, &other] {
                let t = r.sample.map_or(0.0, here);
                merged.merge(r, t, rng.next_f32());
            }
            let Some(y) = merged.sample else {
                return 0.0;
            };
            let z = if unbiased {
                own.count + if neighbour(y) > 0.0 { other.count } else { 0 }
            } else {
                merged.count
            };
            merged.finish(here(y), z);
            f64::from(f(y) * merged.contribution_weight)
        };
        let (unbiased, error) = mean_and_error(100_000, || estimate(true, &mut rng));
        assert!(
            (unbiased - exact).abs() < 4.0 * error,
            "1/Z: {unbiased} vs {exact} (+- {error})"
        );
        let (biased, error) = mean_and_error(100_000, || estimate(false, &mut rng));
        assert!(
            (biased - exact).abs() > 10.0 * error,
            "1/M should be biased: {biased} vs {exact} (+- {error})"
        );
    }

    #[test]
    fn non_finite_weights_are_counted_but_never_kept() {
        let mut r = Reservoir::new();
        assert!(r.update(1, 2.0, 0.5));
        for bad in [f32::NAN, f32::INFINITY, -1.0, 0.0] {
            assert!(!r.update(2, bad, 0.0));
        }
        assert_eq!(r.sample, Some(1));
        assert_eq!(r.count, 5);
        assert_eq!(r.weight_sum, 2.0);
        r.finish(4.0, r.count);
        assert_eq!(r.contribution_weight, 0.1);
        let mut nan_target = r;
        nan_target.finish(f32::NAN, 5);
        assert_eq!(nan_target.contribution_weight, 0.0);
    }

    #[test]
    fn capping_the_count_keeps_the_contribution_weight() {
        let mut rng = Pcg32::new(1, 1);
        let mut r = ris(&mut rng, 64, |x| x + 0.5);
        let t = r.sample.map(|x| x + 0.5).unwrap();
        let before = r.contribution_weight;
        r.cap_count(20);
        assert_eq!(r.count, 20);
        r.finish(t, r.count);
        assert!((r.contribution_weight - before).abs() < 1e-5 * before);
    }
}
