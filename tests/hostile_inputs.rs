//! Files made to mislead the importer, one test each: a URI that leaves the model's folder, an
//! index beyond u32, a NaN vertex reached through a sparse accessor, a hierarchy deeper than
//! chiaro follows, a URI of 70,000 characters; and files the specification allows that look
//! unusual (an accessor without a buffer view, a texture whose image only an extension names,
//! an animation channel with a pointer target), which must load.

mod common;

use base64::Engine;
use bevy_ecs::world::World;
use chiaro::scene::{Fault, LoadOptions, SceneInfo, load_scene_with};
use common::hand_made::{QUAD, bytes_of, load, mesh_gltf, scratch, write};
use serde_json::{Value, json};

/// The quad's glTF with its buffer in `name` beside it, referred to by `uri`.
fn external_buffer(test: &str, uri: &str) -> Value {
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    let bytes = bytes_of(&QUAD.concat(), &[0, 1, 2]);
    std::fs::write(scratch(test).join("quad.bin"), &bytes).unwrap();
    gltf["buffers"][0]["uri"] = json!(uri);
    gltf
}

/// Appends `bytes` to the glTF's buffers as a base64 data URI (buffer 1 after mesh_gltf's).
fn add_embedded_buffer(gltf: &mut Value, bytes: &[u8]) {
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    );
    gltf["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({"byteLength": bytes.len(), "uri": uri}));
}

#[test]
fn uris_leaving_the_folder_are_refused_unless_allowed() {
    // The buffer sits one folder up from the model, in the test's scratch folder.
    let dir = scratch("outside");
    std::fs::create_dir_all(dir.join("model")).unwrap();
    let absolute = dir.join("quad.bin").display().to_string();
    for (uri, why) in [
        ("../quad.bin", "through '..'"),
        ("%2E%2E/quad.bin", "through '..'"),
        (absolute.as_str(), "is an absolute path"),
        (&format!("file://{absolute}"), "is a file: URI"),
    ] {
        let gltf = external_buffer("outside", uri);
        let path = dir.join("model/scene.gltf");
        std::fs::write(&path, serde_json::to_vec(&gltf).unwrap()).unwrap();
        let path = path.display().to_string();
        let err = load(&path).1.unwrap_err();
        assert!(matches!(err.fault, Fault::Uri(_)), "{uri}: {err}");
        let text = err.to_string();
        assert!(
            text.starts_with(&format!("{path}: buffer 0: URI")),
            "{text}"
        );
        assert!(
            text.contains(why) && text.contains("--allow-outside-files"),
            "{text}"
        );
        let allowed = LoadOptions {
            allow_outside_files: true,
            ..LoadOptions::default()
        };
        load_scene_with(&mut World::new(), &path, &allowed)
            .unwrap_or_else(|e| panic!("{uri} allowed: {e}"));
    }
}

#[test]
fn files_inside_the_folder_still_load() {
    let path = write(
        "inside",
        "scene.gltf",
        &external_buffer("inside", "quad.bin"),
    );
    let (mut world, result) = load(&path);
    result.unwrap();
    assert_eq!(SceneInfo::gather(&mut world).triangles, 1);
}

#[test]
fn an_index_beyond_u32_is_refused_not_wrapped() {
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    gltf["cameras"] = json!([{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]);
    gltf["nodes"][0]["camera"] = json!(4294967296u64);
    let path = write("wrap", "wrap.gltf", &gltf);
    let err = load(&path).1.unwrap_err().to_string();
    assert!(
        err.contains("nodes[0].camera is 4294967296, beyond the largest index"),
        "{err}"
    );
    gltf["nodes"][0]["camera"] = json!(0);
    gltf["accessors"][0]["componentType"] = json!(4294972422u64);
    let err = load(&write("wrap", "type.gltf", &gltf))
        .1
        .unwrap_err()
        .to_string();
    assert!(err.contains("accessors[0].componentType"), "{err}");
}

#[test]
fn a_nan_vertex_from_a_sparse_accessor_leaves_bounds_and_camera_finite() {
    // Vertex 1 of the quad becomes NaN through a sparse substitution.
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2, 0, 2, 3]);
    add_embedded_buffer(&mut gltf, &bytes_of(&[f32::NAN, f32::INFINITY, 0.0], &[1]));
    let views = gltf["bufferViews"].as_array_mut().unwrap();
    views.push(json!({"buffer": 1, "byteOffset": 0, "byteLength": 12}));
    views.push(json!({"buffer": 1, "byteOffset": 12, "byteLength": 4}));
    gltf["accessors"][0]["sparse"] = json!({
        "count": 1,
        "indices": {"bufferView": 3, "componentType": 5125},
        "values": {"bufferView": 2}
    });
    let (mut world, result) = load(&write("sparse-nan", "nan.gltf", &gltf));
    let spawned = result.unwrap();
    assert!(
        spawned.repairs[0].action.contains("non-finite position"),
        "{:?}",
        spawned.repairs
    );
    let info = SceneInfo::gather(&mut world);
    assert_eq!(info.triangles, 1, "the triangle without vertex 1 is kept");
    assert!(
        info.bounds.min.is_finite() && info.bounds.max.is_finite(),
        "{:?}",
        info.bounds
    );
    let camera = info.camera.expect("an automatic camera");
    assert!(
        camera.position.is_finite() && camera.forward.is_finite(),
        "{camera:?}"
    );
}

#[test]
fn a_hierarchy_deeper_than_followed_is_refused_by_node() {
    let depth = chiaro::scene::transform::MAX_HIERARCHY_DEPTH + 2;
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    let mut nodes: Vec<Value> = (1..depth).map(|i| json!({"children": [i]})).collect();
    nodes.push(json!({"mesh": 0}));
    gltf["nodes"] = Value::Array(nodes);
    let err = load(&write("deep", "deep.gltf", &gltf))
        .1
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(&format!(
            "node {}: is {} levels below",
            depth - 1,
            depth - 1
        )),
        "{err}"
    );
}

#[test]
fn a_long_uri_is_quoted_cut() {
    let long = format!("{}.png", "a".repeat(70_000));
    let err = load(&write(
        "long",
        "long.gltf",
        &external_buffer("long", &format!("/{long}")),
    ))
    .1
    .unwrap_err()
    .to_string();
    assert!(err.len() < 400, "{} characters: {}", err.len(), &err[..400]);
    assert!(err.contains("(70005 characters)"), "{err}");
}

/// The quad with a base colour texture on UV set 0.
fn textured_quad() -> Value {
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2, 0, 2, 3]);
    let uvs = bytes_of(
        &QUAD.iter().flat_map(|p| [p[0], p[1]]).collect::<Vec<_>>(),
        &[],
    );
    add_embedded_buffer(&mut gltf, &uvs);
    gltf["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": 1, "byteLength": uvs.len()}));
    gltf["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}));
    gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(2);
    gltf["meshes"][0]["primitives"][0]["material"] = json!(0);
    gltf["materials"] = json!([{"pbrMetallicRoughness": {
        "baseColorFactor": [0.5, 0.25, 1.0, 1.0], "baseColorTexture": {"index": 0}}}]);
    gltf
}

#[test]
fn a_texture_whose_image_only_an_extension_names_falls_back_to_the_factor() {
    let mut gltf = textured_quad();
    gltf["extensionsUsed"] = json!(["EXT_texture_webp"]);
    gltf["textures"] = json!([{"extensions": {"EXT_texture_webp": {"source": 0}}}]);
    gltf["images"] = json!([{"uri": "texture.webp"}]);
    let (_, result) = load(&write("webp", "webp.gltf", &gltf));
    let spawned = result.expect("valid glTF: a texture's source may come from an extension");
    assert!(
        spawned.repairs[0]
            .action
            .contains("base colour texture 0 has no image chiaro can decode"),
        "{:?}",
        spawned.repairs
    );
}

#[test]
fn an_accessor_without_a_buffer_view_reads_zeros() {
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    gltf["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({"componentType": 5126, "count": 4, "type": "VEC2"}));
    gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(2);
    let (mut world, result) = load(&write("no-view", "zeros.gltf", &gltf));
    result.expect("valid glTF: an accessor without a buffer view holds zeros");
    assert_eq!(SceneInfo::gather(&mut world).triangles, 1);
}

#[test]
fn an_animation_channel_with_a_pointer_target_is_skipped() {
    let mut gltf = mesh_gltf(&QUAD, &[0, 1, 2]);
    gltf["extensionsUsed"] = json!(["KHR_animation_pointer"]);
    gltf["animations"] = json!([{
        "channels": [{"sampler": 0, "target": {"path": "pointer", "extensions": {
            "KHR_animation_pointer": {"pointer": "/nodes/0/translation"}}}}],
        "samplers": [{"input": 1, "output": 1}]
    }]);
    let (_, result) = load(&write("pointer", "pointer.gltf", &gltf));
    let spawned = result.expect("valid glTF: KHR_animation_pointer's channels have no node");
    assert!(
        spawned.repairs[0]
            .action
            .contains("skipped 1 channels that target no node"),
        "{:?}",
        spawned.repairs
    );
}
