//! The environment: light arriving from infinitely far away, a constant colour or an
//! equirectangular HDR image (.hdr or .exr).

use std::path::Path;

use bevy_ecs::prelude::*;
use glam::Vec3;
use image::ImageReader;

use crate::error::{Fault, Repair, SceneError};

/// Largest environment image side accepted, texels.
pub const MAX_ENVIRONMENT_SIDE: u32 = 16384;

/// Where environment radiance comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSource {
    /// The same linear RGB radiance from every direction.
    Constant(Vec3),
    /// An equirectangular image: longitude along the width, +Y up at the top row.
    Equirect(EquirectImage),
}

/// A decoded equirectangular image of linear RGB radiance.
#[derive(Clone, Debug, PartialEq)]
pub struct EquirectImage {
    /// The file it came from.
    pub path: String,
    /// Width in texels (longitude).
    pub width: u32,
    /// Height in texels (latitude).
    pub height: u32,
    /// Row-major texels, top row first; finite and non-negative.
    pub texels: Vec<Vec3>,
}

/// The scene's environment.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct Environment {
    /// The radiance source.
    pub source: EnvironmentSource,
    /// Multiplies the source's radiance.
    pub strength: f32,
    /// Rotation about +Y, radians.
    pub rotation: f32,
}

impl Default for Environment {
    /// Black: a scene is lit by its own lights only.
    fn default() -> Self {
        Self::constant(Vec3::ZERO)
    }
}

impl Environment {
    /// A constant environment of this radiance.
    pub fn constant(radiance: Vec3) -> Self {
        Self {
            source: EnvironmentSource::Constant(radiance),
            strength: 1.0,
            rotation: 0.0,
        }
    }

    /// Loads an equirectangular .hdr or .exr image. Non-finite or negative texels are set to zero,
    /// and reported as a repair.
    pub fn from_file(path: &Path, strength: f32) -> Result<(Self, Vec<Repair>), SceneError> {
        let name = path.display().to_string();
        let fail = |fault: Fault| SceneError::whole(name.clone(), fault);
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("hdr" | "exr")) {
            return Err(fail(Fault::UnsupportedFormat(".hdr or .exr")));
        }
        if !strength.is_finite() || strength < 0.0 {
            return Err(fail(Fault::Image(format!(
                "environment strength {strength} is not a finite, non-negative number"
            ))));
        }
        let mut reader = ImageReader::open(path).map_err(|e| fail(Fault::Io(e)))?;
        reader.limits(crate::texture::image_limits(MAX_ENVIRONMENT_SIDE));
        let decoded = reader
            .with_guessed_format()
            .map_err(|e| fail(Fault::Io(e)))?
            .decode()
            .map_err(|e| fail(Fault::Image(format!("cannot decode the image: {e}"))))?
            .into_rgb32f();
        let (width, height) = decoded.dimensions();
        let mut fixed = 0;
        let texels = decoded
            .pixels()
            .map(|p| {
                let v = Vec3::from_array(p.0);
                if v.is_finite() && v.min_element() >= 0.0 {
                    v
                } else {
                    fixed += 1;
                    Vec3::ZERO
                }
            })
            .collect();
        let repairs = if fixed > 0 {
            vec![Repair {
                element: "environment image".into(),
                action: format!("set {fixed} non-finite or negative texels to zero"),
            }]
        } else {
            Vec::new()
        };
        let image = EquirectImage {
            path: name,
            width,
            height,
            texels,
        };
        let environment = Self {
            source: EnvironmentSource::Equirect(image),
            strength,
            rotation: 0.0,
        };
        Ok((environment, repairs))
    }

    /// Mean radiance over the sphere (solid-angle weighted), strength included: what a uniformly
    /// diffuse white surface would see. Used by summaries and tests.
    pub fn mean_radiance(&self) -> Vec3 {
        let mean = match &self.source {
            EnvironmentSource::Constant(c) => *c,
            EnvironmentSource::Equirect(img) => {
                let mut sum = Vec3::ZERO;
                let mut weight = 0.0;
                for y in 0..img.height as usize {
                    let theta = (y as f32 + 0.5) / img.height as f32 * std::f32::consts::PI;
                    let w = theta.sin();
                    let row = &img.texels[y * img.width as usize..(y + 1) * img.width as usize];
                    sum += row.iter().copied().sum::<Vec3>() * w;
                    weight += w * img.width as f32;
                }
                if weight > 0.0 {
                    sum / weight
                } else {
                    Vec3::ZERO
                }
            }
        };
        mean * self.strength
    }

    /// The mean radiance the light tables give the environment its share of light picks by
    /// ([`Self::mean_radiance`]), or zero to leave it out of light sampling: a constant
    /// environment is left out, its light found by BRDF sampling alone. Its light samples would be
    /// uniform over the sphere, half of them below the surface, where BRDF sampling already
    /// follows the rest of the integrand (f cos); and its share, scaled by the scene's bounding
    /// radius squared, starves every emitter of picks in a scene that spreads far. pbrt-v4 does
    /// the same for its uniform infinite light under MIS (Pharr, Jakob and Humphreys, "Physically
    /// Based Rendering", 4th ed., section 12.5.1, `allowIncompletePDF`). An image environment
    /// stays: its bright texels (a sun) are what light sampling finds.
    pub fn light_sampling_radiance(&self) -> Vec3 {
        match self.source {
            EnvironmentSource::Constant(_) => Vec3::ZERO,
            EnvironmentSource::Equirect(_) => self.mean_radiance(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrong_extension_is_refused_by_name() {
        let err = Environment::from_file(Path::new("sky.png"), 1.0).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("sky.png: unsupported file type"),
            "{err}"
        );
    }

    #[test]
    fn missing_file_names_the_file() {
        let err = Environment::from_file(Path::new("/nonexistent/sky.hdr"), 1.0).unwrap_err();
        assert!(err.to_string().contains("/nonexistent/sky.hdr"), "{err}");
        assert!(matches!(err.fault, Fault::Io(_)));
    }

    #[test]
    fn constant_mean_is_the_constant_times_strength() {
        let mut env = Environment::constant(Vec3::new(1.0, 2.0, 3.0));
        env.strength = 2.0;
        assert_eq!(env.mean_radiance(), Vec3::new(2.0, 4.0, 6.0));
    }
}
