//! The camera as the passes read it: the rasterizer's jittered view-projection (and the
//! previous frame's, for motion vectors), and the basis the compute passes build primary rays
//! from exactly as the CPU reference does (pinhole or orthographic, glTF conventions, a point
//! of the pixel chosen by the jitter: a box filter over the pixel once frames accumulate).

use crate::gpu_scene::back_faces::CullView;
use bevy_ecs::prelude::*;
use bytemuck::{Pod, Zeroable};
use chiaro_scene::{ActiveCamera, Camera, GlobalTransform, Projection};
use glam::{Mat4, Vec2, Vec3, Vec4};
use thiserror::Error;

/// The scene has no usable camera.
#[derive(Debug, Error)]
#[error("the scene has no active camera with a transform")]
pub struct NoCamera;

/// The camera parameters (mirrored by `shaders/lib/camera.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuCamera {
    /// World to clip space, jittered, columns.
    pub view_proj: [[f32; 4]; 4],
    /// The previous frame's world to clip space, unjittered, columns.
    pub previous_view_proj: [[f32; 4]; 4],
    /// World to clip space, unjittered, columns.
    pub unjittered_view_proj: [[f32; 4]; 4],
    /// Eye position (perspective) or the view plane's centre (orthographic).
    pub origin: [f32; 3],
    /// 1 for orthographic.
    pub orthographic: u32,
    /// Camera right axis (world) scaled by the half-width of the view at distance 1 (or by
    /// xmag).
    pub right: [f32; 3],
    /// Image width in pixels.
    pub width: f32,
    /// Camera up axis scaled by the half-height (or by ymag).
    pub up: [f32; 3],
    /// Image height in pixels.
    pub height: f32,
    /// Camera forward axis (world, unit).
    pub forward: [f32; 3],
    /// Distance of the near plane from the eye (the rasterizer clips nearer points).
    pub near: f32,
    /// The sub-pixel point of this frame, in [0, 1)^2 (x right, y down).
    pub jitter: [f32; 2],
    /// A number of this frame's own, from the seed and the frame index
    /// ([`crate::renderer::coverage_frame_seed`]): the G-buffer hashes it into the coverage
    /// number of alpha-blended fragments. 0 from [`GpuCamera::new`].
    pub frame_seed: u32,
    /// Padding.
    pub pad1: u32,
}

/// The active camera's projection and placement.
pub fn active_camera(world: &World) -> Result<(Camera, GlobalTransform), NoCamera> {
    let entity = world.get_resource::<ActiveCamera>().ok_or(NoCamera)?.0;
    let entity = world.get_entity(entity).map_err(|_| NoCamera)?;
    match (entity.get::<Camera>(), entity.get::<GlobalTransform>()) {
        (Some(c), Some(g)) => Ok((*c, *g)),
        _ => Err(NoCamera),
    }
}

/// A right-handed perspective projection looking down -Z with reversed depth: `znear` maps
/// to 1 and infinity to 0 (`half` = tan(yfov / 2)). Reversed depth keeps float precision at
/// any distance; the far plane is infinite because the CPU reference, whose image the frame
/// must match, has none.
fn perspective(half: f32, aspect: f32, znear: f32) -> Mat4 {
    let f = 1.0 / half;
    Mat4::from_cols(
        Vec4::new(f / aspect, 0.0, 0.0, 0.0),
        Vec4::new(0.0, f, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 0.0, -1.0),
        Vec4::new(0.0, 0.0, znear, 0.0),
    )
}

/// A right-handed orthographic projection with reversed depth: `znear` maps to 1, `zfar` to 0.
fn orthographic(xmag: f32, ymag: f32, znear: f32, zfar: f32) -> Mat4 {
    let zfar = zfar.max(znear + 1e-3);
    Mat4::from_cols(
        Vec4::new(1.0 / xmag, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0 / ymag, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 1.0 / (zfar - znear), 0.0),
        Vec4::new(0.0, 0.0, zfar / (zfar - znear), 1.0),
    )
}

impl GpuCamera {
    /// The parameters for `camera` at `global`, an image of `width` x `height` pixels, sampling
    /// the point `jitter` of each pixel; `previous` is the last frame's unjittered
    /// view-projection (`None`: the same as this frame's).
    pub fn new(
        camera: &Camera,
        global: &GlobalTransform,
        width: u32,
        height: u32,
        jitter: Vec2,
        previous: Option<Mat4>,
    ) -> Self {
        let aspect = width as f32 / height as f32;
        let world = global.0;
        let right_axis = world.transform_vector3(Vec3::X).normalize_or(Vec3::X);
        let up_axis = world.transform_vector3(Vec3::Y).normalize_or(Vec3::Y);
        let forward = world
            .transform_vector3(Vec3::NEG_Z)
            .normalize_or(Vec3::NEG_Z);
        let eye = Vec3::from(world.translation);
        let back = -forward;
        let view = Mat4::from_cols(
            Vec4::new(right_axis.x, up_axis.x, back.x, 0.0),
            Vec4::new(right_axis.y, up_axis.y, back.y, 0.0),
            Vec4::new(right_axis.z, up_axis.z, back.z, 0.0),
            Vec4::new(-right_axis.dot(eye), -up_axis.dot(eye), -back.dot(eye), 1.0),
        );
        let (projection, right, up, orthographic, near) = match camera.projection {
            Projection::Perspective { yfov, znear, .. } => {
                let half = (0.5 * yfov).tan();
                let znear = znear.max(1e-6);
                let p = perspective(half, aspect, znear);
                (p, right_axis * half * aspect, up_axis * half, 0, znear)
            }
            Projection::Orthographic {
                xmag,
                ymag,
                znear,
                zfar,
            } => {
                let p = orthographic(xmag, ymag, znear, zfar);
                (p, right_axis * xmag, up_axis * ymag, 1, znear)
            }
        };
        // The rasterizer samples pixel centres: shift the image so that the centre of pixel x
        // sees the point x + jitter.
        let shift = Vec3::new(
            2.0 * (0.5 - jitter.x) / width as f32,
            -2.0 * (0.5 - jitter.y) / height as f32,
            0.0,
        );
        let unjittered = projection * view;
        let jittered = Mat4::from_translation(shift) * unjittered;
        Self {
            view_proj: jittered.to_cols_array_2d(),
            previous_view_proj: previous.unwrap_or(unjittered).to_cols_array_2d(),
            unjittered_view_proj: unjittered.to_cols_array_2d(),
            origin: world.translation.into(),
            orthographic,
            right: right.to_array(),
            width: width as f32,
            up: up.to_array(),
            height: height as f32,
            forward: forward.to_array(),
            near,
            jitter: jitter.to_array(),
            frame_seed: 0,
            pad1: 0,
        }
    }

    /// The camera as the G-buffer's back-face test sees it; `None` for an orthographic one.
    pub fn cull_view(&self) -> Option<CullView> {
        if self.orthographic != 0 {
            return None;
        }
        // The near plane's corners are the farthest of its points from the eye.
        let corner = Vec3::from(self.right).length_squared() + Vec3::from(self.up).length_squared();
        Some(CullView {
            eye: self.origin.into(),
            near_reach: self.near * (1.0 + corner).sqrt(),
        })
    }

    /// The unjittered view-projection (next frame's `previous`).
    pub fn unjittered(&self) -> Mat4 {
        Mat4::from_cols_array_2d(&self.unjittered_view_proj)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jittered_projection_puts_the_sampled_point_at_the_pixel_centre() {
        let camera = Camera {
            projection: Projection::Perspective {
                yfov: 1.0,
                aspect_ratio: None,
                znear: 0.1,
                zfar: None,
            },
        };
        let (w, h) = (64, 32);
        let jitter = Vec2::new(0.25, 0.8);
        let c = GpuCamera::new(&camera, &GlobalTransform::default(), w, h, jitter, None);
        // The ray through pixel (10, 5) at the jitter, built like the reference's.
        let ndc = Vec2::new(
            2.0 * (10.0 + jitter.x) / w as f32 - 1.0,
            1.0 - 2.0 * (5.0 + jitter.y) / h as f32,
        );
        let dir = Vec3::from(c.forward) + Vec3::from(c.right) * ndc.x + Vec3::from(c.up) * ndc.y;
        let clip = Mat4::from_cols_array_2d(&c.view_proj) * (dir * 3.0).extend(1.0);
        let pixel = Vec2::new(
            (clip.x / clip.w + 1.0) * 0.5 * w as f32,
            (1.0 - clip.y / clip.w) * 0.5 * h as f32,
        );
        assert!((pixel - Vec2::new(10.5, 5.5)).length() < 1e-3, "{pixel}");
        // Reversed depth: the near plane at 1, far points towards 0 but still positive.
        let depth = |distance: f32| {
            let p = Mat4::from_cols_array_2d(&c.view_proj) * Vec4::new(0.0, 0.0, -distance, 1.0);
            p.z / p.w
        };
        assert!((depth(0.1) - 1.0).abs() < 1e-6);
        assert!(depth(1.5e5) > 0.0 && depth(1.5e5) < depth(1.4e5));
    }
}
