// The glTF 2.0 metallic-roughness BRDF (Appendix B, with KHR_materials_specular's fresnel_mix)
// in the local shading frame (z = shading normal; wo and wi unit, pointing away from the
// surface). Mirrors chiaro_shading::brdf, whose documentation is the spec:
//
// dielectric = (1 - specular max(F_d)) base_color / pi + specular F_d D V,
//   F_d = Schlick(min(f0_ior specular_color, 1), h.wi)
// metal = Schlick(base_color, h.wi) D V
// base = mix(dielectric, metal, metallic)
// f = (1 - absorption) mix(base, coat D_c V_c, clearcoat Schlick(0.04, n_c.wo))
//   (KHR_materials_clearcoat's fresnel_coat about the coat's own normal n_c: lib/coat.wgsl)
//
// - D and V (Smith height-correlated G2 / (4 n.wo n.wi)) as in ggx.wgsl (Walter et al. 2007;
//   Heitz 2014); Schlick, 1994, "An Inexpensive BRDF Model for Physically-based Rendering"
//   (F90 = 1).
// - Sampling: Fresnel-weighted lobe choice, cosine-weighted diffuse, GGX visible normals
//   (Heitz 2018), one-sample MIS with the combined pdf (Veach, 1997, thesis, section 9.2.4).
//
// Alpha below MIRROR_ALPHA makes the specular lobe or the coat a perfect mirror (a delta lobe
// that brdf_eval and brdf_pdf leave out and brdf_sample returns with delta = true).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/color.wgsl
#import lib/sampling.wgsl
#import lib/ggx.wgsl
#import lib/features.wgsl
#import lib/sheen.wgsl
#import lib/refraction.wgsl
#import lib/coat.wgsl

// A surface's material at a shading point, after texture lookup (chiaro_shading's
// SurfaceParams). Every field is clamped on use.
struct SurfaceParams {
    base_color: vec3<f32>,
    metallic: f32,
    roughness: f32,
    f0_dielectric: f32,
    specular: f32,
    specular_color: vec3<f32>,
    clearcoat: f32,
    clearcoat_roughness: f32,
    transmission: f32,
    sheen_color: vec3<f32>,
    sheen_roughness: f32,
    absorption: f32,
    // KHR_materials_volume's relative IOR across the surface (0: thin-walled).
    eta: f32,
    // KHR_materials_clearcoat's coat normal in the shading frame (+z: the shading normal).
    coat_normal: vec3<f32>,
}

// A direction drawn by brdf_sample. `valid` is false where the Rust returns None; the other
// fields are then zero.
struct BrdfSample {
    wi: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    delta: bool,
    valid: bool,
}

// The material with every clamp applied and its derived quantities.
struct BrdfMaterial {
    base: vec3<f32>,
    metallic: f32,
    f0_dielectric: vec3<f32>,
    specular: f32,
    alpha: f32,
    scale: f32,
    mirror: bool,
    clearcoat: f32,
    coat_alpha: f32,
    coat_mirror: bool,
    // The coat has a normal of its own, the z of coat_frame.
    coat_tilted: bool,
    coat_frame: Frame,
    transmission: f32,
    sheen_color: vec3<f32>,
    sheen_roughness: f32,
    eta: f32,
    // The transmission lobe is a delta: a smooth surface, or a volume of matching IORs.
    transmission_delta: bool,
}

// ((ior - 1) / (ior + 1))^2; negative IORs count as 0.
fn f0_from_ior(ior_in: f32) -> f32 {
    let ior = max(ior_in, 0.0);
    let r = (ior - 1.0) / (ior + 1.0);
    return r * r;
}

// Schlick's Fresnel with F90 = 1: F0 + (1 - F0) (1 - cos)^5, cos clamped to [0, 1].
fn fresnel_schlick(f0: vec3<f32>, cos_theta: f32) -> vec3<f32> {
    let m = 1.0 - clamp(cos_theta, 0.0, 1.0);
    let m2 = m * m;
    let m5 = m2 * m2 * m;
    return f0 + (vec3<f32>(1.0) - f0) * m5;
}

fn brdf_material(p: SurfaceParams) -> BrdfMaterial {
    let f0_ior = clamp(p.f0_dielectric, 0.0, 1.0);
    let specular_color = max(p.specular_color, vec3<f32>(0.0));
    let alpha = alpha_from_roughness(p.roughness);
    var m: BrdfMaterial;
    m.base = clamp(p.base_color, vec3<f32>(0.0), vec3<f32>(1.0));
    m.metallic = clamp(p.metallic, 0.0, 1.0);
    m.f0_dielectric = min(specular_color * f0_ior, vec3<f32>(1.0));
    m.specular = clamp(p.specular, 0.0, 1.0);
    m.alpha = alpha;
    m.scale = 1.0 - clamp(p.absorption, 0.0, 1.0);
    m.mirror = alpha < MIRROR_ALPHA;
    m.clearcoat = 0.0;
    m.coat_alpha = 1.0;
    m.coat_mirror = false;
    m.coat_tilted = false;
    if FEATURE_CLEARCOAT {
        m.clearcoat = clamp(p.clearcoat, 0.0, 1.0);
        m.coat_alpha = alpha_from_roughness(p.clearcoat_roughness);
        m.coat_mirror = m.coat_alpha < MIRROR_ALPHA;
        brdf_set_coat_frame(&m, p.coat_normal);
    }
    m.transmission = 0.0;
    if FEATURE_TRANSMISSION {
        m.transmission = clamp(p.transmission, 0.0, 1.0);
    }
    m.eta = 0.0;
    if FEATURE_VOLUMES && f32_is_finite(p.eta) && p.eta > 0.0 {
        m.eta = p.eta;
    }
    m.transmission_delta = m.mirror || (m.eta > 0.0 && abs(m.eta - 1.0) < ETA_DELTA_BAND);
    m.sheen_color = vec3<f32>(0.0);
    m.sheen_roughness = 0.0;
    if FEATURE_SHEEN {
        m.sheen_color = clamp(p.sheen_color, vec3<f32>(0.0), vec3<f32>(1.0));
        m.sheen_roughness = clamp(p.sheen_roughness, 0.0, 1.0);
    }
    return m;
}

// The lobes' Fresnel weights at one cosine: the specular lobe's colour and the diffuse lobe's
// (base colour included).
struct FresnelWeights {
    specular: vec3<f32>,
    diffuse: vec3<f32>,
    transmission: vec3<f32>,
}

fn brdf_fresnel(m: BrdfMaterial, cos_theta: f32) -> FresnelWeights {
    return brdf_fresnel_outside(m, cos_theta, brdf_outside_cosine(m, cos_theta));
}

// brdf_fresnel with the dielectric's Schlick term at `outside`, the cosine on the optically
// thinner side (negative: total internal reflection, F_d = 1).
fn brdf_fresnel_outside(m: BrdfMaterial, cos_theta: f32, outside: f32) -> FresnelWeights {
    var dielectric = vec3<f32>(1.0);
    if outside >= 0.0 {
        dielectric = fresnel_schlick(m.f0_dielectric, outside);
    }
    let metal = fresnel_schlick(m.base, cos_theta);
    let dielectric_weight = 1.0 - m.metallic;
    let dielectric_max = max(max(dielectric.x, dielectric.y), dielectric.z);
    var w: FresnelWeights;
    let beneath = m.base * (dielectric_weight * (1.0 - m.specular * dielectric_max));
    w.specular = dielectric * (dielectric_weight * m.specular) + metal * m.metallic;
    w.diffuse = beneath * (1.0 - m.transmission);
    w.transmission = beneath * m.transmission;
    return w;
}

// KHR_materials_sheen's albedo scaling of the base beneath the sheen; exactly 1 without one.
fn brdf_sheen_scaling(m: BrdfMaterial, wo_z: f32, wi_z: f32) -> f32 {
    if !FEATURE_SHEEN {
        return 1.0;
    }
    return sheen_albedo_scaling(m.sheen_color, m.sheen_roughness, wo_z, wi_z);
}

// The sheen's luminance-weighted albedo for this view: its share in the lobe choice.
fn brdf_sheen_estimate(m: BrdfMaterial, wo_z: f32) -> f32 {
    if !FEATURE_SHEEN || max(max(m.sheen_color.x, m.sheen_color.y), m.sheen_color.z) <= 0.0 {
        return 0.0;
    }
    return luminance(m.sheen_color) * sheen_albedo(m.sheen_roughness, wo_z);
}

// The probability of side a against side b (chiaro_shading's split): -1 (the Rust's NaN)
// when both are 0, 0 or 1 when one is, else a / (a + b) kept off the ends.
fn brdf_split(a: f32, b: f32) -> f32 {
    if a <= 0.0 && b <= 0.0 {
        return -1.0;
    } else if b <= 0.0 {
        return 1.0;
    } else if a <= 0.0 {
        return 0.0;
    }
    return clamp(a / (a + b), MIN_LOBE_PROBABILITY, 1.0 - MIN_LOBE_PROBABILITY);
}

// The lobes' selection probabilities for this view (chiaro_shading's LobeProbabilities), all
// 0 when nothing reflects or transmits.
struct BrdfLobeProbabilities {
    coat: f32,
    sheen: f32,
    specular: f32,
    diffuse: f32,
    transmission: f32,
}

fn brdf_lobe_probabilities(m: BrdfMaterial, wo: vec3<f32>) -> BrdfLobeProbabilities {
    let wo_z = wo.z;
    let weights = brdf_fresnel(m, wo_z);
    let specular = luminance(weights.specular);
    var diffuse = luminance(weights.diffuse + weights.transmission);
    if diffuse <= 0.0 && brdf_refracts_past_the_critical_angle(m) {
        // Inside a volume past the critical angle at the normal, tilted microfacets still
        // refract: the transmission keeps the smallest share.
        diffuse = F32_MIN_POSITIVE;
    }
    let coat = brdf_coat_weight(m, wo);
    let sheen = brdf_sheen_estimate(m, wo_z);
    let base = brdf_sheen_scaling(m, wo_z, wo_z) * (specular + diffuse);
    var p = BrdfLobeProbabilities(0.0, 0.0, 0.0, 0.0, 0.0);
    let p_coat = brdf_split(coat, brdf_base_weight(m, wo) * (sheen + base));
    if p_coat < 0.0 {
        return p;
    }
    p.coat = p_coat;
    let p_sheen = brdf_split(sheen, base);
    if p_sheen < 0.0 {
        p.coat = 1.0;
        return p;
    }
    let p_layer = 1.0 - p_coat;
    let p_specular = brdf_split(specular, diffuse);
    if p_specular < 0.0 {
        p.sheen = p_layer;
        return p;
    }
    let p_base = p_layer * (1.0 - p_sheen);
    let beneath = p_base * (1.0 - p_specular);
    p.sheen = p_layer * p_sheen;
    p.specular = p_base * p_specular;
    p.diffuse = beneath * (1.0 - m.transmission);
    p.transmission = beneath * m.transmission;
    return p;
}

// The unit half vector of two directions above the surface, scaled by the largest component
// before normalizing so it cannot underflow.
fn brdf_half_vector(wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let sum = wo + wi;
    let a = abs(sum);
    let largest = max(max(a.x, a.y), a.z);
    if largest <= 0.0 {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    return ggx_normalize(sum / largest);
}

// The lobes for wo, wi above the surface, without the absorption scale and the coat's blend:
// pi f_diffuse, f_specular and the coat's D V (times its cosine ratio: brdf_coat_lobe).
struct BrdfLobes {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
    sheen: vec3<f32>,
    coat: f32,
}

fn brdf_lobes(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>) -> BrdfLobes {
    let h = brdf_half_vector(wo, wi);
    let weights = brdf_fresnel(m, dot(h, wi));
    var l: BrdfLobes;
    l.diffuse = weights.diffuse;
    if m.mirror {
        l.specular = vec3<f32>(0.0);
    } else {
        l.specular = weights.specular * (ndf(h, m.alpha) * visibility(wo, wi, m.alpha));
    }
    l.coat = brdf_coat_lobe(m, wo, wi);
    l.sheen = vec3<f32>(0.0);
    if FEATURE_SHEEN && max(max(m.sheen_color.x, m.sheen_color.y), m.sheen_color.z) > 0.0 {
        l.sheen = m.sheen_color * sheen_eval(m.sheen_roughness, wo, wi);
        let scaling = brdf_sheen_scaling(m, wo.z, wi.z);
        l.diffuse *= scaling;
        l.specular *= scaling;
    }
    return l;
}

// The VNDF pdf of a glossy lobe of this alpha (0 for a mirror).
fn brdf_glossy_pdf(mirror: bool, alpha: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if mirror {
        return 0.0;
    }
    return reflected_vndf_pdf(wo, brdf_half_vector(wo, wi), alpha);
}

// The probability that brdf_sample picks the base's specular lobe for this view.
fn specular_probability(p: SurfaceParams, wo: vec3<f32>) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    return brdf_lobe_probabilities(brdf_material(p), wo).specular;
}

// f(wo, wi) without the cosine: reflection for wi.z > 0, transmission for wi.z < 0; 0 when
// wo.z <= 0 or wi.z = 0.
fn brdf_eval(p: SurfaceParams, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z == 0.0 || f32_is_nan(wi.z) {
        return vec3<f32>(0.0);
    }
    let m = brdf_material(p);
    if wi.z < 0.0 {
        return brdf_transmission_eval(m, wo, wi);
    }
    let l = brdf_lobes(m, wo, wi);
    let coat = brdf_coat_weight(m, wo);
    return ((l.diffuse * INV_PI + l.specular + l.sheen) * brdf_base_weight(m, wo)
        + vec3<f32>(l.coat * coat)) * m.scale;
}

// The glossy lobes' pdf (specular and coat, selection included).
fn brdf_glossy_lobes_pdf(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>, probabilities: BrdfLobeProbabilities) -> f32 {
    var pdf = 0.0;
    if FEATURE_SHEEN && probabilities.sheen > 0.0 {
        pdf += probabilities.sheen * sheen_pdf(m.sheen_roughness, wo, wi);
    }
    if probabilities.specular > 0.0 {
        pdf += probabilities.specular * brdf_glossy_pdf(m.mirror, m.alpha, wo, wi);
    }
    if FEATURE_CLEARCOAT && probabilities.coat > 0.0 {
        pdf += probabilities.coat * brdf_coat_pdf(m, wo, wi);
    }
    return pdf;
}

fn brdf_combined_pdf(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>, probabilities: BrdfLobeProbabilities) -> f32 {
    return probabilities.diffuse * (wi.z * INV_PI) + brdf_glossy_lobes_pdf(m, wo, wi, probabilities);
}

// The solid-angle pdf with which brdf_sample draws wi from its non-delta lobes (for
// wi.z < 0, the transmission lobe's).
fn brdf_pdf(p: SurfaceParams, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z == 0.0 || f32_is_nan(wi.z) {
        return 0.0;
    }
    let m = brdf_material(p);
    let probabilities = brdf_lobe_probabilities(m, wo);
    if wi.z < 0.0 {
        return brdf_transmission_pdf(m, wo, wi, probabilities);
    }
    return brdf_combined_pdf(m, wo, wi, probabilities);
}

// KHR_materials_transmission's thin-walled lobe (chiaro_shading::brdf::transmission): the
// reflection lobe turned through the surface, wi mirrored to the upper side.
fn brdf_mirrored(w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(w.x, w.y, -w.z);
}

fn brdf_transmission_eval(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if !FEATURE_TRANSMISSION || m.transmission <= 0.0 || m.transmission_delta {
        return vec3<f32>(0.0);
    }
    if FEATURE_VOLUMES && m.eta > 0.0 {
        return brdf_refraction_eval(m, wo, wi);
    }
    let up = brdf_mirrored(wi);
    let h = brdf_half_vector(wo, up);
    let lobe = ndf(h, m.alpha) * visibility(wo, up, m.alpha);
    let layers = brdf_base_weight(m, wo) * brdf_sheen_scaling(m, wo.z, up.z);
    return brdf_fresnel(m, dot(h, up)).transmission * (lobe * layers * m.scale);
}

fn brdf_transmission_pdf(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>, probabilities: BrdfLobeProbabilities) -> f32 {
    if !FEATURE_TRANSMISSION || probabilities.transmission <= 0.0 || m.transmission_delta {
        return 0.0;
    }
    if FEATURE_VOLUMES && m.eta > 0.0 {
        return brdf_refraction_pdf(m, wo, wi, probabilities);
    }
    let up = brdf_mirrored(wi);
    return probabilities.transmission * reflected_vndf_pdf(wo, brdf_half_vector(wo, up), m.alpha);
}

// A mirror direction's sample, for a delta lobe picked (the base's specular or, with
// `coat_lobe`, the coat). Where the coat takes the shading normal every delta lobe points the
// same way, so the sample carries all of them over their summed selection probability; a coat
// with a normal of its own reflects alone. Invalid when the reflection leaves below the surface.
fn brdf_mirror_sample(m: BrdfMaterial, wo: vec3<f32>, probabilities: BrdfLobeProbabilities,
    coat_lobe: bool) -> BrdfSample {
    let one_normal = !(FEATURE_CLEARCOAT && m.coat_tilted);
    var weight = vec3<f32>(0.0);
    var pdf = 0.0;
    if m.mirror && probabilities.specular > 0.0 && (one_normal || !coat_lobe) {
        weight += brdf_fresnel(m, wo.z).specular
            * (brdf_base_weight(m, wo) * brdf_sheen_scaling(m, wo.z, wo.z));
        pdf += probabilities.specular;
    }
    if m.coat_mirror && probabilities.coat > 0.0 && (one_normal || coat_lobe) {
        weight += vec3<f32>(brdf_coat_weight(m, wo));
        pdf += probabilities.coat;
    }
    var s: BrdfSample;
    s.wi = select(vec3<f32>(-wo.x, -wo.y, wo.z), brdf_coat_mirror_direction(m, wo), coat_lobe);
    s.delta = true;
    s.valid = s.wi.z > 0.0;
    if !s.valid {
        s.wi = vec3<f32>(0.0);
        return s;
    }
    s.weight = weight * m.scale / pdf;
    s.pdf = pdf;
    return s;
}

// Draws wi for the view wo: u_lobe picks the lobe (coat, sheen, specular, transmission, then
// diffuse), u drives its warp. Invalid (the Rust's None) when wo.z <= 0, when nothing reflects, or when
// the direction drawn is at or below the horizon.
fn brdf_sample(p: SurfaceParams, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BrdfSample {
    var s: BrdfSample;
    s.valid = false;
    s.delta = false;
    if wo.z <= 0.0 {
        return s;
    }
    let m = brdf_material(p);
    let probabilities = brdf_lobe_probabilities(m, wo);
    let p_coat = probabilities.coat;
    let p_sheen = probabilities.sheen;
    let p_specular = probabilities.specular;
    let p_diffuse = probabilities.diffuse;
    let p_transmission = probabilities.transmission;
    if p_coat + p_sheen + p_specular + p_diffuse + p_transmission <= 0.0 {
        return s;
    }
    let u_base = u_lobe - p_coat - p_sheen;
    let coat_lobe = u_lobe < p_coat;
    let sheen_lobe = FEATURE_SHEEN && !coat_lobe && u_lobe - p_coat < p_sheen;
    let specular_lobe = !coat_lobe && !sheen_lobe && u_base < p_specular;
    let transmission_lobe = FEATURE_TRANSMISSION && !coat_lobe && !sheen_lobe && !specular_lobe
        && u_base - p_specular < p_transmission;
    let refraction = FEATURE_VOLUMES && transmission_lobe && m.eta > 0.0;
    if refraction && m.transmission_delta {
        return brdf_refraction_sample(m, wo, vec3<f32>(0.0, 0.0, 1.0), probabilities);
    }
    if transmission_lobe && m.mirror {
        // A smooth thin-walled surface transmits straight through: a delta along -wo.
        s.wi = -wo;
        let layers = brdf_base_weight(m, wo) * brdf_sheen_scaling(m, wo.z, wo.z);
        s.weight = brdf_fresnel(m, wo.z).transmission * layers * m.scale / p_transmission;
        s.pdf = p_transmission;
        s.delta = true;
        s.valid = true;
        return s;
    }
    var wi: vec3<f32>;
    if coat_lobe || specular_lobe || transmission_lobe {
        if (coat_lobe && m.coat_mirror) || (specular_lobe && m.mirror) {
            return brdf_mirror_sample(m, wo, probabilities, coat_lobe);
        }
        // One VNDF call for the glossy lobes (lavapipe runs every arm of a branch), the coat's
        // in its own frame.
        let wo_lobe = select(wo, brdf_coat_local(m, wo), coat_lobe);
        let h_lobe = sample_vndf(wo_lobe, select(m.alpha, m.coat_alpha, coat_lobe), u);
        let reflected_lobe = 2.0 * dot(wo_lobe, h_lobe) * h_lobe - wo_lobe;
        if coat_lobe && (wo_lobe.z <= 0.0 || reflected_lobe.z <= 0.0) {
            // Reflected below the coat: lost, as brdf_coat_pdf counts nothing there.
            return s;
        }
        let h = select(h_lobe, brdf_coat_to_shading(m, h_lobe), coat_lobe);
        if refraction {
            return brdf_refraction_sample(m, wo, h, probabilities);
        }
        wi = 2.0 * dot(wo, h) * h - wo;
    } else if sheen_lobe {
        let drawn = sheen_sample(m.sheen_roughness, wo, u);
        if !drawn.valid {
            return s;
        }
        wi = drawn.wi;
    } else {
        wi = cosine_hemisphere(u);
    }
    if wi.z <= 0.0 {
        return s;
    }
    if transmission_lobe {
        // The reflection's sample mirrored through the surface.
        let through = brdf_mirrored(wi);
        let pdf = brdf_transmission_pdf(m, wo, through, probabilities);
        if f32_is_nan(pdf) || pdf <= 0.0 {
            return s;
        }
        s.wi = through;
        s.weight = brdf_transmission_eval(m, wo, through) * (wi.z / pdf);
        s.pdf = pdf;
        s.valid = true;
        return s;
    }
    let pdf = brdf_combined_pdf(m, wo, wi, probabilities);
    if f32_is_nan(pdf) || pdf <= 0.0 {
        return s;
    }
    // f cos / pdf divided through by cos / pi: finite as wi.z -> 0.
    let l = brdf_lobes(m, wo, wi);
    let coat = brdf_coat_weight(m, wo);
    let numerator = ((l.diffuse + (l.specular + l.sheen) * PI) * brdf_base_weight(m, wo)
        + vec3<f32>(l.coat * coat * PI)) * m.scale;
    let denominator = p_diffuse + brdf_glossy_lobes_pdf(m, wo, wi, probabilities) * PI / wi.z;
    s.wi = wi;
    s.weight = numerator / denominator;
    s.pdf = pdf;
    s.valid = true;
    return s;
}
