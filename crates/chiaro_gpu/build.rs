//! Writes the table of every WGSL file under the workspace's `shaders/` directory, each
//! embedded with `include_str!` by its path from the crate's manifest directory, for
//! `src/shaders.rs`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn collect(dir: &Path, root: &Path, out: &mut Vec<(String, PathBuf)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            collect(&path, root, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            let name = path
                .strip_prefix(root)
                .expect("under shaders/")
                .to_string_lossy()
                .replace('\\', "/");
            out.push((name, path));
        }
    }
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let root = manifest.join("../../shaders");
    let root = root.canonicalize().expect("the workspace has shaders/");
    println!("cargo::rerun-if-changed={}", root.display());
    let mut files = Vec::new();
    collect(&root, &root, &mut files);
    let mut table = String::from("&[\n");
    for (name, path) in &files {
        if let Some(dir) = path.parent() {
            println!("cargo::rerun-if-changed={}", dir.display());
        }
        println!("cargo::rerun-if-changed={}", path.display());
        // The path from the compiling crate's own manifest, not this run's absolute one: a
        // target directory shared by two checkouts may keep this table from the other one.
        writeln!(
            table,
            "    ({name:?}, include_str!(concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/../../shaders/{name}\"))),"
        )
        .unwrap();
    }
    table.push(']');
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it"));
    std::fs::write(out.join("shader_table.rs"), table).expect("OUT_DIR is writable");
}
