// KHR_materials_volume's transmission (chiaro_shading::brdf::refraction, whose documentation is
// the spec): the transmission lobe refracts by the relative IOR eta = n(wi's side) /
// n(wo's side) with Walter et al.'s rough BTDF in radiance form (2007, eq. 21),
//   f_t = weight D(h) V(wo, wi) 4 |wi.h| |wo.h| / (eta wi.h + wo.h)^2,
// h the normalized -(wo + eta wi) on the upper side, sampled by visible normals and refraction
// about h (pdf D_wo(h) eta^2 |wi.h| / (eta wi.h + wo.h)^2); a smooth surface refracts about the
// normal (a delta carrying 1 / eta^2), as does a volume of matching IORs (ETA_DELTA_BAND). Compiled in only with FEATURE_VOLUMES (eta is 0
// without it). Part of lib/brdf.wgsl, which imports it.

// The cosine at which the dielectric's Schlick term is evaluated for a view at `cos`: `cos`
// outside (eta >= 1, or thin-walled), the refracted cosine inside (eta < 1), -1 past the
// critical angle (total internal reflection).
fn brdf_outside_cosine(m: BrdfMaterial, cos_theta: f32) -> f32 {
    if !FEATURE_VOLUMES || m.eta <= 0.0 || m.eta >= 1.0 {
        return cos_theta;
    }
    let sin2_t = max(1.0 - cos_theta * cos_theta, 0.0) / (m.eta * m.eta);
    if sin2_t >= 1.0 {
        return -1.0;
    }
    return sqrt(1.0 - sin2_t);
}

// A rough volume's surface that transmits something: its microfacets refract even past the
// critical angle at the normal (chiaro_shading's refracts_past_the_critical_angle).
fn brdf_refracts_past_the_critical_angle(m: BrdfMaterial) -> bool {
    return FEATURE_VOLUMES && m.eta > 0.0 && m.eta < 1.0 && !m.transmission_delta
        && m.transmission > 0.0
        && m.metallic < 1.0 && max(max(m.base.x, m.base.y), m.base.z) > 0.0;
}

// The generalized half vector of a refraction from wo (above) to wi (below); zero when no
// microfacet refracts wo into wi.
fn brdf_refraction_half_vector(wo: vec3<f32>, wi: vec3<f32>, eta: f32) -> vec3<f32> {
    let sum = -(wo + wi * eta);
    let len = length(sum);
    if !(len > 0.0) {
        return vec3<f32>(0.0);
    }
    let h = sum / len * sign(sum.z);
    if dot(wo, h) > 0.0 && dot(wi, h) < 0.0 {
        return h;
    }
    return vec3<f32>(0.0);
}

// wo refracted through a surface of normal h (wo.h > 0) into the side of relative IOR eta, in
// xyz; w is 0 past the critical angle.
fn brdf_refract(wo: vec3<f32>, h: vec3<f32>, eta: f32) -> vec4<f32> {
    let cos_o = dot(wo, h);
    let sin2_t = max(1.0 - cos_o * cos_o, 0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return vec4<f32>(0.0);
    }
    let cos_t = sqrt(1.0 - sin2_t);
    return vec4<f32>(normalize(-wo / eta + h * (cos_o / eta - cos_t)), 1.0);
}

// The coat's blend and the sheen's albedo scaling for a transmitted pair.
fn brdf_transmitted_layers(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return brdf_base_weight(m, wo) * brdf_sheen_scaling(m, wo.z, -wi.z);
}

fn brdf_refraction_eval(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let h = brdf_refraction_half_vector(wo, wi, m.eta);
    if all(h == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let oh = dot(wo, h);
    let ih = dot(wi, h);
    let denominator = m.eta * ih + oh;
    let lobe = ndf(h, m.alpha) * visibility(wo, wi, m.alpha) * 4.0 * abs(ih * oh)
        / (denominator * denominator);
    if !f32_is_finite(lobe) {
        return vec3<f32>(0.0);
    }
    // Fresnel at the cosine on the thinner side, from whichever direction is there.
    let outside = select(oh, -ih, m.eta < 1.0);
    return brdf_fresnel_outside(m, oh, outside).transmission
        * (lobe * brdf_transmitted_layers(m, wo, wi) * m.scale);
}

fn brdf_refraction_pdf(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>, probabilities: BrdfLobeProbabilities) -> f32 {
    let h = brdf_refraction_half_vector(wo, wi, m.eta);
    if all(h == vec3<f32>(0.0)) {
        return 0.0;
    }
    let oh = dot(wo, h);
    let ih = dot(wi, h);
    let denominator = m.eta * ih + oh;
    let visible = 4.0 * oh * reflected_vndf_pdf(wo, h, m.alpha);
    let pdf = probabilities.transmission * visible * m.eta * m.eta * abs(ih)
        / (denominator * denominator);
    return select(0.0, pdf, f32_is_finite(pdf));
}

// The refraction lobe's sample about the microfacet normal h (the normal itself for a smooth
// surface: a delta); invalid past the critical angle or when wi does not go below.
fn brdf_refraction_sample(m: BrdfMaterial, wo: vec3<f32>, h: vec3<f32>, probabilities: BrdfLobeProbabilities) -> BrdfSample {
    var s: BrdfSample;
    s.valid = false;
    s.delta = false;
    let refracted = brdf_refract(wo, h, m.eta);
    let wi = refracted.xyz;
    if refracted.w == 0.0 || wi.z >= 0.0 {
        return s;
    }
    s.wi = wi;
    if m.transmission_delta {
        s.weight = brdf_fresnel(m, wo.z).transmission
            * (brdf_transmitted_layers(m, wo, wi) * m.scale / (m.eta * m.eta))
            / probabilities.transmission;
        s.pdf = probabilities.transmission;
        s.delta = true;
        s.valid = true;
        return s;
    }
    let pdf = brdf_refraction_pdf(m, wo, wi, probabilities);
    if f32_is_nan(pdf) || pdf <= 0.0 {
        return s;
    }
    s.weight = brdf_refraction_eval(m, wo, wi) * (-wi.z / pdf);
    s.pdf = pdf;
    s.valid = true;
    return s;
}
