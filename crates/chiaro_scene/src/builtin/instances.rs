//! One mesh (an 80-triangle icosphere) instanced `n` times on a square grid over a ground
//! plane, for BVH and upload scaling: `builtin:instances?n=10000`. Eight materials cycle over
//! the grid; a sun and a sky light it.

use glam::Vec3;

use crate::components::{Camera, Light, LightKind, Projection};
use crate::environment::Environment;
use crate::error::SceneError;
use crate::material::Material;
use crate::scene_builder::{Node, SceneBuilder};
use crate::transform::Transform;

use super::Params;
use super::shapes::{floor, icosphere};

/// Instances when `n` is not given.
pub const DEFAULT_INSTANCES: usize = 1024;
/// Most instances accepted.
pub const MAX_INSTANCES: usize = 1_000_000;
/// Distance between grid neighbours (the spheres' radius is 0.5).
const PITCH: f32 = 1.5;

pub(super) fn build(b: &mut SceneBuilder, params: &mut Params) -> Result<(), SceneError> {
    let n = params.count("n", DEFAULT_INSTANCES, MAX_INSTANCES)?;
    let side = (n as f64).sqrt().ceil().max(1.0) as usize;
    let extent = side as f32 * PITCH;
    let ground = b.add_material(Material::diffuse("ground", Vec3::splat(0.4), 0.9));
    if let Some(mesh) = b.add_mesh("mesh \"ground\"", "ground", floor(extent + 2.0))? {
        b.add_instance("ground", mesh, ground, Transform::IDENTITY);
    }
    let palette: Vec<_> = (0..8)
        .map(|k| {
            let hue = k as f32 / 8.0 * std::f32::consts::TAU;
            let color = Vec3::new(hue.cos(), (hue + 2.1).cos(), (hue + 4.2).cos()) * 0.35 + 0.5;
            b.add_material(Material::diffuse(
                &format!("instance colour {k}"),
                color,
                0.2 + 0.1 * k as f32,
            ))
        })
        .collect();
    if let Some(sphere) = b.add_mesh("mesh \"sphere\"", "sphere", icosphere(1, false))? {
        for i in 0..n {
            let (row, col) = (i / side, i % side);
            let at = Vec3::new(
                (col as f32 + 0.5) * PITCH - 0.5 * extent,
                0.5,
                (row as f32 + 0.5) * PITCH - 0.5 * extent,
            );
            let material = palette[(row + col) % palette.len()];
            b.add_instance(
                &format!("instance {i}"),
                sphere,
                material,
                Transform::from_translation(at).with_scale(Vec3::splat(0.5)),
            );
        }
    }
    b.add_node(Node {
        name: Some("sun".into()),
        transform: Transform::looking_at(Vec3::ZERO, Vec3::new(-0.3, -1.0, -0.5), Vec3::Y),
        light: Some(Light {
            kind: LightKind::Directional,
            color: Vec3::new(1.0, 0.95, 0.9),
            intensity: 3.0,
            range: None,
        }),
        ..Node::default()
    });
    let eye = Vec3::new(0.0, 0.6 * extent + 2.0, 0.75 * extent + 3.0);
    b.add_node(Node {
        name: Some("camera".into()),
        transform: Transform::looking_at(eye, Vec3::ZERO, Vec3::Y),
        camera: Some(Camera {
            projection: Projection::Perspective {
                yfov: 50f32.to_radians(),
                aspect_ratio: None,
                znear: 0.05,
                zfar: None,
            },
        }),
        ..Node::default()
    });
    b.set_environment(Environment::constant(Vec3::new(0.3, 0.4, 0.55)));
    Ok(())
}
