//! The choice of lobe [`super::sample`] makes for a view: each lobe's share by an estimate of
//! what it reflects, kept away from 0 and 1 where both sides of a split exist.

use glam::Vec3;

use super::{LobeProbabilities, MIN_LOBE_PROBABILITY, Material};
use crate::color::luminance;

impl Material {
    /// Selection probabilities for the view `wo`: the coat against the rest by their weights
    /// for it, then the sheen against the base beneath it, then within the base the specular
    /// lobe against the diffuse one (and transmission) by the luminance of their Fresnel
    /// weights; each split kept in [`MIN_LOBE_PROBABILITY`], 1 - [`MIN_LOBE_PROBABILITY`] when
    /// both sides exist, exactly 0 or 1 when only one does.
    pub(super) fn lobe_probabilities(&self, wo: Vec3) -> LobeProbabilities {
        if self.lambertian {
            return super::lambert::DIFFUSE_ONLY;
        }
        let wo_z = wo.z;
        let weights = self.fresnel(wo_z);
        let specular = luminance(weights.specular);
        let mut diffuse = luminance(weights.diffuse + weights.transmission);
        if diffuse <= 0.0 && self.refracts_past_the_critical_angle() {
            // Inside a volume past the critical angle at the normal, tilted microfacets still
            // refract: the transmission keeps the smallest share instead of none.
            diffuse = f32::MIN_POSITIVE;
        }
        let coat = self.coat_weight(wo);
        let sheen = self.sheen_estimate(wo_z);
        let base = self.sheen_scaling(wo_z, wo_z) * (specular + diffuse);
        let p_coat = split(coat, self.base_weight(wo) * (sheen + base));
        let none = LobeProbabilities::NONE;
        if p_coat.is_nan() {
            return none;
        }
        let p_sheen = split(sheen, base);
        if p_sheen.is_nan() {
            return LobeProbabilities { coat: 1.0, ..none };
        }
        let p_specular = split(specular, diffuse);
        let p_layer = 1.0 - p_coat;
        if p_specular.is_nan() {
            return LobeProbabilities {
                coat: p_coat,
                sheen: p_layer,
                ..none
            };
        }
        let p_base = p_layer * (1.0 - p_sheen);
        // Beneath the specular layer the diffuse and transmission weights differ only by
        // (1 - transmission) against transmission.
        let beneath = p_base * (1.0 - p_specular);
        LobeProbabilities {
            coat: p_coat,
            sheen: p_layer * p_sheen,
            specular: p_base * p_specular,
            diffuse: beneath * (1.0 - self.transmission),
            transmission: beneath * self.transmission,
        }
    }
}

/// The probability of picking side `a` against side `b` from their weights: NaN when both are
/// zero, 0 or 1 when one is, otherwise a / (a + b) kept in [`MIN_LOBE_PROBABILITY`],
/// 1 - [`MIN_LOBE_PROBABILITY`].
fn split(a: f32, b: f32) -> f32 {
    if a <= 0.0 && b <= 0.0 {
        f32::NAN
    } else if b <= 0.0 {
        1.0
    } else if a <= 0.0 {
        0.0
    } else {
        (a / (a + b)).clamp(MIN_LOBE_PROBABILITY, 1.0 - MIN_LOBE_PROBABILITY)
    }
}
