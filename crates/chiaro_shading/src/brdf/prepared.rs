//! [`Bsdf`]: the BSDF of one material seen from one direction, prepared once for the several
//! queries a path vertex makes (light sampling's value and pdf, then the next direction).

use glam::{Vec2, Vec3};

use super::{
    BrdfSample, LobeProbabilities, Material, SurfaceParams, eval_material, pdf_material,
    sample_material,
};

/// A material with its clamps applied and its lobe probabilities computed for the view `wo`:
/// [`Bsdf::eval`], [`Bsdf::pdf`] and [`Bsdf::sample`] answer exactly as [`super::eval`],
/// [`super::pdf`] and [`super::sample`] do for the same material and `wo`, without redoing
/// that work on every call.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    material: Material,
    wo: Vec3,
    probabilities: LobeProbabilities,
}

impl Bsdf {
    /// Prepares `params` for the view `wo` (local frame, unit).
    pub fn new(params: &SurfaceParams, wo: Vec3) -> Self {
        let material = Material::new(params);
        let probabilities = if wo.z > 0.0 {
            material.lobe_probabilities(wo)
        } else {
            LobeProbabilities::NONE
        };
        Self {
            material,
            wo,
            probabilities,
        }
    }

    /// The probabilities with which [`Bsdf::sample`] picks each lobe
    /// ([`super::lobe_probabilities`]).
    pub fn lobe_probabilities(&self) -> LobeProbabilities {
        self.probabilities
    }

    /// f(wo, wi), as [`super::eval`].
    pub fn eval(&self, wi: Vec3) -> Vec3 {
        if self.wo.z <= 0.0 || wi.z == 0.0 || wi.z.is_nan() {
            return Vec3::ZERO;
        }
        eval_material(&self.material, self.wo, wi)
    }

    /// The pdf of `wi`, as [`super::pdf`].
    pub fn pdf(&self, wi: Vec3) -> f32 {
        if self.wo.z <= 0.0 || wi.z == 0.0 || wi.z.is_nan() {
            return 0.0;
        }
        pdf_material(&self.material, self.wo, wi, self.probabilities)
    }

    /// An incident direction, as [`super::sample`].
    pub fn sample(&self, u_lobe: f32, u: Vec2) -> Option<BrdfSample> {
        if self.wo.z <= 0.0 {
            return None;
        }
        sample_material(&self.material, self.wo, self.probabilities, u_lobe, u)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::random_params;
    use super::*;
    use crate::brdf::{eval, lobe_probabilities, pdf, sample};
    use crate::rng::Pcg32;
    use crate::sampling::uniform_sphere;

    #[test]
    fn prepared_bsdf_answers_as_the_free_functions() {
        let mut rng = Pcg32::new(7, 3);
        let mut sampled = 0;
        for _ in 0..20_000 {
            let params = random_params(&mut rng);
            let wo = uniform_sphere(rng.next_vec2());
            let wi = uniform_sphere(rng.next_vec2());
            let bsdf = Bsdf::new(&params, wo);
            assert_eq!(bsdf.lobe_probabilities(), lobe_probabilities(&params, wo));
            assert_eq!(bsdf.eval(wi), eval(&params, wo, wi), "{params:?} {wo} {wi}");
            assert_eq!(bsdf.pdf(wi), pdf(&params, wo, wi), "{params:?} {wo} {wi}");
            let (u_lobe, u) = (rng.next_f32(), rng.next_vec2());
            let s = bsdf.sample(u_lobe, u);
            assert_eq!(s, sample(&params, wo, u_lobe, u), "{params:?} {wo}");
            sampled += usize::from(s.is_some());
        }
        // About half the views are from below, where both answer None.
        assert!(sampled > 5_000, "{sampled} samples drawn");
    }
}
