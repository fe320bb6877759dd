//! The layers around the metallic-roughness base: KHR_materials_clearcoat's blend over it
//! (fresnel_coat) and KHR_materials_sheen's albedo scaling beneath its sheen, as weights the
//! BRDF's evaluation, sampling and lobe choice share.
//!
//! The coat has a normal of its own ([`super::SurfaceParams::coat_normal`]): the extension's
//! clearcoatNormalTexture, or the interpolated normal when the base alone is normal-mapped.
//! Its blend takes the view's cosine to that normal, and its GGX lobe lives in the frame
//! around it. As in the glTF sample viewer and Cycles, each layer's cosine is its own normal's:
//! the coat's term of f is D_c V_c F_c (n_c.wi) / (n.wi), so that f (n.wi) is the coat's own
//! reflected radiance.

use glam::Vec3;

use super::{COAT_F0, Material, fresnel_schlick, half_vector};
use crate::color::luminance;
use crate::frame::Frame;
use crate::ggx;
use crate::sheen;

/// The shading normal's cosine below which the coat's cosine ratio (n_c.wi) / (n.wi) divides
/// by this floor instead, so that f stays finite at the horizon.
const COAT_COSINE_FLOOR: f32 = 1e-6;

/// The frame around a coat normal given in the shading frame: None when it is the shading
/// normal itself (+z), or cannot be normalized (then the coat takes the shading normal).
pub(super) fn coat_frame(coat_normal: Vec3) -> Option<Frame> {
    let n = coat_normal.normalize_or_zero();
    if n == Vec3::ZERO || n == Vec3::Z || !n.is_finite() {
        return None;
    }
    Some(Frame::from_normal(n))
}

impl Material {
    /// The shading-frame direction `w` in the coat's frame (itself when the coat takes the
    /// shading normal).
    pub(super) fn coat_local(&self, w: Vec3) -> Vec3 {
        self.coat_frame.map_or(w, |f| f.to_local(w))
    }

    /// KHR_materials_clearcoat's blend for the view `wo`: clearcoat F_c(n_c.wo), F_c Schlick
    /// with F0 0.04 (IOR 1.5); 0 when the view is not above the coat. The coat reflects that
    /// much through its own GGX lobe; the base beneath is weighted by one minus it
    /// ([`Material::base_weight`]).
    pub(super) fn coat_weight(&self, wo: Vec3) -> f32 {
        let cos = self.coat_local(wo).z;
        if self.clearcoat <= 0.0 || cos <= 0.0 {
            return 0.0;
        }
        self.clearcoat * fresnel_schlick(Vec3::splat(COAT_F0), cos).x
    }

    /// One minus [`Material::coat_weight`], written as (1 - clearcoat) + clearcoat (1 - F0)
    /// (1 - (1 - cos)^5) with the last factor a polynomial in cos, so that it keeps its
    /// precision at grazing views, where the coat weight tends to 1.
    pub(super) fn base_weight(&self, wo: Vec3) -> f32 {
        let x = self.coat_local(wo).z;
        if self.clearcoat <= 0.0 || x <= 0.0 {
            return 1.0;
        }
        let x = x.min(1.0);
        let one_minus_m5 = x * (5.0 + x * (-10.0 + x * (10.0 + x * (-5.0 + x))));
        (1.0 - self.clearcoat) + self.clearcoat * (1.0 - COAT_F0) * one_minus_m5
    }

    /// The coat's lobe D_c V_c for wo, wi above the shading surface, times its cosine ratio
    /// (n_c.wi) / (n.wi) when it has a normal of its own; 0 for a mirror coat (whose delta is
    /// no part of f) and where either direction is below the coat.
    pub(super) fn coat_lobe(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.clearcoat <= 0.0 || self.coat_mirror {
            return 0.0;
        }
        let Some(frame) = self.coat_frame else {
            let h = half_vector(wo, wi);
            return ggx::ndf(h, self.coat_alpha) * ggx::visibility(wo, wi, self.coat_alpha);
        };
        let (wo_c, wi_c) = (frame.to_local(wo), frame.to_local(wi));
        if wo_c.z <= 0.0 || wi_c.z <= 0.0 {
            return 0.0;
        }
        let h = half_vector(wo_c, wi_c);
        ggx::ndf(h, self.coat_alpha)
            * ggx::visibility(wo_c, wi_c, self.coat_alpha)
            * (wi_c.z / wi.z.max(COAT_COSINE_FLOOR))
    }

    /// The solid-angle pdf of the coat's visible-normal sampling for wo, wi (0 for a mirror
    /// coat and where either direction is below the coat).
    pub(super) fn coat_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.coat_mirror {
            return 0.0;
        }
        let (wo_c, wi_c) = (self.coat_local(wo), self.coat_local(wi));
        if wo_c.z <= 0.0 || wi_c.z <= 0.0 {
            return 0.0;
        }
        ggx::reflected_vndf_pdf(wo_c, half_vector(wo_c, wi_c), self.coat_alpha)
    }

    /// A direction drawn from the coat's visible normals with `u`, in the shading frame; one
    /// below the coat comes back as -z, below the shading surface (the sample is lost, as
    /// [`Material::coat_pdf`] counts nothing there).
    pub(super) fn coat_sample(&self, wo: Vec3, u: glam::Vec2) -> Vec3 {
        let lost = Vec3::NEG_Z;
        let wo_c = self.coat_local(wo);
        if wo_c.z <= 0.0 {
            return lost;
        }
        let h = ggx::sample_vndf(wo_c, self.coat_alpha, u);
        let wi_c = 2.0 * wo_c.dot(h) * h - wo_c;
        if wi_c.z <= 0.0 {
            return lost;
        }
        self.coat_frame.map_or(wi_c, |f| f.to_world(wi_c))
    }

    /// The coat's mirror direction for the view `wo`, in the shading frame.
    pub(super) fn coat_mirror_direction(&self, wo: Vec3) -> Vec3 {
        match self.coat_frame {
            None => Vec3::new(-wo.x, -wo.y, wo.z),
            Some(frame) => 2.0 * wo.dot(frame.normal) * frame.normal - wo,
        }
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
