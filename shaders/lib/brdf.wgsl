// The glTF 2.0 metallic-roughness BRDF (Appendix B, with KHR_materials_specular's fresnel_mix)
// in the local shading frame (z = shading normal; wo and wi unit, pointing away from the
// surface). Mirrors chiaro_shading::brdf, whose documentation is the spec:
//
// dielectric = (1 - specular max(F_d)) base_color / pi + specular F_d D V,
//   F_d = Schlick(min(f0_ior specular_color, 1), h.wi)
// metal = Schlick(base_color, h.wi) D V
// f = (1 - absorption) mix(dielectric, metal, metallic)
//
// - D and V (Smith height-correlated G2 / (4 n.wo n.wi)) as in ggx.wgsl (Walter et al. 2007;
//   Heitz 2014); Schlick, 1994, "An Inexpensive BRDF Model for Physically-based Rendering"
//   (F90 = 1).
// - Sampling: Fresnel-weighted lobe choice, cosine-weighted diffuse, GGX visible normals
//   (Heitz 2018), one-sample MIS with the combined pdf (Veach, 1997, thesis, section 9.2.4).
//
// Alpha below MIRROR_ALPHA makes the specular lobe a perfect mirror (a delta lobe that
// brdf_eval and brdf_pdf leave out and brdf_sample returns with delta = true).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/color.wgsl
#import lib/sampling.wgsl
#import lib/ggx.wgsl

// A surface's material at a shading point, after texture lookup (chiaro_shading's
// SurfaceParams). Every field is clamped on use.
struct SurfaceParams {
    base_color: vec3<f32>,
    metallic: f32,
    roughness: f32,
    f0_dielectric: f32,
    specular: f32,
    specular_color: vec3<f32>,
    absorption: f32,
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
    return m;
}

// The lobes' Fresnel weights at one cosine: the specular lobe's colour and the diffuse lobe's
// (base colour included).
struct FresnelWeights {
    specular: vec3<f32>,
    diffuse: vec3<f32>,
}

fn brdf_fresnel(m: BrdfMaterial, cos_theta: f32) -> FresnelWeights {
    let dielectric = fresnel_schlick(m.f0_dielectric, cos_theta);
    let metal = fresnel_schlick(m.base, cos_theta);
    let dielectric_weight = 1.0 - m.metallic;
    let dielectric_max = max(max(dielectric.x, dielectric.y), dielectric.z);
    var w: FresnelWeights;
    w.specular = dielectric * (dielectric_weight * m.specular) + metal * m.metallic;
    w.diffuse = m.base * (dielectric_weight * (1.0 - m.specular * dielectric_max));
    return w;
}

// (specular, diffuse) selection probabilities for this view: both 0 when nothing reflects.
fn brdf_lobe_probabilities(m: BrdfMaterial, wo_z: f32) -> vec2<f32> {
    let weights = brdf_fresnel(m, wo_z);
    let specular = luminance(weights.specular);
    let diffuse = luminance(weights.diffuse);
    var p: f32;
    if specular <= 0.0 && diffuse <= 0.0 {
        return vec2<f32>(0.0);
    } else if diffuse <= 0.0 {
        p = 1.0;
    } else if specular <= 0.0 {
        p = 0.0;
    } else {
        p = clamp(specular / (specular + diffuse), MIN_LOBE_PROBABILITY, 1.0 - MIN_LOBE_PROBABILITY);
    }
    return vec2<f32>(p, 1.0 - p);
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

// The two lobes for wo, wi above the surface, without the absorption scale:
// (pi f_diffuse, f_specular), as two columns.
struct BrdfLobes {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
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
    return l;
}

// The specular lobe's VNDF pdf (0 for the mirror).
fn brdf_specular_pdf(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if m.mirror {
        return 0.0;
    }
    return reflected_vndf_pdf(wo, brdf_half_vector(wo, wi), m.alpha);
}

// The probability that brdf_sample picks the specular lobe for this view.
fn specular_probability(p: SurfaceParams, wo: vec3<f32>) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    return brdf_lobe_probabilities(brdf_material(p), wo.z).x;
}

// f(wo, wi) without the cosine; 0 when wo.z <= 0 or wi.z <= 0.
fn brdf_eval(p: SurfaceParams, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let m = brdf_material(p);
    let l = brdf_lobes(m, wo, wi);
    return (l.diffuse * INV_PI + l.specular) * m.scale;
}

fn brdf_combined_pdf(m: BrdfMaterial, wo: vec3<f32>, wi: vec3<f32>, probabilities: vec2<f32>) -> f32 {
    var specular = 0.0;
    if probabilities.x > 0.0 {
        specular = probabilities.x * brdf_specular_pdf(m, wo, wi);
    }
    return probabilities.y * (wi.z * INV_PI) + specular;
}

// The solid-angle pdf with which brdf_sample draws wi from its non-delta lobes.
fn brdf_pdf(p: SurfaceParams, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let m = brdf_material(p);
    return brdf_combined_pdf(m, wo, wi, brdf_lobe_probabilities(m, wo.z));
}

// Draws wi for the view wo: u_lobe picks the lobe, u drives its warp. Invalid (the Rust's None)
// when wo.z <= 0, when nothing reflects, or when the direction drawn is at or below the horizon.
fn brdf_sample(p: SurfaceParams, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BrdfSample {
    var s: BrdfSample;
    s.valid = false;
    s.delta = false;
    if wo.z <= 0.0 {
        return s;
    }
    let m = brdf_material(p);
    let probabilities = brdf_lobe_probabilities(m, wo.z);
    let p_specular = probabilities.x;
    let p_diffuse = probabilities.y;
    if p_specular <= 0.0 && p_diffuse <= 0.0 {
        return s;
    }
    var wi: vec3<f32>;
    if u_lobe < p_specular {
        if m.mirror {
            s.wi = vec3<f32>(-wo.x, -wo.y, wo.z);
            s.weight = brdf_fresnel(m, wo.z).specular * m.scale / p_specular;
            s.pdf = p_specular;
            s.delta = true;
            s.valid = true;
            return s;
        }
        let h = sample_vndf(wo, m.alpha, u);
        wi = 2.0 * dot(wo, h) * h - wo;
    } else {
        wi = cosine_hemisphere(u);
    }
    if wi.z <= 0.0 {
        return s;
    }
    let pdf = brdf_combined_pdf(m, wo, wi, probabilities);
    if f32_is_nan(pdf) || pdf <= 0.0 {
        return s;
    }
    // f cos / pdf divided through by cos / pi: finite as wi.z -> 0.
    let l = brdf_lobes(m, wo, wi);
    let numerator = (l.diffuse + l.specular * PI) * m.scale;
    let denominator = p_diffuse + p_specular * brdf_specular_pdf(m, wo, wi) * PI / wi.z;
    s.wi = wi;
    s.weight = numerator / denominator;
    s.pdf = pdf;
    s.valid = true;
    return s;
}
