//! Hand-made glTF files for the import tests: a quad mesh in an embedded buffer, written into a
//! scratch folder of the test's own.

use std::path::PathBuf;

use base64::Engine;
use bevy_ecs::world::World;
use chiaro::scene::{SceneError, SpawnedScene, load_scene};
use serde_json::{Value, json};

/// A scratch folder for one test's files.
pub fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("chiaro-corrupt-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Little-endian bytes of `floats` then `ints`.
pub fn bytes_of(floats: &[f32], ints: &[u32]) -> Vec<u8> {
    floats
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .chain(ints.iter().flat_map(|i| i.to_le_bytes()))
        .collect()
}

/// A glTF with one mesh of `positions` and `indices` in an embedded buffer, drawn by node 0.
pub fn mesh_gltf(positions: &[[f32; 3]], indices: &[u32]) -> Value {
    let floats: Vec<f32> = positions.iter().flatten().copied().collect();
    let data = bytes_of(&floats, indices);
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&data)
    );
    let pos_len = floats.len() * 4;
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "holder"}],
        "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": data.len(), "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": pos_len},
            {"buffer": 0, "byteOffset": pos_len, "byteLength": indices.len() * 4}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": positions.len(), "type": "VEC3",
             "min": [-1.0, -1.0, -1.0], "max": [1.0, 1.0, 1.0]},
            {"bufferView": 1, "componentType": 5125, "count": indices.len(), "type": "SCALAR"}
        ]
    })
}

/// A unit quad's corners, counter-clockwise.
pub const QUAD: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// Writes `json` as `name` in the test's scratch folder; its path.
pub fn write(test: &str, name: &str, json: &Value) -> String {
    let path = scratch(test).join(name);
    std::fs::write(&path, serde_json::to_vec_pretty(json).unwrap()).unwrap();
    path.display().to_string()
}

/// Loads `path` into a new World.
pub fn load(path: &str) -> (World, Result<SpawnedScene, SceneError>) {
    let mut world = World::new();
    let result = load_scene(&mut world, path);
    (world, result)
}

/// An embedded buffer built view by view, with one accessor per view: for hand-made files of
/// several attributes and meshes.
#[derive(Default)]
pub struct EmbeddedBuffer {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl EmbeddedBuffer {
    /// Appends `data` as a view (4-byte aligned) with an accessor of `count` elements of type
    /// `kind` ("VEC3", ...) and component type `component` (5126 float, 5121 unsigned byte, ...),
    /// `normalized` or not; returns the accessor's index.
    pub fn add(
        &mut self,
        data: &[u8],
        count: usize,
        kind: &str,
        component: u32,
        normalized: bool,
    ) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": data.len()}));
        self.bytes.extend_from_slice(data);
        let mut accessor = json!({"bufferView": self.views.len() - 1, "componentType": component,
            "count": count, "type": kind});
        if normalized {
            accessor["normalized"] = json!(true);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Appends float positions (with the bounds glTF requires); their accessor's index.
    pub fn positions(&mut self, positions: &[[f32; 3]]) -> usize {
        let floats: Vec<f32> = positions.iter().flatten().copied().collect();
        let index = self.add(
            &bytes_of(&floats, &[]),
            positions.len(),
            "VEC3",
            5126,
            false,
        );
        let bound = |pick: fn(f32, f32) -> f32| {
            (0..3)
                .map(|k| positions.iter().map(|p| p[k]).reduce(pick).unwrap())
                .collect::<Vec<_>>()
        };
        self.accessors[index]["min"] = json!(bound(f32::min));
        self.accessors[index]["max"] = json!(bound(f32::max));
        index
    }

    /// Appends unsigned int indices; their accessor's index.
    pub fn indices(&mut self, indices: &[u32]) -> usize {
        self.add(
            &bytes_of(&[], indices),
            indices.len(),
            "SCALAR",
            5125,
            false,
        )
    }

    /// Sets `gltf`'s buffers, views and accessors to these.
    pub fn finish(self, gltf: &mut Value) {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bytes)
        );
        gltf["buffers"] = json!([{"byteLength": self.bytes.len(), "uri": uri}]);
        gltf["bufferViews"] = Value::Array(self.views);
        gltf["accessors"] = Value::Array(self.accessors);
    }
}
