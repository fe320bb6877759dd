//! The glTF 2.0 metallic-roughness BRDF exactly as the specification's Appendix B defines it,
//! with the parameters of KHR_materials_specular, KHR_materials_clearcoat, KHR_materials_sheen
//! and KHR_materials_transmission (thin-walled, [`transmission`]), in the local shading frame (z = shading normal; `wo` and `wi` are unit vectors pointing away from the surface):
//!
//! - dielectric = fresnel_mix: (1 - specular max(F_d)) base_color / pi + specular F_d D V,
//!   F_d = Schlick at h.wi with F0 = min(f0_ior specular_color, 1) and F90 = 1
//!   (KHR_materials_specular's form of fresnel_mix; without the extension specular = 1 and
//!   specular_color = 1, which is the core spec's mix(diffuse, specular, F_d));
//! - metal = F_m D V, F_m = Schlick at h.wi with F0 = base_color and F90 = 1 (conductor_fresnel);
//! - base = mix(dielectric, metal, metallic), under KHR_materials_sheen's layer when the
//!   material has one: sheen_color Charlie(wo, wi) + base albedo_scaling ([`crate::sheen`]);
//! - f = (1 - absorption) fresnel_coat: mix(base, coat D_c V_c, clearcoat F_c(n.wo)), with
//!   KHR_materials_clearcoat's coat a GGX lobe of its own roughness and F_c Schlick with F0
//!   0.04 (without the extension clearcoat = 0 and f is the base alone). The coat has its own
//!   normal n_c (`coat_normal`; [`layers`]): F_c takes n_c.wo and the coat's lobe lives in the
//!   frame around n_c, times (n_c.wi) / (n.wi) so that each layer weighs light by its own
//!   normal's cosine.
//!
//! - D: GGX with alpha = roughness^2 ([`crate::ggx::ndf`]; Walter et al., 2007, "Microfacet Models
//!   for Refraction through Rough Surfaces").
//! - V = G2 / (4 |n.wo| |n.wi|): Smith height-correlated masking-shadowing for GGX
//!   ([`crate::ggx::visibility`]; Heitz, 2014, "Understanding the Masking-Shadowing Function in
//!   Microfacet-Based BRDFs").
//! - F: Schlick, 1994, "An Inexpensive BRDF Model for Physically-based Rendering".
//! - `absorption` is the notes' energy-absorption factor (0 by default).
//!
//! The notes' LearnOpenGL form (one Fresnel term with F0 = mix(0.04, base_color, metallic) and a
//! diffuse weight (1 - F)(1 - metallic)) is the same model for metallic 0 and 1 and differs in
//! between; chiaro follows the scene format, which defines the material, and Blender Cycles
//! renders glTF files the same way. The spec's mix is not energy-conserving for bright
//! dielectrics at grazing views (its diffuse weight uses h.wi, not n.wo): a white dielectric of
//! IOR 1.5 seen at cos 0.05 reflects 1.13 at roughness 0.5 and 1.72 as a mirror. That is the
//! format's definition, measured in this module's tests; at normal incidence it reflects 0.805
//! for base colour 0.8 and roughness 0.5, as Cycles does. A purely Lambertian surface is
//! `specular = 0` (KHR_materials_specular's specularFactor 0).
//!
//! Sampling ([`sample`]): one lobe is picked with a Fresnel-weighted estimate
//! ([`specular_probability`]), diffuse by cosine-weighted hemisphere sampling, specular by GGX
//! visible-normal sampling (Heitz, 2018, "Sampling the GGX Distribution of Visible Normals"); the
//! weight uses the combined pdf of both lobes (one-sample MIS with the balance heuristic, Veach,
//! 1997, thesis, section 9.2.4), so [`pdf`] is that combined pdf.
//!
//! Clamps (all applied on entry, so every function sees the same material):
//! - `base_color` per channel, `metallic`, `roughness`, `f0_dielectric`, `specular`,
//!   `clearcoat`, `clearcoat_roughness` and `absorption` to [0, 1]; `specular_color` to at least 0 (the extension lets it exceed 1),
//!   the dielectric's F0 to at most 1;
//! - alpha below [`MIRROR_ALPHA`] makes the specular lobe or the coat a perfect mirror (a delta
//!   lobe);
//! - the cosine passed to Schlick's formula is clamped to [0, 1];
//! - the visibility denominator is kept at least [`crate::ggx::VISIBILITY_DENOMINATOR_FLOOR`].
//!
//! Defined answers: wo.z <= 0 or wi.z = 0 gives zero from [`eval`] and [`pdf`] and `None` from
//! [`sample`]. No finite input (unit directions, parameters anywhere) yields NaN or infinity.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use crate::frame::Frame;
use crate::ggx;
use crate::sampling::cosine_hemisphere;
use crate::sheen;

pub use prepared::Bsdf;

/// Below this alpha (= roughness^2, i.e. roughness below about 0.0316) the specular lobe is a
/// perfect mirror: a delta lobe that [`eval`] and [`pdf`] leave out and [`sample`] returns with
/// `delta: true`. At this alpha D peaks at 1/(pi 1e-6) = 3.2e5 and the reflected lobe is about
/// 2 alpha = 0.002 rad (0.1 degree) wide: visually a mirror, while evaluating it as a lobe would
/// feed huge, noisy f and pdf values to light sampling and MIS. Above it, alpha is used as is
/// (D's peak stays below 3.2e5, far from overflow).
pub const MIRROR_ALPHA: f32 = 1e-3;

/// When both lobes exist, the specular lobe's selection probability is kept in
/// [MIN_LOBE_PROBABILITY, 1 - MIN_LOBE_PROBABILITY], so neither lobe is starved of samples when
/// the Fresnel estimate misjudges it (for example a glossy highlight on a bright diffuse base).
pub const MIN_LOBE_PROBABILITY: f32 = 0.1;

/// A volume's surface whose relative IOR is within this of 1 transmits as a delta, whatever its
/// roughness: at eta = 1 every microfacet passes wo straight on (the rough lobe's width scales
/// with |eta - 1|, and its pdf with the inverse square), so the lobe is a delta along the
/// refracted direction there.
pub const ETA_DELTA_BAND: f32 = 1e-3;

/// The normal-incidence reflectance of a dielectric of IOR 1.5: 0.04.
pub const DEFAULT_F0_DIELECTRIC: f32 = 0.04;

/// The dielectric normal-incidence reflectance for an index of refraction (KHR_materials_ior):
/// ((ior - 1) / (ior + 1))^2. IOR 1.5 gives 0.04, IOR 1 gives 0. Negative IORs are treated as 0.
pub fn f0_from_ior(ior: f32) -> f32 {
    let ior = ior.max(0.0);
    ((ior - 1.0) / (ior + 1.0)).powi(2)
}

/// A surface's material at a shading point, after texture lookup.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceParams {
    /// Linear RGB base colour (diffuse albedo for dielectrics, F0 for metals); clamped to [0, 1].
    pub base_color: Vec3,
    /// 0 = dielectric, 1 = metal; clamped to [0, 1].
    pub metallic: f32,
    /// Perceptual roughness; alpha = roughness^2. Clamped to [0, 1].
    pub roughness: f32,
    /// Dielectric normal-incidence reflectance, ((ior - 1) / (ior + 1))^2 ([`f0_from_ior`]);
    /// clamped to [0, 1].
    pub f0_dielectric: f32,
    /// KHR_materials_specular's strength of the dielectric's specular layer (specularFactor
    /// times the specular texture's alpha; 1 without the extension, 0 for a Lambertian
    /// surface); clamped to [0, 1].
    pub specular: f32,
    /// KHR_materials_specular's colour of the dielectric's F0 (specularColorFactor times the
    /// specular colour texture; 1 without the extension). Negative channels count as 0; the
    /// dielectric's F0 is min(f0_dielectric specular_color, 1).
    pub specular_color: Vec3,
    /// KHR_materials_clearcoat's factor: the strength of a clear coat over the material
    /// (0 without the extension); clamped to [0, 1].
    pub clearcoat: f32,
    /// The clear coat's perceptual roughness (its GGX alpha is its square); clamped to [0, 1].
    pub clearcoat_roughness: f32,
    /// KHR_materials_transmission's factor: the share of the dielectric's diffuse base that is
    /// transmitted through the (thin-walled) surface instead; clamped to [0, 1].
    pub transmission: f32,
    /// KHR_materials_sheen's colour (linear, black without the extension: no sheen); clamped
    /// to [0, 1] per channel.
    pub sheen_color: Vec3,
    /// KHR_materials_sheen's roughness ([`crate::sheen`]); clamped to [0, 1].
    pub sheen_roughness: f32,
    /// Fraction of energy absorbed: f is scaled by (1 - absorption). Clamped to [0, 1].
    pub absorption: f32,
    /// KHR_materials_volume: the index of refraction on the far side of the surface over the
    /// one on wo's side (the IOR when a ray enters the volume, its inverse when it leaves), so
    /// that the transmission lobe refracts ([`transmission`]); 0 for a thin-walled surface
    /// (the default), whose transmission does not refract. Values that are not finite and
    /// positive count as 0.
    pub eta: f32,
    /// KHR_materials_clearcoat's coat normal in the local shading frame: the coat's Fresnel
    /// blend and lobe take it. +z (the default) is the shading normal itself; a vector that
    /// cannot be normalized counts as +z.
    pub coat_normal: Vec3,
}

impl Default for SurfaceParams {
    /// glTF's default material: white, metallic 1, roughness 1, IOR 1.5, no absorption.
    fn default() -> Self {
        Self {
            base_color: Vec3::ONE,
            metallic: 1.0,
            roughness: 1.0,
            f0_dielectric: DEFAULT_F0_DIELECTRIC,
            specular: 1.0,
            specular_color: Vec3::ONE,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            transmission: 0.0,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.0,
            absorption: 0.0,
            eta: 0.0,
            coat_normal: Vec3::Z,
        }
    }
}

/// A direction drawn by [`sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrdfSample {
    /// The incident direction, local frame: wi.z > 0 reflected, wi.z < 0 transmitted.
    pub wi: Vec3,
    /// The throughput multiplier: f |cos| / pdf for non-delta samples; for a delta lobe, its
    /// weight times (1 - absorption) over its selection probability.
    pub weight: Vec3,
    /// The solid-angle pdf of `wi` over the non-delta lobes ([`pdf`]); for a delta lobe, its
    /// selection probability.
    pub pdf: f32,
    /// True for a delta lobe: the mirror reflection, or the straight-through transmission of a
    /// smooth thin-walled surface (alpha below [`MIRROR_ALPHA`]).
    pub delta: bool,
}

/// Schlick's Fresnel approximation with F90 = 1: F0 + (1 - F0) (1 - cos)^5, with cos clamped to
/// [0, 1].
pub fn fresnel_schlick(f0: Vec3, cos_theta: f32) -> Vec3 {
    let m = 1.0 - cos_theta.clamp(0.0, 1.0);
    let m2 = m * m;
    let m5 = m2 * m2 * m;
    f0 + (Vec3::ONE - f0) * m5
}

/// The material with every clamp applied and the derived quantities every function needs.
#[derive(Clone, Copy, Debug)]
struct Material {
    base: Vec3,
    metallic: f32,
    /// The dielectric's F0: min(f0_ior specular_color, 1).
    f0_dielectric: Vec3,
    /// KHR_materials_specular's weight of the dielectric's specular layer.
    specular: f32,
    alpha: f32,
    /// 1 - absorption.
    scale: f32,
    /// Alpha below [`MIRROR_ALPHA`]: the specular lobe is a delta.
    mirror: bool,
    /// KHR_materials_clearcoat's factor.
    clearcoat: f32,
    /// The clear coat's GGX alpha.
    coat_alpha: f32,
    /// The coat's alpha is below [`MIRROR_ALPHA`]: its lobe is a delta.
    coat_mirror: bool,
    /// The frame around the coat's normal; None when it is the shading normal.
    coat_frame: Option<Frame>,
    /// KHR_materials_transmission's factor.
    transmission: f32,
    /// KHR_materials_sheen's colour (black: no sheen).
    sheen_color: Vec3,
    sheen_roughness: f32,
    /// KHR_materials_volume's relative IOR across the surface (0: thin-walled).
    eta: f32,
    /// The transmission lobe is a delta: a smooth surface, or a volume whose IOR matches on
    /// both sides (within [`ETA_DELTA_BAND`]), where every microfacet passes wo straight on.
    transmission_delta: bool,
    /// Lambert's lobe alone, answered in closed form ([`lambert`]).
    lambertian: bool,
}

/// The Fresnel weights of the lobes at one cosine: the specular lobe's colour, the diffuse
/// lobe's and the transmission lobe's (base colour included).
struct FresnelWeights {
    specular: Vec3,
    diffuse: Vec3,
    transmission: Vec3,
}

/// The probabilities with which [`sample`] picks each lobe for one view ([`lobe_probabilities`]):
/// all 0 when the material reflects nothing, otherwise summing to 1. [`sample`] compares its
/// `u_lobe` against them in this order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeProbabilities {
    /// The clear coat's.
    pub coat: f32,
    /// The sheen's.
    pub sheen: f32,
    /// The base's specular lobe's.
    pub specular: f32,
    /// The diffuse lobe's.
    pub diffuse: f32,
    /// The transmission lobe's.
    pub transmission: f32,
}

/// The probabilities with which [`sample`] picks each lobe for the view `wo` (all 0 when
/// wo.z <= 0).
pub fn lobe_probabilities(p: &SurfaceParams, wo: Vec3) -> LobeProbabilities {
    if wo.z <= 0.0 {
        return LobeProbabilities::NONE;
    }
    Material::new(p).lobe_probabilities(wo)
}

impl LobeProbabilities {
    /// Every lobe 0: a material that reflects nothing, or a view from below.
    pub const NONE: Self = Self {
        coat: 0.0,
        sheen: 0.0,
        specular: 0.0,
        diffuse: 0.0,
        transmission: 0.0,
    };
}

impl Material {
    fn new(p: &SurfaceParams) -> Self {
        let f0_ior = p.f0_dielectric.clamp(0.0, 1.0);
        let specular_color = p.specular_color.max(Vec3::ZERO);
        let alpha = ggx::alpha_from_roughness(p.roughness);
        let coat_alpha = ggx::alpha_from_roughness(p.clearcoat_roughness);
        let eta = if p.eta.is_finite() && p.eta > 0.0 {
            p.eta
        } else {
            0.0
        };
        let mut m = Self {
            base: p.base_color.clamp(Vec3::ZERO, Vec3::ONE),
            metallic: p.metallic.clamp(0.0, 1.0),
            f0_dielectric: (specular_color * f0_ior).min(Vec3::ONE),
            specular: p.specular.clamp(0.0, 1.0),
            alpha,
            scale: 1.0 - p.absorption.clamp(0.0, 1.0),
            mirror: alpha < MIRROR_ALPHA,
            clearcoat: p.clearcoat.clamp(0.0, 1.0),
            coat_alpha,
            coat_mirror: coat_alpha < MIRROR_ALPHA,
            // Without a coat its normal is never read.
            coat_frame: if p.clearcoat > 0.0 {
                layers::coat_frame(p.coat_normal)
            } else {
                None
            },
            transmission: p.transmission.clamp(0.0, 1.0),
            sheen_color: p.sheen_color.clamp(Vec3::ZERO, Vec3::ONE),
            sheen_roughness: p.sheen_roughness.clamp(0.0, 1.0),
            eta,
            transmission_delta: alpha < MIRROR_ALPHA
                || (eta > 0.0 && (eta - 1.0).abs() < ETA_DELTA_BAND),
            lambertian: false,
        };
        m.lambertian = m.is_lambertian();
        m
    }

    /// The lobes' Fresnel weights at `cos` (h.wo for evaluation, n.wo for estimates):
    /// specular (1 - metallic) specular F_d + metallic F_m; beneath it
    /// (1 - metallic) (1 - specular max(F_d)) base_color, split into diffuse (1 - transmission)
    /// and transmission. Inside a volume (eta < 1) F_d is Schlick's at the refracted cosine,
    /// the angle on the optically thinner side, and 1 past the critical angle (total internal
    /// reflection): the interface reflects the same share from either side.
    fn fresnel(&self, cos: f32) -> FresnelWeights {
        self.fresnel_outside(cos, self.outside_cosine(cos))
    }

    /// [`Material::fresnel`] at `cos` for the metal and, for the dielectric, at the cosine on
    /// the optically thinner side, `outside` (None: total internal reflection, F_d = 1).
    fn fresnel_outside(&self, cos: f32, outside: Option<f32>) -> FresnelWeights {
        let dielectric = match outside {
            Some(cos) => fresnel_schlick(self.f0_dielectric, cos),
            None => Vec3::ONE,
        };
        let metal = fresnel_schlick(self.base, cos);
        let dielectric_weight = 1.0 - self.metallic;
        let beneath =
            self.base * (dielectric_weight * (1.0 - self.specular * dielectric.max_element()));
        FresnelWeights {
            specular: dielectric * (dielectric_weight * self.specular) + metal * self.metallic,
            diffuse: beneath * (1.0 - self.transmission),
            transmission: beneath * self.transmission,
        }
    }
}

/// KHR_materials_clearcoat's coat: IOR 1.5, so F0 0.04.
pub const COAT_F0: f32 = 0.04;

/// The unit half vector of two unit directions above the surface. The sum is divided by its
/// largest component before normalizing, so it cannot underflow even when wo and wi are nearly
/// opposite at the horizon; the sum is never zero there since both have z > 0.
fn half_vector(wo: Vec3, wi: Vec3) -> Vec3 {
    let sum = wo + wi;
    let largest = sum.abs().max_element();
    if largest <= 0.0 {
        return Vec3::Z;
    }
    (sum / largest).normalize()
}

/// The lobes of f for wo, wi above the surface, without the (1 - absorption) scale and the
/// coat's blend, with the diffuse lobe times pi (so it is exactly the diffuse albedo).
struct Lobes {
    /// pi f_diffuse, times the sheen's albedo scaling.
    diffuse: Vec3,
    /// f_specular, times the sheen's albedo scaling.
    specular: Vec3,
    /// The sheen's f: sheen_color times the Charlie lobe.
    sheen: Vec3,
    /// The coat's D V, times its cosine ratio ([`Material::coat_lobe`]).
    coat: f32,
}

fn lobes(m: &Material, wo: Vec3, wi: Vec3) -> Lobes {
    let h = half_vector(wo, wi);
    let weights = m.fresnel(h.dot(wi));
    let specular = if m.mirror {
        Vec3::ZERO
    } else {
        weights.specular * (ggx::ndf(h, m.alpha) * ggx::visibility(wo, wi, m.alpha))
    };
    let coat = m.coat_lobe(wo, wi);
    let (sheen, scaling) = if m.sheen_color.max_element() <= 0.0 {
        (Vec3::ZERO, 1.0)
    } else {
        (
            m.sheen_color * sheen::eval(m.sheen_roughness, wo, wi),
            m.sheen_scaling(wo.z, wi.z),
        )
    };
    Lobes {
        diffuse: weights.diffuse * scaling,
        specular: specular * scaling,
        sheen,
        coat,
    }
}

/// The solid-angle pdf of VNDF sampling with `alpha` for wo, wi above the surface (0 for a
/// mirror, whose delta is not part of any pdf).
fn glossy_pdf(mirror: bool, alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    if mirror {
        return 0.0;
    }
    ggx::reflected_vndf_pdf(wo, half_vector(wo, wi), alpha)
}

/// The probability that [`sample`] picks the base's specular lobe for this view: the luminance
/// of the specular lobe's Fresnel weight at n.wo against the diffuse lobe's, clamped to
/// [`MIN_LOBE_PROBABILITY`], 1 - [`MIN_LOBE_PROBABILITY`] when both lobes exist, times the
/// base's share against a clear coat; 0 when the material reflects nothing or wo.z <= 0.
pub fn specular_probability(p: &SurfaceParams, wo: Vec3) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    Material::new(p).lobe_probabilities(wo).specular
}

/// The BSDF value f(wo, wi) (no cosine), for unit local directions: the reflection lobes for
/// wi.z > 0, the transmission lobe for wi.z < 0 (zero without KHR_materials_transmission);
/// zero when wo.z <= 0 or wi.z = 0. A lobe with alpha below [`MIRROR_ALPHA`] is a delta, left
/// out.
pub fn eval(p: &SurfaceParams, wo: Vec3, wi: Vec3) -> Vec3 {
    if wo.z <= 0.0 || wi.z == 0.0 || wi.z.is_nan() {
        return Vec3::ZERO;
    }
    eval_material(&Material::new(p), wo, wi)
}

/// [`eval`] for a prepared material, past its checks of `wo` and `wi`.
fn eval_material(m: &Material, wo: Vec3, wi: Vec3) -> Vec3 {
    if m.lambertian {
        return m.lambert_eval(wi);
    }
    if wi.z < 0.0 {
        return m.transmission_eval(wo, wi);
    }
    let l = lobes(m, wo, wi);
    let coat = m.coat_weight(wo);
    ((l.diffuse * FRAC_1_PI + l.specular + l.sheen) * m.base_weight(wo)
        + Vec3::splat(l.coat * coat))
        * m.scale
}

/// The solid-angle pdf with which [`sample`] produces `wi` from its non-delta lobes, lobe
/// selection probabilities included (for wi.z < 0, the transmission lobe's); zero when
/// wo.z <= 0 or wi.z = 0.
pub fn pdf(p: &SurfaceParams, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z == 0.0 || wi.z.is_nan() {
        return 0.0;
    }
    let m = Material::new(p);
    pdf_material(&m, wo, wi, m.lobe_probabilities(wo))
}

/// [`pdf`] for a prepared material and its lobe probabilities for `wo`, past its checks of
/// `wo` and `wi`.
fn pdf_material(m: &Material, wo: Vec3, wi: Vec3, probabilities: LobeProbabilities) -> f32 {
    if m.lambertian {
        return m.lambert_pdf(wi);
    }
    if wi.z < 0.0 {
        return m.transmission_pdf(wo, wi, probabilities);
    }
    combined_pdf(m, wo, wi, probabilities)
}

/// The pdf of the reflection lobes other than the diffuse one (specular, coat, sheen; selection
/// included).
fn glossy_lobes_pdf(m: &Material, wo: Vec3, wi: Vec3, p: LobeProbabilities) -> f32 {
    let mut pdf = 0.0;
    if p.sheen > 0.0 {
        pdf += p.sheen * sheen::pdf(m.sheen_roughness, wo, wi);
    }
    if p.specular > 0.0 {
        pdf += p.specular * glossy_pdf(m.mirror, m.alpha, wo, wi);
    }
    if p.coat > 0.0 {
        pdf += p.coat * m.coat_pdf(wo, wi);
    }
    pdf
}

fn combined_pdf(m: &Material, wo: Vec3, wi: Vec3, p: LobeProbabilities) -> f32 {
    p.diffuse * (wi.z * FRAC_1_PI) + glossy_lobes_pdf(m, wo, wi, p)
}

/// The sample of a mirror direction, when a delta lobe (the base's specular or, with `coat`,
/// the coat) is picked. Where the coat takes the shading normal both deltas point the same
/// way, so the sample carries both, over their summed selection probability; a coat with a
/// normal of its own reflects on its own. None when the reflection leaves below the surface.
fn mirror_sample(m: &Material, wo: Vec3, p: LobeProbabilities, coat: bool) -> Option<BrdfSample> {
    let shared = m.coat_frame.is_none();
    let (mut weight, mut pdf) = (Vec3::ZERO, 0.0);
    if m.mirror && p.specular > 0.0 && (shared || !coat) {
        weight += m.fresnel(wo.z).specular * (m.base_weight(wo) * m.sheen_scaling(wo.z, wo.z));
        pdf += p.specular;
    }
    if m.coat_mirror && p.coat > 0.0 && (shared || coat) {
        weight += Vec3::splat(m.coat_weight(wo));
        pdf += p.coat;
    }
    let wi = if coat {
        m.coat_mirror_direction(wo)
    } else {
        Vec3::new(-wo.x, -wo.y, wo.z)
    };
    if wi.z <= 0.0 {
        return None;
    }
    Some(BrdfSample {
        wi,
        weight: weight * m.scale / pdf,
        pdf,
        delta: true,
    })
}

/// Draws an incident direction for the view `wo` (local frame): `u_lobe` picks the lobe (the
/// coat below its probability, then the sheen, then the specular lobe below
/// [`specular_probability`] more, then the transmission lobe, then the diffuse one), `u` drives that lobe's warp. A transmitted
/// direction has wi.z < 0. `None` when wo.z <= 0, when the material reflects nothing, or
/// when the direction drawn is at or below the horizon (the visible-normal reflection can point
/// below it; that probability mass is simply lost, and [`pdf`] does not count it).
pub fn sample(p: &SurfaceParams, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BrdfSample> {
    if wo.z <= 0.0 {
        return None;
    }
    let m = Material::new(p);
    sample_material(&m, wo, m.lobe_probabilities(wo), u_lobe, u)
}

/// [`sample`] for a prepared material and its lobe probabilities for `wo` (wo.z > 0).
fn sample_material(
    m: &Material,
    wo: Vec3,
    probabilities: LobeProbabilities,
    u_lobe: f32,
    u: Vec2,
) -> Option<BrdfSample> {
    if m.lambertian {
        return m.lambert_sample(u);
    }
    let LobeProbabilities {
        coat: p_coat,
        sheen: p_sheen,
        specular: p_specular,
        diffuse: p_diffuse,
        transmission: p_transmission,
    } = probabilities;
    if p_coat + p_sheen + p_specular + p_diffuse + p_transmission <= 0.0 {
        return None;
    }
    // The lobes in order: coat, sheen, specular, transmission, diffuse.
    let u_base = u_lobe - p_coat - p_sheen;
    let wi = if u_lobe < p_coat {
        if m.coat_mirror {
            return mirror_sample(m, wo, probabilities, true);
        }
        m.coat_sample(wo, u)
    } else if u_lobe - p_coat < p_sheen {
        sheen::sample(m.sheen_roughness, wo, u)?.0
    } else if u_base < p_specular {
        if m.mirror {
            return mirror_sample(m, wo, probabilities, false);
        }
        let h = ggx::sample_vndf(wo, m.alpha, u);
        2.0 * wo.dot(h) * h - wo
    } else if u_base - p_specular < p_transmission {
        return m.transmission_sample(wo, u, probabilities);
    } else {
        cosine_hemisphere(u)
    };
    if wi.z <= 0.0 {
        return None;
    }
    let pdf = combined_pdf(m, wo, wi, probabilities);
    if pdf.is_nan() || pdf <= 0.0 {
        return None;
    }
    // weight = f cos / pdf, divided through by cos / pi so that it stays finite as wi.z -> 0 and
    // is exactly the diffuse albedo for a purely diffuse material.
    let l = lobes(m, wo, wi);
    let coat = m.coat_weight(wo);
    let numerator = ((l.diffuse + (l.specular + l.sheen) * PI) * m.base_weight(wo)
        + Vec3::splat(l.coat * coat * PI))
        * m.scale;
    let denominator = p_diffuse + glossy_lobes_pdf(m, wo, wi, probabilities) * PI / wi.z;
    Some(BrdfSample {
        wi,
        weight: numerator / denominator,
        pdf,
        delta: false,
    })
}

mod lambert;
mod layers;
mod lobe_choice;
mod prepared;
mod refraction;
mod transmission;

#[cfg(test)]
mod chi2_tests;
#[cfg(test)]
mod finite_tests;
#[cfg(test)]
mod refraction_tests;
#[cfg(test)]
mod spec_tests;
#[cfg(test)]
mod tests;
