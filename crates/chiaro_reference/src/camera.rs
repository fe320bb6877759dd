//! Primary rays from the active camera: pinhole perspective or orthographic, as glTF defines
//! them, through a jittered point of the pixel (a box filter over the pixel).

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
}
