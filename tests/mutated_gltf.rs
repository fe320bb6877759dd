//! Mutation testing of the glTF importer: the shared sample models, each mutated many times at
//! random (a number swapped for an extreme, a key deleted, an array emptied or grown, a value
//! nulled or retyped, binary bytes overwritten or truncated), must each load or fail with an
//! error naming the file, never panic, and within a time bound. The mutants are seeded, so a
//! failure names the seed that reproduces it; `CHIARO_MUTANTS=N` runs N per model (default 40).

mod common;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::time::{Duration, Instant};

use chiaro::scene::load_gltf;
use chiaro::shading::rng::Pcg32;
use serde_json::Value;

/// Slowest load allowed for one mutant (a debug build of the importer).
const TIME_BOUND: Duration = Duration::from_secs(20);

/// Numbers that break naive readers: negative, zero, off-by-one, type limits, huge.
const EXTREMES: [f64; 12] = [
    -1.0,
    0.0,
    1.0,
    3.0,
    255.0,
    65535.0,
    2147483648.0,
    4294967295.0,
    1e20,
    -1e20,
    0.5,
    5126.0,
];

/// A GLB's JSON and binary chunks.
fn split_glb(bytes: &[u8]) -> (Value, Vec<u8>) {
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin_start = 20 + json_len + 8;
    let bin = bytes
        .get(bin_start..)
        .map(<[u8]>::to_vec)
        .unwrap_or_default();
    (json, bin)
}

/// A GLB from a JSON value and a binary chunk (padded as the format asks).
fn join_glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut text = serde_json::to_vec(json).unwrap();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + text.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
    }
    out
}

/// Every JSON pointer in `value`, depth first.
fn pointers(value: &Value, at: String, out: &mut Vec<String>) {
    match value {
        Value::Object(map) => {
            for (k, v) in map {
                let next = format!("{at}/{}", k.replace('~', "~0").replace('/', "~1"));
                out.push(next.clone());
                pointers(v, next, out);
            }
        }
        Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                let next = format!("{at}/{i}");
                out.push(next.clone());
                pointers(v, next, out);
            }
        }
        _ => {}
    }
}

fn pick<T: Clone>(rng: &mut Pcg32, items: &[T]) -> T {
    items[(rng.next_u32() as usize) % items.len()].clone()
}

/// One random structural change to `json`, described.
fn mutate_json(json: &mut Value, rng: &mut Pcg32) -> String {
    let mut all = Vec::new();
    pointers(json, String::new(), &mut all);
    let at = pick(rng, &all);
    let (parent, key) = at.rsplit_once('/').unwrap();
    let target = json.pointer_mut(&at).unwrap();
    match rng.next_u32() % 6 {
        0 | 1 => {
            let n = pick(rng, &EXTREMES);
            *target = serde_json::json!(n);
            format!("{at} = {n}")
        }
        2 => {
            *target = Value::Null;
            format!("{at} = null")
        }
        3 => {
            let was_array = target.is_array();
            *target = if was_array {
                Value::Array(vec![])
            } else {
                Value::String("x".into())
            };
            format!("{at} emptied")
        }
        4 => {
            if let Some(items) = target.as_array_mut()
                && let Some(first) = items.first().cloned()
            {
                items.push(first);
                return format!("{at} grown");
            }
            *target = serde_json::json!([0, 1, 2]);
            format!("{at} = [0, 1, 2]")
        }
        _ => {
            let parent = json.pointer_mut(parent).unwrap();
            match parent {
                Value::Object(map) => {
                    map.remove(&key.replace("~1", "/").replace("~0", "~"));
                    format!("{at} deleted")
                }
                Value::Array(items) => {
                    items.remove(key.parse::<usize>().unwrap());
                    format!("{at} removed")
                }
                _ => unreachable!("a pointer's parent is a container"),
            }
        }
    }
}

/// One random change to the binary chunk, described.
fn mutate_bin(bin: &mut Vec<u8>, rng: &mut Pcg32) -> String {
    if bin.is_empty() {
        return "no binary chunk".into();
    }
    if rng.next_u32().is_multiple_of(3) {
        let keep = (rng.next_u32() as usize) % bin.len();
        bin.truncate(keep);
        return format!("binary truncated to {keep} bytes");
    }
    // Overwrite a run with bytes that decode to NaN, infinity, huge indices or zero.
    let patterns: [[u8; 4]; 4] = [
        f32::NAN.to_le_bytes(),
        f32::INFINITY.to_le_bytes(),
        u32::MAX.to_le_bytes(),
        [0; 4],
    ];
    let pattern = pick(rng, &patterns);
    let start = ((rng.next_u32() as usize) % bin.len()) & !3;
    let len = 4 * (1 + rng.next_u32() as usize % 64);
    for (i, b) in bin.iter_mut().skip(start).take(len).enumerate() {
        *b = pattern[i % 4];
    }
    format!(
        "binary {start}..{} overwritten with {pattern:?}",
        start + len
    )
}

/// Loads the mutant; true when it loaded, false when it was refused with a proper error.
fn check_mutant(path: &Path, bytes: &[u8], what: &str) -> bool {
    std::fs::write(path, bytes).unwrap();
    let start = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(|| load_gltf(path)));
    let elapsed = start.elapsed();
    assert!(
        elapsed < TIME_BOUND,
        "{} took {elapsed:?} ({what})",
        path.display()
    );
    match result {
        Err(_) => panic!("{} panicked ({what})", path.display()),
        Ok(Err(e)) => {
            let message = e.to_string();
            assert!(
                message.contains(&path.display().to_string()),
                "the error does not name the file ({what}): {message}"
            );
            false
        }
        Ok(Ok(_)) => true,
    }
}

#[test]
fn mutated_sample_models_load_or_fail_cleanly() {
    let dir = common::shared_dir("scenes");
    let per_model: u64 = std::env::var("CHIARO_MUTANTS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(40);
    let scratch = std::env::temp_dir().join(format!("chiaro-mutants-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();
    let mut outcomes = [0usize; 2];
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("glb") {
            continue;
        }
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let (json, bin) = split_glb(&std::fs::read(&path).unwrap());
        for seed in 0..per_model {
            let mut rng = Pcg32::new(seed, 0x9e37);
            let (mut json, mut bin) = (json.clone(), bin.clone());
            let mut changes = Vec::new();
            for _ in 0..1 + rng.next_u32() % 3 {
                if rng.next_u32().is_multiple_of(4) {
                    changes.push(mutate_bin(&mut bin, &mut rng));
                } else {
                    changes.push(mutate_json(&mut json, &mut rng));
                }
            }
            let mutant = scratch.join(format!("{stem}-{seed}.glb"));
            let what = format!("seed {seed}: {}", changes.join("; "));
            let loaded = check_mutant(&mutant, &join_glb(&json, &bin), &what);
            outcomes[usize::from(loaded)] += 1;
        }
    }
    eprintln!("{} mutants refused, {} loaded", outcomes[0], outcomes[1]);
    assert!(
        outcomes[0] > 0 && outcomes[1] > 0,
        "mutations should both break and spare files: {outcomes:?}"
    );
}
