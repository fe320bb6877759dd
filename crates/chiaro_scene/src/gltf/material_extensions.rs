//! Material extensions read from a material's `extensions` JSON: KHR_materials_specular.
//! Each factor is checked against its range; a value outside it is repaired with a line that
//! says so, never trusted.

use glam::Vec3;

use crate::gltf::materials::MaterialImporter;
use crate::material::Material;

impl MaterialImporter<'_> {
    /// KHR_materials_specular: `specularFactor` in [0, 1] (default 1) and `specularColorFactor`,
    /// three finite values of at least 0 (default 1). Its textures are not read: a repair line
    /// says the factor alone is used.
    pub(super) fn read_specular(&mut self, element: &str, m: &gltf::Material, out: &mut Material) {
        let Some(ext) = m.extension_value("KHR_materials_specular") else {
            return;
        };
        if let Some(value) = ext.get("specularFactor") {
            match value.as_f64() {
                Some(f) if (0.0..=1.0).contains(&f) => out.specular = f as f32,
                Some(f) if f.is_finite() => {
                    self.repair(
                        element.into(),
                        format!("specular factor {f} clamped to [0, 1]"),
                    );
                    out.specular = f.clamp(0.0, 1.0) as f32;
                }
                _ => self.repair(
                    element.into(),
                    format!("specular factor {value} is not a number: 1 used"),
                ),
            }
        }
        if let Some(value) = ext.get("specularColorFactor") {
            let channels: Option<Vec<f64>> = value
                .as_array()
                .filter(|a| a.len() == 3)
                .and_then(|a| a.iter().map(|c| c.as_f64()).collect());
            match channels {
                Some(c) if c.iter().all(|c| c.is_finite() && *c >= 0.0) => {
                    out.specular_color = Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
                }
                _ => self.repair(
                    element.into(),
                    format!("specular colour factor {value} is not three numbers >= 0: 1 used"),
                ),
            }
        }
        for texture in ["specularTexture", "specularColorTexture"] {
            if ext.get(texture).is_some() {
                self.repair(
                    element.into(),
                    format!(
                        "KHR_materials_specular's {texture} is not read: its factor alone is used"
                    ),
                );
            }
        }
    }
}
