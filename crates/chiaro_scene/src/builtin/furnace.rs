//! The white-furnace test: the inside of a closed sphere whose surface is diffuse with albedo 0.5
//! and emits radiance 0.5 everywhere. Every path sees L = 0.5 + 0.5 L, so the exact radiance in
//! every pixel is 1. The material has no specular layer (KHR_materials_specular's factor 0), so
//! that its only lobe is the diffuse one.

use glam::Vec3;

use crate::error::SceneError;
use crate::material::Material;
use crate::scene_builder::SceneBuilder;
use crate::transform::Transform;

use super::shapes::icosphere;

/// Subdivision level of the sphere: 20 * 4^4 = 5120 triangles.
pub const FURNACE_SUBDIVISION: u32 = 4;

pub(super) fn build(b: &mut SceneBuilder) -> Result<(), SceneError> {
    let mut shell = Material::lambertian("furnace shell", Vec3::splat(0.5));
    shell.emissive = Vec3::splat(0.5);
    shell.double_sided = true;
    let material = b.add_material(shell);
    if let Some(mesh) = b.add_mesh(
        "mesh \"sphere\"",
        "sphere",
        icosphere(FURNACE_SUBDIVISION, true),
    )? {
        b.add_instance(
            "sphere",
            mesh,
            material,
            Transform::IDENTITY.with_scale(Vec3::splat(10.0)),
        );
    }
    b.add_camera(Vec3::new(0.0, 1.0, 2.0), Vec3::new(0.0, 0.0, -3.0), 60.0);
    Ok(())
}
