//! The environment light: radiance arriving from infinitely far away, from an equirectangular
//! image or a constant colour.
//!
//! # Equirectangular convention
//!
//! The same as chiaro's built-in sphere UVs: for a unit direction d in the image's frame,
//!
//! - u = 0.5 + atan2(d.z, d.x) / (2 pi) (longitude; u = 0.5 is +X, 0.75 is +Z, 0.25 is -Z,
//!   0 and 1 are -X), column = floor(u width);
//! - v = acos(d.y) / pi (v = 0 is +Y), row = floor(v height): the top row looks up (+Y).
//!
//! Texels are row-major, top row first. `rotation` turns the environment by that many radians
//! about +Y (right-handed, as `glam::Quat::from_rotation_y`): a feature the unrotated image shows
//! in direction d appears in direction R_y(rotation) d.
//!
//! # Lookup and sampling
//!
//! Lookup is nearest-texel (no filtering): radiance is piecewise constant over texels, the same
//! shape as the sampling density, so radiance / pdf varies only by sin(theta) inside a texel.
//! Texels are picked with a [`Distribution2D`] proportional to luminance x sin(theta at the row's
//! centre) (Pharr, Jakob and Humphreys, 2016, "Physically Based Rendering", 3rd ed.,
//! section 14.2.4), then a point is placed uniformly in (u, v) inside the texel; the solid-angle
//! pdf is pmf width height / (2 pi^2 sin(theta)). sin(theta) is kept at least [`MIN_SIN_THETA`]
//! so that the poles give a large, finite pdf.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use crate::color::luminance;
use crate::distribution::Distribution2D;
use crate::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};

/// The smallest sin(theta) used in the environment's solid-angle pdf (exactly at the poles the
/// equirectangular map's Jacobian is singular).
pub const MIN_SIN_THETA: f32 = 1e-7;

/// Where the environment's radiance comes from.
#[derive(Clone, Debug, PartialEq)]
enum Source {
    Constant(Vec3),
    Image {
        /// Radiance (texels times strength), row-major, top row first.
        texels: Vec<Vec3>,
        width: usize,
        height: usize,
        /// None when the image is black: sampling falls back to the uniform sphere.
        distribution: Option<Distribution2D>,
    },
}

/// An environment light: a constant colour or an equirectangular image, importance-sampled.
///
/// ```
/// use chiaro_shading::lights::EnvironmentLight;
/// use glam::{Vec2, Vec3};
///
/// // A 4 x 2 image: the top row (looking up) is bright, the bottom row black.
/// let mut texels = vec![Vec3::splat(2.0); 4];
/// texels.extend([Vec3::ZERO; 4]);
/// let env = EnvironmentLight::new(&texels, 4, 2, 1.0, 0.0);
/// assert_eq!(env.radiance(Vec3::Y), Vec3::splat(2.0));
/// assert_eq!(env.radiance(-Vec3::Y), Vec3::ZERO);
/// let (dir, radiance, pdf) = env.sample(Vec2::new(0.3, 0.6));
/// assert!(dir.y > 0.0 && radiance == Vec3::splat(2.0) && pdf > 0.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentLight {
    source: Source,
    /// cos and sin of the rotation about +Y.
    cos_rotation: f32,
    sin_rotation: f32,
}

impl EnvironmentLight {
    /// The same radiance from every direction (non-finite or negative channels become 0);
    /// sampled uniformly over the sphere.
    pub fn constant(radiance: Vec3) -> Self {
        Self {
            source: Source::Constant(sanitize(radiance)),
            cos_rotation: 1.0,
            sin_rotation: 0.0,
        }
    }

    /// An equirectangular image of linear RGB radiance (`width` x `height` texels, row-major, top
    /// row first; see the module docs for the convention), scaled by `strength` and turned by
    /// `rotation` radians about +Y. Non-finite or negative channels count as 0; so does a
    /// strength that is not a finite non-negative number. A size that does not match the texels
    /// (or is zero) gives a black environment. A black image is sampled uniformly.
    pub fn new(texels: &[Vec3], width: usize, height: usize, strength: f32, rotation: f32) -> Self {
        let rotation = if rotation.is_finite() { rotation } else { 0.0 };
        let (sin_rotation, cos_rotation) = rotation.sin_cos();
        let valid_size = width > 0 && height > 0 && width.checked_mul(height) == Some(texels.len());
        if !valid_size {
            return Self::constant(Vec3::ZERO);
        }
        let strength = if strength.is_finite() && strength > 0.0 {
            strength
        } else {
            0.0
        };
        let texels: Vec<Vec3> = texels.iter().map(|&t| sanitize(t) * strength).collect();
        let weights: Vec<f32> = texels
            .iter()
            .enumerate()
            .map(|(i, &t)| {
                let theta = ((i / width) as f32 + 0.5) / height as f32 * PI;
                luminance(t) * theta.sin()
            })
            .collect();
        let distribution = Distribution2D::new(&weights, width, height);
        Self {
            source: Source::Image {
                texels,
                width,
                height,
                distribution,
            },
            cos_rotation,
            sin_rotation,
        }
    }

    /// The constant radiance, `None` for an image.
    pub fn constant_radiance(&self) -> Option<Vec3> {
        match &self.source {
            Source::Constant(c) => Some(*c),
            Source::Image { .. } => None,
        }
    }

    /// The image's radiance texels (strength applied), width and height; `None` for a constant.
    pub fn texels(&self) -> Option<(&[Vec3], usize, usize)> {
        match &self.source {
            Source::Constant(_) => None,
            Source::Image {
                texels,
                width,
                height,
                ..
            } => Some((texels, *width, *height)),
        }
    }

    /// The image's texel distribution; `None` for a constant or a black image (both sampled
    /// uniformly over the sphere).
    pub fn distribution(&self) -> Option<&Distribution2D> {
        match &self.source {
            Source::Constant(_) => None,
            Source::Image { distribution, .. } => distribution.as_ref(),
        }
    }

    /// cos and sin of the rotation about +Y.
    pub fn rotation_cos_sin(&self) -> (f32, f32) {
        (self.cos_rotation, self.sin_rotation)
    }

    /// True when no direction carries any radiance.
    pub fn is_black(&self) -> bool {
        match &self.source {
            Source::Constant(c) => *c == Vec3::ZERO,
            Source::Image { distribution, .. } => distribution.is_none(),
        }
    }

    /// World direction -> image frame (undo the rotation about +Y).
    fn to_image(&self, d: Vec3) -> Vec3 {
        let (c, s) = (self.cos_rotation, self.sin_rotation);
        Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z)
    }

    /// Image frame -> world direction (apply the rotation about +Y).
    fn to_world(&self, d: Vec3) -> Vec3 {
        let (c, s) = (self.cos_rotation, self.sin_rotation);
        Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
    }

    /// The texel (column, row) an image-frame unit direction falls in, and sin(theta) there.
    fn texel_of(d: Vec3, width: usize, height: usize) -> (usize, usize, f32) {
        let u = 0.5 + d.z.atan2(d.x) / TAU;
        // sin(theta) from x and z, and theta by atan2: precise near the poles, where
        // sqrt(1 - y^2) and acos(y) lose most of their digits.
        let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
        let v = sin_theta.atan2(d.y) / PI;
        // `as usize` saturates (and maps NaN to 0), so this cannot index out of bounds.
        let column = ((u * width as f32) as usize).min(width - 1);
        let row = ((v * height as f32) as usize).min(height - 1);
        (column, row, sin_theta)
    }

    /// Radiance arriving from world direction `dir` (any length; a zero or non-finite direction
    /// reads as +Y): the nearest texel times strength, or the constant.
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        match &self.source {
            Source::Constant(c) => *c,
            Source::Image {
                texels,
                width,
                height,
                ..
            } => {
                let d = self.to_image(dir.try_normalize().unwrap_or(Vec3::Y));
                let (column, row, _) = Self::texel_of(d, *width, *height);
                texels[row * width + column]
            }
        }
    }

    /// Samples a world direction toward the environment: (direction, radiance from it,
    /// solid-angle pdf). The pdf is always positive and finite.
    pub fn sample(&self, u: Vec2) -> (Vec3, Vec3, f32) {
        match &self.source {
            Source::Constant(c) => (uniform_sphere(u), *c, UNIFORM_SPHERE_PDF),
            Source::Image {
                texels,
                width,
                height,
                distribution,
            } => {
                let Some(distribution) = distribution else {
                    return (uniform_sphere(u), Vec3::ZERO, UNIFORM_SPHERE_PDF);
                };
                let (column, row, pmf, inside) = distribution.sample_remapped(u);
                let u_img = (column as f32 + inside.x) / *width as f32;
                let v_img = (row as f32 + inside.y) / *height as f32;
                let phi = TAU * (u_img - 0.5);
                let theta = PI * v_img;
                let (sin_theta, cos_theta) = theta.sin_cos();
                let (sin_phi, cos_phi) = phi.sin_cos();
                let d = Vec3::new(sin_theta * cos_phi, cos_theta, sin_theta * sin_phi);
                let pdf = Self::solid_angle_pdf(pmf, *width, *height, sin_theta);
                (self.to_world(d), texels[row * width + column], pdf)
            }
        }
    }

    /// pmf width height / (2 pi^2 sin(theta)), with sin(theta) at least [`MIN_SIN_THETA`].
    fn solid_angle_pdf(pmf: f32, width: usize, height: usize, sin_theta: f32) -> f32 {
        pmf * (width as f32 * height as f32) / (2.0 * PI * PI * sin_theta.max(MIN_SIN_THETA))
    }

    /// The solid-angle pdf with which [`EnvironmentLight::sample`] produces world direction `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        match &self.source {
            Source::Constant(_) => UNIFORM_SPHERE_PDF,
            Source::Image {
                width,
                height,
                distribution,
                ..
            } => {
                let Some(distribution) = distribution else {
                    return UNIFORM_SPHERE_PDF;
                };
                let d = self.to_image(dir.try_normalize().unwrap_or(Vec3::Y));
                let (column, row, sin_theta) = Self::texel_of(d, *width, *height);
                Self::solid_angle_pdf(distribution.pmf(column, row), *width, *height, sin_theta)
            }
        }
    }
}

/// Non-finite or negative channels become 0.
fn sanitize(c: Vec3) -> Vec3 {
    let f = |x: f32| if x.is_finite() && x > 0.0 { x } else { 0.0 };
    Vec3::new(f(c.x), f(c.y), f(c.z))
}
