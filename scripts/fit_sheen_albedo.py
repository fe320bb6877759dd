#!/usr/bin/env python3
"""Fits the directional albedo E(mu, r) of KHR_materials_sheen's lobe (chiaro_shading::sheen).

E(mu, r) = integral over the hemisphere of D_charlie(h) V_charlie(wo, wi) cos(theta_i) dwi, for a
view at cosine mu and sheen roughness r (alpha = max(r^2, ALPHA_FLOOR)), sheen colour 1. D is
Estevez and Kulla's (2017) "Charlie" distribution, V their visibility with the fitted Lambda
(the KHR_materials_sheen spec's recommended one).

E diverges as mu -> 0 (the fitted Lambda is finite at the horizon, so V ~ 1/(4 mu Lambda(0))),
so what is fitted is the smooth, finite

    T(mu, r) = 4 mu (1 + Lambda(mu)) E(mu, r)
             = integral of D(h) (1 + Lambda(mu)) / (1 + Lambda(mu) + Lambda(cos theta_i)) dwi,

as T = exp(P(x, r)), x = mu^(3/4), r = sqrt(alpha):

    P = c0 ln r + c1 + c2 r + c3 r^2
        + x (c4 + c5 r + c6 / r + c7 / r^2)
        + x^2 (c8 + c9 r + c10 / r + c11 / r^2)
        + x^3 (c12 + c13 r + c14 / r + c15 / r^2)

and E = T / (4 mu (1 + Lambda(mu))). The coefficients minimise the largest absolute error of E
(Gauss-Newton on the least squares, then Lawson's reweighting towards the minimax) over a grid
of mu in [MU_MIN, 1] and r in [sqrt(ALPHA_FLOOR), 1], E by Gauss-Legendre quadrature in f64.

Run from the repository root: python3 scripts/fit_sheen_albedo.py
It writes crates/chiaro_shading/src/sheen/albedo_fit.rs (coefficients and the error bound) and
prints the errors it measured on a validation grid offset from the fitting grid. Needs numpy.
"""

import math
import pathlib

import numpy as np

# Keep in step with chiaro_shading::sheen (the test there checks the fit against its own
# quadrature).
ALPHA_FLOOR = 1e-3
MU_MIN = 1e-4
# Estevez and Kulla's Lambda fit: (a, b, c, d, e) at alpha = 1 and at alpha = 0; chiaro_shading
# interpolates with t = (1 - alpha)^2.
LAMBDA_AT_1 = (21.5473, 3.82987, 0.19823, -1.97760, -4.32054)
LAMBDA_AT_0 = (25.3245, 3.32435, 0.16801, -1.27393, -4.85967)
OUT = pathlib.Path("crates/chiaro_shading/src/sheen/albedo_fit.rs")


def lambda_l(x, alpha):
    t = (1.0 - alpha) ** 2
    a, b, c, d, e = (p1 + (p0 - p1) * t for p1, p0 in zip(LAMBDA_AT_1, LAMBDA_AT_0))
    return a / (1.0 + b * x**c) + d * x + e


def lambda_sheen(cos, alpha):
    return np.where(
        cos < 0.5,
        np.exp(lambda_l(cos, alpha)),
        np.exp(2.0 * lambda_l(0.5, alpha) - lambda_l(1.0 - cos, alpha)),
    )


def nodes(points, segments, lo, hi):
    x, w = np.polynomial.legendre.leggauss(points)
    edges = np.linspace(lo, hi, segments + 1)
    xs, ws = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        xs.append(0.5 * (b - a) * x + 0.5 * (a + b))
        ws.append(0.5 * (b - a) * w)
    return np.concatenate(xs), np.concatenate(ws)


# theta_i over [0, pi/2] and phi over [0, pi] (the integrand is even in phi), 16 segments of 12
# points each: the sharpest lobe (alpha = 1e-3) is about 0.05 rad wide.
THETA, W_THETA = nodes(12, 16, 0.0, math.pi / 2)
PHI, W_PHI = nodes(12, 16, 0.0, math.pi)
TT, PP = np.meshgrid(THETA, PHI, indexing="ij")
WEIGHTS = 2.0 * np.outer(W_THETA * np.sin(THETA), W_PHI)
COS_I = np.cos(TT)
SIN_I = np.sin(TT)


def t_quadrature(mu, r):
    """T(mu, r) for arrays of mu, one r."""
    alpha = max(r * r, ALPHA_FLOOR)
    mu = np.asarray(mu, float)[:, None, None]
    sin_o = np.sqrt(1.0 - mu * mu)
    hx = SIN_I * np.cos(PP) + sin_o
    hy = SIN_I * np.sin(PP)
    hz = COS_I + mu
    sin2 = (hx * hx + hy * hy) / (hx * hx + hy * hy + hz * hz)
    d = (2.0 + 1.0 / alpha) * sin2 ** (0.5 / alpha) / (2.0 * math.pi)
    lo = 1.0 + lambda_sheen(mu, alpha)
    integrand = d * lo / (lo + lambda_sheen(COS_I, alpha))
    return np.sum(WEIGHTS * integrand, axis=(1, 2))


def scale(mu, r):
    """4 mu (1 + Lambda(mu)): E = T / scale."""
    return 4.0 * mu * (1.0 + lambda_sheen(mu, np.maximum(r * r, ALPHA_FLOOR)))


def features(mu, r):
    r = np.sqrt(np.maximum(r * r, ALPHA_FLOOR))
    x = np.sqrt(mu * np.sqrt(mu))
    cols = [np.log(r), np.ones_like(r), r, r * r]
    for i in (1, 2, 3):
        cols += [x**i, x**i * r, x**i / r, x**i / (r * r)]
    return np.stack(cols, 1)


def table(mus, rs):
    mu = np.concatenate([mus for _ in rs])
    r = np.repeat(rs, len(mus))
    t = np.concatenate([t_quadrature(mus, rr) for rr in rs])
    return mu, r, t


def fit(mu, r, t):
    b = features(mu, r)
    s = scale(mu, r)
    # Start: least squares on ln T, weighted towards where T matters.
    w0 = np.sqrt(np.maximum(t, 1e-8))
    c = np.linalg.lstsq(b * w0[:, None], np.log(np.maximum(t, 1e-30)) * w0, rcond=None)[0]
    w = np.full(len(t), 1.0 / len(t))
    damping = 1e-2

    def residual(c):
        model = np.exp(np.minimum(b @ c, 30.0))
        return model, (model - t) / s

    model, res = residual(c)
    best = (np.abs(res).max(), c.copy())
    for it in range(800):
        j = (model / s)[:, None] * b * np.sqrt(w)[:, None]
        rr = res * np.sqrt(w)
        diag = np.sqrt(np.sum(j * j, 0)) + 1e-30
        for _ in range(30):
            a = np.vstack([j, math.sqrt(damping) * np.diag(diag)])
            step = np.linalg.lstsq(a, np.concatenate([rr, np.zeros(len(c))]), rcond=None)[0]
            m2, r2 = residual(c - step)
            if np.sum(w * r2 * r2) <= np.sum(w * res * res):
                c, model, res = c - step, m2, r2
                damping = max(damping * 0.3, 1e-12)
                break
            damping *= 10.0
        worst = np.abs(res).max()
        if worst < best[0]:
            best = (worst, c.copy())
        if it >= 100 and it % 5 == 0:
            # Lawson: weight up where the error is large, towards the minimax fit.
            w = w * (np.abs(res) / worst + 1e-3) ** 0.5
            w /= w.sum()
    return best[1]


def e_fit(c, mu, r):
    """The fit as chiaro_shading evaluates it, in f32 (x and the polynomial in Horner form)."""
    f = np.float32
    mu = np.maximum(np.asarray(mu, f), f(MU_MIN))
    r = np.sqrt(np.maximum(np.asarray(r, f) ** 2, f(ALPHA_FLOOR))).astype(f)
    c = c.astype(f)
    x = np.sqrt(mu * np.sqrt(mu))
    inv = f(1) / r
    k = [c[4 * i] + c[4 * i + 1] * r + (c[4 * i + 2] + c[4 * i + 3] * inv) * inv for i in (1, 2, 3)]
    p = c[0] * np.log(r) + c[1] + r * (c[2] + r * c[3]) + x * (k[0] + x * (k[1] + x * k[2]))
    return np.exp(p).astype(f) / scale(mu.astype(float), r.astype(float))


def main():
    # Fitting grid: mu log-spaced and linear, r denser at the small end.
    mus = np.unique(np.concatenate([np.geomspace(MU_MIN, 1.0, 49), np.linspace(MU_MIN, 1.0, 49)]))
    r_lo = math.sqrt(ALPHA_FLOOR)
    rs = r_lo + (1.0 - r_lo) * np.linspace(0.0, 1.0, 33) ** 1.5
    mu, r, t = table(mus, rs)
    c = fit(mu, r, t)
    train = np.abs(e_fit(c, mu, r) - t / scale(mu, r)).max()
    # Validation grid: between the fitting grid's points, r = 0 (the floor) included.
    vmus = np.unique(np.concatenate([np.geomspace(MU_MIN * 1.3, 0.99, 61), np.linspace(0.013, 0.997, 61)]))
    vrs = np.concatenate([[0.0], r_lo + (1.0 - r_lo) * np.linspace(0.01, 0.995, 41) ** 1.5])
    vmu, vr, vt = table(vmus, vrs)
    e_true = vt / scale(vmu, np.maximum(vr, r_lo))
    err = np.abs(e_fit(c, vmu, vr) - e_true)
    worst = err.max()
    k = int(np.argmax(err))
    print(f"max |E fit - E| on the fitting grid {train:.5f}, on the validation grid {worst:.5f}")
    print(f"  worst at mu {vmu[k]:.4g}, r {vr[k]:.4g} (E {e_true[k]:.4f})")
    print(f"  largest E on the validation grid {e_true.max():.3f}")
    bound = math.ceil(max(worst, train) * 1.2 * 1000) / 1000
    # The shortest decimal that reads back as the same f32 (what clippy and WGSL want).
    shortest = (np.format_float_positional(np.float32(v), unique=True, trim="0") for v in c)
    coefficients = ",\n".join(f"    {v}" for v in shortest)
    OUT.write_text(
        "// Generated by scripts/fit_sheen_albedo.py: do not edit, rerun it.\n"
        "\n"
        "/// The coefficients c0..c15 of [`super::albedo`]'s fit (see the module documentation).\n"
        f"pub(super) const ALBEDO_FIT: [f32; {len(c)}] = [\n{coefficients},\n];\n"
        "\n"
        "/// The bound on |[`super::albedo`] - E| for mu in [[`super::ALBEDO_MIN_COSINE`], 1] and\n"
        "/// any roughness: the largest error the fitting script measured, in f32, on its fitting\n"
        f"/// grid and on a validation grid between it ({max(worst, train):.5f}), plus a fifth,\n"
        "/// rounded up to 0.001.\n"
        f"pub const ALBEDO_FIT_MAX_ERROR: f32 = {bound!r};\n"
    )
    print(f"wrote {OUT} (bound {bound})")


if __name__ == "__main__":
    main()
