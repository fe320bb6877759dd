//! EXT_mesh_gpu_instancing: a node drawing its mesh many times, with per-instance translation,
//! rotation and scale accessors. Each instance becomes a child entity of the node, sharing the
//! node's stored meshes.

use glam::{Quat, Vec3};

use crate::gltf::accessor::{AccessorReader, Formats};
use crate::transform::Transform;

/// The per-instance transforms of `node`, `None` when it does not use the extension. Rotations
/// are normalised; instances with a non-finite or zero-scale transform are left out, and their
/// number is returned so the caller can report it.
pub(crate) fn instance_transforms(
    reader: &AccessorReader,
    document: &gltf::Document,
    node: &gltf::Node,
) -> Result<Option<(Vec<Transform>, usize)>, String> {
    let Some(ext) = node.extension_value("EXT_mesh_gpu_instancing") else {
        return Ok(None);
    };
    let accessor = |name: &str| -> Result<Option<gltf::Accessor>, String> {
        match ext["attributes"].get(name) {
            None => Ok(None),
            Some(v) => {
                let index = v
                    .as_u64()
                    .ok_or_else(|| format!("EXT_mesh_gpu_instancing {name} is not an index"))?;
                document
                    .accessors()
                    .nth(index as usize)
                    .map(Some)
                    .ok_or_else(|| {
                        format!("EXT_mesh_gpu_instancing {name} refers to missing accessor {index}")
                    })
            }
        }
    };
    let translations = match accessor("TRANSLATION")? {
        Some(a) => Some(reader.read_f32::<3>(&a, Formats::Float)?),
        None => None,
    };
    let rotations = match accessor("ROTATION")? {
        Some(a) => Some(reader.read_f32::<4>(&a, Formats::Float)?),
        None => None,
    };
    let scales = match accessor("SCALE")? {
        Some(a) => Some(reader.read_f32::<3>(&a, Formats::Float)?),
        None => None,
    };
    let lengths: Vec<usize> = [
        translations.as_ref().map(Vec::len),
        rotations.as_ref().map(Vec::len),
        scales.as_ref().map(Vec::len),
    ]
    .into_iter()
    .flatten()
    .collect();
    let Some(&count) = lengths.first() else {
        return Err("EXT_mesh_gpu_instancing has no attributes".into());
    };
    if lengths.iter().any(|&l| l != count) {
        return Err(format!(
            "EXT_mesh_gpu_instancing attributes have different counts {lengths:?}"
        ));
    }
    let mut transforms = Vec::with_capacity(count);
    let mut dropped = 0;
    for k in 0..count {
        let translation = translations
            .as_ref()
            .map_or(Vec3::ZERO, |t| Vec3::from(t[k]));
        let rotation = rotations
            .as_ref()
            .map_or(Quat::IDENTITY, |r| Quat::from_array(r[k]));
        let scale = scales.as_ref().map_or(Vec3::ONE, |s| Vec3::from(s[k]));
        let usable = translation.is_finite()
            && rotation.is_finite()
            && rotation.length() > 1e-6
            && scale.is_finite()
            && scale.abs().min_element() >= crate::gltf::nodes::MIN_SCALE;
        if usable {
            transforms.push(Transform {
                translation,
                rotation: rotation.normalize(),
                scale,
            });
        } else {
            dropped += 1;
        }
    }
    Ok(Some((transforms, dropped)))
}
