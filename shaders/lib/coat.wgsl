// KHR_materials_clearcoat's coat (chiaro_shading::brdf::layers, whose documentation is the
// spec): its blend over the base, clearcoat Schlick(0.04, n_c.wo), and its GGX lobe, both about
// the coat's own normal n_c, the lobe times (n_c.wi) / (n.wi). Compiled in only with
// FEATURE_CLEARCOAT (clearcoat is 0 without it). Part of lib/brdf.wgsl, which imports it.

#import lib/frame.wgsl

// The shading normal's cosine below which the coat's cosine ratio divides by this instead.
const COAT_COSINE_FLOOR: f32 = 1e-6;

// The coat's frame, from its normal in the shading frame: `tilted` false when it is the
// shading normal itself or cannot be normalized (chiaro_shading's coat_frame).
fn brdf_set_coat_frame(m: ptr<function, BrdfMaterial>, coat_normal: vec3<f32>) {
    (*m).coat_tilted = false;
    let l = length(coat_normal);
    if !(l > 0.0 && l < 3.0e38) {
        return;
    }
    let n = coat_normal * (1.0 / l);
    if all(n == vec3<f32>(0.0, 0.0, 1.0)) || !f32_is_finite(n.x + n.y + n.z) {
        return;
    }
    (*m).coat_tilted = true;
    (*m).coat_frame = frame_from_normal(n);
}

// The shading-frame direction w in the coat's frame.
fn brdf_coat_local(m: BrdfMaterial, w: vec3<f32>) -> vec3<f32> {
    if FEATURE_CLEARCOAT && m.coat_tilted {
        return frame_to_local(m.coat_frame, w);
    }
    return w;
}

// The coat-frame direction w in the shading frame.
fn brdf_coat_to_shading(m: BrdfMaterial, w: vec3<f32>) -> vec3<f32> {
    if FEATURE_CLEARCOAT && m.coat_tilted {
        return frame_to_world(m.coat_frame, w);
    }
    return w;
}

// KHR_materials_clearcoat's blend for the view wo: clearcoat Schlick(0.04, n_c.wo); 0 when the
// view is not above the coat.
fn brdf_coat_weight(m: BrdfMaterial, wo: vec3<f32>) -> f32 {
    if !FEATURE_CLEARCOAT || m.clearcoat <= 0.0 {
        return 0.0;
    }
    let cos_theta = brdf_coat_local(m, wo).z;
    if cos_theta <= 0.0 {
        return 0.0;
    }
    return m.clearcoat * fresnel_schlick(vec3<f32>(COAT_F0), cos_theta).x;
}

// One minus brdf_coat_weight, as (1 - clearcoat) + clearcoat (1 - F0) (1 - (1 - cos)^5) with
// the last factor a polynomial in cos: precise at grazing views.
fn brdf_base_weight(m: BrdfMaterial, wo: vec3<f32>) -> f32 {
    if !FEATURE_CLEARCOAT || m.clearcoat <= 0.0 {
        return 1.0;
    }
    let cos_theta = brdf_coat_local(m, wo).z;
    if cos_theta <= 0.0 {
        return 1.0;
    }
    let x = min(cos_theta, 1.0);
    let one_minus_m5 = x * (5.0 + x * (-10.0 + x * (10.0 + x * (-5.0 + x))));
    return (1.0 - m.clearcoat) + m.clearcoat * (1.0 - COAT_F0) * one_minus_m5;
}

// The coat's D V for wo, wi above the shading surface, times (n_c.wi) / (n.wi) when it has a
// normal of its own; 0 for a mirror coat and where either direction is below the coat.
fn brdf_coat_lobe(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if !FEATURE_CLEARCOAT || m.clearcoat <= 0.0 || m.coat_mirror {
        return 0.0;
    }
    if !m.coat_tilted {
        let h = brdf_half_vector(wo, wi);
        return ndf(h, m.coat_alpha) * visibility(wo, wi, m.coat_alpha);
    }
    let wo_c = frame_to_local(m.coat_frame, wo);
    let wi_c = frame_to_local(m.coat_frame, wi);
    if wo_c.z <= 0.0 || wi_c.z <= 0.0 {
        return 0.0;
    }
    let h = brdf_half_vector(wo_c, wi_c);
    return ndf(h, m.coat_alpha) * visibility(wo_c, wi_c, m.coat_alpha)
        * (wi_c.z / max(wi.z, COAT_COSINE_FLOOR));
}

// The pdf of the coat's visible-normal sampling (0 for a mirror coat and where either
// direction is below the coat).
fn brdf_coat_pdf(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if m.coat_mirror {
        return 0.0;
    }
    let wo_c = brdf_coat_local(m, wo);
    let wi_c = brdf_coat_local(m, wi);
    if wo_c.z <= 0.0 || wi_c.z <= 0.0 {
        return 0.0;
    }
    return reflected_vndf_pdf(wo_c, brdf_half_vector(wo_c, wi_c), m.coat_alpha);
}

// The coat's mirror direction for the view wo, in the shading frame.
fn brdf_coat_mirror_direction(m: BrdfMaterial, wo: vec3<f32>) -> vec3<f32> {
    if FEATURE_CLEARCOAT && m.coat_tilted {
        let n = m.coat_frame.normal;
        return 2.0 * dot(wo, n) * n - wo;
    }
    return vec3<f32>(-wo.x, -wo.y, wo.z);
}
