//! Primary rays from the active camera: pinhole perspective or orthographic, as glTF defines
//! them, through a jittered point of the pixel (a box filter over the pixel). A perspective
//! camera also answers where it sees a world point and with what importance, for light paths
//! connected to it ([`CameraRays::importance`]).

use chiaro_bvh::Ray;
use chiaro_scene::{Camera, GlobalTransform, Projection};
use glam::{Affine3A, Vec2, Vec3};

/// A camera ready to shoot rays into an image of a given size.
#[derive(Clone, Debug)]
pub struct CameraRays {
    world: Affine3A,
    projection: Projection,
    width: u32,
    height: u32,
}

impl CameraRays {
    /// The camera placed by `global`, for an image of `width` x `height` pixels. The image's own
    /// aspect ratio is used (a glTF aspect ratio only matters to rasterizers fitting a viewport).
    pub fn new(camera: &Camera, global: &GlobalTransform, width: u32, height: u32) -> Self {
        Self {
            world: global.0,
            projection: camera.projection,
            width,
            height,
        }
    }

    /// The ray through pixel (x, y), row 0 at the top, at offset `jitter` in [0, 1)^2 within it.
    pub fn ray(&self, x: u32, y: u32, jitter: Vec2) -> Ray {
        let aspect = self.width as f32 / self.height as f32;
        let ndc = Vec2::new(
            2.0 * (x as f32 + jitter.x) / self.width as f32 - 1.0,
            1.0 - 2.0 * (y as f32 + jitter.y) / self.height as f32,
        );
        // Clip planes are a rasterizer's concern: rays start at the eye (or the view plane).
        let (origin, direction) = match self.projection {
            Projection::Perspective { yfov, .. } => {
                let half = (0.5 * yfov).tan();
                (
                    Vec3::ZERO,
                    Vec3::new(ndc.x * half * aspect, ndc.y * half, -1.0),
                )
            }
            Projection::Orthographic { xmag, ymag, .. } => {
                (Vec3::new(ndc.x * xmag, ndc.y * ymag, 0.0), Vec3::NEG_Z)
            }
        };
        let world_direction = self.world.transform_vector3(direction).normalize();
        Ray {
            origin: self.world.transform_point3(origin),
            direction: world_direction,
            t_min: 0.0,
            t_max: f32::INFINITY,
        }
    }
}

/// How a perspective camera sees a direction from its eye: the measurement of
/// [`CameraRays::importance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraImportance {
    /// Raster position, pixels from the top-left corner.
    pub raster: Vec2,
    /// Cosine between the direction and the view axis.
    pub cos: f32,
    /// The importance We = 1 / (A cos^4) (A the film's area at distance 1): the camera's
    /// response to radiance arriving along the direction, over the whole image.
    pub we: f32,
    /// Solid-angle pdf with which [`CameraRays::ray`] (at a uniform pixel and jitter) draws the
    /// direction: 1 / (A cos^3).
    pub pdf: f32,
}

impl CameraRays {
    /// The eye's world position (a perspective camera's ray origin).
    pub fn eye(&self) -> Vec3 {
        self.world.translation.into()
    }

    /// True for a pinhole perspective camera: the only kind light paths can reach (an
    /// orthographic camera sees along one direction only).
    pub fn is_perspective(&self) -> bool {
        matches!(self.projection, Projection::Perspective { .. })
    }

    /// Where the unit world direction `w` from the eye lands on the image, and the camera's
    /// importance and direction pdf there; None outside the image or for an orthographic
    /// camera. Exact for camera transforms without shear or non-uniform scale.
    pub fn importance(&self, w: Vec3) -> Option<CameraImportance> {
        let Projection::Perspective { yfov, .. } = self.projection else {
            return None;
        };
        let local = self
            .world
            .inverse()
            .transform_vector3(w)
            .normalize_or_zero();
        let cos = -local.z;
        if cos <= 0.0 {
            return None;
        }
        let aspect = self.width as f32 / self.height as f32;
        let half = (0.5 * yfov).tan();
        let ndc = Vec2::new(local.x / cos / (half * aspect), local.y / cos / half);
        if ndc.x.abs() >= 1.0 || ndc.y.abs() >= 1.0 {
            return None;
        }
        let raster = Vec2::new(
            0.5 * (ndc.x + 1.0) * self.width as f32,
            0.5 * (1.0 - ndc.y) * self.height as f32,
        );
        let area = 4.0 * half * half * aspect;
        let pdf = 1.0 / (area * cos * cos * cos);
        Some(CameraImportance {
            raster,
            cos,
            we: pdf / cos,
            pdf,
        })
    }

    /// The solid-angle pdf of drawing the unit world direction `w` from the eye (zero outside
    /// the image).
    pub fn direction_pdf(&self, w: Vec3) -> f32 {
        self.importance(w).map_or(0.0, |i| i.pdf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_looks_down_minus_z_and_corners_span_the_fov() {
        let camera = Camera {
            projection: Projection::Perspective {
                yfov: 90f32.to_radians(),
                aspect_ratio: None,
                znear: 0.1,
                zfar: None,
            },
        };
        let rays = CameraRays::new(&camera, &GlobalTransform::default(), 100, 50);
        let centre = rays.ray(50, 25, Vec2::ZERO);
        assert!(centre.direction.abs_diff_eq(Vec3::NEG_Z, 1e-6));
        // Top-left corner: y = tan(45) = 1, x = -aspect = -2 at z = -1.
        let corner = rays.ray(0, 0, Vec2::ZERO);
        assert!(
            corner
                .direction
                .abs_diff_eq(Vec3::new(-2.0, 1.0, -1.0).normalize(), 1e-6)
        );
    }

    /// The importance maps a ray's direction back to the pixel point it went through, and its
    /// pdf integrates to 1 over the image (summed over pixel centres, each pixel's solid angle
    /// about its pdf's reciprocal over the pixel count).
    #[test]
    fn importance_inverts_the_ray_and_its_pdf_is_normalised() {
        let camera = Camera {
            projection: Projection::Perspective {
                yfov: 60f32.to_radians(),
                aspect_ratio: None,
                znear: 0.1,
                zfar: None,
            },
        };
        let global = GlobalTransform(Affine3A::from_rotation_translation(
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(1.0, 2.0, 3.0),
        ));
        let (w, h) = (64, 32);
        let rays = CameraRays::new(&camera, &global, w, h);
        let ray = rays.ray(10, 20, Vec2::new(0.25, 0.75));
        let seen = rays.importance(ray.direction).expect("inside the image");
        assert!(
            seen.raster.abs_diff_eq(Vec2::new(10.25, 20.75), 1e-3),
            "{seen:?}"
        );
        assert!(rays.eye().abs_diff_eq(Vec3::new(1.0, 2.0, 3.0), 1e-6));
        // Solid angle of the image: sum over pixels of (film area a pixel) cos^3 = 1 / pdf a
        // pixel, so the sum of 1 / (pdf N) is the solid angle, and of pdf x that is 1.
        let mut integral = 0.0;
        let mut solid_angle = 0.0;
        for y in 0..h {
            for x in 0..w {
                let d = rays.ray(x, y, Vec2::splat(0.5)).direction;
                let i = rays.importance(d).unwrap();
                let pixel_solid_angle = 1.0 / (i.pdf * (w * h) as f32);
                solid_angle += pixel_solid_angle;
                integral += i.pdf * pixel_solid_angle;
            }
        }
        assert!((integral - 1.0f32).abs() < 1e-4, "{integral}");
        assert!(solid_angle > 0.5 && solid_angle < 2.0, "{solid_angle}");
        assert!(rays.importance(-ray.direction).is_none());
    }
}
