//! Material extensions read from a material's `extensions` JSON: KHR_materials_specular,
//! KHR_materials_clearcoat, KHR_materials_sheen, KHR_materials_transmission and
//! KHR_materials_volume. Each factor is checked against its range; a value outside it is
//! repaired with a line that says so, never trusted. Their textures multiply the factors
//! ([`crate::material::LayerTextures`]); the clear coat's normal texture is the coat's own
//! normal map ([`Material::clearcoat_normal_texture`]).

use glam::Vec3;
use serde_json::Value;

use crate::gltf::materials::{MaterialImporter, Slot, transform_from_json};
use crate::material::{Material, TextureRef, Volume};
use crate::texture::ColorSpace;

impl MaterialImporter<'_> {
    /// KHR_materials_specular: `specularFactor` in [0, 1] (default 1) and `specularColorFactor`,
    /// three finite values of at least 0 (default 1).
    pub(super) fn read_specular(&mut self, element: &str, m: &gltf::Material, out: &mut Material) {
        let Some(ext) = m.extension_value("KHR_materials_specular") else {
            return;
        };
        if let Some(f) = self.unit_factor(element, ext, "specularFactor", "specular factor") {
            out.specular = f;
        }
        if let Some(value) = ext.get("specularColorFactor") {
            match three_numbers(value) {
                Some(color) if color.min_element() >= 0.0 => out.specular_color = color,
                _ => self.repair(
                    element.into(),
                    format!("specular colour factor {value} is not three numbers >= 0: 1 used"),
                ),
            }
        }
        out.layer_textures.specular = self.layer_texture(
            element,
            ext,
            "specularTexture",
            "specular",
            ColorSpace::Linear,
        );
        out.layer_textures.specular_color = self.layer_texture(
            element,
            ext,
            "specularColorTexture",
            "specular colour",
            ColorSpace::Srgb,
        );
    }

    /// KHR_materials_clearcoat: `clearcoatFactor` and `clearcoatRoughnessFactor`, each in
    /// [0, 1] (default 0), their textures, and `clearcoatNormalTexture` with its `scale`
    /// (a number, default 1).
    pub(super) fn read_clearcoat(&mut self, element: &str, m: &gltf::Material, out: &mut Material) {
        let Some(ext) = m.extension_value("KHR_materials_clearcoat") else {
            return;
        };
        if let Some(f) = self.unit_factor(element, ext, "clearcoatFactor", "clear coat factor") {
            out.clearcoat = f;
        }
        if let Some(f) = self.unit_factor(
            element,
            ext,
            "clearcoatRoughnessFactor",
            "clear coat roughness",
        ) {
            out.clearcoat_roughness = f;
        }
        out.layer_textures.clearcoat = self.layer_texture(
            element,
            ext,
            "clearcoatTexture",
            "clear coat",
            ColorSpace::Linear,
        );
        out.layer_textures.clearcoat_roughness = self.layer_texture(
            element,
            ext,
            "clearcoatRoughnessTexture",
            "clear coat roughness",
            ColorSpace::Linear,
        );
        out.clearcoat_normal_texture = self.layer_texture(
            element,
            ext,
            "clearcoatNormalTexture",
            "clear coat normal",
            ColorSpace::Linear,
        );
        if let Some(scale) = ext
            .get("clearcoatNormalTexture")
            .and_then(|t| t.get("scale"))
        {
            match scale.as_f64() {
                Some(s) if (s as f32).is_finite() => out.clearcoat_normal_scale = s as f32,
                _ => self.repair(
                    element.into(),
                    format!("clear coat normal scale {scale} is not a number: 1 used"),
                ),
            }
        }
    }

    /// KHR_materials_transmission: `transmissionFactor` in [0, 1] (default 0). The surface is
    /// thin-walled unless KHR_materials_volume gives it a `thicknessFactor` above 0
    /// ([`MaterialImporter::read_volume`]).
    pub(super) fn read_transmission(
        &mut self,
        element: &str,
        m: &gltf::Material,
        out: &mut Material,
    ) {
        if let Some(ext) = m.extension_value("KHR_materials_transmission") {
            if let Some(f) =
                self.unit_factor(element, ext, "transmissionFactor", "transmission factor")
            {
                out.transmission = f;
            }
            out.layer_textures.transmission = self.layer_texture(
                element,
                ext,
                "transmissionTexture",
                "transmission",
                ColorSpace::Linear,
            );
        }
        self.read_volume(element, m, out);
    }

    /// KHR_materials_volume: a `thicknessFactor` above 0 makes the mesh a medium (refraction
    /// by the IOR, Beer-Lambert attenuation inside) when the material transmits; its
    /// `attenuationColor` (three numbers in [0, 1], default white) and `attenuationDistance`
    /// (above 0, default infinite) set the attenuation. The thickness itself (and its texture)
    /// only approximates the medium for rasterizers; a tracer follows the rays through it.
    fn read_volume(&mut self, element: &str, m: &gltf::Material, out: &mut Material) {
        let Some(ext) = m.extension_value("KHR_materials_volume") else {
            return;
        };
        let thickness = match ext.get("thicknessFactor") {
            None => 0.0,
            Some(value) => match value.as_f64() {
                Some(t) if t.is_finite() && t >= 0.0 => t,
                _ => {
                    self.repair(
                        element.into(),
                        format!("volume thickness {value} is not a number >= 0: thin-walled"),
                    );
                    0.0
                }
            },
        };
        if thickness <= 0.0 || out.transmission <= 0.0 {
            return;
        }
        let mut volume = Volume::default();
        if let Some(value) = ext.get("attenuationColor") {
            match three_numbers(value) {
                Some(color) if color.min_element() > 0.0 && color.max_element() <= 1.0 => {
                    volume.attenuation_color = color;
                }
                _ => self.repair(
                    element.into(),
                    format!(
                        "attenuation colour {value} is not three numbers in (0, 1]: white used"
                    ),
                ),
            }
        }
        if let Some(value) = ext.get("attenuationDistance") {
            match value.as_f64() {
                Some(d) if d > 0.0 && (d as f32).is_finite() => {
                    volume.attenuation_distance = d as f32;
                }
                _ => self.repair(
                    element.into(),
                    format!("attenuation distance {value} is not a number > 0: no attenuation"),
                ),
            }
        }
        out.volume = Some(volume);
    }

    /// KHR_materials_sheen: `sheenColorFactor`, three numbers in [0, 1] (default black: no
    /// sheen), and `sheenRoughnessFactor` in [0, 1] (default 0).
    pub(super) fn read_sheen(&mut self, element: &str, m: &gltf::Material, out: &mut Material) {
        let Some(ext) = m.extension_value("KHR_materials_sheen") else {
            return;
        };
        if let Some(value) = ext.get("sheenColorFactor") {
            match three_numbers(value) {
                Some(color) => {
                    out.sheen_color = color.clamp(Vec3::ZERO, Vec3::ONE);
                    if out.sheen_color != color {
                        self.repair(
                            element.into(),
                            format!("sheen colour {color} clamped to [0, 1]"),
                        );
                    }
                }
                _ => self.repair(
                    element.into(),
                    format!("sheen colour {value} is not three numbers: no sheen"),
                ),
            }
        }
        if let Some(f) = self.unit_factor(element, ext, "sheenRoughnessFactor", "sheen roughness") {
            out.sheen_roughness = f;
        }
        out.layer_textures.sheen_color = self.layer_texture(
            element,
            ext,
            "sheenColorTexture",
            "sheen colour",
            ColorSpace::Srgb,
        );
        out.layer_textures.sheen_roughness = self.layer_texture(
            element,
            ext,
            "sheenRoughnessTexture",
            "sheen roughness",
            ColorSpace::Linear,
        );
    }

    /// The number `field` of `ext` in [0, 1]: a finite number outside is clamped, anything
    /// else is ignored (the default stays), each with a repair line. None when absent.
    fn unit_factor(&mut self, element: &str, ext: &Value, field: &str, name: &str) -> Option<f32> {
        let value = ext.get(field)?;
        match value.as_f64() {
            Some(f) if (0.0..=1.0).contains(&f) => Some(f as f32),
            Some(f) if f.is_finite() => {
                self.repair(element.into(), format!("{name} {f} clamped to [0, 1]"));
                Some(f.clamp(0.0, 1.0) as f32)
            }
            _ => {
                self.repair(
                    element.into(),
                    format!("{name} {value} is not a number: the default is used"),
                );
                None
            }
        }
    }

    /// The texture info `field` of `ext` (its `index`, `texCoord` and KHR_texture_transform),
    /// decoded in `space` as the `name` texture of one of [`crate::material::LayerTextures`].
    /// None when absent; None with a repair line when it names no texture of the file or cannot
    /// be decoded.
    fn layer_texture(
        &mut self,
        element: &str,
        ext: &Value,
        field: &str,
        name: &str,
        space: ColorSpace,
    ) -> Option<TextureRef> {
        let info = ext.get(field)?;
        let document = self.document;
        let texture = info
            .get("index")
            .and_then(Value::as_u64)
            .and_then(|i| document.textures().nth(usize::try_from(i).ok()?));
        let Some(texture) = texture else {
            self.repair(
                element.into(),
                format!("{field} {info} names no texture of the file: its factor alone is used"),
            );
            return None;
        };
        let tex_coord = match info.get("texCoord").map(Value::as_u64) {
            None => 0,
            Some(Some(set)) => u32::try_from(set).unwrap_or(u32::MAX),
            Some(None) => {
                self.repair(
                    element.into(),
                    format!("{field}'s texCoord is not a whole number: UV set 0 used"),
                );
                0
            }
        };
        let transform = info
            .get("extensions")
            .and_then(|e| e.get("KHR_texture_transform"))
            .map(transform_from_json);
        let slot = Slot {
            texture,
            tex_coord,
            transform,
        };
        self.slot(element, name, slot, space)
    }
}

/// A JSON array of exactly three finite numbers, as a vector.
fn three_numbers(value: &Value) -> Option<Vec3> {
    let channels: Vec<f32> = value
        .as_array()
        .filter(|a| a.len() == 3)?
        .iter()
        .map(|c| c.as_f64().map(|c| c as f32))
        .collect::<Option<_>>()?;
    let color = Vec3::from_slice(&channels);
    color.is_finite().then_some(color)
}
