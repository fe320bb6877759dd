//! glTF metallic-roughness materials, with the extensions chiaro reads and the notes' energy
//! absorption factor, in the shared [`Materials`] store.

use glam::{Affine2, Vec3, Vec4};

use crate::asset_store::{AssetId, AssetStore};
use crate::texture::TextureId;

/// Index of a material in [`Materials`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MaterialId(pub u32);

/// How a texture is addressed outside [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum WrapMode {
    /// Tiles (glTF's default).
    #[default]
    Repeat,
    /// Tiles, mirrored every other time.
    MirroredRepeat,
    /// Clamps to the edge texel.
    ClampToEdge,
}

/// How a texture is filtered.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Filter {
    /// Bilinear (and trilinear with mip maps); the default.
    #[default]
    Linear,
    /// Nearest texel.
    Nearest,
}

/// How a texture is sampled: the glTF sampler.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Sampler {
    /// Wrapping along U.
    pub wrap_u: WrapMode,
    /// Wrapping along V.
    pub wrap_v: WrapMode,
    /// Magnification filter.
    pub mag_filter: Filter,
    /// Minification filter.
    pub min_filter: Filter,
}

/// A material's use of a texture: which one, through which UV set, transform and sampler.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// The texture in [`crate::Textures`].
    pub texture: TextureId,
    /// UV set (0 or 1).
    pub uv_set: u32,
    /// KHR_texture_transform as a matrix applied to the UV (identity when absent).
    pub transform: Affine2,
    /// The sampler.
    pub sampler: Sampler,
}

/// How alpha is interpreted.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum AlphaMode {
    /// Alpha ignored.
    #[default]
    Opaque,
    /// Fragments with alpha below the cutoff are not there at all.
    Mask {
        /// The alpha cutoff (glTF default 0.5).
        cutoff: f32,
    },
    /// Blended in glTF; chiaro reads alpha as coverage: the probability that a ray stops at
    /// the surface, which it otherwise passes straight through (`chiaro_shading::coverage`).
    Blend,
}

/// A glTF metallic-roughness material. Factors multiply their textures.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name from the file, or given by the builder.
    pub name: String,
    /// Linear RGBA base colour factor.
    pub base_color: Vec4,
    /// sRGB base colour texture.
    pub base_color_texture: Option<TextureRef>,
    /// Metallic factor in [0, 1].
    pub metallic: f32,
    /// Perceptual roughness factor in [0, 1]; GGX alpha = roughness^2.
    pub roughness: f32,
    /// Linear texture: roughness in G, metallic in B.
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Linear tangent-space normal map.
    pub normal_texture: Option<TextureRef>,
    /// Scale of the normal map's XY.
    pub normal_scale: f32,
    /// Linear emissive factor (glTF limits it to [0, 1]; strength scales it).
    pub emissive: Vec3,
    /// sRGB emissive texture.
    pub emissive_texture: Option<TextureRef>,
    /// KHR_materials_emissive_strength (1 when absent).
    pub emissive_strength: f32,
    /// Alpha interpretation.
    pub alpha_mode: AlphaMode,
    /// Whether back faces are shaded too (else they are culled and shade as black).
    pub double_sided: bool,
    /// Index of refraction for the dielectric F0 (KHR_materials_ior; 1.5 gives F0 = 0.04).
    pub ior: f32,
    /// KHR_materials_specular's specularFactor in [0, 1]: the strength of the dielectric's
    /// specular layer (1 when absent; 0 makes a dielectric purely Lambertian).
    pub specular: f32,
    /// KHR_materials_specular's specularColorFactor (linear, each channel at least 0): it
    /// scales the dielectric's F0, which is then capped at 1 (1 when absent).
    pub specular_color: Vec3,
    /// KHR_materials_clearcoat's clearcoatFactor in [0, 1]: a clear coat's strength over the
    /// material (0 when absent: no coat).
    pub clearcoat: f32,
    /// KHR_materials_clearcoat's clearcoatRoughnessFactor in [0, 1] (0 when absent).
    pub clearcoat_roughness: f32,
    /// KHR_materials_clearcoat's clearcoatNormalTexture: the coat's own tangent-space normal
    /// map (linear). Without it the coat takes the interpolated normal: the base's normal map
    /// does not reach the coat.
    pub clearcoat_normal_texture: Option<TextureRef>,
    /// Scale of the coat normal map's XY.
    pub clearcoat_normal_scale: f32,
    /// KHR_materials_transmission's transmissionFactor in [0, 1] (0 when absent): the share of
    /// the dielectric's diffuse base transmitted through the surface, which is thin-walled.
    /// A transmissive surface shades both faces ([`Material::shades_both_sides`]).
    pub transmission: f32,
    /// KHR_materials_volume: with a volume the mesh bounds a medium (a closed mesh, front
    /// faces outward), so transmitted light refracts by [`Material::ior`] and is attenuated
    /// inside; None (the default) leaves the surface thin-walled.
    pub volume: Option<Volume>,
    /// KHR_materials_sheen's sheenColorFactor (linear, each channel in [0, 1]; black when
    /// absent: no sheen).
    pub sheen_color: Vec3,
    /// KHR_materials_sheen's sheenRoughnessFactor in [0, 1] (0 when absent).
    pub sheen_roughness: f32,
    /// The extensions' textures, each multiplying its factor above.
    pub layer_textures: LayerTextures,
    /// The notes' energy absorption factor in [0, 1]: the BRDF is scaled by (1 - absorption).
    /// Read from the material's glTF `extras` as `{"absorption": x}`; 0 when absent.
    pub absorption: f32,
}

/// The textures of the material extensions, each multiplying its factor in [`Material`]: the
/// channel named is the one the extension reads (linear unless said sRGB).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LayerTextures {
    /// KHR_materials_specular's specularTexture (A): the specular factor.
    pub specular: Option<TextureRef>,
    /// KHR_materials_specular's specularColorTexture (RGB, sRGB): the specular colour.
    pub specular_color: Option<TextureRef>,
    /// KHR_materials_clearcoat's clearcoatTexture (R): the coat's strength.
    pub clearcoat: Option<TextureRef>,
    /// KHR_materials_clearcoat's clearcoatRoughnessTexture (G): the coat's roughness.
    pub clearcoat_roughness: Option<TextureRef>,
    /// KHR_materials_transmission's transmissionTexture (R): the transmitted share.
    pub transmission: Option<TextureRef>,
    /// KHR_materials_sheen's sheenColorTexture (RGB, sRGB): the sheen colour.
    pub sheen_color: Option<TextureRef>,
    /// KHR_materials_sheen's sheenRoughnessTexture (A): the sheen roughness.
    pub sheen_roughness: Option<TextureRef>,
}

impl LayerTextures {
    /// The slots by name, empty ones included.
    pub fn slots(&self) -> [(&'static str, &Option<TextureRef>); 7] {
        [
            ("specular", &self.specular),
            ("specular colour", &self.specular_color),
            ("clear coat", &self.clearcoat),
            ("clear coat roughness", &self.clearcoat_roughness),
            ("transmission", &self.transmission),
            ("sheen colour", &self.sheen_color),
            ("sheen roughness", &self.sheen_roughness),
        ]
    }

    /// True when any slot holds a texture.
    pub fn any(&self) -> bool {
        self.slots().iter().any(|(_, slot)| slot.is_some())
    }
}

/// The medium inside a KHR_materials_volume mesh: Beer-Lambert attenuation, light of colour
/// `attenuation_color` left after `attenuation_distance` (the extension's thickness only serves
/// rasterizers that do not trace the medium, and is not kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Volume {
    /// The colour white light becomes after `attenuation_distance` inside (linear, each channel
    /// in (0, 1]).
    pub attenuation_color: Vec3,
    /// Distance, in scene units, at which light has the attenuation colour (positive; +infinity:
    /// no attenuation).
    pub attenuation_distance: f32,
}

impl Default for Volume {
    /// The extension's defaults: white at an infinite distance, a clear medium.
    fn default() -> Self {
        Self {
            attenuation_color: Vec3::ONE,
            attenuation_distance: f32::INFINITY,
        }
    }
}

impl Volume {
    /// The attenuation coefficient per unit distance, -ln(attenuation_color) /
    /// attenuation_distance per channel (0 for a clear medium): light crossing a distance d
    /// inside keeps exp(-coefficient d).
    pub fn attenuation_coefficient(&self) -> Vec3 {
        if !(self.attenuation_distance.is_finite() && self.attenuation_distance > 0.0) {
            return Vec3::ZERO;
        }
        let color = self
            .attenuation_color
            .clamp(Vec3::splat(f32::MIN_POSITIVE), Vec3::ONE);
        -Vec3::new(color.x.ln(), color.y.ln(), color.z.ln()) / self.attenuation_distance
    }
}

impl Default for Material {
    /// glTF's defaults, used for primitives without a material: white base colour, metallic 1,
    /// roughness 1, opaque, single-sided.
    fn default() -> Self {
        Self {
            name: String::from("default"),
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            emissive_strength: 1.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            ior: 1.5,
            specular: 1.0,
            specular_color: Vec3::ONE,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            clearcoat_normal_texture: None,
            clearcoat_normal_scale: 1.0,
            transmission: 0.0,
            volume: None,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.0,
            layer_textures: LayerTextures::default(),
            absorption: 0.0,
        }
    }
}

impl Material {
    /// An untextured dielectric with this linear base colour and roughness.
    pub fn diffuse(name: &str, color: Vec3, roughness: f32) -> Self {
        Self {
            name: name.to_owned(),
            base_color: color.extend(1.0),
            metallic: 0.0,
            roughness,
            ..Self::default()
        }
    }

    /// A purely Lambertian surface of this linear colour: a dielectric with no specular layer
    /// (KHR_materials_specular's factor 0), roughness 1.
    pub fn lambertian(name: &str, color: Vec3) -> Self {
        Self {
            specular: 0.0,
            ..Self::diffuse(name, color, 1.0)
        }
    }

    /// An emitter: black base colour, `radiance` as emissive factor times strength. The factor
    /// keeps glTF's [0, 1] range; any excess goes into the strength.
    pub fn emitter(name: &str, radiance: Vec3) -> Self {
        let strength = radiance.max_element().max(1.0);
        Self {
            name: name.to_owned(),
            base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
            metallic: 0.0,
            emissive: radiance / strength,
            emissive_strength: strength,
            ..Self::default()
        }
    }

    /// Emitted radiance without texture: emissive factor times strength.
    pub fn emitted_radiance(&self) -> Vec3 {
        self.emissive * self.emissive_strength
    }

    /// True when both faces of the surface shade (reflect, transmit and emit): a double-sided
    /// material, or a transmissive one, whose back face light reaches through the front.
    pub fn shades_both_sides(&self) -> bool {
        self.double_sided || self.transmission > 0.0
    }

    /// True when the material can emit light.
    pub fn is_emissive(&self) -> bool {
        self.emitted_radiance().max_element() > 0.0
    }

    /// Dielectric normal-incidence Fresnel reflectance from the IOR: ((ior - 1) / (ior + 1))^2.
    pub fn dielectric_f0(&self) -> f32 {
        ((self.ior - 1.0) / (self.ior + 1.0)).powi(2)
    }

    /// The texture slots in use, by name.
    pub fn texture_slots(&self) -> impl Iterator<Item = (&'static str, &TextureRef)> {
        [
            ("base colour", &self.base_color_texture),
            ("metallic-roughness", &self.metallic_roughness_texture),
            ("normal", &self.normal_texture),
            ("emissive", &self.emissive_texture),
            ("clear coat normal", &self.clearcoat_normal_texture),
        ]
        .into_iter()
        .chain(self.layer_textures.slots())
        .filter_map(|(name, slot)| slot.as_ref().map(|t| (name, t)))
    }

    /// Every texture slot, empty ones included, to rewrite in place.
    pub fn texture_slots_mut(&mut self) -> [&mut Option<TextureRef>; 12] {
        let l = &mut self.layer_textures;
        [
            &mut self.base_color_texture,
            &mut self.metallic_roughness_texture,
            &mut self.normal_texture,
            &mut self.emissive_texture,
            &mut self.clearcoat_normal_texture,
            &mut l.specular,
            &mut l.specular_color,
            &mut l.clearcoat,
            &mut l.clearcoat_roughness,
            &mut l.transmission,
            &mut l.sheen_color,
            &mut l.sheen_roughness,
        ]
    }

    /// The UV set a tangent-space normal map reads (the base's, else the coat's): the one the
    /// mesh's tangents follow.
    pub fn tangent_uv_set(&self) -> Option<u32> {
        self.normal_texture
            .or(self.clearcoat_normal_texture)
            .map(|t| t.uv_set)
    }
}

/// Every material of the scene.
pub type Materials = AssetStore<MaterialId, Material>;

impl AssetId for MaterialId {
    fn from_index(index: u32) -> Self {
        Self(index)
    }

    fn index(self) -> usize {
        self.0 as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_ior_gives_the_usual_f0() {
        assert!((Material::default().dielectric_f0() - 0.04).abs() < 1e-6);
    }

    #[test]
    fn emitter_keeps_the_factor_in_range() {
        let m = Material::emitter("light", Vec3::new(17.0, 12.0, 4.0));
        assert!(m.emissive.max_element() <= 1.0);
        assert!(
            m.emitted_radiance()
                .abs_diff_eq(Vec3::new(17.0, 12.0, 4.0), 1e-4)
        );
        assert!(m.is_emissive());
        assert!(!Material::default().is_emissive());
    }
}
