//! KHR_materials_volume's transmission: the specular_btdf refracts through the interface by the
//! relative IOR eta = n(wi's side) / n(wo's side). Rough surfaces use Walter et al.'s
//! microfacet BTDF (2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 21),
//! in its radiance form:
//!
//! f_t(wo, wi) = weight D(h) G2(wo, wi) |wi.h| |wo.h| / (|n.wo| |n.wi| (eta wi.h + wo.h)^2)
//!             = weight D(h) V(wo, wi) 4 |wi.h| |wo.h| / (eta wi.h + wo.h)^2,
//!
//! with h the generalized half vector, the normalized -(wo + eta wi) turned to the upper side,
//! and weight the transmission's Fresnel weight at wo.h (the same as the thin-walled lobe's).
//! The radiance form carries the 1 / eta^2 by which radiance changes as it crosses the
//! interface, so a path that enters and leaves a volume gains nothing. Directions are drawn by
//! visible-normal sampling and refraction about h; the pdf is D_wo(h) times the Jacobian
//! eta^2 |wi.h| / (eta wi.h + wo.h)^2 (Walter et al., eq. 17). A smooth surface, or one
//! whose IOR matches on both sides ([`super::ETA_DELTA_BAND`]), refracts about the normal: a
//! delta lobe. Past the critical angle (eta < 1) nothing is transmitted:
//! the Fresnel weights reflect everything there ([`Material::outside_cosine`]).

use glam::{Vec2, Vec3};

use super::{BrdfSample, LobeProbabilities, Material};
use crate::ggx;

/// The generalized half vector of a refraction from `wo` (above) to `wi` (below) with
/// relative IOR `eta`, on the upper side; None when no microfacet refracts `wo` into `wi`
/// (either direction on the wrong side of h, or a zero sum: wi = -wo at eta 1).
fn refraction_half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<Vec3> {
    let sum = -(wo + wi * eta);
    let length = sum.length();
    if length.is_nan() || length <= 0.0 {
        return None;
    }
    let h = sum / length * sum.z.signum();
    (wo.dot(h) > 0.0 && wi.dot(h) < 0.0).then_some(h)
}

/// `wo` refracted through a surface of normal `h` (wo.h > 0) into the side of relative IOR
/// `eta`; None past the critical angle.
fn refract(wo: Vec3, h: Vec3, eta: f32) -> Option<Vec3> {
    let cos_o = wo.dot(h);
    let sin2_t = (1.0 - cos_o * cos_o).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wo / eta + h * (cos_o / eta - cos_t)).normalize())
}

impl Material {
    /// The cosine at which Schlick's formula is evaluated for a view at cosine `cos` to the
    /// (micro)normal: `cos` itself on the optically denser side's outside (eta >= 1, or a
    /// thin-walled surface), the refracted cosine when the view is inside the denser medium
    /// (eta < 1), None past its critical angle (total internal reflection).
    pub(super) fn outside_cosine(&self, cos: f32) -> Option<f32> {
        if self.eta <= 0.0 || self.eta >= 1.0 {
            return Some(cos);
        }
        let sin2_t = (1.0 - cos * cos).max(0.0) / (self.eta * self.eta);
        (sin2_t < 1.0).then(|| (1.0 - sin2_t).sqrt())
    }

    /// Whether this is a rough volume's surface that transmits something: its microfacets
    /// can refract even where the view is past the critical angle at the normal.
    pub(super) fn refracts_past_the_critical_angle(&self) -> bool {
        self.eta > 0.0
            && self.eta < 1.0
            && !self.transmission_delta
            && self.transmission > 0.0
            && self.metallic < 1.0
            && self.base.max_element() > 0.0
    }

    /// The layers above the base for a transmitted pair: the coat's blend and the sheen's
    /// albedo scaling, with wi's cosine taken on its own side.
    fn transmitted_layers(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.base_weight(wo) * self.sheen_scaling(wo.z, -wi.z)
    }

    /// f_t for a rough surface and wi below it, the absorption scale included.
    pub(super) fn refraction_eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let Some(h) = refraction_half_vector(wo, wi, self.eta) else {
            return Vec3::ZERO;
        };
        let (oh, ih) = (wo.dot(h), wi.dot(h));
        let denominator = self.eta * ih + oh;
        let lobe =
            ggx::ndf(h, self.alpha) * ggx::visibility(wo, wi, self.alpha) * 4.0 * (ih * oh).abs()
                / (denominator * denominator);
        if !lobe.is_finite() {
            return Vec3::ZERO;
        }
        // Fresnel at the cosine on the thinner side, taken from whichever direction is there
        // (computing it from the other through Snell's law loses precision near grazing).
        let outside = if self.eta < 1.0 { -ih } else { oh };
        self.fresnel_outside(oh, Some(outside)).transmission
            * (lobe * self.transmitted_layers(wo, wi) * self.scale)
    }

    /// The pdf with which the refraction lobe draws wi (selection included).
    pub(super) fn refraction_pdf(&self, wo: Vec3, wi: Vec3, p: LobeProbabilities) -> f32 {
        let Some(h) = refraction_half_vector(wo, wi, self.eta) else {
            return 0.0;
        };
        let (oh, ih) = (wo.dot(h), wi.dot(h));
        let denominator = self.eta * ih + oh;
        // D_wo(h) = G1(wo) (wo.h) D(h) / wo.z = 4 (wo.h) reflected_vndf_pdf.
        let visible = 4.0 * oh * ggx::reflected_vndf_pdf(wo, h, self.alpha);
        let pdf =
            p.transmission * visible * self.eta * self.eta * ih.abs() / (denominator * denominator);
        if pdf.is_finite() { pdf } else { 0.0 }
    }

    /// A refracted direction drawn with `u`: a visible normal, then `wo` refracted about it;
    /// the straight refraction about the normal for a smooth surface (a delta). None past the
    /// critical angle, or when the direction does not go below the surface.
    pub(super) fn refraction_sample(
        &self,
        wo: Vec3,
        u: Vec2,
        p: LobeProbabilities,
    ) -> Option<BrdfSample> {
        if self.transmission_delta {
            let wi = refract(wo, Vec3::Z, self.eta)?;
            let weight = self.fresnel(wo.z).transmission
                * (self.transmitted_layers(wo, wi) * self.scale / (self.eta * self.eta));
            return Some(BrdfSample {
                wi,
                weight: weight / p.transmission,
                pdf: p.transmission,
                delta: true,
            });
        }
        let h = ggx::sample_vndf(wo, self.alpha, u);
        let wi = refract(wo, h, self.eta)?;
        if wi.z >= 0.0 {
            return None;
        }
        let pdf = self.refraction_pdf(wo, wi, p);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BrdfSample {
            wi,
            weight: self.refraction_eval(wo, wi) * (-wi.z / pdf),
            pdf,
            delta: false,
        })
    }
}
