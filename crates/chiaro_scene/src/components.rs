//! The components an entity of a chiaro scene carries besides its transforms: what it draws
//! ([`MeshInstance`]), what light it emits ([`Light`]) and how it sees ([`Camera`]), plus the
//! resource naming the camera in use ([`ActiveCamera`]). Names are bevy_ecs's own `Name`.

use bevy_ecs::prelude::*;
use glam::Vec3;

use crate::material::MaterialId;
use crate::mesh::MeshId;

/// One placement of a shared mesh with a material. Many instances may share one mesh: its data
/// and its BLAS exist once.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[require(crate::transform::Transform)]
pub struct MeshInstance {
    /// The mesh in [`crate::Meshes`].
    pub mesh: MeshId,
    /// The material in [`crate::Materials`].
    pub material: MaterialId,
}

/// Marks a mesh instance posed by a glTF skin: its mesh is its own, the vertices moved by the
/// joints (at load, the pose the file's node transforms describe; afterwards, with a
/// [`crate::deformation::DeformedMesh`], wherever the joints move).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Skinned {
    /// The skin's index in its glTF file.
    pub skin: u32,
    /// How many joints the skin has.
    pub joints: u32,
}

/// The shape of a punctual light, after KHR_lights_punctual.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Emits in all directions from the entity's origin; intensity in W/sr.
    Point,
    /// Emits down the entity's local -Z inside a cone; intensity in W/sr. Full intensity
    /// inside `inner_cone_angle`, smooth falloff to zero at `outer_cone_angle` (radians from the
    /// axis, 0 <= inner < outer <= pi/2).
    Spot {
        /// Angle from the axis where falloff starts, radians.
        inner_cone_angle: f32,
        /// Angle from the axis where the light reaches zero, radians.
        outer_cone_angle: f32,
    },
    /// Parallel light travelling down the entity's local -Z; intensity (irradiance) in W/m^2.
    Directional,
}

/// A punctual light: point, spot or directional, in radiometric units (glTF import converts
/// KHR_lights_punctual's photometric ones: see [`crate::LightUnits`]).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(crate::transform::Transform)]
pub struct Light {
    /// The kind and its cone, if any.
    pub kind: LightKind,
    /// Linear RGB colour; multiplies `intensity`.
    pub color: Vec3,
    /// Radiant intensity in W/sr for point and spot lights, irradiance in W/m^2 for
    /// directional lights.
    pub intensity: f32,
    /// Distance beyond which a point or spot light may be treated as zero (`None`: unlimited).
    pub range: Option<f32>,
}

impl Light {
    /// Colour times intensity: what a renderer multiplies by the geometric terms.
    pub fn radiant_intensity(&self) -> Vec3 {
        self.color * self.intensity
    }
}

/// How a camera projects, as glTF defines it. The camera looks down its local -Z with +Y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Perspective projection.
    Perspective {
        /// Vertical field of view, radians, in (0, pi).
        yfov: f32,
        /// Width over height; `None` uses the output image's.
        aspect_ratio: Option<f32>,
        /// Near clip distance, > 0.
        znear: f32,
        /// Far clip distance; `None` is infinite.
        zfar: Option<f32>,
    },
    /// Orthographic projection.
    Orthographic {
        /// Half the view's width, world units.
        xmag: f32,
        /// Half the view's height, world units.
        ymag: f32,
        /// Near clip distance, >= 0.
        znear: f32,
        /// Far clip distance, > znear.
        zfar: f32,
    },
}

/// A camera; its entity's [`crate::GlobalTransform`] places it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(crate::transform::Transform)]
pub struct Camera {
    /// The projection.
    pub projection: Projection,
}

/// The camera entity renders use.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActiveCamera(pub Entity);
