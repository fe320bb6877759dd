//! A Lambertian material (no metal, specular layer, coat, sheen or transmission, a base colour
//! that reflects) in closed form: f = base_color (1 - absorption) / pi, cosine-weighted sampling
//! with pdf cos / pi and weight base_color (1 - absorption), the diffuse lobe picked always.
//! That is what the general lobes reduce to there, operation for operation, so the answers are
//! bit-identical (tested); they skip the Fresnel terms, the half vector and the lobe choice that
//! the diffuse surfaces of a render would otherwise pay for at every query.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::{BrdfSample, LobeProbabilities, Material};
use crate::color::luminance;
use crate::sampling::cosine_hemisphere;

/// The lobe choice of a Lambertian material.
pub(super) const DIFFUSE_ONLY: LobeProbabilities = LobeProbabilities {
    diffuse: 1.0,
    ..LobeProbabilities::NONE
};

impl Material {
    /// Whether the clamped material is Lambert's lobe alone (see the module docs).
    pub(super) fn is_lambertian(&self) -> bool {
        self.metallic == 0.0
            && self.specular == 0.0
            && self.clearcoat == 0.0
            && self.transmission == 0.0
            && self.sheen_color == Vec3::ZERO
            && luminance(self.base) > 0.0
    }

    /// f for wi.z != 0.
    pub(super) fn lambert_eval(&self, wi: Vec3) -> Vec3 {
        if wi.z > 0.0 {
            self.base * FRAC_1_PI * self.scale
        } else {
            Vec3::ZERO
        }
    }

    /// The pdf of wi (wi.z != 0).
    pub(super) fn lambert_pdf(&self, wi: Vec3) -> f32 {
        if wi.z > 0.0 { wi.z * FRAC_1_PI } else { 0.0 }
    }

    /// A cosine-weighted direction.
    pub(super) fn lambert_sample(&self, u: Vec2) -> Option<BrdfSample> {
        let wi = cosine_hemisphere(u);
        let pdf = wi.z * FRAC_1_PI;
        (wi.z > 0.0 && pdf > 0.0).then_some(BrdfSample {
            wi,
            weight: self.base * self.scale,
            pdf,
            delta: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::random_params;
    use super::super::{SurfaceParams, eval_material, pdf_material, sample_material};
    use super::*;
    use crate::rng::Pcg32;
    use crate::sampling::uniform_sphere;

    #[test]
    fn closed_form_is_the_general_lobes_bit_for_bit() {
        let mut rng = Pcg32::new(7, 3);
        let mut checked = 0;
        for k in 0..20_000 {
            // The library's random materials made Lambertian: black now and then, absorbing,
            // rough or mirror-smooth, IOR 1 or not.
            let params = SurfaceParams {
                metallic: 0.0,
                specular: 0.0,
                clearcoat: 0.0,
                transmission: 0.0,
                sheen_color: Vec3::ZERO,
                ..random_params(&mut rng)
            };
            let fast = Material::new(&params);
            assert_eq!(fast.lambertian, fast.is_lambertian());
            let general = Material {
                lambertian: false,
                ..fast
            };
            let wo = uniform_sphere(rng.next_vec2());
            let wi = uniform_sphere(rng.next_vec2());
            if !fast.lambertian || wo.z <= 0.0 || wi.z == 0.0 {
                continue;
            }
            let probabilities = general.lobe_probabilities(wo);
            assert_eq!(
                fast.lobe_probabilities(wo),
                probabilities,
                "{params:?} {wo}"
            );
            assert_eq!(
                eval_material(&fast, wo, wi),
                eval_material(&general, wo, wi),
                "{params:?} {wo} {wi}"
            );
            assert_eq!(
                pdf_material(&fast, wo, wi, DIFFUSE_ONLY),
                pdf_material(&general, wo, wi, probabilities),
                "{params:?} {wo} {wi}"
            );
            let (u_lobe, u) = (rng.next_f32(), rng.next_vec2());
            assert_eq!(
                sample_material(&fast, wo, DIFFUSE_ONLY, u_lobe, u),
                sample_material(&general, wo, probabilities, u_lobe, u),
                "{params:?} {wo} {k}"
            );
            checked += 1;
        }
        assert!(checked > 3_000, "{checked} Lambertian views checked");
    }
}
