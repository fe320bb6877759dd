//! chiaro's scene as `bevy_ecs` data.
//!
//! Entities carry a [`Transform`] (and the propagated [`GlobalTransform`]), and a
//! [`MeshInstance`], [`Light`] or [`Camera`]. Meshes, materials and textures are shared assets in
//! the [`Meshes`], [`Materials`] and [`Textures`] resources, stored once however many instances
//! use them. [`Environment`] and [`ActiveCamera`] are resources too.
//!
//! Scenes come from glTF files ([`load_gltf`]) or are built in ([`builtin`]); [`load_scene`]
//! takes either by name. Loading validates everything first and touches the World only on
//! success; what it repaired is in [`ImportReport`].
//!
//! ```
//! use bevy_ecs::prelude::*;
//! use chiaro_scene::{SceneInfo, load_scene, propagate_transforms};
//!
//! let mut world = World::new();
//! load_scene(&mut world, "builtin:cornell").unwrap();
//! // The app's schedule keeps world matrices current, as it would each frame.
//! let mut schedule = Schedule::default();
//! schedule.add_systems(propagate_transforms);
//! schedule.run(&mut world);
//! let info = SceneInfo::gather(&mut world);
//! assert_eq!(info.triangles, 32);
//! assert!(info.camera.is_some());
//! ```

pub mod animation;
pub mod asset_store;
pub mod bounds;
pub mod builtin;
pub mod components;
pub mod deformation;
pub mod environment;
pub mod error;
pub mod features;
pub mod framing;
mod gltf;
pub mod info;
pub mod load;
pub mod material;
pub mod memory;
pub mod mesh;
pub mod mesh_repair;
pub mod morph;
pub mod scene_builder;
pub mod skinning;
mod tangents;
pub mod texture;
pub mod transform;

pub use animation::{Animations, Time, animate_nodes, pose_at};
pub use asset_store::{AssetId, AssetStore};
pub use bevy_ecs::name::Name;
pub use bounds::Aabb;
pub use components::{ActiveCamera, Camera, Light, LightKind, MeshInstance, Projection, Skinned};
pub use environment::{Environment, EnvironmentSource, EquirectImage};
pub use error::{Fault, ImportReport, Repair, SceneError};
pub use features::{EnvironmentFeature, SceneFeatureStats, SceneFeatures, update_scene_features};
pub use gltf::{
    MAX_FILE_BYTES, MAX_TEXTURE_SIDE, MAX_ZERO_FILLED_ELEMENTS, MIN_SCALE, SUPPORTED_EXTENSIONS,
    load_gltf, load_gltf_with,
};
pub use info::SceneInfo;
pub use load::{
    LUMENS_PER_WATT, LightUnits, LoadOptions, load_scene, load_scene_with, scene_builder_for,
    scene_builder_with,
};
pub use material::{AlphaMode, LayerTextures, Material, MaterialId, Materials, TextureRef, Volume};
pub use memory::{MemoryEstimate, OverBudget};
pub use mesh::{Mesh, MeshId, Meshes};
pub use mesh_repair::{MeshData, MeshFault};
pub use scene_builder::{AutoCamera, Node, SceneBuilder, SourceNode, SpawnedScene};
pub use texture::{ColorSpace, Texture, TextureId, Textures};
pub use transform::{GlobalTransform, Transform, propagate_transforms};
