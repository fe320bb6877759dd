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

/// Bytes a model file's start is looked at before the rest is read.
const SNIFFED_BYTES: usize = 4096;

/// Reads a .gltf or .glb file whole, after checking from its first bytes that it is one: a GLB
/// header (magic, version 2, a total length equal to the file's size) or JSON text opening with
/// `{`. A file of something else (or of zeros, such as a large sparse file) is refused without
/// reading more than its first few kilobytes.
pub(crate) fn read_model_file(path: &Path) -> Result<Vec<u8>, Fault> {
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(Fault::Io(std::io::Error::other("not a regular file")));
    }
    let mut head = Vec::with_capacity(SNIFFED_BYTES);
    (&file).take(SNIFFED_BYTES as u64).read_to_end(&mut head)?;
    check_model_start(&head, meta.len())?;
    read_file(path)
}

/// Whether `head`, the start of a file of `size` bytes, begins a GLB or a JSON document.
fn check_model_start(head: &[u8], size: u64) -> Result<(), Fault> {
    let not_gltf = |why: String| Err(Fault::Gltf(why));
    if let Some(header) = head.strip_prefix(b"glTF") {
        if head.len() < 12 {
            return not_gltf(format!("GLB header needs 12 bytes, the file has {size}"));
        }
        let version = u32::from_le_bytes([header[0], header[1], header[2], header[3]]);
        let length = u32::from_le_bytes([header[4], header[5], header[6], header[7]]);
        if version != 2 {
            return not_gltf(format!("GLB version {version} is not 2"));
        }
        if u64::from(length) != size {
            return not_gltf(format!(
                "GLB header says {length} bytes, the file has {size}"
            ));
        }
        return Ok(());
    }
    let text = head.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(head);
    match text.iter().find(|b| !b.is_ascii_whitespace()) {
        Some(b'{') => Ok(()),
        Some(&b) => not_gltf(format!(
            "neither a GLB nor JSON: it starts with byte 0x{b:02x}, not 'glTF' or '{{'"
        )),
        None if head.len() < SNIFFED_BYTES => not_gltf("the file is empty or blank".into()),
        None => not_gltf(format!(
            "neither a GLB nor JSON: its first {SNIFFED_BYTES} bytes are blank"
        )),
    }
}

/// Where a URI's bytes are.
#[derive(Debug)]
pub(crate) enum UriSource {
    /// Embedded as a data URI, decoded.
    Embedded(Vec<u8>),
    /// A file, resolved against the glTF's folder.
    File(PathBuf),
}

/// Longest URI quoted whole in a message; longer ones are cut, with their length.
const MAX_QUOTED_URI: usize = 80;

/// `uri` as a message quotes it: whole when short, else its start and its length.
pub(crate) fn quoted_uri(uri: &str) -> String {
    match uri.char_indices().nth(MAX_QUOTED_URI) {
        None => format!("'{uri}'"),
        Some((cut, _)) => format!("'{}...' ({} characters)", &uri[..cut], uri.chars().count()),
    }
}

/// Which files a glTF may name: its own folder's (the default), or any (the opt-in
/// [`crate::LoadOptions::allow_outside_files`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FileAccess<'a> {
    /// The glTF's folder.
    pub base: &'a Path,
    /// Whether absolute paths, `file:` URIs and `..` leaving `base` are followed.
    pub allow_outside: bool,
}

impl FileAccess<'_> {
    /// Resolves a glTF URI: base64 data URIs are decoded, relative references (percent-decoded)
    /// are joined to the folder. Other schemes are refused, and so, unless the access allows
    /// files outside the folder, are `file:` URIs, absolute paths, `..` that climbs out of the
    /// folder and links inside it that lead out. Nothing on disk is looked at before the URI
    /// has passed the textual checks, so a refusal says nothing of what exists outside.
    pub fn resolve(&self, uri: &str) -> Result<UriSource, String> {
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
        let outside = |why: &str| {
            Err(format!(
                "URI {} {why}: files outside the model's folder are read only when allowed \
                 (--allow-outside-files)",
                quoted_uri(uri)
            ))
        };
        let scheme_end = uri.find(':');
        let is_windows_drive = scheme_end == Some(1);
        let mut path = uri;
        if let Some(end) = scheme_end
            && !is_windows_drive
            && !uri[..end].contains(['/', '\\'])
        {
            if !uri[..end].eq_ignore_ascii_case("file") {
                return Err(format!(
                    "URI {}: scheme '{}' is not supported",
                    quoted_uri(uri),
                    &uri[..end]
                ));
            }
            if !self.allow_outside {
                return outside("is a file: URI");
            }
            path = uri[end + 1..].strip_prefix("//").unwrap_or(&uri[end + 1..]);
        }
        let decoded = urlencoding::decode(path)
            .map_err(|e| format!("URI {} is not valid UTF-8: {e}", quoted_uri(uri)))?;
        let relative = Path::new(decoded.as_ref());
        if self.allow_outside {
            return Ok(UriSource::File(self.base.join(relative)));
        }
        if is_windows_drive || decoded.starts_with(['/', '\\']) || relative.has_root() {
            return outside("is an absolute path");
        }
        if climbs_out(decoded.as_ref()) {
            return outside("leaves the model's folder through '..'");
        }
        let joined = self.base.join(relative);
        // A link inside the folder may lead out of it: compare where both really are.
        if let (Ok(real), Ok(real_base)) = (joined.canonicalize(), self.base.canonicalize())
            && !real.starts_with(&real_base)
        {
            return outside("leads out of the model's folder through a link");
        }
        Ok(UriSource::File(joined))
    }
}

/// Whether a relative path's `..` components climb above its start (either separator counts).
fn climbs_out(relative: &str) -> bool {
    let mut depth = 0usize;
    for part in relative.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => match depth.checked_sub(1) {
                Some(d) => depth = d,
                None => return true,
            },
            _ => depth += 1,
        }
    }
    false
}

/// Loads every buffer of the document: the GLB binary chunk, a data URI or an external file.
/// Errors name the buffer.
pub(crate) fn load_buffers(
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    access: FileAccess,
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
            gltf::buffer::Source::Uri(uri) => match access.resolve(uri) {
                Ok(UriSource::Embedded(bytes)) => bytes,
                Ok(UriSource::File(path)) => read_file(&path)
                    .map_err(|fault| (format!("{element} file {}", path.display()), fault))?,
                Err(message) => return Err((element, Fault::Uri(message))),
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

    fn inside(base: &str) -> FileAccess<'_> {
        FileAccess {
            base: Path::new(base),
            allow_outside: false,
        }
    }

    fn file(access: FileAccess, uri: &str) -> PathBuf {
        match access.resolve(uri) {
            Ok(UriSource::File(p)) => p,
            Ok(UriSource::Embedded(_)) => panic!("{uri}: expected a file"),
            Err(e) => panic!("{uri}: {e}"),
        }
    }

    #[test]
    fn data_uris_decode() {
        match inside(".").resolve("data:application/octet-stream;base64,AAEC") {
            Ok(UriSource::Embedded(bytes)) => assert_eq!(bytes, vec![0, 1, 2]),
            _ => panic!("expected embedded bytes"),
        }
        assert!(inside(".").resolve("data:text/plain,hello").is_err());
    }

    #[test]
    fn relative_uris_are_percent_decoded_and_joined() {
        assert_eq!(
            file(inside("/models"), "my%20tex.png"),
            Path::new("/models/my tex.png")
        );
        assert_eq!(
            file(inside("/models"), "a/../b/./c.bin"),
            Path::new("/models/a/../b/./c.bin")
        );
    }

    #[test]
    fn uris_leaving_the_folder_are_refused_unless_allowed() {
        for (uri, why) in [
            ("../../../tmp/x.png", "through '..'"),
            ("a/../../x.png", "through '..'"),
            ("%2E%2E/x.png", "through '..'"),
            ("..\\x.png", "through '..'"),
            ("/tmp/x.png", "absolute path"),
            ("%2Ftmp/x.png", "absolute path"),
            ("/etc/passwd", "absolute path"),
            ("file:///tmp/x.png", "file: URI"),
            ("FILE:/tmp/x.png", "file: URI"),
            ("C:/x.png", "absolute path"),
        ] {
            let err = inside("/models")
                .resolve(uri)
                .err()
                .unwrap_or_else(|| panic!("{uri} should be refused"));
            assert!(err.contains(why), "{uri}: {err}");
            assert!(err.contains("--allow-outside-files"), "{err}");
        }
        let open = FileAccess {
            base: Path::new("/models"),
            allow_outside: true,
        };
        assert_eq!(file(open, "file:///tmp/x.png"), Path::new("/tmp/x.png"));
        assert_eq!(file(open, "/etc/passwd"), Path::new("/etc/passwd"));
        assert_eq!(file(open, "../x.png"), Path::new("/models/../x.png"));
    }

    #[cfg(unix)]
    #[test]
    fn links_leading_out_of_the_folder_are_refused() {
        let dir = std::env::temp_dir().join(format!("chiaro-links-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("model")).unwrap();
        std::fs::write(dir.join("secret.bin"), [1, 2, 3]).unwrap();
        std::fs::write(dir.join("model/own.bin"), [1]).unwrap();
        std::os::unix::fs::symlink(dir.join("secret.bin"), dir.join("model/link.bin")).unwrap();
        let base = dir.join("model");
        let access = FileAccess {
            base: &base,
            allow_outside: false,
        };
        assert!(
            access
                .resolve("link.bin")
                .unwrap_err()
                .contains("through a link")
        );
        assert_eq!(file(access, "own.bin"), base.join("own.bin"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn long_uris_are_quoted_cut() {
        let long = "a".repeat(70_000);
        let quoted = quoted_uri(&long);
        assert!(
            quoted.len() < 120 && quoted.contains("(70000 characters)"),
            "{quoted}"
        );
        assert_eq!(quoted_uri("a.png"), "'a.png'");
        let err = inside(".").resolve(&format!("/{long}")).unwrap_err();
        assert!(err.len() < 300, "{}", err.len());
    }

    #[test]
    fn network_uris_are_refused() {
        let err = inside(".")
            .resolve("https://example.com/a.bin")
            .err()
            .unwrap();
        assert!(err.contains("'https'"), "{err}");
    }

    #[test]
    fn files_that_are_no_gltf_are_refused_from_their_first_bytes() {
        let dir = std::env::temp_dir().join(format!("chiaro-sniff-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // 2 GB of nothing: sparse, so it costs no disk, and it must not be read.
        for name in ["sparse.glb", "sparse.gltf"] {
            let path = dir.join(name);
            std::fs::File::create(&path)
                .unwrap()
                .set_len(2 << 30)
                .unwrap();
            let start = std::time::Instant::now();
            let err = read_model_file(&path).unwrap_err().to_string();
            assert!(err.contains("neither a GLB nor JSON"), "{err}");
            assert!(start.elapsed().as_secs_f32() < 0.5, "{:?}", start.elapsed());
        }
        let glb = |version: u32, length: u32| {
            let mut b = b"glTF".to_vec();
            b.extend(version.to_le_bytes());
            b.extend(length.to_le_bytes());
            b
        };
        assert!(check_model_start(&glb(2, 12), 12).is_ok());
        let lying = check_model_start(&glb(2, 12), 2 << 30).unwrap_err();
        assert!(
            lying.to_string().contains("header says 12 bytes"),
            "{lying}"
        );
        assert!(
            check_model_start(&glb(1, 12), 12)
                .unwrap_err()
                .to_string()
                .contains("version 1")
        );
        assert!(check_model_start(b"\xEF\xBB\xBF  {\"asset\":{}}", 20).is_ok());
        assert!(
            check_model_start(b"", 0)
                .unwrap_err()
                .to_string()
                .contains("empty")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn devices_are_not_read() {
        assert!(read_file(Path::new("/dev/zero")).is_err());
    }
}
