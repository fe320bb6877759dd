// KHR_materials_sheen's sheen lobe and its albedo-scaling layer in the local frame
// (z = shading normal). Mirrors chiaro_shading::sheen function for function; its constants
// (floors, the Lambda fit, the albedo fit's coefficients) come from the generated module.
//
// - Estevez and Kulla, 2017, "Production Friendly Microfacet Sheen BRDF" (SIGGRAPH course
//   notes): the "Charlie" distribution D and the visibility V with their fitted Lambda.
// - The directional albedo E is chiaro's own fit (scripts/fit_sheen_albedo.py).
//
// Not yet called by brdf.wgsl: the BRDF's integration uses sheen_eval, sheen_pdf, sheen_sample
// and sheen_albedo_scaling.

#import lib/generated.wgsl
#import lib/sampling.wgsl

// max(r^2, SHEEN_ALPHA_FLOOR), r clamped to [0, 1].
fn sheen_alpha(roughness: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    return max(r * r, SHEEN_ALPHA_FLOOR);
}

// Estevez and Kulla's l(x) = a / (1 + b x^c) + d x + e, interpolated by (1 - alpha)^2.
fn sheen_lambda_l(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let a = SHEEN_LAMBDA_A1 + (SHEEN_LAMBDA_A0 - SHEEN_LAMBDA_A1) * t;
    let b = SHEEN_LAMBDA_B1 + (SHEEN_LAMBDA_B0 - SHEEN_LAMBDA_B1) * t;
    let c = SHEEN_LAMBDA_C1 + (SHEEN_LAMBDA_C0 - SHEEN_LAMBDA_C1) * t;
    let d = SHEEN_LAMBDA_D1 + (SHEEN_LAMBDA_D0 - SHEEN_LAMBDA_D1) * t;
    let e = SHEEN_LAMBDA_E1 + (SHEEN_LAMBDA_E0 - SHEEN_LAMBDA_E1) * t;
    var xc = 0.0;
    if x > 0.0 {
        xc = pow(x, c);
    }
    return a / (1.0 + b * xc) + d * x + e;
}

// The fitted Lambda at cosine `cos` in [0, 1].
fn sheen_lambda(cos: f32, alpha: f32) -> f32 {
    if cos < 0.5 {
        return exp(sheen_lambda_l(cos, alpha));
    }
    return exp(2.0 * sheen_lambda_l(0.5, alpha) - sheen_lambda_l(1.0 - cos, alpha));
}

// The squared sine of the half vector of two unit directions above the surface.
fn sheen_half_vector_sin2(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let sum = wo + wi;
    let largest = max(max(abs(sum.x), abs(sum.y)), abs(sum.z));
    if largest <= 0.0 {
        return 0.0;
    }
    let s = sum / largest;
    let tangential = s.x * s.x + s.y * s.y;
    return min(tangential / (tangential + s.z * s.z), 1.0);
}

// f = D V for sheen colour 1 (no cosine); 0 when wo.z <= 0 or wi.z <= 0.
fn sheen_eval(roughness: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let alpha = sheen_alpha(roughness);
    let sin2 = sheen_half_vector_sin2(wo, wi);
    var d = 0.0;
    if sin2 > 0.0 {
        d = (2.0 + 1.0 / alpha) * pow(sin2, 0.5 / alpha) * (0.5 * INV_PI);
    }
    let lambdas = 1.0 + sheen_lambda(wo.z, alpha) + sheen_lambda(wi.z, alpha);
    let denominator = max(lambdas * 4.0 * wo.z * wi.z, VISIBILITY_DENOMINATOR_FLOOR);
    return d / denominator;
}

// The albedo fit's k_i = c_4i + c_4i+1 s + (c_4i+2 + c_4i+3 / s) / s.
fn sheen_albedo_k(c0: f32, c1: f32, c2: f32, c3: f32, s: f32, inv: f32) -> f32 {
    return c0 + c1 * s + (c2 + c3 * inv) * inv;
}

// E(mu): the lobe's directional albedo by chiaro_shading::sheen::albedo's fit; mu clamped to
// [SHEEN_ALBEDO_MIN_COSINE, 1].
fn sheen_albedo(roughness: f32, mu_in: f32) -> f32 {
    let alpha = sheen_alpha(roughness);
    let mu = clamp(mu_in, SHEEN_ALBEDO_MIN_COSINE, 1.0);
    let s = sqrt(alpha);
    let inv = 1.0 / s;
    let x = sqrt(mu * sqrt(mu));
    let k1 = sheen_albedo_k(SHEEN_E4, SHEEN_E5, SHEEN_E6, SHEEN_E7, s, inv);
    let k2 = sheen_albedo_k(SHEEN_E8, SHEEN_E9, SHEEN_E10, SHEEN_E11, s, inv);
    let k3 = sheen_albedo_k(SHEEN_E12, SHEEN_E13, SHEEN_E14, SHEEN_E15, s, inv);
    let p = SHEEN_E0 * log(s) + SHEEN_E1 + s * (SHEEN_E2 + s * SHEEN_E3)
        + x * (k1 + x * (k2 + x * k3));
    return exp(p) / (4.0 * mu * (1.0 + sheen_lambda(mu, alpha)));
}

// min(1 - max3(sheen_color) E(wo_z), 1 - max3(sheen_color) E(wi_z)) clamped to [0, 1]; colour
// channels clamped to [0, 1]; exactly 1 for a black sheen.
fn sheen_albedo_scaling(sheen_color: vec3<f32>, roughness: f32, wo_z: f32, wi_z: f32) -> f32 {
    let c = clamp(sheen_color, vec3<f32>(0.0), vec3<f32>(1.0));
    let strength = max(max(c.x, c.y), c.z);
    if strength <= 0.0 {
        return 1.0;
    }
    let e = max(sheen_albedo(roughness, wo_z), sheen_albedo(roughness, wi_z));
    return clamp(1.0 - strength * e, 0.0, 1.0);
}

// The pdf of sheen_sample: uniform over the hemisphere, 0 when wo.z <= 0 or wi.z <= 0.
fn sheen_pdf(roughness: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    return UNIFORM_HEMISPHERE_PDF;
}

// A direction drawn by sheen_sample: `valid` is false where the Rust returns None.
struct SheenSample {
    wi: vec3<f32>,
    pdf: f32,
    valid: bool,
}

// A direction uniform over the hemisphere for the view wo; invalid when wo.z <= 0 or the
// direction lies on the horizon.
fn sheen_sample(roughness: f32, wo: vec3<f32>, u: vec2<f32>) -> SheenSample {
    var s: SheenSample;
    s.valid = false;
    if wo.z <= 0.0 {
        return s;
    }
    s.wi = uniform_hemisphere(u);
    s.pdf = sheen_pdf(roughness, wo, s.wi);
    s.valid = s.pdf > 0.0;
    return s;
}
