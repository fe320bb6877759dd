// The GGX (Trowbridge-Reitz) microfacet distribution in the local frame (z = shading normal).
// Mirrors chiaro_shading::ggx function for function.
//
// - Walter, Marschner, Li and Torrance, 2007, "Microfacet Models for Refraction through Rough
//   Surfaces" (D).
// - Heitz, 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs"
//   (Smith Lambda, height-correlated G2).
// - Heitz, 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)) (sample_vndf).
//
// Every function clamps alpha to at least ALPHA_FLOOR.

#import lib/generated.wgsl
#import lib/float.wgsl

// alpha = roughness^2, roughness clamped to [0, 1].
fn alpha_from_roughness(roughness: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    return r * r;
}

// GGX D(h) for the unit half vector h; 0 when h.z <= 0.
fn ndf(h: vec3<f32>, alpha: f32) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let a = max(alpha, ALPHA_FLOOR);
    let a2 = a * a;
    let t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
    return INV_PI / (a2 * t * t);
}

// sqrt(z^2 + alpha^2 (x^2 + y^2)): the recurring term of Smith's Lambda for GGX.
fn smith_root(w: vec3<f32>, alpha: f32) -> f32 {
    let a = max(alpha, ALPHA_FLOOR);
    let a2 = a * a;
    return sqrt(w.z * w.z + a2 * (w.x * w.x + w.y * w.y));
}

// Smith's Lambda for GGX; infinite at the horizon, zero at the normal.
fn lambda(w: vec3<f32>, alpha: f32) -> f32 {
    let z = abs(w.z);
    if z == 0.0 {
        return f32_infinity();
    }
    return 0.5 * f32_max_zero(smith_root(w, alpha) / z - 1.0);
}

// Smith's masking function G1(w).
fn smith_g1(w: vec3<f32>, alpha: f32) -> f32 {
    let z = abs(w.z);
    let denominator = z + smith_root(w, alpha);
    if denominator <= 0.0 {
        return 0.0;
    }
    return 2.0 * z / denominator;
}

// Height-correlated G2 = 1 / (1 + Lambda(wo) + Lambda(wi)).
fn smith_g2(wo: vec3<f32>, wi: vec3<f32>, alpha: f32) -> f32 {
    let zo = abs(wo.z);
    let zi = abs(wi.z);
    let denominator = zi * smith_root(wo, alpha) + zo * smith_root(wi, alpha);
    if denominator <= 0.0 {
        return 0.0;
    }
    return 2.0 * zo * zi / denominator;
}

// V = G2 / (4 |n.wo| |n.wi|), denominator kept at least VISIBILITY_DENOMINATOR_FLOOR.
fn visibility(wo: vec3<f32>, wi: vec3<f32>, alpha: f32) -> f32 {
    let zo = abs(wo.z);
    let zi = abs(wi.z);
    let denominator = zi * smith_root(wo, alpha) + zo * smith_root(wi, alpha);
    return 0.5 / max(denominator, VISIBILITY_DENOMINATOR_FLOOR);
}

// v / |v| as glam's normalize computes it (times the reciprocal of the length).
fn ggx_normalize(v: vec3<f32>) -> vec3<f32> {
    return v * (1.0 / length(v));
}

// A microfacet normal from the distribution of normals visible from wo (wo.z > 0): u.x sets
// the radius, u.y the angle on the projected disk (Heitz 2018, listing 1).
fn sample_vndf(wo: vec3<f32>, alpha: f32, u: vec2<f32>) -> vec3<f32> {
    let a = max(alpha, ALPHA_FLOOR);
    let v = ggx_normalize(vec3<f32>(a * wo.x, a * wo.y, wo.z));
    let len_sq = v.x * v.x + v.y * v.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if len_sq > 0.0 {
        t1 = vec3<f32>(-v.y, v.x, 0.0) / sqrt(len_sq);
    }
    let t2 = cross(v, t1);
    let r = sqrt(max(u.x, 0.0));
    let phi = TAU * u.y;
    let p1 = r * cos(phi);
    var p2 = r * sin(phi);
    let s = 0.5 * (1.0 + v.z);
    p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * p2;
    let n_h = t1 * p1 + t2 * p2 + v * sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    return ggx_normalize(vec3<f32>(a * n_h.x, a * n_h.y, max(n_h.z, 0.0)));
}

// The solid-angle pdf of wi = reflect(-wo, h) for h from sample_vndf; 0 when wo.z <= 0.
fn reflected_vndf_pdf(wo: vec3<f32>, h: vec3<f32>, alpha: f32) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    return ndf(h, alpha) / (2.0 * (wo.z + smith_root(wo, alpha)));
}
