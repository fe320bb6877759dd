//! Random, seeded mutations of a GLB for the importer's mutation test: changes to its JSON (a
//! number swapped for an extreme, an index, count, offset or stride made huge or negative, a key
//! deleted, an array emptied or grown, a value nulled or retyped, a node made its own ancestor,
//! a buffer or image URI made malformed or pointed outside the folder, a number written as NaN)
//! and to its bytes (binary data overwritten with NaN, infinity or huge indices, bytes flipped,
//! the file or its binary chunk truncated).

use chiaro::shading::rng::Pcg32;
use serde_json::{Value, json};

/// Numbers that break naive readers: negative, zero, off-by-one, type limits, huge.
const EXTREMES: [f64; 14] = [
    -1.0,
    0.0,
    1.0,
    3.0,
    255.0,
    65535.0,
    2147483648.0,
    4294967295.0,
    4294967297.0,
    1e20,
    -1e20,
    0.5,
    5126.0,
    -2147483649.0,
];

/// Keys of the fields that say where data is and how much: the importer's bounds checks.
const LAYOUT_KEYS: [&str; 14] = [
    "count",
    "byteOffset",
    "byteLength",
    "byteStride",
    "bufferView",
    "buffer",
    "indices",
    "mesh",
    "node",
    "camera",
    "material",
    "componentType",
    "source",
    "index",
];

/// URIs a hostile file may name: malformed data, other schemes, places outside its folder.
const BAD_URIS: [&str; 9] = [
    "data:application/octet-stream;base64,@@@@",
    "data:application/octet-stream;base64,AAA",
    "data:text/plain,plain",
    "../../../../etc/passwd",
    "/etc/passwd",
    "file:///etc/passwd",
    "%2e%2e/%2e%2e/etc/passwd",
    "https://example.com/a.bin",
    "missing-file.bin",
];

/// A GLB's JSON and binary chunks.
pub fn split_glb(bytes: &[u8]) -> (Value, Vec<u8>) {
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin_start = 20 + json_len + 8;
    let bin = bytes
        .get(bin_start..)
        .map(<[u8]>::to_vec)
        .unwrap_or_default();
    (json, bin)
}

/// A GLB from JSON text and a binary chunk (padded as the format asks).
pub fn join_glb(text: &[u8], bin: &[u8]) -> Vec<u8> {
    let mut text = text.to_vec();
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

/// The last key of a JSON pointer.
fn last_key(pointer: &str) -> &str {
    pointer.rsplit_once('/').map_or(pointer, |(_, key)| key)
}

/// One random change to `json`, described.
pub fn mutate_json(json: &mut Value, rng: &mut Pcg32) -> String {
    let mut all = Vec::new();
    pointers(json, String::new(), &mut all);
    let layout: Vec<&String> = all
        .iter()
        .filter(|p| LAYOUT_KEYS.contains(&last_key(p)))
        .collect();
    match rng.next_u32() % 10 {
        0 | 1 if !layout.is_empty() => {
            let at = pick(rng, &layout).clone();
            let n = pick(rng, &EXTREMES);
            *json.pointer_mut(&at).unwrap() = json!(n);
            format!("{at} = {n}")
        }
        2 => make_a_cycle(json, rng),
        3 => bad_uri(json, rng),
        _ => mutate_any(json, &all, rng),
    }
}

/// A structural change anywhere: an extreme number, null, emptied, grown or deleted.
fn mutate_any(json: &mut Value, all: &[String], rng: &mut Pcg32) -> String {
    let at = pick(rng, all);
    let (parent, key) = at.rsplit_once('/').unwrap();
    let target = json.pointer_mut(&at).unwrap();
    match rng.next_u32() % 6 {
        0 | 1 => {
            let n = pick(rng, &EXTREMES);
            *target = json!(n);
            format!("{at} = {n}")
        }
        2 => {
            *target = Value::Null;
            format!("{at} = null")
        }
        3 => {
            *target = if target.is_array() {
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
            *target = json!([0, 1, 2]);
            format!("{at} = [0, 1, 2]")
        }
        _ => match json.pointer_mut(parent).unwrap() {
            Value::Object(map) => {
                map.remove(&key.replace("~1", "/").replace("~0", "~"));
                format!("{at} deleted")
            }
            Value::Array(items) => {
                items.remove(key.parse::<usize>().unwrap());
                format!("{at} removed")
            }
            _ => unreachable!("a pointer's parent is a container"),
        },
    }
}

/// A node made a child of itself or of one of its children.
fn make_a_cycle(json: &mut Value, rng: &mut Pcg32) -> String {
    let Some(nodes) = json.get_mut("nodes").and_then(Value::as_array_mut) else {
        return "no nodes to make a cycle of".into();
    };
    let n = nodes.len();
    let parent = (rng.next_u32() as usize) % n.max(1);
    let Some(node) = nodes.get_mut(parent) else {
        return "no nodes to make a cycle of".into();
    };
    let child = node["children"]
        .as_array()
        .and_then(|c| c.first())
        .and_then(Value::as_u64)
        .map_or(parent, |c| c as usize);
    // The child (or the node itself) lists the node as its own child.
    if let Some(target) = json["nodes"].get_mut(child) {
        let children = target
            .as_object_mut()
            .map(|m| m.entry("children").or_insert(json!([])));
        if let Some(Value::Array(list)) = children {
            list.push(json!(parent));
        }
    }
    format!("node {child} lists its ancestor {parent} as a child")
}

/// A buffer's or image's URI replaced by a hostile one.
fn bad_uri(json: &mut Value, rng: &mut Pcg32) -> String {
    let uri = pick(rng, &BAD_URIS);
    let images = json
        .get("images")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    if images > 0 && rng.next_u32().is_multiple_of(2) {
        let i = (rng.next_u32() as usize) % images;
        let image = &mut json["images"][i];
        if let Some(map) = image.as_object_mut() {
            map.remove("bufferView");
            map.remove("mimeType");
            map.insert("uri".into(), json!(uri));
        }
        return format!("image {i} uri = {uri}");
    }
    if let Some(buffer) = json["buffers"].get_mut(0).and_then(Value::as_object_mut) {
        buffer.insert("uri".into(), json!(uri));
    }
    format!("buffer 0 uri = {uri}")
}

/// The JSON as text, sometimes with a number written as NaN or Infinity (which JSON has no
/// words for).
pub fn json_text(json: &Value, rng: &mut Pcg32) -> (Vec<u8>, Option<String>) {
    let text = serde_json::to_string(json).unwrap();
    if !rng.next_u32().is_multiple_of(12) {
        return (text.into_bytes(), None);
    }
    let word = pick(rng, &["NaN", "Infinity", "-Infinity", "1e999"]);
    match text.find(":0") {
        Some(at) => (
            format!("{}:{word}{}", &text[..at], &text[at + 2..]).into_bytes(),
            Some(format!("a 0 written as {word}")),
        ),
        None => (text.into_bytes(), None),
    }
}

/// One random change to the binary chunk, described.
pub fn mutate_bin(bin: &mut Vec<u8>, rng: &mut Pcg32) -> String {
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

/// One random change to the whole file's bytes: bits flipped, or the file cut short.
pub fn mutate_file(bytes: &mut Vec<u8>, rng: &mut Pcg32) -> String {
    if rng.next_u32().is_multiple_of(2) {
        let keep = (rng.next_u32() as usize) % bytes.len();
        bytes.truncate(keep);
        return format!("file truncated to {keep} bytes");
    }
    let flips = 1 + rng.next_u32() % 8;
    for _ in 0..flips {
        let at = (rng.next_u32() as usize) % bytes.len();
        bytes[at] ^= 1 << (rng.next_u32() % 8);
    }
    format!("{flips} bits flipped")
}
