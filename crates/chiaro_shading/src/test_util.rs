//! Test helpers: quadrature and a chi-square goodness-of-fit test (compiled for tests only).
//!
//! The chi-square test follows the procedure of Mitsuba's and pbrt's sampling tests: histogram the
//! samples over cells, integrate the pdf over each cell numerically for the expected counts, pool
//! cells with small expected counts (< 5) so the statistic is close to chi-square distributed,
//! and reject at significance 1% with the Sidak correction for the number of tests in the family.

/// Gauss-Legendre nodes and weights on [-1, 1], found by Newton's method on the Legendre
/// polynomial P_n (Golub and Welsch, 1969, give the theory; any textbook gives the recurrence).
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// An n-point rule (exact for polynomials of degree 2n - 1).
    pub fn new(n: usize) -> Self {
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        for i in 0..n.div_ceil(2) {
            // Initial guess near the i-th root, then Newton on P_n.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 0.0;
            for _ in 0..100 {
                // Three-term recurrence: (k + 1) P_{k+1} = (2k + 1) x P_k - k P_{k-1}.
                let (mut p0, mut p1) = (1.0f64, x);
                for k in 1..n {
                    let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
                    p0 = p1;
                    p1 = p2;
                }
                let pn = if n == 0 { 1.0 } else { p1 };
                let pn_minus_1 = p0;
                derivative = n as f64 * (x * pn - pn_minus_1) / (x * x - 1.0);
                let step = pn / derivative;
                x -= step;
                if step.abs() < 1e-15 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * derivative * derivative);
            nodes[i] = x;
            weights[i] = w;
            nodes[n - 1 - i] = -x;
            weights[n - 1 - i] = w;
        }
        Self { nodes, weights }
    }

    /// Integral of f over [a, b].
    pub fn integrate(&self, a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let half = 0.5 * (b - a);
        let mid = 0.5 * (a + b);
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(|(x, w)| w * f(mid + half * x))
            .sum::<f64>()
            * half
    }
}

/// Integral of f over [a, b] with an n-point Gauss-Legendre rule.
pub fn gauss_legendre(a: f64, b: f64, n: usize, f: impl FnMut(f64) -> f64) -> f64 {
    GaussLegendre::new(n).integrate(a, b, f)
}

/// A rectangle of the integration domain.
#[derive(Clone, Copy, Debug)]
pub struct Rect {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
}

/// Adaptive 2D Simpson integration of f over `rect` to absolute tolerance `tol` (each quarter
/// gets half the parent's tolerance: a heuristic, as in most adaptive quadrature). `force(rect)`
/// returns true for rectangles that must be subdivided regardless of the error estimate (used to
/// resolve a known narrow peak that a coarse rule could step over); forced subdivision stops at
/// `max_depth` like the adaptive one.
pub fn adaptive_simpson_2d(
    f: &mut impl FnMut(f64, f64) -> f64,
    rect: Rect,
    tol: f64,
    force: &impl Fn(Rect) -> bool,
    max_depth: u32,
) -> f64 {
    let whole = simpson_2d(f, rect);
    refine(f, rect, whole, tol, force, max_depth)
}

fn simpson_2d(f: &mut impl FnMut(f64, f64) -> f64, r: Rect) -> f64 {
    let xs = [r.x0, 0.5 * (r.x0 + r.x1), r.x1];
    let ys = [r.y0, 0.5 * (r.y0 + r.y1), r.y1];
    let w = [1.0, 4.0, 1.0];
    let mut sum = 0.0;
    for (i, &x) in xs.iter().enumerate() {
        for (j, &y) in ys.iter().enumerate() {
            sum += w[i] * w[j] * f(x, y);
        }
    }
    sum * (r.x1 - r.x0) * (r.y1 - r.y0) / 36.0
}

fn refine(
    f: &mut impl FnMut(f64, f64) -> f64,
    r: Rect,
    whole: f64,
    tol: f64,
    force: &impl Fn(Rect) -> bool,
    depth: u32,
) -> f64 {
    let (xm, ym) = (0.5 * (r.x0 + r.x1), 0.5 * (r.y0 + r.y1));
    let quarters = [
        Rect {
            x0: r.x0,
            x1: xm,
            y0: r.y0,
            y1: ym,
        },
        Rect {
            x0: xm,
            x1: r.x1,
            y0: r.y0,
            y1: ym,
        },
        Rect {
            x0: r.x0,
            x1: xm,
            y0: ym,
            y1: r.y1,
        },
        Rect {
            x0: xm,
            x1: r.x1,
            y0: ym,
            y1: r.y1,
        },
    ];
    let parts = quarters.map(|q| simpson_2d(f, q));
    let sum: f64 = parts.iter().sum();
    let error = (sum - whole).abs();
    if depth == 0 || (error <= 15.0 * tol && !force(r)) {
        // No Richardson extrapolation: it can turn a non-negative integrand's tiny integral
        // negative, which a chi-square test cannot use as an expected count.
        return sum;
    }
    quarters
        .iter()
        .zip(parts)
        .map(|(&q, p)| refine(f, q, p, 0.5 * tol, force, depth - 1))
        .sum()
}

/// ln Gamma(a) for a positive multiple of 1/2 (all a chi-square test needs), exactly by the
/// recurrence Gamma(a + 1) = a Gamma(a) from Gamma(1) = 1 and Gamma(1/2) = sqrt(pi).
fn ln_gamma_half_integer(a: f64) -> f64 {
    let twice = (2.0 * a).round();
    assert!(twice >= 1.0 && (2.0 * a - twice).abs() < 1e-9, "{a}");
    let (mut x, mut acc) = if (twice as u64).is_multiple_of(2) {
        (1.0, 0.0)
    } else {
        (0.5, 0.5 * std::f64::consts::PI.ln())
    };
    while x < a - 0.25 {
        acc += x.ln();
        x += 1.0;
    }
    acc
}

/// The regularized upper incomplete gamma function Q(a, x) for a half-integer a: the series for
/// P = 1 - Q below x = a + 1, Legendre's continued fraction (evaluated by the modified Lentz
/// method) above.
fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = -x + a * x.ln() - ln_gamma_half_integer(a);
    if x < a + 1.0 {
        // P(a, x) = x^a e^-x / Gamma(a + 1) * sum_k x^k / ((a + 1) ... (a + k)).
        let (mut term, mut sum, mut denominator) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            denominator += 1.0;
            term *= x / denominator;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        // Q(a, x) = e^-x x^a / Gamma(a) * 1 / (x + 1 - a - 1 (1 - a) / (x + 3 - a - ...)).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        log_prefactor.exp() * h
    }
}

/// The p-value of a chi-square statistic with `dof` degrees of freedom: P(X >= stat).
pub fn chi_square_p_value(stat: f64, dof: usize) -> f64 {
    gamma_q(0.5 * dof as f64, 0.5 * stat)
}

/// Smallest expected count of a cell before it is pooled with others.
const MIN_EXPECTED: f64 = 5.0;

/// Pearson's chi-square test of observed against expected counts at significance 1%, corrected
/// for `num_tests` tests in the family by Sidak (alpha = 1 - 0.99^(1 / num_tests)). Cells with an
/// expected count under 5 are pooled in order of increasing expectation. A sample in a cell whose
/// expected count is 0 fails at once. Returns the p-value, or a message saying why it failed.
pub fn chi_square_test(
    observed: &[f64],
    expected: &[f64],
    num_tests: usize,
) -> Result<f64, String> {
    assert_eq!(observed.len(), expected.len());
    let mut cells: Vec<(f64, f64)> = expected
        .iter()
        .copied()
        .zip(observed.iter().copied())
        .collect();
    cells.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut stat, mut dof) = (0.0f64, 0usize);
    let (mut pool_e, mut pool_o) = (0.0f64, 0.0f64);
    for &(e, o) in &cells {
        if e <= 0.0 {
            if o > 0.0 {
                return Err(format!("{o} samples in a cell with expected count {e}"));
            }
            continue;
        }
        if e < MIN_EXPECTED {
            pool_e += e;
            pool_o += o;
            if pool_e >= MIN_EXPECTED {
                stat += (pool_o - pool_e).powi(2) / pool_e;
                dof += 1;
                pool_e = 0.0;
                pool_o = 0.0;
            }
        } else {
            stat += (o - e).powi(2) / e;
            dof += 1;
        }
    }
    if pool_e > 0.0 || pool_o > 0.0 {
        // The last small pool stands as its own cell.
        stat += (pool_o - pool_e).powi(2) / pool_e.max(1e-12);
        dof += 1;
    }
    if dof < 2 {
        return Err(format!("only {dof} cells after pooling"));
    }
    let p = chi_square_p_value(stat, dof - 1);
    let alpha = 1.0 - 0.99f64.powf(1.0 / num_tests as f64);
    if p < alpha {
        Err(format!(
            "chi-square {stat:.1} with {} dof: p = {p:.3e} < {alpha:.3e}",
            dof - 1
        ))
    } else {
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_for_polynomials() {
        let g = GaussLegendre::new(5);
        let v = g.integrate(0.0, 2.0, |x| x.powi(9) - 3.0 * x * x + 1.0);
        assert!((v - (1024.0 / 10.0 - 8.0 + 2.0)).abs() < 1e-9, "{v}");
        let v = gauss_legendre(0.0, std::f64::consts::PI, 64, f64::sin);
        assert!((v - 2.0).abs() < 1e-12);
        let odd = gauss_legendre(-1.0, 1.0, 7, |x| x.powi(3));
        assert!(odd.abs() < 1e-14);
    }

    #[test]
    fn adaptive_simpson_resolves_a_narrow_peak() {
        // A Gaussian of width 1e-3 at (0.3137, 0.7123): integral pi sigma^2.
        let (cx, cy, s) = (0.3137, 0.7123, 1e-3);
        let mut f = |x: f64, y: f64| (-((x - cx).powi(2) + (y - cy).powi(2)) / (s * s)).exp();
        let rect = Rect {
            x0: 0.0,
            x1: 1.0,
            y0: 0.0,
            y1: 1.0,
        };
        let near = |r: Rect| {
            let size = (r.x1 - r.x0).max(r.y1 - r.y0);
            size > s
                && cx > r.x0 - 5.0 * s
                && cx < r.x1 + 5.0 * s
                && cy > r.y0 - 5.0 * s
                && cy < r.y1 + 5.0 * s
        };
        let v = adaptive_simpson_2d(&mut f, rect, 1e-10, &near, 20);
        let exact = std::f64::consts::PI * s * s;
        assert!((v - exact).abs() < 1e-3 * exact, "{v} vs {exact}");
    }

    #[test]
    fn p_values_match_tables() {
        // Quantiles from standard chi-square tables.
        for (stat, dof, p) in [
            (3.841_459, 1, 0.05),
            (6.634_897, 1, 0.01),
            (23.209_25, 10, 0.01),
            (18.307_04, 10, 0.05),
            (135.806_7, 100, 0.01),
            (124.342_1, 100, 0.05),
        ] {
            let got = chi_square_p_value(stat, dof);
            assert!(
                (got - p).abs() < 1e-4 * p.max(0.01) * 10.0,
                "{stat} {dof}: {got}"
            );
        }
        // Two degrees of freedom: Q = exp(-x/2) exactly.
        for x in [0.5, 2.0, 10.0, 40.0] {
            assert!((chi_square_p_value(x, 2) - (-0.5 * x).exp()).abs() < 1e-12);
        }
        assert!((ln_gamma_half_integer(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!(
            (ln_gamma_half_integer(1.5) - (0.5 * std::f64::consts::PI.sqrt()).ln()).abs() < 1e-12
        );
    }

    #[test]
    fn chi_square_accepts_fair_and_rejects_unfair_counts() {
        let expected = vec![100.0; 10];
        let fair = [
            95.0, 104.0, 98.0, 110.0, 91.0, 102.0, 99.0, 101.0, 97.0, 103.0,
        ];
        assert!(chi_square_test(&fair, &expected, 1).is_ok());
        let unfair = [
            150.0, 50.0, 100.0, 100.0, 100.0, 100.0, 100.0, 100.0, 100.0, 100.0,
        ];
        assert!(chi_square_test(&unfair, &expected, 1).is_err());
        assert!(chi_square_test(&[1.0, 99.0], &[0.0, 100.0], 1).is_err());
    }
}
