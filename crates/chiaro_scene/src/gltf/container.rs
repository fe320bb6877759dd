//! Parsing a glTF or GLB file into a validated document. The GLB container is checked here
//! (header, chunk bounds and alignment, chunk order) and mesh attribute references are checked
//! before the gltf crate validates the JSON, because the crate panics on a GLB header shorter
//! than itself and on a primitive attribute naming a missing accessor. Required extensions are
//! checked against the ones chiaro reads.

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

fn word(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// Checks a GLB container's structure: version 2, a total length matching the data, chunks
/// inside it with 4-byte aligned lengths, a JSON chunk first, at most one BIN chunk right after.
fn check_glb(bytes: &[u8]) -> Result<(), String> {
    if bytes.len() < 12 {
        return Err(format!(
            "GLB header needs 12 bytes, the file has {}",
            bytes.len()
        ));
    }
    let version = word(bytes, 4);
    if version != 2 {
        return Err(format!("GLB version {version} is not 2"));
    }
    let length = word(bytes, 8) as usize;
    if length != bytes.len() {
        return Err(format!(
            "GLB header says {length} bytes, the file has {}",
            bytes.len()
        ));
    }
    let mut at = 12;
    let mut index = 0;
    while at < length {
        if length - at < 8 {
            return Err(format!(
                "GLB chunk {index} header is cut short at byte {at}"
            ));
        }
        let (chunk_length, chunk_type) = (word(bytes, at) as usize, word(bytes, at + 4));
        if chunk_length % 4 != 0 {
            return Err(format!(
                "GLB chunk {index} length {chunk_length} is not a multiple of 4"
            ));
        }
        if chunk_length > length - at - 8 {
            return Err(format!(
                "GLB chunk {index} ({chunk_length} bytes) runs past the end of the file"
            ));
        }
        match (index, chunk_type) {
            (0, CHUNK_JSON) | (1, CHUNK_BIN) => {}
            (0, _) => return Err("GLB's first chunk is not JSON".into()),
            (_, CHUNK_JSON | CHUNK_BIN) => {
                return Err(format!("GLB chunk {index} repeats a JSON or BIN chunk"));
            }
            _ => {} // unknown chunk types are skipped, as the spec allows
        }
        at += 8 + chunk_length;
        index += 1;
    }
    if index == 0 {
        return Err("GLB has no JSON chunk".into());
    }
    Ok(())
}

/// Every accessor a mesh primitive names exists (the gltf crate's validation indexes them
/// unchecked).
fn check_attribute_references(root: &gltf::json::Root) -> Result<(), String> {
    let count = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let targets = primitive
                .targets
                .iter()
                .flatten()
                .flat_map(|t| [t.positions, t.normals, t.tangents].into_iter().flatten());
            let attributes = primitive.attributes.values().copied();
            for index in attributes.chain(primitive.indices).chain(targets) {
                if index.value() >= count {
                    return Err(format!(
                        "mesh {m} primitive {p} refers to accessor {} but there are {count}",
                        index.value()
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Every image has exactly one source, a URI or a buffer view, and one stored in a buffer view
/// names its MIME type, as the specification requires (the gltf crate's validation lets these
/// pass, then unwraps them when the image's source is read).
fn check_image_sources(root: &gltf::json::Root) -> Result<(), String> {
    for (i, image) in root.images.iter().enumerate() {
        match (&image.uri, image.buffer_view, &image.mime_type) {
            (Some(_), None, _) | (None, Some(_), Some(_)) => {}
            (None, Some(_), None) => {
                return Err(format!(
                    "image {i} is stored in a buffer view but has no mimeType"
                ));
            }
            (Some(_), Some(_), _) => {
                return Err(format!("image {i} has both a uri and a bufferView"));
            }
            (None, None, _) => return Err(format!("image {i} has neither a uri nor a bufferView")),
        }
    }
    Ok(())
}

/// The JSON text of a .gltf or .glb file and the GLB's binary chunk, the container checked.
fn split(bytes: &[u8]) -> Result<(&[u8], Option<Vec<u8>>), String> {
    if !bytes.starts_with(GLB_MAGIC) {
        return Ok((bytes, None));
    }
    check_glb(bytes)?;
    // check_glb found chunk 0 whole inside the file, and chunk 1, if any, after it.
    let json_end = 20 + word(bytes, 12) as usize;
    let blob = (bytes.len() >= json_end + 8 && word(bytes, json_end + 4) == CHUNK_BIN).then(|| {
        let start = json_end + 8;
        bytes[start..start + word(bytes, json_end) as usize].to_vec()
    });
    Ok((&bytes[20..json_end], blob))
}

/// Drops the animation channels that target no node (KHR_animation_pointer's, which name
/// their target by a JSON pointer instead), which the gltf crate cannot represent; chiaro
/// plays node animations only, so the rest of the file reads the same. Returns what was
/// dropped.
fn drop_pointer_channels(root: &mut serde_json::Value) -> Vec<String> {
    let mut notes = Vec::new();
    let Some(animations) = root.get_mut("animations").and_then(|a| a.as_array_mut()) else {
        return notes;
    };
    for (a, animation) in animations.iter_mut().enumerate() {
        let Some(channels) = animation.get_mut("channels").and_then(|c| c.as_array_mut()) else {
            continue;
        };
        let before = channels.len();
        channels.retain(|c| c.get("target").is_none_or(|t| t.get("node").is_some()));
        if channels.len() < before {
            notes.push(format!(
                "animation {a}: skipped {} channels that target no node (animation pointers)",
                before - channels.len()
            ));
        }
    }
    notes
}

/// Validates the document as the gltf crate would, except for two things the specification
/// allows and chiaro handles: an accessor without a buffer view (all zeros, unless sparse) and
/// a texture whose image comes from an extension only (e.g. EXT_texture_webp), which chiaro
/// cannot decode and leaves out, using the material's factors.
fn validate(root: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::validation::{Error, Validate};
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path().to_string();
        let allowed = matches!(error, Error::Missing)
            && ((path.starts_with("accessors[") && path.ends_with("].bufferView"))
                || (path.starts_with("textures[") && path.ends_with("].source")));
        if !allowed {
            errors.push(format!("{path}: {error}"));
        }
    });
    match errors.is_empty() {
        true => Ok(()),
        false => Err(format!("invalid glTF: {}", errors.join("; "))),
    }
}

/// A parsed glTF: the validated document, the GLB binary chunk, and notes on what was left out.
pub(crate) struct Parsed {
    /// The document.
    pub document: gltf::Document,
    /// The GLB's binary chunk.
    pub blob: Option<Vec<u8>>,
    /// Parts skipped while parsing, for the import report.
    pub notes: Vec<String>,
}

/// Parses and validates a .gltf or .glb file's bytes: the document and the GLB binary chunk.
pub(crate) fn parse(bytes: &[u8]) -> Result<Parsed, String> {
    let (json, blob) = split(bytes)?;
    let mut value: serde_json::Value =
        serde_json::from_slice(json).map_err(|e| format!("JSON: {e}"))?;
    super::integers::check_integer_fields(&value)?;
    let notes = drop_pointer_channels(&mut value);
    let mut root: gltf::json::Root = serde_json::from_value(value).map_err(|e| e.to_string())?;
    if let Some(ext) = root
        .extensions_required
        .iter()
        .find(|e| !super::SUPPORTED_EXTENSIONS.contains(&e.as_str()))
    {
        return Err(format!(
            "requires extension {ext}, which chiaro does not support"
        ));
    }
    // The gltf crate refuses required extensions it does not model itself, such as
    // EXT_mesh_gpu_instancing, which chiaro reads from the raw JSON.
    root.extensions_required
        .retain(|e| gltf::json::extensions::ENABLED_EXTENSIONS.contains(&e.as_str()));
    check_attribute_references(&root)?;
    check_image_sources(&root)?;
    validate(&root)?;
    Ok(Parsed {
        document: gltf::Document::from_json_without_validation(root),
        blob,
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(chunks: &[(u32, &[u8])], length_delta: i64) -> Vec<u8> {
        let mut body = Vec::new();
        for (ty, data) in chunks {
            body.extend((data.len() as u32).to_le_bytes());
            body.extend(ty.to_le_bytes());
            body.extend(*data);
        }
        let total = (12 + body.len()) as i64 + length_delta;
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend((total as u32).to_le_bytes());
        out.extend(body);
        out
    }

    #[test]
    fn well_formed_glb_passes() {
        let json = br#"{"asset":{"version":"2.0"}}"#;
        let mut padded = json.to_vec();
        padded.resize(json.len().div_ceil(4) * 4, b' ');
        check_glb(&glb(&[(CHUNK_JSON, &padded), (CHUNK_BIN, &[0; 8])], 0)).unwrap();
        assert!(parse(&glb(&[(CHUNK_JSON, &padded)], 0)).is_ok());
    }

    #[test]
    fn broken_containers_are_refused() {
        let json = [b' '; 8];
        assert!(
            check_glb(b"glTF\x02\0\0\0")
                .unwrap_err()
                .contains("12 bytes")
        );
        assert!(
            check_glb(&glb(&[(CHUNK_JSON, &json)], -4))
                .unwrap_err()
                .contains("header says")
        );
        assert!(
            check_glb(&glb(&[(CHUNK_JSON, &json[..6])], 0))
                .unwrap_err()
                .contains("multiple of 4")
        );
        assert!(
            check_glb(&glb(&[(CHUNK_BIN, &json)], 0))
                .unwrap_err()
                .contains("first chunk")
        );
        let twice = glb(
            &[(CHUNK_JSON, &json), (CHUNK_BIN, &json), (CHUNK_BIN, &json)],
            0,
        );
        assert!(check_glb(&twice).unwrap_err().contains("repeats"));
        let mut short_header = glb(&[(CHUNK_JSON, &json)], 0);
        short_header[8..12].copy_from_slice(&4u32.to_le_bytes());
        assert!(parse(&short_header).is_err());
    }

    #[test]
    fn images_without_a_usable_source_are_refused() {
        let with_images = |images: &str| {
            format!(
                r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":4,"uri":"data:application/octet-stream;base64,AAAAAA=="}}],"bufferViews":[{{"buffer":0,"byteLength":4}}],"images":[{images}]}}"#
            )
        };
        let refused = |images: &str| {
            parse(with_images(images).as_bytes())
                .err()
                .unwrap_or_else(|| panic!("{images} should be refused"))
        };
        assert!(
            refused(r#"{"bufferView":0}"#)
                .contains("image 0 is stored in a buffer view but has no mimeType")
        );
        assert!(refused(r#"{"name":"nothing"}"#).contains("neither a uri nor a bufferView"));
        assert!(
            refused(r#"{"uri":"a.png","bufferView":0,"mimeType":"image/png"}"#)
                .contains("both a uri and a bufferView")
        );
        assert!(
            parse(with_images(r#"{"bufferView":0,"mimeType":"image/png"}"#).as_bytes()).is_ok()
        );
        assert!(parse(with_images(r#"{"uri":"a.png"}"#).as_bytes()).is_ok());
    }
}
