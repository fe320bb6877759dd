//! glTF 2.0 import (.gltf with embedded or external buffers, and .glb) into a [`SceneBuilder`].
//!
//! Read: the default scene (or the first), its node hierarchy, triangle primitives (strips and
//! fans converted, points and lines skipped), materials with KHR_materials_emissive_strength,
//! KHR_materials_ior, KHR_materials_specular's, KHR_materials_clearcoat's,
//! KHR_materials_sheen's and KHR_materials_transmission's factors, KHR_materials_volume,
//! KHR_texture_transform, KHR_lights_punctual, EXT_mesh_gpu_instancing, cameras, skins (each
//! skinned mesh instance posed once at load, see `skins`), node animations (`animations`). Every byte range is
//! checked before it is read; faults are errors naming the file and the element, or repairs
//! reported with what was dropped and how many (see [`crate::mesh_repair`]).

mod accessor;
mod animations;
mod container;
mod gpu_instancing;
mod integers;
mod material_extensions;
mod materials;
mod nodes;
mod primitives;
mod skins;
mod sources;

use std::path::Path;

pub use accessor::MAX_ZERO_FILLED_ELEMENTS;
pub use materials::MAX_TEXTURE_SIDE;
pub use nodes::MIN_SCALE;
pub use sources::MAX_FILE_BYTES;

use crate::error::{Fault, SceneError};
use crate::load::LoadOptions;
use crate::scene_builder::SceneBuilder;

/// Extensions chiaro reads; a file that requires any other is refused.
pub const SUPPORTED_EXTENSIONS: [&str; 10] = [
    "EXT_mesh_gpu_instancing",
    "KHR_lights_punctual",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_texture_transform",
];

/// Loads a .gltf or .glb file into a builder, ready to spawn, with the default
/// [`LoadOptions`] (files inside the model's folder only).
pub fn load_gltf(path: &Path) -> Result<SceneBuilder, SceneError> {
    load_gltf_with(path, &LoadOptions::default())
}

/// Loads a .gltf or .glb file into a builder, ready to spawn.
pub fn load_gltf_with(path: &Path, options: &LoadOptions) -> Result<SceneBuilder, SceneError> {
    let source = path.display().to_string();
    let whole = |fault: Fault| SceneError::whole(source.clone(), fault);
    let bytes = sources::read_model_file(path).map_err(whole)?;
    let container::Parsed {
        document,
        blob,
        notes,
    } = container::parse(&bytes).map_err(|e| whole(Fault::Gltf(e)))?;
    drop(bytes);
    let base = path.parent().unwrap_or(Path::new("."));
    let access = sources::FileAccess {
        base,
        allow_outside: options.allow_outside_files,
    };
    let at = |(element, fault): (String, Fault)| SceneError::at(source.clone(), element, fault);
    let buffers = sources::load_buffers(&document, blob, access).map_err(at)?;
    check_buffer_views(&document, &buffers).map_err(at)?;
    check_cameras(&document).map_err(at)?;

    let mut builder = SceneBuilder::new(source);
    for note in notes {
        builder.repair("document", note);
    }
    let mut importer = materials::MaterialImporter::new(&document, &buffers, access);
    let materials = importer.convert_all();
    for texture in std::mem::take(&mut importer.textures) {
        builder.add_texture(texture);
    }
    builder.extend_repairs(std::mem::take(&mut importer.repairs));
    for material in &materials {
        builder.add_material(material.clone());
    }
    let reader = accessor::AccessorReader { buffers: &buffers };
    nodes::NodeImporter::new(
        &document,
        reader,
        &mut builder,
        &materials,
        options.light_units,
    )
    .import()?;
    animations::import(
        &document,
        &accessor::AccessorReader { buffers: &buffers },
        &mut builder,
    );
    if builder.nodes().iter().all(|n| n.instance.is_none()) {
        builder.repair("scene", "has no triangles to render");
    }
    Ok(builder)
}

/// Every buffer view lies inside its buffer, with a legal stride (a multiple of 4 in 4..=252,
/// none on index data), whether or not the scene uses it.
fn check_buffer_views(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
) -> Result<(), (String, Fault)> {
    for view in document.views() {
        let element = nodes::element("buffer view", view.index(), view.name());
        let fault = |why: String| Err((element.clone(), Fault::Accessor(why)));
        let buffer_len = buffers.get(view.buffer().index()).map_or(0, Vec::len);
        if view
            .offset()
            .checked_add(view.length())
            .is_none_or(|end| end > buffer_len)
        {
            return fault(format!(
                "offset {} + length {} does not fit buffer {} of {buffer_len} bytes",
                view.offset(),
                view.length(),
                view.buffer().index()
            ));
        }
        if let Some(stride) = view.stride() {
            if stride % 4 != 0 || !(4..=252).contains(&stride) {
                return fault(format!(
                    "byte stride {stride} is not a multiple of 4 in 4..=252"
                ));
            }
            if view.target() == Some(gltf::buffer::Target::ElementArrayBuffer) {
                return fault("index data must not have a byte stride".into());
            }
        }
    }
    Ok(())
}

/// Every camera defines a usable projection, whether or not a node uses it.
fn check_cameras(document: &gltf::Document) -> Result<(), (String, Fault)> {
    for camera in document.cameras() {
        let element = nodes::element("camera", camera.index(), camera.name());
        let raw = &document.as_json().cameras[camera.index()];
        if raw.perspective.is_some() && raw.orthographic.is_some() {
            return Err((
                element,
                Fault::Camera("has both perspective and orthographic parameters".into()),
            ));
        }
        nodes::camera(&camera).map_err(|fault| (element, fault))?;
    }
    Ok(())
}
