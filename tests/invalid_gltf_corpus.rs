//! The Khronos glTF validator's test corpus (../shared/gltf-invalid/data, 263 files, each with the
//! validator's report): every file must end in Ok or in an error naming the file, within a time
//! bound, without a panic. Where the validator found errors in what chiaro reads, Ok is allowed
//! only for the files listed in `SAFE_AFTER_REPAIR`, each with the reason, and for files that
//! load with nothing to draw and say so (their faulty meshes are in no scene, or every triangle
//! was dropped with a warning): nothing of the fault reaches a render.

mod common;

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use bevy_ecs::world::World;
use chiaro::scene::load_scene;

/// Wall-clock bound per file (debug build, one core).
const PER_FILE: Duration = Duration::from_secs(10);

/// Report pointers whose errors touch what chiaro reads.
const READ_BY_CHIARO: [&str; 13] = [
    "/buffers",
    "/bufferViews",
    "/accessors",
    "/meshes",
    "/nodes",
    "/materials",
    "/textures",
    "/images",
    "/samplers",
    "/cameras",
    "/scene",
    "/skins",
    "/extensionsRequired",
];

/// Files the validator reports errors in (touching what chiaro reads) that chiaro loads, and why
/// the result is safe.
const SAFE_AFTER_REPAIR: &[(&str, &str)] = &[
    (
        "accessor/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "buffer/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "buffer_view/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "camera/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "image/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "material/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "mesh/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "node/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "sampler/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "scene/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "texture/empty_array.gltf",
        "an empty array declares no elements: nothing is read",
    ),
    (
        "node/empty_children_array.gltf",
        "an empty children array means no children",
    ),
    (
        "scene/empty_nodes_array.gltf",
        "a scene with no nodes loads as an empty scene, with a warning",
    ),
    (
        "accessor_data/invalid_elements_float.gltf",
        "the non-finite accessor is used by no mesh; in a mesh, triangles with non-finite positions are dropped and counted",
    ),
    (
        "accessor_data/out_of_range_elements_float.gltf",
        "data outside the declared min/max: chiaro never trusts min/max, bounds come from the data",
    ),
    (
        "accessor_data/out_of_range_elements_sint16.gltf",
        "data outside the declared min/max: chiaro never trusts min/max, bounds come from the data",
    ),
    (
        "accessor_data/out_of_range_elements_sint8.gltf",
        "data outside the declared min/max: chiaro never trusts min/max, bounds come from the data",
    ),
    (
        "accessor_data/out_of_range_elements_uint16.gltf",
        "data outside the declared min/max: chiaro never trusts min/max, bounds come from the data",
    ),
    (
        "accessor_data/out_of_range_elements_uint32.gltf",
        "data outside the declared min/max: chiaro never trusts min/max, bounds come from the data",
    ),
    (
        "accessor_data/out_of_range_elements_uint8.gltf",
        "data outside the declared min/max: chiaro never trusts min/max, bounds come from the data",
    ),
    (
        "buffer/invalid_uri_data.gltf",
        "the data URI's media type is malformed but its base64 payload decodes to the declared length",
    ),
    (
        "buffer/invalid_uri_data_mime.gltf",
        "the data URI's media type is unusual but its base64 payload decodes to the declared length",
    ),
    (
        "buffer_view/invalid_stride_too_big.gltf",
        "a stride longer than the view: every accessor read checks each element's range, and this view is unused",
    ),
    (
        "image/empty_object.gltf",
        "an image with no source is used by no material; one that were would fall back to the factor with a warning",
    ),
    (
        "image/invalid_data_uri.gltf",
        "unreadable image: the material slot falls back to its factor, with a warning",
    ),
    (
        "image/invalid_data_uri_mime_type.gltf",
        "unreadable image: the material slot falls back to its factor, with a warning",
    ),
    (
        "image/invalid_image_data.gltf",
        "undecodable image: the material slot falls back to its factor, with a warning",
    ),
    (
        "image/invalid_uri_scheme.gltf",
        "unsupported URI scheme, never fetched: the slot falls back to its factor, with a warning",
    ),
    (
        "image/not_found.gltf",
        "missing image file: the slot falls back to its factor, with a warning",
    ),
    (
        "image/png_eos.gltf",
        "truncated PNG: the slot falls back to its factor, with a warning",
    ),
    (
        "node/matrix_indecomposable.gltf",
        "a matrix with shear is approximated by its scale-rotation-translation part, with a warning",
    ),
    (
        "node/matrix_trs.gltf",
        "a node with both matrix and TRS: the matrix is used, as the gltf crate reads it",
    ),
    (
        "node/rotation_non_unit.gltf",
        "a non-unit rotation is normalised, with a warning",
    ),
    (
        "node/skin_with_no_mesh.gltf",
        "a skin on a node without a mesh poses nothing: the node is a plain transform",
    ),
    (
        "node/weights_with_no_mesh.gltf",
        "morph weights are not read: the node is a plain transform",
    ),
];

fn corpus_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("gltf" | "glb")
            ) {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The validator's errors (severity 0) that point into what chiaro reads.
fn relevant_errors(report: &serde_json::Value) -> Vec<String> {
    report["issues"]["messages"]
        .as_array()
        .into_iter()
        .flatten()
        .filter(|m| m["severity"] == 0)
        .filter(|m| {
            let pointer = m["pointer"].as_str().unwrap_or("");
            pointer.is_empty() || READ_BY_CHIARO.iter().any(|p| pointer.starts_with(p))
        })
        .map(|m| format!("{} at {}", m["code"], m["pointer"]))
        .collect()
}

enum Outcome {
    /// Loaded; true when the scene has nothing to draw and the import report says so.
    Loaded(bool),
    Refused(String),
    Panicked,
    TimedOut,
}

fn load_with_timeout(path: &Path) -> (Outcome, Duration) {
    let (tx, rx) = mpsc::channel();
    let spec = path.display().to_string();
    let start = Instant::now();
    std::thread::spawn(move || {
        let result = std::panic::catch_unwind(|| {
            let mut world = World::new();
            load_scene(&mut world, &spec)
                .map(|spawned| {
                    spawned
                        .repairs
                        .iter()
                        .any(|r| r.action == "has no triangles to render")
                })
                .map_err(|e| e.to_string())
        });
        let _ = tx.send(result);
    });
    let outcome = match rx.recv_timeout(PER_FILE) {
        Ok(Ok(Ok(empty))) => Outcome::Loaded(empty),
        Ok(Ok(Err(message))) => Outcome::Refused(message),
        Ok(Err(_)) => Outcome::Panicked,
        Err(_) => Outcome::TimedOut,
    };
    (outcome, start.elapsed())
}

#[test]
fn every_corpus_file_loads_or_is_refused_by_name() {
    let dir = common::shared_dir("gltf-invalid/data");
    let files = corpus_files(&dir);
    assert_eq!(files.len(), 263, "the corpus should hold 263 files");
    let mut failures = Vec::new();
    let (mut loaded, mut refused) = (0, 0);
    for path in &files {
        let name = path.strip_prefix(&dir).unwrap().display().to_string();
        let report_path = PathBuf::from(format!("{}.report.json", path.display()));
        let report: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&report_path).unwrap()).unwrap();
        let errors = relevant_errors(&report);
        let (outcome, took) = load_with_timeout(path);
        match outcome {
            Outcome::Panicked => failures.push(format!("{name}: panicked")),
            Outcome::TimedOut => failures.push(format!("{name}: no answer within {PER_FILE:?}")),
            Outcome::Refused(message) => {
                refused += 1;
                if !message.starts_with(&path.display().to_string()) {
                    failures.push(format!("{name}: error does not name the file: {message}"));
                }
            }
            Outcome::Loaded(empty) => {
                loaded += 1;
                let listed = SAFE_AFTER_REPAIR.iter().any(|(f, _)| *f == name);
                if !errors.is_empty() && !listed && !empty {
                    failures.push(format!(
                        "{name}: loaded despite validator errors {errors:?}"
                    ));
                }
                if errors.is_empty() && listed {
                    failures.push(format!(
                        "{name}: listed as repaired but the validator reports no error"
                    ));
                }
            }
        }
        if took > PER_FILE {
            failures.push(format!("{name}: took {took:?}"));
        }
    }
    println!("{loaded} loaded, {refused} refused");
    assert!(
        failures.is_empty(),
        "{} problems:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
