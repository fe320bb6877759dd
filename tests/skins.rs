//! Skinned meshes are posed by their skin at load: a two-joint glTF written here, its vertices
//! skinned by hand; every fault in a skin's data refused by name; and the shared rigged samples
//! (RiggedSimple, CesiumMan) posed away from their unskinned placement.

mod common;

use base64::Engine;
use bevy_ecs::prelude::*;
use bevy_ecs::system::RunSystemOnce;
use chiaro::scene::{
    GlobalTransform, MeshInstance, Meshes, Name, SceneInfo, Skinned, load_scene,
    propagate_transforms,
};
use common::hand_made::{load, write};
use glam::{Mat4, Quat, Vec3};
use serde_json::{Value, json};

/// Vertices of the hand-made mesh: a strip up +Y, the top two vertices on joint 1, the bottom
/// two on joint 0, one in the middle on both.
const POSITIONS: [[f32; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 2.0, 0.0],
    [1.0, 2.0, 0.0],
    [0.5, 1.0, 0.0],
];
/// (joint, weight) pairs of each vertex.
const INFLUENCES: [[(u8, f32); 2]; 5] = [
    [(0, 1.0), (0, 0.0)],
    [(0, 1.0), (0, 0.0)],
    [(1, 1.0), (0, 0.0)],
    [(1, 1.0), (0, 0.0)],
    [(0, 0.5), (1, 0.5)],
];
const INDICES: [u16; 9] = [0, 1, 4, 1, 3, 4, 4, 3, 2];

/// Joint 1's pose: at (0, 1, 0) (where it was bound), turned 90 degrees about +Z.
fn bent() -> Mat4 {
    Mat4::from_rotation_translation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2), Vec3::Y)
}

/// The skinned glTF: node 0 holds the mesh and the skin, with a translation the specification
/// says to ignore; node 1 is joint 0 at the origin, node 2 (its child) joint 1.
fn skinned_gltf(joints: &[[u8; 4]], weights: &[[f32; 4]], inverse_binds: &[Mat4]) -> Value {
    let mut data = Vec::new();
    let mut view = |bytes: Vec<u8>| {
        while !data.len().is_multiple_of(4) {
            data.push(0);
        }
        let (offset, length) = (data.len(), bytes.len());
        data.extend(bytes);
        json!({"buffer": 0, "byteOffset": offset, "byteLength": length})
    };
    let floats = |f: &[f32]| f.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let views = vec![
        view(floats(POSITIONS.as_flattened())),
        view(floats(&[0.0, 0.0, 1.0].repeat(POSITIONS.len()))),
        view(joints.as_flattened().to_vec()),
        view(floats(weights.as_flattened())),
        view(INDICES.iter().flat_map(|i| i.to_le_bytes()).collect()),
        view(floats(
            &inverse_binds
                .iter()
                .flat_map(|m| m.to_cols_array())
                .collect::<Vec<f32>>(),
        )),
    ];
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&data)
    );
    let q = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2).to_array();
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "skinned", "mesh": 0, "skin": 0, "translation": [10.0, 0.0, 0.0]},
            {"name": "root joint", "children": [2]},
            {"name": "bent joint", "translation": [0.0, 1.0, 0.0], "rotation": q}
        ],
        "skins": [{"joints": [1, 2], "inverseBindMatrices": 5}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "JOINTS_0": 2, "WEIGHTS_0": 3},
            "indices": 4
        }]}],
        "buffers": [{"byteLength": data.len(), "uri": uri}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": POSITIONS.len(), "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [1.0, 2.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": POSITIONS.len(), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5121, "count": joints.len(), "type": "VEC4"},
            {"bufferView": 3, "componentType": 5126, "count": weights.len(), "type": "VEC4"},
            {"bufferView": 4, "componentType": 5123, "count": INDICES.len(), "type": "SCALAR"},
            {"bufferView": 5, "componentType": 5126, "count": inverse_binds.len(), "type": "MAT4"}
        ]
    })
}

fn influences() -> (Vec<[u8; 4]>, Vec<[f32; 4]>) {
    INFLUENCES
        .iter()
        .map(|[(j0, w0), (j1, w1)]| ([*j0, *j1, 0, 0], [*w0, *w1, 0.0, 0.0]))
        .unzip()
}

/// The bind-time inverse matrices: joint 0 at the origin, joint 1 at (0, 1, 0).
fn inverse_binds() -> Vec<Mat4> {
    vec![Mat4::IDENTITY, Mat4::from_translation(Vec3::NEG_Y)]
}

/// World positions of the vertices of the instance on node `name`.
fn world_positions(world: &mut World, name: &str) -> Vec<Vec3> {
    world.run_system_once(propagate_transforms).unwrap();
    let mut query = world.query::<(&Name, &MeshInstance, &GlobalTransform)>();
    let (_, instance, global) = query
        .iter(world)
        .find(|(n, _, _)| n.as_str() == name)
        .unwrap_or_else(|| panic!("no instance named {name}"));
    let (instance, global) = (*instance, *global);
    let mesh = world.resource::<Meshes>().get(instance.mesh).unwrap();
    mesh.positions()
        .iter()
        .map(|p| global.transform_point(*p))
        .collect()
}

/// Positions skinned by hand: world(joint) * inverseBind(joint) * position, blended by weight.
fn skinned_by_hand(inverse_binds: &[Mat4]) -> Vec<Vec3> {
    skinned_by_hand_with(inverse_binds, bent())
}

/// The same with joint 1 at `joint_1` (its world matrix).
fn skinned_by_hand_with(inverse_binds: &[Mat4], joint_1: Mat4) -> Vec<Vec3> {
    let joints = [Mat4::IDENTITY, joint_1];
    POSITIONS
        .iter()
        .zip(INFLUENCES)
        .map(|(p, influences)| {
            influences
                .iter()
                .map(|&(j, w)| {
                    (joints[j as usize] * inverse_binds[j as usize])
                        .transform_point3(Vec3::from(*p))
                        * w
                })
                .sum()
        })
        .collect()
}

#[test]
fn a_two_joint_skin_poses_the_mesh_as_skinned_by_hand() {
    let (joints, weights) = influences();
    let path = write(
        "skin",
        "two_joints.gltf",
        &skinned_gltf(&joints, &weights, &inverse_binds()),
    );
    let (mut world, result) = load(&path);
    let spawned = result.unwrap();
    assert!(spawned.repairs.is_empty(), "{:?}", spawned.repairs);
    let posed = world_positions(&mut world, "skinned");
    let expected = skinned_by_hand(&inverse_binds());
    // By hand: the top corners turned about (0, 1, 0) to x = -1; the middle vertex halfway.
    assert!(expected[2].abs_diff_eq(Vec3::new(-1.0, 1.0, 0.0), 1e-6));
    assert!(expected[3].abs_diff_eq(Vec3::new(-1.0, 2.0, 0.0), 1e-6));
    assert!(expected[4].abs_diff_eq(Vec3::new(0.25, 1.25, 0.0), 1e-6));
    assert_eq!(posed.len(), expected.len());
    for (v, (got, want)) in posed.iter().zip(&expected).enumerate() {
        assert!(
            got.abs_diff_eq(*want, 1e-5),
            "vertex {v}: {got} where {want}"
        );
    }
    let info = SceneInfo::gather(&mut world);
    assert_eq!(info.skinned_instances, 1);
    assert_eq!(info.skins.values().copied().collect::<Vec<_>>(), vec![2]);
    let text = info.to_string();
    assert!(
        text.contains("skinned: 1 instance posed at load by 1 skin (joints: 2)"),
        "{text}"
    );
}

/// The skin follows its joints: turning the bent joint the other way (an edit of its
/// Transform, as an animation makes) re-poses the mesh as skinning by hand does, through the
/// skinning system; an edit elsewhere leaves the mesh alone.
#[test]
fn a_skinned_mesh_follows_its_joints_as_they_move() {
    let (joints, weights) = influences();
    let path = write(
        "skin",
        "follows.gltf",
        &skinned_gltf(&joints, &weights, &inverse_binds()),
    );
    let (mut world, result) = load(&path);
    result.unwrap();
    let mut schedule = Schedule::default();
    schedule.add_systems(
        (
            propagate_transforms,
            chiaro::scene::deformation::deform_meshes,
        )
            .chain(),
    );
    schedule.run(&mut world);
    // Nothing moved: the mesh store is not even touched.
    world.clear_trackers();
    schedule.run(&mut world);
    assert!(!world.is_resource_changed::<Meshes>());
    let before = world_positions(&mut world, "skinned");
    let turn_back = Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2);
    let mut joint = world.query::<(&Name, &mut chiaro::scene::Transform)>();
    for (name, mut t) in joint.iter_mut(&mut world) {
        if name.as_str() == "bent joint" {
            t.rotation = turn_back;
        }
    }
    world.clear_trackers();
    schedule.run(&mut world);
    assert!(world.is_resource_changed::<Meshes>());
    let posed = world_positions(&mut world, "skinned");
    let expected = skinned_by_hand_with(
        &inverse_binds(),
        Mat4::from_rotation_translation(turn_back, Vec3::Y),
    );
    // By hand: the top corners turned the other way about (0, 1, 0), to x = +1.
    assert!(expected[2].abs_diff_eq(Vec3::new(1.0, 1.0, 0.0), 1e-6));
    assert!(expected[3].abs_diff_eq(Vec3::new(1.0, 0.0, 0.0), 1e-6));
    for (v, (got, want)) in posed.iter().zip(&expected).enumerate() {
        assert!(
            got.abs_diff_eq(*want, 1e-5),
            "vertex {v}: {got} where {want}"
        );
    }
    assert_ne!(posed, before);
}

#[test]
fn a_skin_without_inverse_bind_matrices_uses_the_identity() {
    let (joints, weights) = influences();
    let mut json = skinned_gltf(&joints, &weights, &inverse_binds());
    json["skins"][0]
        .as_object_mut()
        .unwrap()
        .remove("inverseBindMatrices");
    let path = write("skin", "no_ibm.gltf", &json);
    let (mut world, result) = load(&path);
    result.unwrap();
    let posed = world_positions(&mut world, "skinned");
    let expected = skinned_by_hand(&[Mat4::IDENTITY, Mat4::IDENTITY]);
    for (v, (got, want)) in posed.iter().zip(&expected).enumerate() {
        assert!(
            got.abs_diff_eq(*want, 1e-5),
            "vertex {v}: {got} where {want}"
        );
    }
    // Without the inverse bind, joint 1's vertices move up by its translation as well.
    assert!(
        posed[2].abs_diff_eq(Vec3::new(-2.0, 1.0, 0.0), 1e-5),
        "{}",
        posed[2]
    );
}

#[test]
fn bad_skin_data_is_refused_naming_the_file_and_the_fault() {
    let (joints, weights) = influences();
    let refused = |name: &str, json: &Value, words: &str| {
        let path = write("skin", name, json);
        let err = load(&path).1.unwrap_err().to_string();
        assert!(
            err.starts_with(&path) && err.contains(words),
            "{name}: {err}"
        );
    };
    let mut far = joints.clone();
    far[3][0] = 2;
    refused(
        "joint_out_of_range.gltf",
        &skinned_gltf(&far, &weights, &inverse_binds()),
        "vertex 3 names joint 2, but skin 0 has 2 joints",
    );
    let mut nan = weights.clone();
    nan[1][0] = f32::NAN;
    refused(
        "nan_weight.gltf",
        &skinned_gltf(&joints, &nan, &inverse_binds()),
        "WEIGHTS_0 of vertex 1 holds NaN",
    );
    let mut none = weights.clone();
    none[0] = [0.0; 4];
    refused(
        "zero_weights.gltf",
        &skinned_gltf(&joints, &none, &inverse_binds()),
        "the weights of vertex 0 sum to 0",
    );
    refused(
        "short_joints.gltf",
        &skinned_gltf(&joints[..4], &weights[..4], &inverse_binds()),
        "JOINTS_0 has 4 elements but there are 5 positions",
    );
    refused(
        "one_ibm.gltf",
        &skinned_gltf(&joints, &weights, &inverse_binds()[..1]),
        "has 2 joints but its inverse bind matrices (accessor 5) hold 1",
    );
    let mut infinite = inverse_binds();
    infinite[1].w_axis.x = f32::INFINITY;
    refused(
        "infinite_ibm.gltf",
        &skinned_gltf(&joints, &weights, &infinite),
        "inverse bind matrix 1 is not finite",
    );
    let mut float_joints = skinned_gltf(&joints, &weights, &inverse_binds());
    float_joints["accessors"][2]["componentType"] = json!(5126);
    float_joints["accessors"][2]["count"] = json!(1);
    refused("float_joints.gltf", &float_joints, "U8 or U16");
}

/// `glb` with its JSON chunk replaced by `json` (the binary chunk kept).
fn repacked_glb(glb: &[u8], json: &Value) -> Vec<u8> {
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let rest = &glb[20 + json_len..];
    let mut text = serde_json::to_vec(json).unwrap();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + rest.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(text);
    out.extend(rest);
    out
}

/// The local bounds (min, max) of the first skinned instance's mesh in `path`, and the skin's
/// joint count.
fn posed_bounds(path: &std::path::Path) -> ((Vec3, Vec3), u32) {
    let mut world = World::new();
    load_scene(&mut world, path.to_str().unwrap()).unwrap();
    let mut query = world.query::<(&MeshInstance, &Skinned)>();
    let (instance, skinned) = query.iter(&world).next().expect("a skinned instance");
    let (instance, skinned) = (*instance, *skinned);
    let bounds = world
        .resource::<Meshes>()
        .get(instance.mesh)
        .unwrap()
        .bounds();
    ((bounds.min, bounds.max), skinned.joints)
}

/// The shared rigged samples (RiggedSimple, CesiumMan) as their files pose them: their node
/// transforms are the bind pose, so posing gives back the stored vertices' bounds (which it
/// would not if the joint matrices missed the inverse bind matrices or the inverse of the mesh
/// node's world, which rotates both models upright). With one joint turned a quarter turn (the
/// file's JSON edited), the posed bounds move away from the stored ones.
#[test]
fn shared_rigged_samples_are_posed_by_their_skins() {
    let dir = common::shared_dir("scenes/animated");
    let scratch = common::hand_made::scratch("skin-samples");
    for (file, joints) in [("RiggedSimple.glb", 2), ("CesiumMan.glb", 19)] {
        let path = dir.join(file);
        let glb = std::fs::read(&path).unwrap();
        let mut json = common::gltf_json(&glb);
        let accessor = json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
            .as_u64()
            .unwrap() as usize;
        let corner = |key: &str| {
            let v: Vec<f32> = json["accessors"][accessor][key]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap() as f32)
                .collect();
            Vec3::from_slice(&v)
        };
        let stored = (corner("min"), corner("max"));
        let size = (stored.1 - stored.0).length();
        let off = |posed: (Vec3, Vec3)| {
            (posed.0 - stored.0)
                .length()
                .max((posed.1 - stored.1).length())
                / size
        };

        let (rest, joint_count) = posed_bounds(&path);
        assert_eq!(joint_count, joints, "{file}");
        eprintln!("{file}: rest pose {rest:?}, stored {stored:?}");
        assert!(
            off(rest) < 1e-4,
            "{file}: the rest pose moved the bounds by {}",
            off(rest)
        );

        let joint = json["skins"][0]["joints"][1].as_u64().unwrap() as usize;
        let node = &mut json["nodes"][joint];
        assert!(
            node.get("matrix").is_none(),
            "{file}: joint {joint} has a matrix"
        );
        let old = node["rotation"].as_array().map_or(Quat::IDENTITY, |q| {
            let q: Vec<f32> = q.iter().map(|x| x.as_f64().unwrap() as f32).collect();
            Quat::from_slice(&q)
        });
        let turned = old * Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
        node["rotation"] = json!(turned.to_array());
        let bent_path = scratch.join(file);
        std::fs::write(&bent_path, repacked_glb(&glb, &json)).unwrap();
        let (bent, _) = posed_bounds(&bent_path);
        eprintln!(
            "{file}: joint node {joint} turned: {bent:?}, {:.3} of the size off",
            off(bent)
        );
        assert!(off(bent) > 0.05, "{file}: turning a joint left the bounds");
    }
}
