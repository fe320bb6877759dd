//! Discrete distributions proportional to non-negative weights, sampled by inverting the CDF.
//!
//! [`Distribution1D`] picks an index (lights by power, environment rows); [`Distribution2D`] picks
//! a cell of a grid as a marginal over rows times a conditional per row (environment texels), as
//! in Pharr, Jakob and Humphreys, 2016, "Physically Based Rendering", 3rd ed., section 13.6.7.
//!
//! Sampling is a binary search over the CDF, O(log n). Sums are accumulated in f64 and the CDF is
//! stored in f32 with its last entry exactly 1, so a uniform number in [0, 1) always lands on an
//! index of positive weight. The probability masses reported are `weight / total`.

use glam::Vec2;

/// The largest f32 below 1: uniform numbers are clamped to [0, this].
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A distribution over the indices 0..n proportional to non-negative weights.
///
/// ```
/// use chiaro_shading::distribution::Distribution1D;
///
/// let d = Distribution1D::new(&[1.0, 0.0, 3.0]).unwrap();
/// assert_eq!(d.sample(0.1), (0, 0.25));
/// assert_eq!(d.sample(0.5), (2, 0.75));
/// assert_eq!(d.pmf(1), 0.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    /// The weights as given.
    weights: Vec<f32>,
    /// n + 1 entries, cdf[0] = 0, cdf[n] = 1, non-decreasing.
    cdf: Vec<f32>,
    /// Sum of the weights.
    total: f32,
    /// 1 / total, in f64 for the masses.
    inv_total: f64,
}

impl Distribution1D {
    /// A distribution proportional to `weights`. None when there are no weights, any weight is
    /// negative or not finite, or they sum to zero (or to more than f32 can hold).
    pub fn new(weights: &[f32]) -> Option<Self> {
        if weights.is_empty() || weights.iter().any(|w| !w.is_finite() || *w < 0.0) {
            return None;
        }
        let total: f64 = weights.iter().map(|&w| w as f64).sum();
        if total <= 0.0 || !(total as f32).is_finite() {
            return None;
        }
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        cdf.push(0.0);
        let mut running = 0.0f64;
        for &w in weights {
            running += w as f64;
            cdf.push((running / total) as f32);
        }
        // Exactly 1 at the end, and at every entry after the last positive weight, so those
        // zero-weight entries can never be chosen.
        let last_positive = weights.iter().rposition(|&w| w > 0.0).unwrap_or(0);
        for c in &mut cdf[last_positive + 1..] {
            *c = 1.0;
        }
        Some(Self {
            weights: weights.to_vec(),
            cdf,
            total: total as f32,
            inv_total: 1.0 / total,
        })
    }

    /// The number of indices.
    pub fn len(&self) -> usize {
        self.weights.len()
    }

    /// Always false: a distribution has at least one index (see [`Distribution1D::new`]).
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// The sum of the weights.
    pub fn total(&self) -> f32 {
        self.total
    }

    /// The CDF: `len() + 1` entries from 0 to exactly 1, non-decreasing (for a GPU copy).
    pub fn cdf(&self) -> &[f32] {
        &self.cdf
    }

    /// The probability of picking `index`: its weight over the total (0 outside the range).
    pub fn pmf(&self, index: usize) -> f32 {
        self.weights
            .get(index)
            .map_or(0.0, |&w| (w as f64 * self.inv_total) as f32)
    }

    /// Picks an index for the uniform number `u` in [0, 1) (clamped into it): the index whose CDF
    /// interval holds `u`. Returns the index and its probability mass; the mass is always
    /// positive.
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let (index, pmf, _) = self.sample_remapped(u);
        (index, pmf)
    }

    /// Like [`Distribution1D::sample`], and also returns where `u` fell inside the chosen index's
    /// CDF interval, rescaled to [0, 1): a fresh uniform number for a further choice (used to place
    /// a point inside an environment texel without another random number).
    pub fn sample_remapped(&self, u: f32) -> (usize, f32, f32) {
        let u = if u.is_nan() {
            0.0
        } else {
            u.clamp(0.0, ONE_MINUS_EPSILON)
        };
        let n = self.weights.len();
        // The largest index i in 0..n with cdf[i] <= u. cdf[0] = 0 <= u, so it exists.
        let index = self.cdf[1..n].partition_point(|&c| c <= u);
        let (lo, hi) = (self.cdf[index], self.cdf[index + 1]);
        let width = hi - lo;
        let remapped = if width > 0.0 {
            ((u - lo) / width).clamp(0.0, ONE_MINUS_EPSILON)
        } else {
            0.0
        };
        (index, self.pmf(index), remapped)
    }
}

/// A distribution over the cells of a `width` x `height` grid proportional to non-negative
/// weights: a row from the marginal (row sums), then a column from that row's conditional.
///
/// ```
/// use chiaro_shading::distribution::Distribution2D;
/// use glam::Vec2;
///
/// // 2 x 2, row-major: row 0 = [0, 1], row 1 = [1, 2].
/// let d = Distribution2D::new(&[0.0, 1.0, 1.0, 2.0], 2, 2).unwrap();
/// let (x, y, pmf) = d.sample(Vec2::new(0.9, 0.9));
/// assert_eq!((x, y), (1, 1));
/// assert!((pmf - 0.5).abs() < 1e-6);
/// assert_eq!(d.pmf(0, 0), 0.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2D {
    width: usize,
    height: usize,
    /// One per row; rows of zero weight get a uniform placeholder that is never chosen.
    conditional: Vec<Distribution1D>,
    /// Over the rows, proportional to their sums.
    marginal: Distribution1D,
}

impl Distribution2D {
    /// A distribution over a grid whose row-major `weights` (row y, column x at `y * width + x`)
    /// number `width * height`. None when the size does not match or is zero, any weight is
    /// negative or not finite, or they sum to zero.
    pub fn new(weights: &[f32], width: usize, height: usize) -> Option<Self> {
        let count = width.checked_mul(height)?;
        if count == 0 || weights.len() != count {
            return None;
        }
        if weights.iter().any(|w| !w.is_finite() || *w < 0.0) {
            return None;
        }
        let mut row_sums = Vec::with_capacity(height);
        let mut conditional = Vec::with_capacity(height);
        let uniform = vec![1.0; width];
        for row in weights.chunks_exact(width) {
            row_sums.push(row.iter().map(|&w| w as f64).sum::<f64>() as f32);
            let d = Distribution1D::new(row).or_else(|| Distribution1D::new(&uniform))?;
            conditional.push(d);
        }
        let marginal = Distribution1D::new(&row_sums)?;
        Some(Self {
            width,
            height,
            conditional,
            marginal,
        })
    }

    /// Grid width (columns).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Grid height (rows).
    pub fn height(&self) -> usize {
        self.height
    }

    /// The sum of all weights.
    pub fn total(&self) -> f32 {
        self.marginal.total()
    }

    /// The distribution over rows (for a GPU copy).
    pub fn marginal(&self) -> &Distribution1D {
        &self.marginal
    }

    /// The distribution over the columns of row `y` (for a GPU copy); `None` past the last row.
    pub fn conditional(&self, y: usize) -> Option<&Distribution1D> {
        self.conditional.get(y)
    }

    /// The probability of picking cell (x, y): row mass times column mass within the row (equal
    /// to weight / total up to rounding); 0 outside the grid.
    pub fn pmf(&self, x: usize, y: usize) -> f32 {
        if x >= self.width || y >= self.height {
            return 0.0;
        }
        self.marginal.pmf(y) * self.conditional[y].pmf(x)
    }

    /// Picks a cell: `u.y` chooses the row, `u.x` the column. Returns (x, y, probability mass).
    pub fn sample(&self, u: Vec2) -> (usize, usize, f32) {
        let (x, y, pmf, _) = self.sample_remapped(u);
        (x, y, pmf)
    }

    /// Like [`Distribution2D::sample`], and also returns both uniform numbers remapped into the
    /// chosen cell (see [`Distribution1D::sample_remapped`]): a uniformly distributed position
    /// inside the cell, x then y.
    pub fn sample_remapped(&self, u: Vec2) -> (usize, usize, f32, Vec2) {
        let (y, row_pmf, v) = self.marginal.sample_remapped(u.y);
        let (x, column_pmf, w) = self.conditional[y].sample_remapped(u.x);
        (x, y, row_pmf * column_pmf, Vec2::new(w, v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;
    use crate::test_util::chi_square_test;

    #[test]
    fn rejects_bad_weights() {
        assert!(Distribution1D::new(&[]).is_none());
        assert!(Distribution1D::new(&[0.0, 0.0]).is_none());
        assert!(Distribution1D::new(&[1.0, -1.0]).is_none());
        assert!(Distribution1D::new(&[1.0, f32::NAN]).is_none());
        assert!(Distribution1D::new(&[1.0, f32::INFINITY]).is_none());
        assert!(Distribution1D::new(&[f32::MAX, f32::MAX]).is_none());
        assert!(Distribution2D::new(&[1.0; 6], 2, 2).is_none());
        assert!(Distribution2D::new(&[], 0, 0).is_none());
        assert!(Distribution2D::new(&[0.0; 4], 2, 2).is_none());
        assert!(Distribution2D::new(&[1.0, -1.0, 1.0, 1.0], 2, 2).is_none());
        assert!(Distribution2D::new(&[1.0], usize::MAX, 2).is_none());
    }

    #[test]
    fn masses_sum_to_one_and_match_weights() {
        let w = [0.5, 0.0, 2.0, 1.5, 0.0, 0.0];
        let d = Distribution1D::new(&w).unwrap();
        assert_eq!(d.len(), 6);
        assert!(!d.is_empty());
        assert_eq!(d.total(), 4.0);
        let sum: f32 = (0..w.len()).map(|i| d.pmf(i)).sum();
        assert!((sum - 1.0).abs() < 1e-6);
        assert_eq!(d.pmf(2), 0.5);
        assert_eq!(d.pmf(99), 0.0);
    }

    #[test]
    fn never_picks_zero_weights_even_at_the_ends() {
        let d = Distribution1D::new(&[0.0, 1.0, 0.0, 0.0, 1.0, 0.0]).unwrap();
        for u in [
            0.0,
            1e-9,
            0.25,
            0.5,
            0.5 - 1e-8,
            0.75,
            0.999_999_9,
            1.0,
            2.0,
            -1.0,
            f32::NAN,
        ] {
            let (i, p) = d.sample(u);
            assert!(i == 1 || i == 4, "u = {u} -> {i}");
            assert_eq!(p, 0.5);
        }
        assert_eq!(d.sample(0.49).0, 1);
        assert_eq!(d.sample(0.5).0, 4);
        let single = Distribution1D::new(&[3.0]).unwrap();
        assert_eq!(single.sample(0.7), (0, 1.0));
    }

    #[test]
    fn remapped_number_is_uniform_within_the_interval() {
        let d = Distribution1D::new(&[1.0, 3.0]).unwrap();
        let (i, _, r) = d.sample_remapped(0.25 + 0.75 * 0.5);
        assert_eq!(i, 1);
        assert!((r - 0.5).abs() < 1e-6);
        let (i, _, r) = d.sample_remapped(0.125);
        assert_eq!(i, 0);
        assert!((r - 0.5).abs() < 1e-6);
    }

    #[test]
    fn one_dimensional_frequencies_match_pmf() {
        let mut rng = Pcg32::new(17, 1);
        let w: Vec<f32> = (0..40)
            .map(|i| {
                if i % 7 == 3 {
                    0.0
                } else {
                    rng.next_f32().powi(2) * 5.0
                }
            })
            .collect();
        let d = Distribution1D::new(&w).unwrap();
        let n = 200_000;
        let mut counts = vec![0.0f64; w.len()];
        for _ in 0..n {
            let (i, p) = d.sample(rng.next_f32());
            assert_eq!(p, d.pmf(i));
            counts[i] += 1.0;
        }
        let expected: Vec<f64> = (0..w.len()).map(|i| d.pmf(i) as f64 * n as f64).collect();
        chi_square_test(&counts, &expected, 1).unwrap();
    }

    #[test]
    fn two_dimensional_frequencies_match_pmf() {
        let (width, height) = (12, 9);
        let mut rng = Pcg32::new(23, 5);
        let mut w: Vec<f32> = (0..width * height).map(|_| rng.next_f32()).collect();
        // An all-zero row and a zero column cell.
        for x in 0..width {
            w[4 * width + x] = 0.0;
        }
        w[2 * width + 7] = 0.0;
        let d = Distribution2D::new(&w, width, height).unwrap();
        assert_eq!((d.width(), d.height()), (width, height));
        let total: f32 = w.iter().sum();
        assert!((d.total() - total).abs() < 1e-4);
        let mut sum = 0.0;
        for y in 0..height {
            for x in 0..width {
                let p = d.pmf(x, y);
                assert!((p - w[y * width + x] / total).abs() < 1e-6);
                sum += p;
            }
        }
        assert!((sum - 1.0).abs() < 1e-5);
        let n = 200_000;
        let mut counts = vec![0.0f64; width * height];
        for _ in 0..n {
            let (x, y, p, r) = d.sample_remapped(rng.next_vec2());
            assert!(p > 0.0 && (p - d.pmf(x, y)).abs() < 1e-7);
            assert!((0.0..1.0).contains(&r.x) && (0.0..1.0).contains(&r.y));
            counts[y * width + x] += 1.0;
        }
        let expected: Vec<f64> = (0..width * height)
            .map(|i| d.pmf(i % width, i / width) as f64 * n as f64)
            .collect();
        chi_square_test(&counts, &expected, 1).unwrap();
    }

    /// The chi-square test must be able to fail: a wrong distribution is caught.
    #[test]
    fn frequencies_of_a_different_distribution_are_rejected() {
        let d = Distribution1D::new(&[1.0, 1.0, 1.0, 1.1]).unwrap();
        let mut rng = Pcg32::new(1, 1);
        let n = 200_000;
        let mut counts = vec![0.0f64; 4];
        for _ in 0..n {
            counts[d.sample(rng.next_f32()).0] += 1.0;
        }
        let expected = vec![n as f64 / 4.0; 4];
        assert!(chi_square_test(&counts, &expected, 1).is_err());
    }
}
