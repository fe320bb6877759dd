//! glTF 2.0 import (.gltf with embedded or external buffers, and .glb) into a [`SceneBuilder`].
//!
//! Read: the default scene (or the first), its node hierarchy, triangle primitives (strips and
//! fans converted, points and lines skipped), materials with KHR_materials_emissive_strength,
//! KHR_materials_ior and KHR_texture_transform, KHR_lights_punctual, cameras. Every byte range is
//! checked before it is read; faults are errors naming the file and the element, or repairs
//! reported with what was dropped and how many (see [`crate::mesh_repair`]).

mod accessor;
mod materials;
mod nodes;
mod primitives;
mod sources;

use std::path::Path;

pub use accessor::MAX_ZERO_FILLED_ELEMENTS;
pub use materials::MAX_TEXTURE_SIDE;
pub use nodes::MIN_SCALE;
pub use sources::MAX_FILE_BYTES;

use crate::error::{Fault, SceneError};
use crate::scene_builder::SceneBuilder;

/// Extensions chiaro reads; a file that requires any other is refused.
pub const SUPPORTED_EXTENSIONS: [&str; 4] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_texture_transform",
];

/// Loads a .gltf or .glb file into a builder, ready to spawn.
pub fn load_gltf(path: &Path) -> Result<SceneBuilder, SceneError> {
    let source = path.display().to_string();
    let whole = |fault: Fault| SceneError::whole(source.clone(), fault);
    let bytes = sources::read_file(path).map_err(whole)?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| whole(Fault::Gltf(e.to_string())))?;
    drop(bytes);
    let document = gltf.document;
    if let Some(ext) = document
        .extensions_required()
        .find(|e| !SUPPORTED_EXTENSIONS.contains(e))
    {
        return Err(whole(Fault::Gltf(format!(
            "requires extension {ext}, which chiaro does not support"
        ))));
    }
    let base = path.parent().unwrap_or(Path::new("."));
    let buffers = sources::load_buffers(&document, gltf.blob, base)
        .map_err(|(element, fault)| SceneError::at(source.clone(), element, fault))?;

    let mut builder = SceneBuilder::new(source);
    let mut importer = materials::MaterialImporter::new(&document, &buffers, base);
    let materials = importer.convert_all();
    for texture in std::mem::take(&mut importer.textures) {
        builder.add_texture(texture);
    }
    builder.extend_repairs(std::mem::take(&mut importer.repairs));
    for material in &materials {
        builder.add_material(material.clone());
    }
    let reader = accessor::AccessorReader { buffers: &buffers };
    nodes::NodeImporter::new(&document, reader, &mut builder, &materials).import()?;
    if builder.nodes().iter().all(|n| n.instance.is_none()) {
        builder.repair("scene", "has no triangles to render");
    }
    Ok(builder)
}
