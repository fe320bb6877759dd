//! Bytes behind a glTF: the file itself, its buffers (GLB chunk, data URI or external file) and
//! its images' encoded bytes. Sizes are checked before anything is read, so a declared length or
//! a URI can never make chiaro read or allocate more than the data that is really there.

use std::io::Read;
use std::path::{Path, PathBuf};

use base64::Engine;

use crate::error::Fault;

/// Largest file (glTF, GLB, buffer or image) chiaro reads, bytes.
pub const MAX_FILE_BYTES: u64 = 4 << 30;

/// Reads a regular file whole, refusing anything larger than [`MAX_FILE_BYTES`] or not a regular
/// file (a device or FIFO could be endless).
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, Fault> {
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(Fault::Io(std::io::Error::other("not a regular file")));
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(Fault::TooLarge {
            size: meta.len(),
            limit: MAX_FILE_BYTES,
        });
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(MAX_FILE_BYTES).read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// Where a URI's bytes are.
pub(crate) enum UriSource {
    /// Embedded as a data URI, decoded.
    Embedded(Vec<u8>),
    /// A file, resolved against the glTF's folder.
    File(PathBuf),
}

/// Resolves a glTF URI: base64 data URIs are decoded, relative references (percent-decoded)
/// are joined to `base`. Other schemes are refused.
pub(crate) fn resolve_uri(base: &Path, uri: &str) -> Result<UriSource, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (header, data) = rest
            .split_once(',')
            .ok_or_else(|| "malformed data URI (no comma)".to_owned())?;
        if !header.ends_with(";base64") {
            return Err("data URI is not base64-encoded".to_owned());
        }
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map(UriSource::Embedded)
            .map_err(|e| format!("data URI is not valid base64: {e}"));
    }
    let scheme_end = uri.find(':');
    let is_windows_drive = scheme_end == Some(1);
    if let Some(end) = scheme_end
        && !is_windows_drive
        && !uri[..end].contains(['/', '\\'])
        && &uri[..end] != "file"
    {
        return Err(format!("URI scheme '{}' is not supported", &uri[..end]));
    }
    let path = uri.strip_prefix("file://").unwrap_or(uri);
    let decoded = urlencoding::decode(path).map_err(|e| format!("URI is not valid UTF-8: {e}"))?;
    Ok(UriSource::File(base.join(decoded.as_ref())))
}

/// Loads every buffer of the document: the GLB binary chunk, a data URI or an external file.
/// Errors name the buffer.
pub(crate) fn load_buffers(
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    base: &Path,
) -> Result<Vec<Vec<u8>>, (String, Fault)> {
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let element = match buffer.name() {
            Some(name) => format!("buffer {} ({name:?})", buffer.index()),
            None => format!("buffer {}", buffer.index()),
        };
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                (
                    element.clone(),
                    Fault::Gltf("refers to a GLB binary chunk the file does not have".into()),
                )
            })?,
            gltf::buffer::Source::Uri(uri) => match resolve_uri(base, uri) {
                Ok(UriSource::Embedded(bytes)) => bytes,
                Ok(UriSource::File(path)) => read_file(&path)
                    .map_err(|fault| (format!("{element} file {}", path.display()), fault))?,
                Err(message) => return Err((element, Fault::Gltf(message))),
            },
        };
        let declared = buffer.length() as u64;
        if (data.len() as u64) < declared {
            return Err((
                element,
                Fault::BufferTooShort {
                    declared,
                    actual: data.len() as u64,
                },
            ));
        }
        data.truncate(declared as usize);
        buffers.push(data);
    }
    Ok(buffers)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_uris_decode() {
        match resolve_uri(Path::new("."), "data:application/octet-stream;base64,AAEC") {
            Ok(UriSource::Embedded(bytes)) => assert_eq!(bytes, vec![0, 1, 2]),
            _ => panic!("expected embedded bytes"),
        }
        assert!(resolve_uri(Path::new("."), "data:text/plain,hello").is_err());
    }

    #[test]
    fn relative_uris_are_percent_decoded_and_joined() {
        match resolve_uri(Path::new("/models"), "my%20tex.png") {
            Ok(UriSource::File(p)) => assert_eq!(p, Path::new("/models/my tex.png")),
            _ => panic!("expected a file"),
        }
    }

    #[test]
    fn network_uris_are_refused() {
        let err = resolve_uri(Path::new("."), "https://example.com/a.bin")
            .err()
            .unwrap();
        assert!(err.contains("'https'"), "{err}");
    }

    #[test]
    fn devices_are_not_read() {
        assert!(read_file(Path::new("/dev/zero")).is_err());
    }
}
