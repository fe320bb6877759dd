//! The layers around the metallic-roughness base: KHR_materials_clearcoat's blend over it
//! (fresnel_coat) and KHR_materials_sheen's albedo scaling beneath its sheen, as weights the
//! BRDF's evaluation, sampling and lobe choice share.

use glam::Vec3;

use super::{COAT_F0, Material, fresnel_schlick};
use crate::color::luminance;
use crate::sheen;

impl Material {
    /// KHR_materials_clearcoat's blend for the view: clearcoat F_c(n.wo), F_c Schlick with
    /// F0 0.04 (IOR 1.5). The coat reflects that much through its own GGX lobe; the base
    /// beneath is weighted by one minus it ([`Material::base_weight`]).
    pub(super) fn coat_weight(&self, wo_z: f32) -> f32 {
        if self.clearcoat <= 0.0 {
            return 0.0;
        }
        self.clearcoat * fresnel_schlick(Vec3::splat(COAT_F0), wo_z).x
    }

    /// One minus [`Material::coat_weight`], written as (1 - clearcoat) + clearcoat (1 - F0)
    /// (1 - (1 - cos)^5) with the last factor a polynomial in cos, so that it keeps its
    /// precision at grazing views, where the coat weight tends to 1.
    pub(super) fn base_weight(&self, wo_z: f32) -> f32 {
        if self.clearcoat <= 0.0 {
            return 1.0;
        }
        let x = wo_z.clamp(0.0, 1.0);
        let one_minus_m5 = x * (5.0 + x * (-10.0 + x * (10.0 + x * (-5.0 + x))));
        (1.0 - self.clearcoat) + self.clearcoat * (1.0 - COAT_F0) * one_minus_m5
    }

    /// KHR_materials_sheen's albedo scaling of the base beneath the sheen
    /// ([`crate::sheen::albedo_scaling`]); exactly 1 without a sheen.
    pub(super) fn sheen_scaling(&self, wo_z: f32, wi_z: f32) -> f32 {
        sheen::albedo_scaling(self.sheen_color, self.sheen_roughness, wo_z, wi_z)
    }

    /// The sheen lobe's albedo for this view, luminance-weighted: its share in the lobe choice.
    pub(super) fn sheen_estimate(&self, wo_z: f32) -> f32 {
        if self.sheen_color.max_element() <= 0.0 {
            return 0.0;
        }
        luminance(self.sheen_color) * sheen::albedo(self.sheen_roughness, wo_z)
    }
}
