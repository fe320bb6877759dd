//! KHR_materials_transmission's lobe, for a thin-walled surface (the extension's default: the
//! surface is two interfaces back to back, so there is no refraction on average).
//!
//! The spec's dielectric base becomes mix(diffuse, specular_btdf base_color, transmission)
//! beneath fresnel_mix's specular layer. Its specular_btdf is "the same microfacet lobe as the
//! specular reflection, sampled along the line of sight through the surface": for wi below the
//! surface, f_t(wo, wi) = weight D(h) V(wo, wi') with wi' = wi mirrored to the upper side
//! (wi.x, wi.y, -wi.z) and h their half vector, so the transmitted lobe is the reflected one
//! turned through the surface, and is sampled the same way (visible normals, reflect, mirror).
//! V is the height-correlated Smith visibility the reflection uses (the extension's
//! non-normative note writes the separable form). A smooth surface (alpha below
//! [`MIRROR_ALPHA`](super::MIRROR_ALPHA)) transmits straight through: a delta lobe along -wo.
//!
//! With KHR_materials_volume (a relative IOR `eta` above 0) the lobe refracts instead
//! ([`super::refraction`]).

use glam::{Vec2, Vec3};

use super::{BrdfSample, LobeProbabilities, Material, half_vector};
use crate::ggx;

/// `w` mirrored through the surface plane: (x, y, -z).
fn mirrored(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl Material {
    /// f for wi below the surface (wi.z < 0), the absorption scale included.
    pub(super) fn transmission_eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if self.transmission <= 0.0 || self.transmission_delta {
            return Vec3::ZERO;
        }
        if self.eta > 0.0 {
            return self.refraction_eval(wo, wi);
        }
        let up = mirrored(wi);
        let h = half_vector(wo, up);
        let lobe = ggx::ndf(h, self.alpha) * ggx::visibility(wo, up, self.alpha);
        let layers = self.base_weight(wo) * self.sheen_scaling(wo.z, up.z);
        self.fresnel(h.dot(up)).transmission * (lobe * layers * self.scale)
    }

    /// The pdf with which the transmission lobe draws wi below the surface (selection
    /// included; 0 for the delta).
    pub(super) fn transmission_pdf(&self, wo: Vec3, wi: Vec3, p: LobeProbabilities) -> f32 {
        if p.transmission <= 0.0 || self.transmission_delta {
            return 0.0;
        }
        if self.eta > 0.0 {
            return self.refraction_pdf(wo, wi, p);
        }
        let up = mirrored(wi);
        p.transmission * ggx::reflected_vndf_pdf(wo, half_vector(wo, up), self.alpha)
    }

    /// A transmitted direction drawn with `u`: the reflection lobe's visible-normal sample,
    /// mirrored through the surface; None when the reflection falls below the horizon.
    pub(super) fn transmission_sample(
        &self,
        wo: Vec3,
        u: Vec2,
        p: LobeProbabilities,
    ) -> Option<BrdfSample> {
        if self.eta > 0.0 {
            return self.refraction_sample(wo, u, p);
        }
        if self.transmission_delta {
            let layers = self.base_weight(wo) * self.sheen_scaling(wo.z, wo.z);
            let weight = self.fresnel(wo.z).transmission * layers * self.scale;
            return Some(BrdfSample {
                wi: -wo,
                weight: weight / p.transmission,
                pdf: p.transmission,
                delta: true,
            });
        }
        let h = ggx::sample_vndf(wo, self.alpha, u);
        let up = 2.0 * wo.dot(h) * h - wo;
        if up.z <= 0.0 {
            return None;
        }
        let wi = mirrored(up);
        let pdf = self.transmission_pdf(wo, wi, p);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = self.transmission_eval(wo, wi) * (up.z / pdf);
        Some(BrdfSample {
            wi,
            weight,
            pdf,
            delta: false,
        })
    }
}
