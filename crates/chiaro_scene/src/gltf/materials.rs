//! glTF materials and the textures they use. Textures are decoded once per (image, colour space)
//! pair, on first use. An image that is missing or cannot be decoded is not an error: the slot
//! falls back to its factor alone and a repair line says so.

use std::collections::HashMap;
use std::io::Cursor;

use glam::{Affine2, Mat2, Vec2, Vec3, Vec4};
use image::ImageReader;

use crate::error::Repair;
use crate::gltf::sources::{FileAccess, UriSource, read_file};
use crate::material::{AlphaMode, Filter, Material, Sampler, TextureRef, WrapMode};
use crate::texture::{ColorSpace, Texture, TextureId};

/// Largest texture side accepted, texels.
pub const MAX_TEXTURE_SIDE: u32 = 16384;

/// Converts materials and decodes their textures.
pub(crate) struct MaterialImporter<'a> {
    pub document: &'a gltf::Document,
    pub buffers: &'a [Vec<u8>],
    pub access: FileAccess<'a>,
    pub textures: Vec<Texture>,
    pub repairs: Vec<Repair>,
    decoded: HashMap<(usize, ColorSpace), Option<TextureId>>,
}

/// glTF's texture-reference fields, common to the three kinds of texture info.
pub(super) struct Slot<'a> {
    pub texture: gltf::Texture<'a>,
    pub tex_coord: u32,
    pub transform: Option<(Vec2, f32, Vec2, Option<u32>)>,
}

fn wrap(mode: gltf::texture::WrappingMode) -> WrapMode {
    match mode {
        gltf::texture::WrappingMode::Repeat => WrapMode::Repeat,
        gltf::texture::WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        gltf::texture::WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
    }
}

fn sampler(s: &gltf::texture::Sampler) -> Sampler {
    use gltf::texture::{MagFilter, MinFilter};
    Sampler {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        mag_filter: match s.mag_filter() {
            Some(MagFilter::Nearest) => Filter::Nearest,
            _ => Filter::Linear,
        },
        min_filter: match s.min_filter() {
            Some(MinFilter::Nearest | MinFilter::NearestMipmapNearest) => Filter::Nearest,
            _ => Filter::Linear,
        },
    }
}

/// KHR_texture_transform read from raw JSON (the normal texture's info has no typed accessor).
pub(super) fn transform_from_json(value: &serde_json::Value) -> (Vec2, f32, Vec2, Option<u32>) {
    let pair = |key: &str, default: Vec2| {
        value
            .get(key)
            .and_then(|v| v.as_array())
            .and_then(|a| {
                Some(Vec2::new(
                    a.first()?.as_f64()? as f32,
                    a.get(1)?.as_f64()? as f32,
                ))
            })
            .unwrap_or(default)
    };
    let rotation = value
        .get("rotation")
        .and_then(|v| v.as_f64())
        .unwrap_or(0.0) as f32;
    let tex_coord = value
        .get("texCoord")
        .and_then(|v| v.as_u64())
        .map(|v| v as u32);
    (
        pair("offset", Vec2::ZERO),
        rotation,
        pair("scale", Vec2::ONE),
        tex_coord,
    )
}

/// KHR_texture_transform's matrix: translation * rotation * scale, with its rotation convention
/// (a positive angle turns UVs clockwise as seen in the image).
pub(crate) fn texture_transform_matrix(offset: Vec2, rotation: f32, scale: Vec2) -> Affine2 {
    let (s, c) = rotation.sin_cos();
    let rotate = Mat2::from_cols(Vec2::new(c, -s), Vec2::new(s, c));
    Affine2::from_mat2_translation(rotate * Mat2::from_diagonal(scale), offset)
}

impl<'a> MaterialImporter<'a> {
    pub fn new(
        document: &'a gltf::Document,
        buffers: &'a [Vec<u8>],
        access: FileAccess<'a>,
    ) -> Self {
        Self {
            document,
            buffers,
            access,
            textures: Vec::new(),
            repairs: Vec::new(),
            decoded: HashMap::new(),
        }
    }

    pub(super) fn repair(&mut self, element: String, action: String) {
        self.repairs.push(Repair { element, action });
    }

    /// Converts every material of the document, in order.
    pub fn convert_all(&mut self) -> Vec<Material> {
        let document = self.document;
        document.materials().map(|m| self.convert(&m)).collect()
    }

    fn convert(&mut self, m: &gltf::Material<'a>) -> Material {
        let element = match m.name() {
            Some(name) => format!("material {} ({name:?})", m.index().unwrap_or(0)),
            None => format!("material {}", m.index().unwrap_or(0)),
        };
        let pbr = m.pbr_metallic_roughness();
        let info_slot = |info: gltf::texture::Info<'a>| Slot {
            texture: info.texture(),
            tex_coord: info.tex_coord(),
            transform: info.texture_transform().map(|t| {
                (
                    Vec2::from(t.offset()),
                    t.rotation(),
                    Vec2::from(t.scale()),
                    t.tex_coord(),
                )
            }),
        };
        let base_slot = pbr.base_color_texture().map(info_slot);
        let mr_slot = pbr.metallic_roughness_texture().map(info_slot);
        let emissive_slot = m.emissive_texture().map(info_slot);
        let normal = m.normal_texture();
        let normal_scale = normal.as_ref().map_or(1.0, |n| n.scale());
        let normal_slot = normal.map(|n| Slot {
            texture: n.texture(),
            tex_coord: n.tex_coord(),
            transform: n
                .extension_value("KHR_texture_transform")
                .map(transform_from_json),
        });

        let mut material = Material {
            name: m.name().map_or_else(|| element.clone(), str::to_owned),
            base_color: Vec4::from(pbr.base_color_factor()),
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            normal_scale,
            emissive: Vec3::from(m.emissive_factor()),
            emissive_strength: m.emissive_strength().unwrap_or(1.0),
            alpha_mode: match m.alpha_mode() {
                gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
                gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                    cutoff: m.alpha_cutoff().unwrap_or(0.5),
                },
                gltf::material::AlphaMode::Blend => AlphaMode::Blend,
            },
            double_sided: m.double_sided(),
            ior: m.ior().unwrap_or(1.5),
            absorption: 0.0,
            ..Material::default()
        };
        material.base_color_texture =
            base_slot.and_then(|s| self.slot(&element, "base colour", s, ColorSpace::Srgb));
        material.metallic_roughness_texture =
            mr_slot.and_then(|s| self.slot(&element, "metallic-roughness", s, ColorSpace::Linear));
        material.normal_texture =
            normal_slot.and_then(|s| self.slot(&element, "normal", s, ColorSpace::Linear));
        material.emissive_texture =
            emissive_slot.and_then(|s| self.slot(&element, "emissive", s, ColorSpace::Srgb));
        material.absorption = self.absorption(&element, m);
        self.read_specular(&element, m, &mut material);
        self.read_clearcoat(&element, m, &mut material);
        self.read_transmission(&element, m, &mut material);
        self.read_sheen(&element, m, &mut material);
        self.sanitize_factors(&element, &mut material);
        material
    }

    /// The notes' absorption factor from `extras: {"absorption": x}`, clamped to [0, 1].
    fn absorption(&mut self, element: &str, m: &gltf::Material) -> f32 {
        let Some(raw) = m.extras() else { return 0.0 };
        let value: serde_json::Value = serde_json::from_str(raw.get()).unwrap_or_default();
        let Some(field) = value.get("absorption") else {
            return 0.0;
        };
        match field.as_f64() {
            Some(a) if (0.0..=1.0).contains(&a) => a as f32,
            Some(a) if a.is_finite() => {
                self.repair(element.into(), format!("absorption {a} clamped to [0, 1]"));
                a.clamp(0.0, 1.0) as f32
            }
            _ => {
                self.repair(
                    element.into(),
                    format!("absorption {field} is not a number: 0 used"),
                );
                0.0
            }
        }
    }

    /// Clamps factors to the ranges glTF defines; reports each clamp.
    fn sanitize_factors(&mut self, element: &str, m: &mut Material) {
        let mut fixes = Vec::new();
        let mut unit = |name: &str, v: &mut f32, default: f32| {
            if !v.is_finite() {
                fixes.push(format!("{name} {v} replaced by {default}"));
                *v = default;
            } else if !(0.0..=1.0).contains(v) {
                fixes.push(format!("{name} {v} clamped to [0, 1]"));
                *v = v.clamp(0.0, 1.0);
            }
        };
        for (k, c) in m.base_color.as_mut().iter_mut().enumerate() {
            unit(&format!("base colour component {k}"), c, 1.0);
        }
        unit("metallic", &mut m.metallic, 1.0);
        unit("roughness", &mut m.roughness, 1.0);
        for (k, c) in m.emissive.as_mut().iter_mut().enumerate() {
            unit(&format!("emissive component {k}"), c, 0.0);
        }
        if !m.emissive_strength.is_finite() || m.emissive_strength < 0.0 {
            fixes.push(format!(
                "emissive strength {} replaced by 1",
                m.emissive_strength
            ));
            m.emissive_strength = 1.0;
        }
        if !m.normal_scale.is_finite() {
            fixes.push(format!("normal scale {} replaced by 1", m.normal_scale));
            m.normal_scale = 1.0;
        }
        if !m.clearcoat_normal_scale.is_finite() {
            fixes.push(format!(
                "clear coat normal scale {} replaced by 1",
                m.clearcoat_normal_scale
            ));
            m.clearcoat_normal_scale = 1.0;
        }
        if !m.ior.is_finite() || (m.ior < 1.0 && m.ior != 0.0) {
            fixes.push(format!("IOR {} replaced by 1.5", m.ior));
            m.ior = 1.5;
        }
        if let AlphaMode::Mask { cutoff } = &mut m.alpha_mode
            && (!cutoff.is_finite() || *cutoff < 0.0)
        {
            fixes.push(format!("alpha cutoff {cutoff} replaced by 0.5"));
            *cutoff = 0.5;
        }
        for fix in fixes {
            self.repair(element.to_owned(), fix);
        }
    }

    pub(super) fn slot(
        &mut self,
        element: &str,
        slot_name: &str,
        slot: Slot,
        space: ColorSpace,
    ) -> Option<TextureRef> {
        let (offset, rotation, scale, override_coord) =
            slot.transform.unwrap_or((Vec2::ZERO, 0.0, Vec2::ONE, None));
        let mut uv_set = override_coord.unwrap_or(slot.tex_coord);
        if uv_set > 1 {
            self.repair(
                element.into(),
                format!("{slot_name} texture uses UV set {uv_set}; chiaro reads sets 0 and 1: set 0 used"),
            );
            uv_set = 0;
        }
        let transform = texture_transform_matrix(offset, rotation, scale);
        if !transform.is_finite() {
            self.repair(
                element.into(),
                format!("{slot_name} texture transform is not finite: ignored"),
            );
        }
        let texture = self.texture(element, slot_name, &slot.texture, space)?;
        Some(TextureRef {
            texture,
            uv_set,
            transform: if transform.is_finite() {
                transform
            } else {
                Affine2::IDENTITY
            },
            sampler: sampler(&slot.texture.sampler()),
        })
    }

    fn texture(
        &mut self,
        element: &str,
        slot_name: &str,
        texture: &gltf::Texture,
        space: ColorSpace,
    ) -> Option<TextureId> {
        // A texture whose image only an extension names (EXT_texture_webp, say) has no source
        // here; the gltf crate's sentinel is u32::MAX.
        if self.document.as_json().textures[texture.index()]
            .source
            .value()
            == u32::MAX as usize
        {
            self.repair(
                element.into(),
                format!(
                    "{slot_name} texture {} has no image chiaro can decode (only an extension's): \
                     the factor alone is used",
                    texture.index()
                ),
            );
            return None;
        }
        let image = texture.source();
        let key = (image.index(), space);
        if let Some(done) = self.decoded.get(&key) {
            return *done;
        }
        let result = self.decode(&image).map(|(name, width, height, rgba8)| {
            self.textures.push(Texture {
                name,
                width,
                height,
                rgba8,
                color_space: space,
            });
            TextureId(self.textures.len() as u32 - 1)
        });
        let id = match result {
            Ok(id) => Some(id),
            Err(why) => {
                self.repair(
                    element.into(),
                    format!(
                        "{slot_name} texture (image {}) {why}: the factor alone is used",
                        image.index()
                    ),
                );
                None
            }
        };
        self.decoded.insert(key, id);
        id
    }

    /// The image's name, size and RGBA8 texels, or why it cannot be had.
    fn decode(&self, image: &gltf::Image) -> Result<(String, u32, u32, Vec<u8>), String> {
        let (name, bytes) = match image.source() {
            gltf::image::Source::View { view, .. } => {
                let buffer = self
                    .buffers
                    .get(view.buffer().index())
                    .ok_or("refers to a missing buffer")?;
                let bytes = view
                    .offset()
                    .checked_add(view.length())
                    .and_then(|end| buffer.get(view.offset()..end))
                    .ok_or_else(|| {
                        format!("buffer view {} does not fit its buffer", view.index())
                    })?;
                (
                    format!("image {} (buffer view {})", image.index(), view.index()),
                    bytes.to_vec(),
                )
            }
            gltf::image::Source::Uri { uri, .. } => match self.access.resolve(uri)? {
                UriSource::Embedded(bytes) => {
                    (format!("image {} (data URI)", image.index()), bytes)
                }
                UriSource::File(path) => {
                    let bytes =
                        read_file(&path).map_err(|e| format!("file {}: {e}", path.display()))?;
                    (path.display().to_string(), bytes)
                }
            },
        };
        let mut reader = ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| format!("{name}: {e}"))?;
        reader.limits(crate::texture::image_limits(MAX_TEXTURE_SIDE));
        let decoded = reader
            .decode()
            .map_err(|e| format!("{name} cannot be decoded: {e}"))?
            .into_rgba8();
        let (width, height) = decoded.dimensions();
        Ok((name, width, height, decoded.into_raw()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_transform_follows_the_extension_spec() {
        // The extension's matrix: a +90 degree rotation takes (1, 0) to (0, -1), then the offset.
        let m =
            texture_transform_matrix(Vec2::new(0.5, 0.0), std::f32::consts::FRAC_PI_2, Vec2::ONE);
        let uv = m.transform_point2(Vec2::new(1.0, 0.0));
        assert!(uv.abs_diff_eq(Vec2::new(0.5, -1.0), 1e-6), "{uv}");
        let s = texture_transform_matrix(Vec2::ZERO, 0.0, Vec2::new(2.0, 3.0));
        assert_eq!(s.transform_point2(Vec2::ONE), Vec2::new(2.0, 3.0));
    }
}
