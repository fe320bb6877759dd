//! Hand-made corrupt inputs, one test each: every one ends in a clear error naming the file and
//! the element, or loads with a repair that says what was dropped.

mod common;

use std::time::{Duration, Instant};

use chiaro::scene::{Fault, Materials, MeshFault, SceneInfo};
use common::hand_made::{QUAD, load, mesh_gltf, scratch, write};
use serde_json::json;

#[test]
fn nan_vertex_drops_the_triangles_that_use_it() {
    let mut positions = QUAD.to_vec();
    positions.push([f32::NAN, 0.5, 0.0]);
    // serde_json writes NaN as null, so the NaN must go into the binary buffer: it does, via
    // bytes_of. The accessor min/max stay finite.
    let path = write(
        "nan",
        "nan.gltf",
        &mesh_gltf(&positions, &[0, 1, 2, 0, 2, 3, 1, 4, 2]),
    );
    let (mut world, result) = load(&path);
    let spawned = result.expect("a NaN vertex is repaired, not fatal");
    assert_eq!(spawned.repairs.len(), 1, "{:?}", spawned.repairs);
    assert_eq!(spawned.repairs[0].element, "mesh 0 (\"quad\") primitive 0");
    assert_eq!(
        spawned.repairs[0].action,
        "dropped 1 triangles with a non-finite position"
    );
    assert_eq!(SceneInfo::gather(&mut world).triangles, 2);
}

#[test]
fn index_past_the_end_is_refused_by_name() {
    let path = write("oob", "oob.gltf", &mesh_gltf(&QUAD, &[0, 1, 2, 0, 2, 7]));
    let (world, result) = load(&path);
    let err = result.unwrap_err();
    assert!(matches!(
        err.fault,
        Fault::Mesh(MeshFault::IndexOutOfRange {
            index: 7,
            position: 5,
            vertex_count: 4
        })
    ));
    assert_eq!(
        err.to_string(),
        format!(
            "{path}: mesh 0 (\"quad\") primitive 0: index 7 (at position 5) is past the end of 4 vertices"
        )
    );
    assert!(
        world.get_resource::<Materials>().is_none(),
        "a failed load leaves the world untouched"
    );
}

#[test]
fn ten_gigabyte_buffer_in_a_one_kilobyte_file_is_refused_at_once() {
    let dir = scratch("huge");
    std::fs::write(dir.join("small.bin"), vec![0u8; 1024]).unwrap();
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    gltf["buffers"] = json!([{"byteLength": 10_000_000_000u64, "uri": "small.bin"}]);
    let path = write("huge", "huge.gltf", &gltf);
    let start = Instant::now();
    let (_, result) = load(&path);
    assert!(
        start.elapsed() < Duration::from_secs(2),
        "took {:?}",
        start.elapsed()
    );
    let err = result.unwrap_err();
    assert!(
        matches!(
            err.fault,
            Fault::BufferTooShort {
                declared: 10_000_000_000,
                actual: 1024
            }
        ),
        "{err}"
    );
    assert!(
        err.to_string()
            .starts_with(&format!("{path}: buffer 0: declares 10000000000 bytes")),
        "{err}"
    );
}

#[test]
fn cyclic_node_graph_is_refused_by_name() {
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    // 1 -> 2 -> 3 -> 1: every node has one parent, and the chain closes on itself.
    gltf["nodes"] = json!([{"mesh": 0}, {"children": [2]}, {"children": [3]}, {"children": [1]}]);
    let path = write("cycle", "cycle.gltf", &gltf);
    let err = load(&path).1.unwrap_err();
    assert!(matches!(err.fault, Fault::Hierarchy(_)), "{err}");
    let message = err.to_string();
    assert!(message.starts_with(&path), "{message}");
    assert!(
        message.ends_with("is its own ancestor: the node graph has a cycle"),
        "{message}"
    );
}

#[test]
fn missing_texture_loads_warns_and_falls_back_to_the_factor() {
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    gltf["meshes"][0]["primitives"][0]["material"] = json!(0);
    gltf["materials"] = json!([{"name": "painted", "pbrMetallicRoughness": {
        "baseColorFactor": [0.2, 0.4, 0.6, 1.0], "baseColorTexture": {"index": 0}}}]);
    gltf["textures"] = json!([{"source": 0}]);
    gltf["images"] = json!([{"uri": "no-such-texture.png"}]);
    let path = write("missing-texture", "textured.gltf", &gltf);
    let (world, result) = load(&path);
    let spawned = result.expect("a missing texture is not fatal");
    assert_eq!(spawned.repairs.len(), 1, "{:?}", spawned.repairs);
    let repair = &spawned.repairs[0];
    assert_eq!(repair.element, "material 0 (\"painted\")");
    assert!(
        repair.action.contains("no-such-texture.png")
            && repair.action.contains("the factor alone is used"),
        "{repair}"
    );
    let material = world
        .resource::<Materials>()
        .get(chiaro::scene::MaterialId(0))
        .unwrap()
        .clone();
    assert!(material.base_color_texture.is_none());
    assert_eq!(material.base_color, glam::Vec4::new(0.2, 0.4, 0.6, 1.0));
}

#[test]
fn zero_scale_node_is_skipped_with_its_subtree() {
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    gltf["scenes"] = json!([{"nodes": [0, 2]}]);
    gltf["nodes"] = json!([
        {"name": "hidden", "scale": [0.0, 0.0, 0.0], "children": [1]},
        {"mesh": 0},
        {"mesh": 0, "name": "visible"}
    ]);
    let path = write("zero-scale", "zero.gltf", &gltf);
    let (mut world, result) = load(&path);
    let spawned = result.expect("a zero-scale node is skipped, not fatal");
    assert_eq!(spawned.repairs.len(), 1);
    assert_eq!(spawned.repairs[0].element, "node 0 (\"hidden\")");
    assert!(
        spawned.repairs[0]
            .action
            .contains("subtree (2 nodes) are skipped"),
        "{}",
        spawned.repairs[0]
    );
    assert_eq!(SceneInfo::gather(&mut world).instances, 1);
}

#[test]
fn malformed_json_and_missing_files_are_named() {
    let path = scratch("malformed").join("broken.gltf");
    std::fs::write(&path, b"{\"asset\": {\"version\": ").unwrap();
    let err = load(path.to_str().unwrap()).1.unwrap_err();
    assert!(matches!(err.fault, Fault::Gltf(_)));
    assert!(err.to_string().starts_with(path.to_str().unwrap()), "{err}");

    let err = load("/no/such/scene.glb").1.unwrap_err();
    assert!(matches!(err.fault, Fault::Io(_)));
    assert!(
        err.to_string()
            .starts_with("/no/such/scene.glb: cannot read it"),
        "{err}"
    );
}
