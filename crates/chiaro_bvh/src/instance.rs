//! Instances: one placement of a mesh's BLAS in the world, checked before it enters the TLAS.
//!
//! An instance is left out (with a logged warning, counted in [`crate::BvhStats`]) when its
//! world matrix is non-finite or singular, when its inverse is non-finite or so ill-conditioned
//! that single precision means nothing ([`MAX_CONDITION`]), when its world box is non-finite or
//! reaches beyond [`MAX_WORLD_COORDINATE`], or when its mesh has no BLAS (not in
//! [`chiaro_scene::Meshes`]). No such instance reaches a builder or a traversal.

use bevy_ecs::entity::Entity;
use chiaro_scene::{Aabb, MaterialId, MeshId};
use glam::{Affine3A, DMat3, Vec3};

use crate::blas::Blas;
use crate::slab::TLAS_PAD_ULPS;

/// Largest absolute world coordinate of an instance's box.
pub const MAX_WORLD_COORDINATE: f32 = 1.0e18;

/// Largest accepted condition number `|M| |M^-1|` (infinity norms) of an instance matrix. Above
/// it the inverse has no correct digit in `f32`.
pub const MAX_CONDITION: f32 = 1.0e7;

/// An instance in the BVH: the entity it came from, what it draws, and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceRecord {
    /// The entity carrying the [`chiaro_scene::MeshInstance`].
    pub entity: Entity,
    /// Its mesh (and BLAS).
    pub mesh: MeshId,
    /// Its material.
    pub material: MaterialId,
    /// Object-to-world matrix (the entity's [`chiaro_scene::GlobalTransform`]).
    pub world: Affine3A,
    /// World-to-object matrix, the inverse of `world`; rays are carried into object space with
    /// it.
    pub inverse: Affine3A,
}

/// Why an instance was left out of the BVH.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum InstanceRejection {
    /// The world matrix has a NaN or infinite entry.
    #[error("its world matrix is not finite")]
    NonFiniteMatrix,
    /// The world matrix's linear part has a zero (or non-finite) determinant or inverse.
    #[error("its world matrix is singular")]
    Singular,
    /// The matrix is too ill-conditioned for single precision.
    #[error("its world matrix is too ill-conditioned (condition number {0:e})")]
    IllConditioned(f32),
    /// The world box is non-finite or beyond [`MAX_WORLD_COORDINATE`].
    #[error("its world bounds are non-finite or beyond 1e18")]
    HugeBounds,
    /// The mesh id has no BLAS (not in `Meshes`, or without triangles).
    #[error("its mesh {0:?} is not in Meshes or has no triangles")]
    MissingMesh(MeshId),
}

/// What the TLAS keeps of an instance: its padded world box and its matrix's condition number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct InstanceBounds {
    pub bounds: Aabb,
    pub kappa: f32,
}

/// Infinity norm (largest absolute row sum) of a 3x3 matrix.
fn norm_inf(m: &DMat3) -> f64 {
    let t = m.transpose();
    (t.x_axis.abs() + t.y_axis.abs() + t.z_axis.abs()).max_element()
}

/// Checks an instance and computes its record and TLAS bounds.
pub(crate) fn prepare_instance(
    entity: Entity,
    mesh: MeshId,
    material: MaterialId,
    world: Affine3A,
    blas: Option<&Blas>,
) -> Result<(InstanceRecord, InstanceBounds), InstanceRejection> {
    let blas = blas
        .filter(|b| b.triangle_count() > 0)
        .ok_or(InstanceRejection::MissingMesh(mesh))?;
    if !world.is_finite() {
        return Err(InstanceRejection::NonFiniteMatrix);
    }
    // Inverted in double precision: exact to the last f32 digit for well-conditioned matrices,
    // and no overflow of the determinant for large scales.
    let world64 = world.as_daffine3();
    let det = world64.matrix3.determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(InstanceRejection::Singular);
    }
    let inverse64 = world64.inverse();
    let inverse = inverse64.as_affine3a();
    if !inverse.is_finite() || inverse.matrix3.as_dmat3().determinant() == 0.0 {
        return Err(InstanceRejection::Singular);
    }
    let kappa = (norm_inf(&world64.matrix3) * norm_inf(&inverse64.matrix3)).max(1.0);
    if !kappa.is_finite() || kappa > f64::from(MAX_CONDITION) {
        return Err(InstanceRejection::IllConditioned(kappa as f32));
    }
    let kappa = kappa as f32;
    let bounds = blas.bounds().transformed(&world);
    let magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
    if magnitude.is_nan() || magnitude > MAX_WORLD_COORDINATE {
        return Err(InstanceRejection::HugeBounds);
    }
    let translation = Vec3::from(world.translation).abs().max_element();
    let pad = TLAS_PAD_ULPS * f32::EPSILON * kappa * (magnitude + translation);
    let padded = Aabb {
        min: bounds.min - pad,
        max: bounds.max + pad,
    };
    let record = InstanceRecord {
        entity,
        mesh,
        material,
        world,
        inverse,
    };
    Ok((
        record,
        InstanceBounds {
            bounds: padded,
            kappa,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{Mesh, MeshData};
    use glam::Quat;

    fn blas() -> Blas {
        let data = MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            ..MeshData::default()
        };
        Blas::build(&Mesh::new("t", data).unwrap().0)
    }

    fn prepare(world: Affine3A, blas: Option<&Blas>) -> Result<InstanceBounds, InstanceRejection> {
        prepare_instance(
            Entity::from_raw_u32(1).unwrap(),
            MeshId(0),
            MaterialId(0),
            world,
            blas,
        )
        .map(|(_, b)| b)
    }

    #[test]
    fn good_instances_get_padded_bounds_and_condition() {
        let b = blas();
        let rotated = Affine3A::from_scale_rotation_translation(
            Vec3::splat(3.0),
            Quat::from_rotation_y(0.7),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let bounds = prepare(rotated, Some(&b)).unwrap();
        assert!(
            bounds.kappa >= 1.0 && bounds.kappa < 3.0,
            "{}",
            bounds.kappa
        );
        let exact = b.bounds().transformed(&rotated);
        assert!(
            bounds.bounds.min.cmplt(exact.min).all() && bounds.bounds.max.cmpgt(exact.max).all()
        );
    }

    #[test]
    fn bad_instances_are_refused() {
        let b = blas();
        let cases = [
            (
                Affine3A::from_translation(Vec3::NAN),
                InstanceRejection::NonFiniteMatrix,
            ),
            (
                Affine3A::from_translation(Vec3::new(f32::INFINITY, 0.0, 0.0)),
                InstanceRejection::NonFiniteMatrix,
            ),
            (
                Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)),
                InstanceRejection::Singular,
            ),
            (
                Affine3A::from_scale(Vec3::splat(1e20)),
                InstanceRejection::HugeBounds,
            ),
            (
                Affine3A::from_translation(Vec3::splat(1e19)),
                InstanceRejection::HugeBounds,
            ),
        ];
        for (world, why) in cases {
            assert_eq!(prepare(world, Some(&b)), Err(why), "{world:?}");
        }
        assert!(matches!(
            prepare(Affine3A::from_scale(Vec3::new(1e5, 1e-5, 1.0)), Some(&b)),
            Err(InstanceRejection::IllConditioned(_))
        ));
        assert_eq!(
            prepare(Affine3A::IDENTITY, None),
            Err(InstanceRejection::MissingMesh(MeshId(0)))
        );
    }
}
