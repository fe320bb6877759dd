//! Material extensions read from a material's `extensions` JSON: KHR_materials_specular,
//! KHR_materials_clearcoat, KHR_materials_sheen, KHR_materials_transmission and
//! KHR_materials_volume. Each factor is checked against its range; a value outside it is
//! repaired with a line that says so, never trusted. Their textures are not read yet: a file
//! that names one gets a repair line saying that the factor alone is used.

use glam::Vec3;
use serde_json::Value;

use crate::gltf::materials::MaterialImporter;
use crate::material::{Material, Volume};

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
        self.textures_not_read(
            element,
            ext,
            "KHR_materials_specular",
            &["specularTexture", "specularColorTexture"],
        );
    }

    /// KHR_materials_clearcoat: `clearcoatFactor` and `clearcoatRoughnessFactor`, each in
    /// [0, 1] (default 0). The coat shares the material's shading normal.
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
        self.textures_not_read(
            element,
            ext,
            "KHR_materials_clearcoat",
            &[
                "clearcoatTexture",
                "clearcoatRoughnessTexture",
                "clearcoatNormalTexture",
            ],
        );
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
            self.textures_not_read(
                element,
                ext,
                "KHR_materials_transmission",
                &["transmissionTexture"],
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
        self.textures_not_read(
            element,
            ext,
            "KHR_materials_sheen",
            &["sheenColorTexture", "sheenRoughnessTexture"],
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

    /// One repair line per texture of `extension` that the file names and chiaro does not read.
    fn textures_not_read(&mut self, element: &str, ext: &Value, extension: &str, names: &[&str]) {
        for texture in names {
            if ext.get(*texture).is_some() {
                self.repair(
                    element.into(),
                    format!("{extension}'s {texture} is not read: its factor alone is used"),
                );
            }
        }
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
