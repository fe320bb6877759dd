//! Every model in ../shared/scenes imports, and what chiaro holds matches what the file's own
//! JSON declares, counted here from the JSON independently of chiaro's importer.

mod common;

use std::collections::{BTreeMap, BTreeSet};

use bevy_ecs::hierarchy::Children;
use bevy_ecs::world::World;
use chiaro::scene::{ColorSpace, MeshInstance, Meshes, SceneInfo, SourceNode, load_scene};
use serde_json::Value;

/// Counts derived from a glTF's JSON.
#[derive(Debug, Default, PartialEq)]
struct Expected {
    gltf_meshes: usize,
    primitives: usize,
    triangles: usize,
    instances: usize,
    materials: usize,
    textures: usize,
    nodes: usize,
}

fn array(v: &Value) -> &[Value] {
    v.as_array().map_or(&[], Vec::as_slice)
}

fn expected(json: &Value) -> (Expected, BTreeMap<u64, u64>) {
    let scene = json["scene"].as_u64().unwrap_or(0) as usize;
    let mut stack: Vec<u64> = array(&json["scenes"][scene]["nodes"])
        .iter()
        .filter_map(Value::as_u64)
        .collect();
    let mut node_mesh = BTreeMap::new();
    let mut e = Expected::default();
    let mut used_meshes = BTreeSet::new();
    while let Some(n) = stack.pop() {
        e.nodes += 1;
        let node = &json["nodes"][n as usize];
        if let Some(mesh) = node["mesh"].as_u64() {
            used_meshes.insert(mesh);
            node_mesh.insert(n, mesh);
            let copies = match node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]
                .as_object()
            {
                Some(attributes) => {
                    let accessor = attributes.values().next().unwrap().as_u64().unwrap() as usize;
                    json["accessors"][accessor]["count"].as_u64().unwrap() as usize
                }
                None => 1,
            };
            e.instances += copies * array(&json["meshes"][mesh as usize]["primitives"]).len();
        }
        stack.extend(array(&node["children"]).iter().filter_map(Value::as_u64));
    }
    let mut default_material = false;
    for &mesh in &used_meshes {
        e.gltf_meshes += 1;
        for p in array(&json["meshes"][mesh as usize]["primitives"]) {
            e.primitives += 1;
            default_material |= p["material"].is_null();
            let count_of = |accessor: &Value| {
                json["accessors"][accessor.as_u64().unwrap() as usize]["count"]
                    .as_u64()
                    .unwrap()
            };
            let corners = match &p["indices"] {
                Value::Null => count_of(&p["attributes"]["POSITION"]),
                indices => count_of(indices),
            };
            e.triangles += (corners / 3) as usize;
        }
    }
    e.materials = array(&json["materials"]).len() + usize::from(default_material);
    // Textures are decoded once per (image, colour space) that a material slot uses.
    let mut textures = BTreeSet::new();
    for m in array(&json["materials"]) {
        let slots = [
            (
                &m["pbrMetallicRoughness"]["baseColorTexture"],
                ColorSpace::Srgb,
            ),
            (
                &m["pbrMetallicRoughness"]["metallicRoughnessTexture"],
                ColorSpace::Linear,
            ),
            (&m["normalTexture"], ColorSpace::Linear),
            (&m["emissiveTexture"], ColorSpace::Srgb),
        ];
        for (slot, space) in slots {
            if let Some(t) = slot["index"].as_u64() {
                let image = json["textures"][t as usize]["source"].as_u64().unwrap();
                textures.insert((image, space == ColorSpace::Srgb));
            }
        }
    }
    e.textures = textures.len();
    (e, node_mesh)
}

#[test]
fn every_shared_model_imports_with_the_counts_its_json_declares() {
    let dir = common::shared_dir("scenes");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if !matches!(
            path.extension().and_then(|e| e.to_str()),
            Some("glb" | "gltf")
        ) {
            continue;
        }
        let (want, node_mesh) = expected(&common::gltf_json(&std::fs::read(&path).unwrap()));
        let mut world = World::new();
        let spawned = load_scene(&mut world, path.to_str().unwrap())
            .unwrap_or_else(|e| panic!("{} failed to import: {e}", path.display()));
        let info = SceneInfo::gather(&mut world);

        // Group the mesh ids each node draws by the glTF mesh it names: a glTF mesh used by
        // many nodes must give the same stored meshes every time.
        let mut by_gltf_mesh: BTreeMap<u64, BTreeSet<Vec<u32>>> = BTreeMap::new();
        let mut query = world.query::<(&SourceNode, Option<&MeshInstance>, Option<&Children>)>();
        for (source, instance, children) in query.iter(&world) {
            let Some(&mesh) = node_mesh.get(&(source.0 as u64)) else {
                continue;
            };
            let mut ids: Vec<u32> = instance.map(|i| i.mesh.0).into_iter().collect();
            for &child in children.into_iter().flatten() {
                if world.get::<SourceNode>(child).is_none()
                    && let Some(i) = world.get::<MeshInstance>(child)
                {
                    ids.push(i.mesh.0);
                }
            }
            by_gltf_mesh.entry(mesh).or_default().insert(ids);
        }
        assert!(
            by_gltf_mesh.values().all(|sets| sets.len() == 1),
            "{}: a shared mesh was stored twice",
            path.display()
        );

        // Zero-area triangles in the file are dropped, and each drop is reported with its count.
        let dropped: usize = spawned
            .repairs
            .iter()
            .filter_map(|r| {
                r.action
                    .strip_prefix("dropped ")?
                    .split_once(" triangles with zero area")?
                    .0
                    .parse::<usize>()
                    .ok()
            })
            .sum();
        assert!(
            dropped * 1000 <= want.triangles,
            "{}: {dropped} triangles dropped",
            path.display()
        );
        let got = Expected {
            gltf_meshes: by_gltf_mesh.len(),
            primitives: world.resource::<Meshes>().len(),
            triangles: info.mesh_triangles + dropped,
            instances: info.instances,
            materials: info.materials.len(),
            textures: info.textures,
            nodes: world.query::<&SourceNode>().iter(&world).count(),
        };
        assert_eq!(got, want, "{}", path.display());
        let other: Vec<_> = spawned
            .repairs
            .iter()
            .filter(|r| !r.action.contains("with zero area"))
            .collect();
        assert!(
            other.is_empty(),
            "{}: unexpected repairs {other:?}",
            path.display()
        );
        checked += 1;
    }
    assert_eq!(
        checked,
        5,
        "expected the five sample models in {}",
        dir.display()
    );
}

#[test]
fn every_shared_model_reports_the_material_features_its_json_declares() {
    let dir = common::shared_dir("scenes");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if !matches!(
            path.extension().and_then(|e| e.to_str()),
            Some("glb" | "gltf")
        ) {
            continue;
        }
        let json = common::gltf_json(&std::fs::read(&path).unwrap());
        let materials = array(&json["materials"]);
        let any = |f: &dyn Fn(&Value) -> bool| materials.iter().any(f);
        let mut world = World::new();
        load_scene(&mut world, path.to_str().unwrap()).unwrap();
        let features = SceneInfo::gather(&mut world).features;
        let name = path.display();
        assert_eq!(
            features.normal_maps,
            any(&|m| m.get("normalTexture").is_some()),
            "{name}"
        );
        assert_eq!(
            features.base_color_textures,
            any(&|m| m["pbrMetallicRoughness"].get("baseColorTexture").is_some()),
            "{name}"
        );
        assert_eq!(
            features.metallic_roughness_textures,
            any(&|m| m["pbrMetallicRoughness"]
                .get("metallicRoughnessTexture")
                .is_some()),
            "{name}"
        );
        assert_eq!(
            features.alpha_masks,
            any(&|m| m["alphaMode"] == "MASK"),
            "{name}"
        );
        assert_eq!(
            features.double_sided,
            any(&|m| m["doubleSided"] == true),
            "{name}"
        );
        checked += 1;
    }
    assert!(checked >= 3, "only {checked} models in {}", dir.display());
}
