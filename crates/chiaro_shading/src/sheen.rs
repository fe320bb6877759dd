//! KHR_materials_sheen's sheen lobe and its albedo-scaling layer, in the local shading frame
//! (z = shading normal; `wo` and `wi` unit vectors pointing away from the surface).
//! [`crate::brdf`] layers it between its base and its clear coat through [`eval`], [`pdf`],
//! [`sample`], [`albedo`] and [`albedo_scaling`], and `shaders/lib/sheen.wgsl` mirrors every
//! function here.
//!
//! The lobe, for sheen colour 1 and sheen roughness r (alpha = r^2), is
//! f = D(h) V(wo, wi) (the spec's sheen Fresnel is 1):
//!
//! - D: the "Charlie" distribution, (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi) (Estevez and
//!   Kulla, 2017, "Production Friendly Microfacet Sheen BRDF", SIGGRAPH course notes).
//! - V = 1 / ((1 + Lambda(n.wo) + Lambda(n.wi)) 4 n.wo n.wi), with Estevez and Kulla's fitted
//!   Lambda ([`LAMBDA_FIT`]): exp(l(cos)) below cos 0.5, exp(2 l(0.5) - l(1 - cos)) above,
//!   l(x) = a / (1 + b x^c) + d x + e with (a, b, c, d, e) interpolated between their values at
//!   alpha 1 and alpha 0 by (1 - alpha)^2.
//!
//! Why this V and not Neubelt and Pettineo's 1 / (4 (n.wo + n.wi - n.wo n.wi)) (Ashikhmin and
//! Premoze's, which the spec offers as the cheaper choice): KHR_materials_sheen recommends it and
//! warns that the other makes the layer gain energy under albedo scaling; it is the Smith-form
//! shadowing that goes with the Charlie distribution (reciprocal); and by the fitting script's
//! quadrature its albedo stays below 0.95 for sheen roughness 0.3 and above, where Neubelt's
//! reaches 1.35 at grazing views (at the floor, grazing, 6.1 against 12.5). Its cost is one `pow`
//! and one `exp` per cosine.
//!
//! The layer ([`albedo_scaling`]): f_layer = sheen_color f + base albedo_scaling, with
//! albedo_scaling = min(1 - max3(sheen_color) E(n.wo), 1 - max3(sheen_color) E(n.wi)) and E the
//! lobe's directional albedo ([`albedo`]), clamped to [0, 1]. In the BRDF the layer sits between
//! the base (the metal/dielectric mix) and the clear coat: the coat's blend takes the layer where
//! it now takes the base, the spec's order (clearcoat over sheen over base).
//!
//! Defined answers and floors:
//! - alpha = max(r^2, [`ALPHA_FLOOR`]) with r clamped to [0, 1] ([`alpha_from_roughness`]).
//! - wo.z <= 0 or wi.z <= 0: [`eval`] and [`pdf`] give 0, [`sample`] gives `None`.
//! - V's denominator is kept at least [`crate::ggx::VISIBILITY_DENOMINATOR_FLOOR`], so two
//!   directions at the horizon give a large finite value, never infinity.
//! - [`albedo`] evaluates at mu = max(mu, [`ALBEDO_MIN_COSINE`]).
//!
//! Sampling ([`sample`], [`pdf`]): uniform over the hemisphere. The lobe peaks at grazing
//! angles, on both sides of the view (back-scattering and forward), and its f cos falls only as
//! Lambda(n.wi) grows close to the horizon; a cosine-weighted warp starves exactly the grazing
//! directions where it is largest, and sampling D's half vectors (which lie near the tangent
//! plane for small roughness) reflects most of them below the horizon. The uniform warp costs nothing, covers the whole lobe, and keeps the sample weight
//! f cos / pdf = 2 pi f cos bounded for a fixed view.
//!
//! No finite input (unit directions, any roughness and colour) yields NaN or infinity.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use crate::ggx::VISIBILITY_DENOMINATOR_FLOOR;
use crate::sampling::{UNIFORM_HEMISPHERE_PDF, uniform_hemisphere};

mod albedo_fit;

use albedo_fit::ALBEDO_FIT;
pub use albedo_fit::ALBEDO_FIT_MAX_ERROR;

/// The smallest alpha the sheen lobe uses (sheen roughness about 0.032). The spec's sheen
/// roughness defaults to 0, where D would be a delta on the tangent plane: the floor keeps D's
/// peak at (2 + 1000) / (2 pi) = 160, the exponent 1 / (2 alpha) of sin^2 at 500 (within `pow`'s
/// accuracy on GPUs), and the lobe about 0.05 rad (3 degrees) from the horizon: such a sheen is
/// visible only at grazing views (its albedo is below 0.08 from a view 6 degrees above the
/// horizon), as the spec's r = 0 intends, while the albedo fit stays accurate.
pub const ALPHA_FLOOR: f32 = 1e-3;

/// [`albedo`] evaluates E at no smaller cosine. Below it (a view within 0.006 degrees of the
/// horizon) the lobe's true albedo rises without bound: the fitted Lambda is finite at the
/// horizon, so V grows as 1 / (4 n.wo Lambda(0)).
pub const ALBEDO_MIN_COSINE: f32 = 1e-4;

/// Estevez and Kulla's fit of l(x) = a / (1 + b x^c) + d x + e, (a, b, c, d, e): row 0 at
/// alpha = 1, row 1 at alpha = 0 (the constants KHR_materials_sheen quotes).
pub const LAMBDA_FIT: [[f32; 5]; 2] = [
    [21.5473, 3.82987, 0.19823, -1.97760, -4.32054],
    [25.3245, 3.32435, 0.16801, -1.27393, -4.85967],
];

/// The constants `shaders/lib/sheen.wgsl` reads from the generated module: the floors, the
/// Lambda fit and the albedo fit's coefficients.
pub const SHADER_CONSTANTS: [(&str, f32); 28] = [
    ("SHEEN_ALPHA_FLOOR", ALPHA_FLOOR),
    ("SHEEN_ALBEDO_MIN_COSINE", ALBEDO_MIN_COSINE),
    ("SHEEN_LAMBDA_A1", LAMBDA_FIT[0][0]),
    ("SHEEN_LAMBDA_B1", LAMBDA_FIT[0][1]),
    ("SHEEN_LAMBDA_C1", LAMBDA_FIT[0][2]),
    ("SHEEN_LAMBDA_D1", LAMBDA_FIT[0][3]),
    ("SHEEN_LAMBDA_E1", LAMBDA_FIT[0][4]),
    ("SHEEN_LAMBDA_A0", LAMBDA_FIT[1][0]),
    ("SHEEN_LAMBDA_B0", LAMBDA_FIT[1][1]),
    ("SHEEN_LAMBDA_C0", LAMBDA_FIT[1][2]),
    ("SHEEN_LAMBDA_D0", LAMBDA_FIT[1][3]),
    ("SHEEN_LAMBDA_E0", LAMBDA_FIT[1][4]),
    ("SHEEN_E0", ALBEDO_FIT[0]),
    ("SHEEN_E1", ALBEDO_FIT[1]),
    ("SHEEN_E2", ALBEDO_FIT[2]),
    ("SHEEN_E3", ALBEDO_FIT[3]),
    ("SHEEN_E4", ALBEDO_FIT[4]),
    ("SHEEN_E5", ALBEDO_FIT[5]),
    ("SHEEN_E6", ALBEDO_FIT[6]),
    ("SHEEN_E7", ALBEDO_FIT[7]),
    ("SHEEN_E8", ALBEDO_FIT[8]),
    ("SHEEN_E9", ALBEDO_FIT[9]),
    ("SHEEN_E10", ALBEDO_FIT[10]),
    ("SHEEN_E11", ALBEDO_FIT[11]),
    ("SHEEN_E12", ALBEDO_FIT[12]),
    ("SHEEN_E13", ALBEDO_FIT[13]),
    ("SHEEN_E14", ALBEDO_FIT[14]),
    ("SHEEN_E15", ALBEDO_FIT[15]),
];

/// The sheen lobe's alpha for a sheen roughness: max(r^2, [`ALPHA_FLOOR`]), r clamped to
/// [0, 1].
pub fn alpha_from_roughness(roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    (r * r).max(ALPHA_FLOOR)
}

/// Estevez and Kulla's l(x) for this alpha.
fn lambda_l(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let [p1, p0] = LAMBDA_FIT;
    let at = |k: usize| p1[k] + (p0[k] - p1[k]) * t;
    // pow(0, c) is left undefined by WGSL: x = 0 is handled here, the same on both sides.
    let xc = if x > 0.0 { x.powf(at(2)) } else { 0.0 };
    at(0) / (1.0 + at(1) * xc) + at(3) * x + at(4)
}

/// Estevez and Kulla's fitted Lambda for a direction at cosine `cos` (in [0, 1]) to the normal.
fn lambda(cos: f32, alpha: f32) -> f32 {
    if cos < 0.5 {
        lambda_l(cos, alpha).exp()
    } else {
        (2.0 * lambda_l(0.5, alpha) - lambda_l(1.0 - cos, alpha)).exp()
    }
}

/// The squared sine of the half vector of two unit directions above the surface: the sum is
/// divided by its largest component before squaring, so nothing underflows at the horizon.
fn half_vector_sin2(wo: Vec3, wi: Vec3) -> f32 {
    let sum = wo + wi;
    let largest = sum.abs().max_element();
    if largest <= 0.0 {
        return 0.0;
    }
    let s = sum / largest;
    let tangential = s.x * s.x + s.y * s.y;
    (tangential / (tangential + s.z * s.z)).min(1.0)
}

/// The sheen lobe f = D V for sheen colour 1 and sheen roughness `roughness` (no cosine), for
/// unit local directions; zero when wo.z <= 0 or wi.z <= 0.
pub fn eval(roughness: f32, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let alpha = alpha_from_roughness(roughness);
    let sin2 = half_vector_sin2(wo, wi);
    let d = if sin2 > 0.0 {
        (2.0 + 1.0 / alpha) * sin2.powf(0.5 / alpha) * (0.5 * FRAC_1_PI)
    } else {
        0.0
    };
    let lambdas = 1.0 + lambda(wo.z, alpha) + lambda(wi.z, alpha);
    let denominator = (lambdas * 4.0 * wo.z * wi.z).max(VISIBILITY_DENOMINATOR_FLOOR);
    d / denominator
}

/// E(mu): the lobe's directional albedo (the integral of [`eval`] times n.wi over the
/// hemisphere) seen at cosine `mu`, for sheen colour 1 and sheen roughness `roughness`, by an
/// analytic fit within [`ALBEDO_FIT_MAX_ERROR`] of it for mu in [[`ALBEDO_MIN_COSINE`], 1] and
/// any roughness (mu is raised to [`ALBEDO_MIN_COSINE`] and clamped to at most 1):
///
/// E = exp(P) / (4 mu (1 + Lambda(mu))), x = mu^(3/4), s = sqrt(alpha),
/// P = c0 ln s + c1 + c2 s + c3 s^2 + x (k1 + x (k2 + x k3)),
/// k_i = c_4i + c_4i+1 s + c_4i+2 / s + c_4i+3 / s^2,
///
/// the coefficients fitted by `scripts/fit_sheen_albedo.py` to E computed by quadrature. The
/// factor 1 / (4 mu (1 + Lambda(mu))) is V's own view-dependence, which leaves exp(P) smooth and
/// finite down to mu = 0. E exceeds 1 for smooth sheens at grazing views (6.1 at alpha 1e-3 and
/// mu 1e-3; 1.9 at r = 0.1 and mu = 0.01): so does the lobe it fits.
pub fn albedo(roughness: f32, mu: f32) -> f32 {
    let alpha = alpha_from_roughness(roughness);
    let mu = mu.clamp(ALBEDO_MIN_COSINE, 1.0);
    let s = alpha.sqrt();
    let inv = 1.0 / s;
    let x = (mu * mu.sqrt()).sqrt();
    let c = &ALBEDO_FIT;
    let k = |i: usize| c[4 * i] + c[4 * i + 1] * s + (c[4 * i + 2] + c[4 * i + 3] * inv) * inv;
    let p = c[0] * s.ln() + c[1] + s * (c[2] + s * c[3]) + x * (k(1) + x * (k(2) + x * k(3)));
    p.exp() / (4.0 * mu * (1.0 + lambda(mu, alpha)))
}

/// KHR_materials_sheen's albedo scaling of the base beneath the sheen:
/// min(1 - max3(sheen_color) E(wo_z), 1 - max3(sheen_color) E(wi_z)), clamped to [0, 1]
/// (E exceeds 1 for smooth sheens at grazing angles, see [`albedo`]). Colour channels are
/// clamped to [0, 1]; a black sheen gives exactly 1.
pub fn albedo_scaling(sheen_color: Vec3, roughness: f32, wo_z: f32, wi_z: f32) -> f32 {
    let strength = sheen_color.clamp(Vec3::ZERO, Vec3::ONE).max_element();
    if strength <= 0.0 {
        return 1.0;
    }
    let e = albedo(roughness, wo_z).max(albedo(roughness, wi_z));
    (1.0 - strength * e).clamp(0.0, 1.0)
}

/// The solid-angle pdf with which [`sample`] draws `wi`: 1 / (2 pi) above the surface, zero when
/// wo.z <= 0 or wi.z <= 0.
pub fn pdf(_roughness: f32, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    UNIFORM_HEMISPHERE_PDF
}

/// Draws an incident direction for the view `wo` uniformly over the hemisphere (see the module
/// documentation for why), from the uniform numbers `u`: `(wi, pdf)`, or `None` when
/// wo.z <= 0 or the direction drawn lies on the horizon (u.x = 0).
pub fn sample(roughness: f32, wo: Vec3, u: Vec2) -> Option<(Vec3, f32)> {
    if wo.z <= 0.0 {
        return None;
    }
    let wi = uniform_hemisphere(u);
    let pdf = pdf(roughness, wo, wi);
    (pdf > 0.0).then_some((wi, pdf))
}

#[cfg(test)]
mod tests;
