//! The records of the scene's storage buffers beyond the BVH, as the GPU reads them. Each is
//! `#[repr(C)]` + `Pod` with explicit padding and mirrored field for field (same names) by a
//! struct of `shaders/lib/scene_bindings.wgsl`; a test reads those through naga and compares
//! sizes and offsets.

use bytemuck::{Pod, Zeroable};

use crate::shaders::SharedConstant;

/// A texture slot, vertex attribute or table entry that is absent.
pub const NO_INDEX: u32 = u32::MAX;

/// Material flag: alpha mode mask (texels with alpha below the cutoff are holes).
pub const MATERIAL_ALPHA_MASK: u32 = 1;
/// Material flag: both faces shade (else a back face absorbs everything).
pub const MATERIAL_DOUBLE_SIDED: u32 = 2;
/// Material flag: alpha mode blend (alpha is the probability that a ray stops there:
/// `chiaro_shading::coverage`).
pub const MATERIAL_ALPHA_BLEND: u32 = 4;
/// Material flag: a KHR_materials_volume mesh, a medium behind its front faces (its
/// transmission refracts by the IOR; light inside is attenuated).
pub const MATERIAL_VOLUME: u32 = 8;

/// Mesh flag: the mesh has UV set 0.
pub const MESH_HAS_UV0: u32 = 1;
/// Mesh flag: the mesh has UV set 1.
pub const MESH_HAS_UV1: u32 = 2;
/// Mesh flag: the mesh has tangents (normal maps apply).
pub const MESH_HAS_TANGENTS: u32 = 4;

/// Punctual light kind: point.
pub const LIGHT_POINT: u32 = 0;
/// Punctual light kind: spot.
pub const LIGHT_SPOT: u32 = 1;
/// Punctual light kind: directional.
pub const LIGHT_DIRECTIONAL: u32 = 2;

/// Environment kind: black (no environment light).
pub const ENV_BLACK: u32 = 0;
/// Environment kind: a constant radiance.
pub const ENV_CONSTANT: u32 = 1;
/// Environment kind: an equirectangular image with an importance table.
pub const ENV_IMAGE: u32 = 2;

/// Sampler bits: wrap mode along U in bits 0..2, along V in bits 2..4 (0 repeat, 1 mirrored
/// repeat, 2 clamp), bit 4 set for nearest filtering.
pub const SAMPLER_NEAREST: u32 = 16;

/// With at most this many punctual lights the direct pass evaluates every one per pixel;
/// with more it picks one by power.
pub const ALL_PUNCTUAL_LIGHTS_MAX: u32 = 8;

/// With at most this many emissive triangles the area lights get no light tree and are picked
/// by power alone: on so few, picking by importance measured no better
/// (docs/experiments/light-trees-only-for-many-lights.md), and a pipeline without the trees' code
/// runs faster.
pub const AREA_LIGHTS_BY_POWER_MAX: usize = 8;

/// `light_sampling` of the direct and indirect passes' params: pick by power alone.
pub const LIGHT_SAMPLING_POWER: u32 = 0;
/// `light_sampling` of the passes' params: pick through the light trees.
pub const LIGHT_SAMPLING_TREE: u32 = 1;

/// The constants above, for the generated WGSL module.
pub fn constants() -> Vec<SharedConstant> {
    use SharedConstant::{F32, U32};
    vec![
        U32("NO_INDEX", NO_INDEX),
        U32("MATERIAL_ALPHA_MASK", MATERIAL_ALPHA_MASK),
        U32("MATERIAL_DOUBLE_SIDED", MATERIAL_DOUBLE_SIDED),
        U32("MATERIAL_ALPHA_BLEND", MATERIAL_ALPHA_BLEND),
        U32("MATERIAL_VOLUME", MATERIAL_VOLUME),
        U32("MESH_HAS_UV0", MESH_HAS_UV0),
        U32("MESH_HAS_UV1", MESH_HAS_UV1),
        U32("MESH_HAS_TANGENTS", MESH_HAS_TANGENTS),
        U32("LIGHT_POINT", LIGHT_POINT),
        U32("LIGHT_SPOT", LIGHT_SPOT),
        U32("LIGHT_DIRECTIONAL", LIGHT_DIRECTIONAL),
        U32("ENV_BLACK", ENV_BLACK),
        U32("ENV_CONSTANT", ENV_CONSTANT),
        U32("ENV_IMAGE", ENV_IMAGE),
        U32("SAMPLER_NEAREST", SAMPLER_NEAREST),
        U32("ALL_PUNCTUAL_LIGHTS_MAX", ALL_PUNCTUAL_LIGHTS_MAX),
        U32("LIGHT_SAMPLING_POWER", LIGHT_SAMPLING_POWER),
        U32("LIGHT_SAMPLING_TREE", LIGHT_SAMPLING_TREE),
        U32("TEXEL_ROW_BITS", super::texel_mirror::TEXEL_ROW_BITS),
        F32(
            "LIGHT_TREE_UNIFORM_SHARE",
            chiaro_shading::light_tree::UNIFORM_SHARE,
        ),
    ]
}

/// One vertex of a mesh (object space).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuVertex {
    /// Position.
    pub position: [f32; 3],
    /// UV set 0, u.
    pub u0: f32,
    /// Unit normal.
    pub normal: [f32; 3],
    /// UV set 0, v.
    pub v0: f32,
    /// Tangent with the bitangent sign in `w` (zero without tangents).
    pub tangent: [f32; 4],
    /// UV set 1 (zero without it).
    pub uv1: [f32; 2],
    /// Linear RGBA vertex colour as four unorm16, R in the low half of word 0 and A in the
    /// high half of word 1 (`gather::pack_color`); white without colours. It fills what
    /// was padding: a scene without colours pays no memory for them.
    pub color: [u32; 2],
}

/// Where a mesh's data lies in the vertex and index buffers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuMesh {
    /// Index of the mesh's first index in the index buffer (triangle t uses indices
    /// `index_base + 3 t ..`), which hold global vertex indices.
    pub index_base: u32,
    /// Index of the mesh's first vertex.
    pub vertex_base: u32,
    /// Number of triangles.
    pub triangle_count: u32,
    /// `MESH_HAS_*` bits.
    pub flags: u32,
}

/// A material's use of a texture.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuTextureSlot {
    /// Texture index, [`NO_INDEX`] when the slot is empty.
    pub texture: u32,
    /// UV set (0 or 1).
    pub uv_set: u32,
    /// Wrap and filter bits (see [`SAMPLER_NEAREST`]).
    pub sampler: u32,
    /// Padding, zero.
    pub pad: u32,
    /// KHR_texture_transform's 2x2 matrix, columns (m00, m10, m01, m11).
    pub transform_m: [f32; 4],
    /// Its translation in `xy`, `zw` zero.
    pub transform_t: [f32; 4],
}

impl Default for GpuTextureSlot {
    fn default() -> Self {
        Self {
            texture: NO_INDEX,
            uv_set: 0,
            sampler: 0,
            pad: 0,
            transform_m: [1.0, 0.0, 0.0, 1.0],
            transform_t: [0.0; 4],
        }
    }
}

/// A glTF metallic-roughness material (see `chiaro_scene::Material`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuMaterial {
    /// Base colour factor (linear RGB, alpha).
    pub base_color: [f32; 4],
    /// Emitted radiance (emissive factor x strength).
    pub emission: [f32; 3],
    /// Alpha cutoff of a masked material.
    pub alpha_cutoff: f32,
    /// Metallic factor.
    pub metallic: f32,
    /// Roughness factor.
    pub roughness: f32,
    /// Dielectric F0 from the IOR.
    pub f0_dielectric: f32,
    /// The notes' energy absorption.
    pub absorption: f32,
    /// Normal map scale.
    pub normal_scale: f32,
    /// `MATERIAL_*` bits.
    pub flags: u32,
    /// KHR_materials_specular's factor (1 without the extension).
    pub specular: f32,
    /// KHR_materials_clearcoat's factor (0: no coat).
    pub clearcoat: f32,
    /// KHR_materials_specular's colour factor (1 without the extension).
    pub specular_color: [f32; 3],
    /// The clear coat's roughness.
    pub clearcoat_roughness: f32,
    /// KHR_materials_sheen's colour (black: no sheen).
    pub sheen_color: [f32; 3],
    /// KHR_materials_sheen's roughness.
    pub sheen_roughness: f32,
    /// KHR_materials_transmission's factor (0: opaque).
    pub transmission: f32,
    /// The index of refraction (KHR_materials_ior): a volume's surface refracts by it.
    pub ior: f32,
    /// The clear coat normal map's scale.
    pub clearcoat_normal_scale: f32,
    /// Padding, zero.
    pub pad1: u32,
    /// KHR_materials_volume's attenuation coefficient per unit distance (zero: clear, or no
    /// volume).
    pub attenuation: [f32; 3],
    /// Padding, zero.
    pub pad2: u32,
    /// Base colour texture.
    pub base_color_texture: GpuTextureSlot,
    /// Metallic (B) and roughness (G) texture.
    pub metallic_roughness_texture: GpuTextureSlot,
    /// Normal map.
    pub normal_texture: GpuTextureSlot,
    /// Emissive texture.
    pub emissive_texture: GpuTextureSlot,
    /// KHR_materials_specular's specular texture (A).
    pub specular_texture: GpuTextureSlot,
    /// KHR_materials_specular's colour texture (RGB).
    pub specular_color_texture: GpuTextureSlot,
    /// KHR_materials_clearcoat's texture (R).
    pub clearcoat_texture: GpuTextureSlot,
    /// KHR_materials_clearcoat's roughness texture (G).
    pub clearcoat_roughness_texture: GpuTextureSlot,
    /// KHR_materials_transmission's texture (R).
    pub transmission_texture: GpuTextureSlot,
    /// KHR_materials_sheen's colour texture (RGB).
    pub sheen_color_texture: GpuTextureSlot,
    /// KHR_materials_sheen's roughness texture (A).
    pub sheen_roughness_texture: GpuTextureSlot,
    /// KHR_materials_clearcoat's normal map.
    pub clearcoat_normal_texture: GpuTextureSlot,
}

/// Where a texture's texels lie in the texel atlas buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuTextureInfo {
    /// Index of texel (0, 0) in the texel buffer (one RGBA8 texel per `u32`, row-major).
    pub offset: u32,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// 1 when RGB is sRGB-encoded, 0 when linear.
    pub srgb: u32,
}

/// A punctual light (KHR_lights_punctual), world space.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuLight {
    /// Position (point and spot).
    pub position: [f32; 3],
    /// `LIGHT_*` kind.
    pub kind: u32,
    /// Unit axis a spot points along, or the direction a directional light travels.
    pub direction: [f32; 3],
    /// Range; +infinity when unlimited.
    pub range: f32,
    /// Colour x intensity (W/sr, or W/m^2 for directional lights).
    pub intensity: [f32; 3],
    /// Power-proportional CDF up to and including this light.
    pub cdf: f32,
    /// Spot inner cone angle, radians.
    pub inner: f32,
    /// Spot outer cone angle, radians.
    pub outer: f32,
    /// Probability of picking this light when one is picked by power.
    pub pmf: f32,
    /// A directional light's power-proportional CDF among the directional lights only, up to
    /// and including it (running on, flat, through the other kinds; 1 from the last
    /// directional light on): how tree sampling picks a directional light.
    pub directional_cdf: f32,
}

/// One entry of the area-light table: an emissive triangle of an instance, or the
/// environment (`instance == NO_INDEX`), picked in proportion to its power.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuAreaLight {
    /// Instance (index into the BVH instances), [`NO_INDEX`] for the environment.
    pub instance: u32,
    /// Triangle of the instance's mesh.
    pub triangle: u32,
    /// CDF up to and including this entry.
    pub cdf: f32,
    /// Probability of picking this entry.
    pub pmf: f32,
}

/// One node of a light tree (`chiaro_shading::light_tree::LightTreeNode`): the bounds of its
/// lights and its links. Both trees (area, then punctual) share one buffer; indices are into
/// it (see `gpu_scene::light_trees` for the layout).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuLightTreeNode {
    /// Lower corner of the lights' bounding box.
    pub min: [f32; 3],
    /// Their power (luminance).
    pub power: f32,
    /// Upper corner.
    pub max: [f32; 3],
    /// Half-angle of the cone of normals.
    pub theta_o: f32,
    /// Unit axis of the emission cone.
    pub axis: [f32; 3],
    /// Spread of emission beyond the cone of normals.
    pub theta_e: f32,
    /// Inner node: the first child's index. Leaf: the light's index in its table (area-light
    /// table or punctual lights).
    pub first: u32,
    /// Inner node: the second child's index. Leaf: [`NO_INDEX`].
    pub second: u32,
    /// The parent's index, [`NO_INDEX`] for a root.
    pub parent: u32,
    /// 1 for a leaf, 0 for an inner node.
    pub leaf: u32,
}

/// Per-instance data beside `chiaro_bvh::GpuInstance`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuInstanceExtra {
    /// Rows of the previous frame's object-to-world 3x4 matrix (for motion vectors).
    pub previous_object_to_world: [[f32; 4]; 3],
    /// Index of the instance's triangle 0 in the area-light table, [`NO_INDEX`] when the instance
    /// does not emit (triangle t is entry `area_first + t`).
    pub area_first: u32,
    /// 1 when the world matrix mirrors (negative determinant): the front face is clockwise.
    pub mirrored: u32,
    /// Padding, zero.
    pub pad0: u32,
    /// Padding, zero.
    pub pad1: u32,
}

/// Scene-wide values: counts and the environment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(16))]
pub struct GpuSceneInfo {
    /// Constant environment radiance (strength included).
    pub env_radiance: [f32; 3],
    /// `ENV_*` kind.
    pub env_kind: u32,
    /// Environment image width.
    pub env_width: u32,
    /// Environment image height.
    pub env_height: u32,
    /// cos of the environment's rotation about +Y.
    pub env_cos_rotation: f32,
    /// sin of it.
    pub env_sin_rotation: f32,
    /// Number of punctual lights.
    pub light_count: u32,
    /// Number of area-light table entries (environment included).
    pub area_count: u32,
    /// Probability of picking the environment from the area-light table.
    pub env_pmf: f32,
    /// Number of instances.
    pub instance_count: u32,
    /// Root of the tree over the area table's emissive triangles, [`NO_INDEX`] when none (it
    /// is built only with more than [`AREA_LIGHTS_BY_POWER_MAX`] of them).
    pub area_tree: u32,
    /// Root of the tree over the point and spot lights, [`NO_INDEX`] when none (it is built
    /// only with more than [`ALL_PUNCTUAL_LIGHTS_MAX`] punctual lights).
    pub punctual_tree: u32,
    /// The directional lights' share of the punctual lights' power: under tree sampling, the
    /// probability of picking one of them (by power) rather than walking the punctual tree.
    pub directional_share: f32,
    /// The area tree's leaf of area-table entry 0: entry i's is `area_leaves + i` (the
    /// environment, the last entry, has none).
    pub area_leaves: u32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::size_of;

    #[test]
    fn sizes_are_multiples_of_their_alignment() {
        assert_eq!(size_of::<GpuVertex>(), 64);
        assert_eq!(size_of::<GpuMaterial>(), 704);
        assert_eq!(size_of::<GpuLight>(), 64);
        assert_eq!(size_of::<GpuInstanceExtra>(), 64);
        assert_eq!(size_of::<GpuSceneInfo>(), 64);
        assert_eq!(size_of::<GpuLightTreeNode>(), 64);
        assert_eq!(GpuTextureSlot::default().texture, NO_INDEX);
    }
}
