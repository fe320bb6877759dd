//! glTF's index and enum fields checked on the raw JSON before the
//! gltf crate reads it: that crate keeps them as u32 and takes a larger number modulo 2^32, so
//! `"camera": 4294967297` would quietly name camera 1. Any such field holding an integer beyond
//! u32 is refused with its JSON path.

use serde_json::Value;

/// Keys whose values are 32-bit integers (or arrays of them) in the gltf crate's model of
/// glTF 2.0 and the extensions chiaro reads: indices and enums. Byte lengths, offsets, strides
/// and counts it keeps in 64 bits, and chiaro checks them against the data.
const INTEGER_KEYS: [&str; 28] = [
    "buffer",
    "bufferView",
    "camera",
    "children",
    "componentType",
    "index",
    "indices",
    "input",
    "inverseBindMatrices",
    "joints",
    "light",
    "magFilter",
    "material",
    "mesh",
    "minFilter",
    "mode",
    "node",
    "nodes",
    "output",
    "sampler",
    "scene",
    "skeleton",
    "skin",
    "source",
    "target",
    "texCoord",
    "wrapS",
    "wrapT",
];

/// Keys whose values are objects (or arrays of objects) mapping names to integers: a
/// primitive's attributes and its morph targets.
const MAP_KEYS: [&str; 2] = ["attributes", "targets"];

/// What a JSON value is to this check.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    /// Anything: numbers in it are not checked.
    Other,
    /// An integer field, or an array of them.
    Integer,
    /// An object of integer fields, or an array of them.
    Map,
}

/// Finds the first integer field beyond u32 in a glTF's JSON, as a message naming its path;
/// `extras` (application data) are not looked into.
pub(crate) fn check_integer_fields(root: &Value) -> Result<(), String> {
    let mut stack: Vec<(String, &Value, Kind)> = vec![(String::new(), root, Kind::Other)];
    while let Some((path, value, kind)) = stack.pop() {
        match value {
            Value::Number(n) if kind == Kind::Integer => {
                let too_large = n.as_u64().is_some_and(|v| v > u64::from(u32::MAX))
                    || n.as_f64().is_some_and(|v| v >= 4294967296.0);
                if too_large {
                    return Err(format!(
                        "{path} is {n}, beyond the largest index or count glTF data can hold \
                         here (4294967295)"
                    ));
                }
            }
            Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    stack.push((format!("{path}[{i}]"), item, kind));
                }
            }
            Value::Object(fields) => {
                for (key, item) in fields {
                    if key == "extras" {
                        continue;
                    }
                    let child = if path.is_empty() {
                        key.clone()
                    } else {
                        format!("{path}.{key}")
                    };
                    let child_kind = if kind == Kind::Map {
                        Kind::Integer
                    } else if MAP_KEYS.contains(&key.as_str()) {
                        Kind::Map
                    } else if INTEGER_KEYS.contains(&key.as_str()) && !item.is_object() {
                        Kind::Integer
                    } else {
                        Kind::Other
                    };
                    stack.push((child, item, child_kind));
                }
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str) -> Result<(), String> {
        check_integer_fields(&serde_json::from_str(text).unwrap())
    }

    #[test]
    fn indices_beyond_u32_are_refused_by_path() {
        let err = check(r#"{"nodes":[{"mesh":0},{"camera":4294967297}]}"#).unwrap_err();
        assert!(err.starts_with("nodes[1].camera is 4294967297"), "{err}");
        let err = check(r#"{"accessors":[{"componentType":4294972422}]}"#).unwrap_err();
        assert!(err.contains("accessors[0].componentType"), "{err}");
        let err = check(r#"{"scenes":[{"nodes":[0, 4294967296]}]}"#).unwrap_err();
        assert!(err.contains("scenes[0].nodes[1]"), "{err}");
        let err =
            check(r#"{"meshes":[{"primitives":[{"attributes":{"POSITION":1e10}}]}]}"#).unwrap_err();
        assert!(err.contains("attributes.POSITION"), "{err}");
        assert!(check(r#"{"scene":4294967296}"#).is_err());
        let err = check(r#"{"meshes":[{"primitives":[{"targets":[{"NORMAL":4294967296}]}]}]}"#)
            .unwrap_err();
        assert!(err.contains("targets[0].NORMAL"), "{err}");
        let err =
            check(r#"{"animations":[{"channels":[{"target":{"node":4294967296}}]}]}"#).unwrap_err();
        assert!(err.contains("channels[0].target.node"), "{err}");
    }

    #[test]
    fn floats_extras_and_u32_values_pass() {
        check(r#"{"nodes":[{"camera":4294967295,"translation":[5e9,0,0]}]}"#).unwrap();
        check(r#"{"nodes":[{"extras":{"mesh":99999999999}}]}"#).unwrap();
        check(r#"{"accessors":[{"min":[-1e30],"max":[1e30]}]}"#).unwrap();
        check(r#"{"animations":[{"channels":[{"target":{"node":0,"path":"weights"}}]}]}"#).unwrap();
    }
}
