//! [`Bsdf`]: the BSDF of one material seen from one direction, prepared once for the several
//! queries a path vertex makes (light sampling's value and pdf, then the next direction).
//!
//! A Lambertian material (no metal, specular layer, coat, sheen or transmission, a base colour
//! that reflects) is answered in closed form: f = base_color (1 - absorption) / pi, cosine-
//! weighted sampling with pdf cos / pi and weight base_color (1 - absorption). That is what the
//! general lobes reduce to there, operation for operation, so the answers are bit-identical
//! (tested); they skip the Fresnel terms, the half vector and the lobe choice that the diffuse
//! scenes of a reference render would otherwise pay for at every vertex.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::{
    BrdfSample, LobeProbabilities, Material, SurfaceParams, eval_material, pdf_material,
    sample_material,
};
use crate::color::luminance;
use crate::sampling::cosine_hemisphere;

/// A material with its clamps applied and its lobe probabilities computed for the view `wo`:
/// [`Bsdf::eval`], [`Bsdf::pdf`] and [`Bsdf::sample`] answer exactly as [`super::eval`],
/// [`super::pdf`] and [`super::sample`] do for the same material and `wo`, without redoing
/// that work on every call.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    material: Material,
    wo: Vec3,
    probabilities: LobeProbabilities,
    /// Lambert's lobe alone, seen from above (see the module docs).
    lambertian: bool,
}

/// The probabilities the lobe choice gives a Lambertian material.
const DIFFUSE_ONLY: LobeProbabilities = LobeProbabilities {
    diffuse: 1.0,
    ..LobeProbabilities::NONE
};

impl Bsdf {
    /// Prepares `params` for the view `wo` (local frame, unit).
    pub fn new(params: &SurfaceParams, wo: Vec3) -> Self {
        let material = Material::new(params);
        let lambertian = wo.z > 0.0
            && material.metallic == 0.0
            && material.specular == 0.0
            && material.clearcoat == 0.0
            && material.transmission == 0.0
            && material.sheen_color == Vec3::ZERO
            && luminance(material.base) > 0.0;
        let probabilities = if lambertian {
            DIFFUSE_ONLY
        } else if wo.z > 0.0 {
            material.lobe_probabilities(wo)
        } else {
            LobeProbabilities::NONE
        };
        Self {
            material,
            wo,
            probabilities,
            lambertian,
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
        if self.lambertian {
            return if wi.z > 0.0 {
                self.material.base * FRAC_1_PI * self.material.scale
            } else {
                Vec3::ZERO
            };
        }
        eval_material(&self.material, self.wo, wi)
    }

    /// The pdf of `wi`, as [`super::pdf`].
    pub fn pdf(&self, wi: Vec3) -> f32 {
        if self.wo.z <= 0.0 || wi.z == 0.0 || wi.z.is_nan() {
            return 0.0;
        }
        if self.lambertian {
            return if wi.z > 0.0 { wi.z * FRAC_1_PI } else { 0.0 };
        }
        pdf_material(&self.material, self.wo, wi, self.probabilities)
    }

    /// An incident direction, as [`super::sample`].
    pub fn sample(&self, u_lobe: f32, u: Vec2) -> Option<BrdfSample> {
        if self.wo.z <= 0.0 {
            return None;
        }
        if self.lambertian {
            let wi = cosine_hemisphere(u);
            let pdf = wi.z * FRAC_1_PI;
            return (wi.z > 0.0 && pdf > 0.0).then_some(BrdfSample {
                wi,
                weight: self.material.base * self.material.scale,
                pdf,
                delta: false,
            });
        }
        sample_material(&self.material, self.wo, self.probabilities, u_lobe, u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::{eval, lobe_probabilities, pdf, sample};
    use crate::rng::Pcg32;

    /// A material with every parameter drawn, extensions included, and now and then a mirror,
    /// a coat normal of its own or a volume.
    fn random_params(rng: &mut Pcg32) -> SurfaceParams {
        let mut v = || rng.next_f32();
        let color = |v: &mut dyn FnMut() -> f32| Vec3::new(v(), v(), v());
        if v() < 0.3 {
            // Lambertian, now and then black or absorbing, or with IOR 1.
            return SurfaceParams {
                base_color: if v() < 0.1 { Vec3::ZERO } else { color(&mut v) },
                metallic: 0.0,
                specular: 0.0,
                f0_dielectric: if v() < 0.5 { 0.0 } else { 0.04 },
                roughness: v(),
                absorption: if v() < 0.5 { 0.0 } else { v() },
                ..SurfaceParams::default()
            };
        }
        SurfaceParams {
            base_color: color(&mut v),
            metallic: v(),
            roughness: if v() < 0.2 { 0.0 } else { v() },
            f0_dielectric: v() * 0.2,
            specular: v(),
            specular_color: color(&mut v) * 2.0,
            clearcoat: if v() < 0.5 { 0.0 } else { v() },
            clearcoat_roughness: v(),
            transmission: if v() < 0.5 { 0.0 } else { v() },
            sheen_color: if v() < 0.5 { Vec3::ZERO } else { color(&mut v) },
            sheen_roughness: v(),
            absorption: v() * 0.5,
            eta: if v() < 0.7 { 0.0 } else { 0.5 + v() },
            coat_normal: if v() < 0.5 {
                Vec3::Z
            } else {
                Vec3::new(v() - 0.5, v() - 0.5, 1.0).normalize()
            },
        }
    }

    fn direction(rng: &mut Pcg32) -> Vec3 {
        let z = rng.next_f32() * 2.0 - 1.0;
        let phi = rng.next_f32() * std::f32::consts::TAU;
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    #[test]
    fn prepared_bsdf_answers_as_the_free_functions() {
        let mut rng = Pcg32::new(7, 3);
        let mut sampled = 0;
        for _ in 0..20_000 {
            let params = random_params(&mut rng);
            let wo = direction(&mut rng);
            let wi = direction(&mut rng);
            let bsdf = Bsdf::new(&params, wo);
            assert_eq!(bsdf.lobe_probabilities(), lobe_probabilities(&params, wo));
            assert_eq!(bsdf.eval(wi), eval(&params, wo, wi), "{params:?} {wo} {wi}");
            assert_eq!(bsdf.pdf(wi), pdf(&params, wo, wi), "{params:?} {wo} {wi}");
            let (u_lobe, u) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
            let s = bsdf.sample(u_lobe, u);
            assert_eq!(s, sample(&params, wo, u_lobe, u), "{params:?} {wo}");
            sampled += usize::from(s.is_some());
        }
        // About half the views are from below, where both answer None.
        assert!(sampled > 5_000, "{sampled} samples drawn");
    }
}
