//! glTF node animations: a file written by the test with a linear translation, a stepped
//! rotation and a cubic-spline scale, posed at given times against values computed by hand;
//! channels chiaro cannot play are left out with a repair line while the rest plays; and the
//! GPU frame follows the time (`--time` poses the scene, `--animate` advances it).

mod common;

use base64::Engine;
use bevy_ecs::world::World;
use chiaro::scene::{Animations, Name, SceneInfo, Transform, load_scene, pose_at};
use glam::{Quat, Vec3};
use serde_json::json;

/// The buffer: a unit quad (positions, indices), key times [0, 1], translations, rotations,
/// cubic-spline scales, times that do not increase, and key times [0, 0.5].
fn buffer() -> Vec<u8> {
    let mut out = Vec::new();
    let mut floats = |values: &[f32]| {
        for v in values {
            out.extend(v.to_le_bytes());
        }
    };
    floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0]); // 0: 48 bytes
    let quarter = std::f32::consts::FRAC_1_SQRT_2;
    let mut tail = Vec::new();
    for i in [0u16, 1, 2, 0, 2, 3] {
        tail.extend(i.to_le_bytes()); // 48: 12 bytes
    }
    let mut rest = Vec::new();
    for v in [
        0.0f32, 1.0, // 60: times
        0.0, 0.0, 0.0, 2.0, 0.0, 0.0, // 68: translations
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, quarter, quarter, // 92: rotations
        0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, // 124: key 0 (in, value, out)
        0.0, 0.0, 0.0, 3.0, 3.0, 3.0, 0.0, 0.0, 0.0, // key 1
        0.0, 0.0, // 196: times that do not increase
        0.0, 0.5, // 204: times [0, 0.5]
    ] {
        rest.extend(v.to_le_bytes());
    }
    out.extend(tail);
    out.extend(rest);
    out
}

fn animated_file() -> std::path::PathBuf {
    let data = buffer();
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&data)
    );
    let view = |offset: usize, length: usize| json!({"buffer": 0, "byteOffset": offset, "byteLength": length});
    let json = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "mover", "mesh": 0, "translation": [5.0, 0.0, 0.0]},
            {"name": "eye", "translation": [0.5, 0.5, 4.0], "camera": 0}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "materials": [{"name": "glow", "emissiveFactor": [1.0, 1.0, 1.0],
                       "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0]}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "buffers": [{"byteLength": data.len(), "uri": uri}],
        "bufferViews": [
            view(0, 48), view(48, 12), view(60, 8), view(68, 24), view(92, 32),
            view(124, 72), view(196, 8), view(204, 8)
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0]},
            {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 4, "componentType": 5126, "count": 2, "type": "VEC4"},
            {"bufferView": 5, "componentType": 5126, "count": 6, "type": "VEC3"},
            {"bufferView": 6, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [0.0]},
            {"bufferView": 7, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [0.5]}
        ],
        "animations": [
            {"name": "move",
             "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "translation"}},
                {"sampler": 1, "target": {"node": 0, "path": "rotation"}},
                {"sampler": 2, "target": {"node": 0, "path": "scale"}}
             ],
             "samplers": [
                {"input": 2, "output": 3, "interpolation": "LINEAR"},
                {"input": 7, "output": 4, "interpolation": "STEP"},
                {"input": 2, "output": 5, "interpolation": "CUBICSPLINE"}
             ]},
            {"name": "broken",
             "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "translation"}},
                {"sampler": 1, "target": {"node": 0, "path": "weights"}},
                {"sampler": 2, "target": {"node": 0, "path": "translation"}}
             ],
             "samplers": [
                {"input": 6, "output": 3},
                {"input": 2, "output": 2},
                {"input": 2, "output": 3}
             ]}
        ]
    });
    let dir = std::env::temp_dir().join(format!("chiaro-animation-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("animated.gltf");
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    path
}

fn mover(world: &mut World) -> Transform {
    let mut q = world.query::<(&Name, &Transform)>();
    *q.iter(world)
        .find(|(n, _)| n.as_str() == "mover")
        .expect("the mover node")
        .1
}

/// At 0.25 s: translation halfway to 0.5 of the way (0.5, 0, 0), the rotation's first key
/// (its keys are at 0 and 0.5 s), scale 1 + 2 h01(0.25) = 1.3125. At 0.75 s: (1.5, 0, 0), the
/// second rotation key (90 degrees about z, held after 0.5 s), scale 1 h00(0.75) + 3
/// h01(0.75) = 2.6875. At 1.75 s the clip (1 s long) has looped to 0.75 s.
#[test]
fn nodes_are_posed_at_the_time_asked() {
    let path = animated_file();
    let mut world = World::new();
    let spawned = load_scene(&mut world, path.to_str().unwrap()).unwrap();
    assert_eq!(
        mover(&mut world).translation,
        Vec3::new(5.0, 0.0, 0.0),
        "the file's pose"
    );
    let quarter_turn = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    for (seconds, x, rotation, scale) in [
        (0.25, 0.5, Quat::IDENTITY, 1.3125),
        (0.75, 1.5, quarter_turn, 2.6875),
        (1.75, 1.5, quarter_turn, 2.6875),
    ] {
        pose_at(&mut world, seconds);
        let t = mover(&mut world);
        assert!(
            (t.translation - Vec3::new(x, 0.0, 0.0)).length() < 1e-5,
            "{seconds} s: {t:?}"
        );
        assert!(
            t.rotation.angle_between(rotation) < 1e-5,
            "{seconds} s: {t:?}"
        );
        assert!(
            (t.scale - Vec3::splat(scale)).length() < 1e-5,
            "{seconds} s: {t:?}"
        );
    }

    // What cannot be played is left out, named; the rest of "broken" still plays.
    let actions: Vec<String> = spawned
        .repairs
        .iter()
        .map(|r| format!("{}: {}", r.element, r.action))
        .collect();
    for expected in [
        "animation 1 (\"broken\"), channel 0, sampler 0: key times are not increasing: key 1 at 0 s follows 0 s: channel left out",
        "animation 1 (\"broken\"), channel 1: drives the morph weights of a node whose mesh has no morph targets: channel left out",
    ] {
        assert!(
            actions.iter().any(|a| a == expected),
            "{expected:?} not in {actions:?}"
        );
    }
    let animations = world.resource::<Animations>();
    let channels: Vec<usize> = animations.clips.iter().map(|c| c.channels.len()).collect();
    assert_eq!(channels, [3, 1]);
    let info = SceneInfo::gather(&mut world);
    assert_eq!(
        info.animations,
        [("move".to_owned(), 3, 1.0), ("broken".to_owned(), 1, 1.0)]
    );
}

/// The CLI: `render --time` poses the scene, and `--animate` moves it frame by frame: the
/// glowing quad's centroid moves between 0.1 s and 0.7 s, and an animated run from 0.1 s at 5
/// fps ends, after 4 frames, where `--time 0.7` puts it.
#[test]
fn render_follows_the_animation_time() {
    let path = animated_file();
    let dir = path.parent().unwrap().to_owned();
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render",
            path.to_str().unwrap(),
            "--size",
            "24x24",
            "--mode",
            "direct",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let run = common::chiaro(&args);
        if common::gpu_missing(&run) {
            return None;
        }
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        Some(chiaro::eval::HdrImage::read(&out).unwrap().pixels)
    };
    // The glowing quad's centroid in pixels, over a black background.
    let centroid = |image: &[Vec3]| {
        let (mut sum, mut weight) = (glam::DVec2::ZERO, 0.0f64);
        for (i, p) in image.iter().enumerate() {
            let at = glam::DVec2::new((i % 24) as f64, (i / 24) as f64);
            sum += at * f64::from(p.x);
            weight += f64::from(p.x);
        }
        assert!(weight > 1.0, "the quad is in view");
        sum / weight
    };
    let Some(early) = render("early.exr", &["--time", "0.1", "--frames", "1"]) else {
        return;
    };
    let late = render("late.exr", &["--time", "0.7", "--frames", "1"]).unwrap();
    let (early, late) = (centroid(&early), centroid(&late));
    assert!(
        early.distance(late) > 3.0,
        "the quad moved: {early} -> {late} px"
    );
    // 4 frames at 5 fps from 0.1 s: the last is at 0.7 s, and the direct mode's image is the
    // last frame's alone once the scene moved. Its subpixel jitter differs (at most half a
    // pixel each way); a frame off would be about 3 px away.
    let animated = render(
        "animated.exr",
        &["--time", "0.1", "--animate", "--fps", "5", "--frames", "4"],
    )
    .unwrap();
    let animated = centroid(&animated);
    assert!(
        animated.distance(late) < 0.75,
        "the last animated frame is at 0.7 s: {animated} against {late} px"
    );
}

/// The skinned sample CesiumMan walks: its animation drives its skin's joints, and the skin
/// follows them. Posed at 0 s and at 1 s, its mesh's bounds differ; and a GPU renderer that drew
/// it at 0 s and is then moved to 1 s through the World's `Time` (its systems re-skin the mesh,
/// rebuild that BLAS and upload it) agrees with the CPU reference of the pose at 1 s within
/// three times their combined noise, where its image at 0 s does not.
#[test]
fn a_skinned_sample_walks_on_the_cpu_and_the_gpu() {
    use chiaro::scene::{Environment, MeshInstance, Meshes, Skinned, Time};
    let path = common::shared_dir("scenes/animated").join("CesiumMan.glb");
    let load = || {
        let mut world = World::new();
        load_scene(&mut world, path.to_str().unwrap()).unwrap();
        world.insert_resource(Environment::constant(Vec3::ONE));
        world
    };
    let bounds = |world: &mut World| {
        let mut q = world.query_filtered::<&MeshInstance, bevy_ecs::query::With<Skinned>>();
        let mesh = q.iter(world).next().expect("a skinned instance").mesh;
        world.resource::<Meshes>().get(mesh).unwrap().bounds()
    };
    let mut cpu_world = load();
    pose_at(&mut cpu_world, 0.0);
    let at_0 = bounds(&mut cpu_world);
    pose_at(&mut cpu_world, 1.0);
    let at_1 = bounds(&mut cpu_world);
    let moved = (at_0.min - at_1.min)
        .length()
        .max((at_0.max - at_1.max).length());
    assert!(
        moved > 0.05 * (at_0.max - at_0.min).length(),
        "the mesh did not move: {at_0:?} {at_1:?}"
    );

    let size = 32;
    let cpu = chiaro::reference::render_world(
        &mut cpu_world,
        &chiaro::reference::RenderSettings {
            width: size,
            height: size,
            spp: 256,
            ..Default::default()
        },
        false,
    )
    .unwrap();
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = chiaro::gpu::Renderer::new(gpu);
    let mut gpu_world = load();
    gpu_world.insert_resource(Time { seconds: 0.0 });
    let settings = |seed| chiaro::gpu::RenderSettings {
        width: size,
        height: size,
        frames: 32,
        seed,
        frame: chiaro::gpu::FrameSettings {
            mode: chiaro::gpu::RenderMode::Reference,
            spp: 4,
            ..Default::default()
        },
    };
    let before = renderer.render(&mut gpu_world, &settings(1)).unwrap().hdr;
    gpu_world.insert_resource(Time { seconds: 1.0 });
    let a = renderer.render(&mut gpu_world, &settings(1)).unwrap().hdr;
    let b = renderer.render(&mut gpu_world, &settings(2)).unwrap().hdr;
    let rel_mse = |x: &[Vec3], y: &[Vec3]| chiaro::eval::metrics::rel_mse(x, y, 0.01);
    let noise = rel_mse(&cpu.halves[0], &cpu.halves[1]) / 4.0 + rel_mse(&a, &b) / 2.0;
    let error = rel_mse(&a, &cpu.image);
    let stale = rel_mse(&before, &cpu.image);
    eprintln!(
        "GPU at 1 s against the CPU: relMSE {error:.3e}; at 0 s: {stale:.3e}; noise {noise:.3e}"
    );
    assert!(
        error < 3.0 * noise,
        "relMSE {error} against a bound of {}",
        3.0 * noise
    );
    assert!(
        stale > 3.0 * noise,
        "the pose at 0 s is indistinguishable: {stale}"
    );
}

/// The accessor `index` of a .glb's binary chunk as f32s (tightly packed floats).
fn glb_floats(glb: &[u8], json: &serde_json::Value, index: usize) -> Vec<f32> {
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let bin = &glb[20 + json_len + 8..];
    let accessor = &json["accessors"][index];
    let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
    let offset =
        view["byteOffset"].as_u64().unwrap_or(0) + accessor["byteOffset"].as_u64().unwrap_or(0);
    let per = match accessor["type"].as_str().unwrap() {
        "SCALAR" => 1,
        "VEC3" => 3,
        other => panic!("{other}"),
    };
    let count = accessor["count"].as_u64().unwrap() as usize * per;
    bin[offset as usize..][..4 * count]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

/// AnimatedMorphCube's animation drives its two morph weights: at 0.05 s they are its keys at
/// 1/30 and 2/30 s interpolated halfway (decoded from the file here), and its mesh is the
/// stored positions plus each target's displacements times its weight.
#[test]
fn morph_weights_are_played_and_deform_the_mesh() {
    use chiaro::scene::morph::MorphWeights;
    use chiaro::scene::{MeshInstance, Meshes};
    let path = common::shared_dir("scenes/animated").join("AnimatedMorphCube.glb");
    let glb = std::fs::read(&path).unwrap();
    let json = common::gltf_json(&glb);
    let sampler = &json["animations"][0]["samplers"][0];
    let times = glb_floats(&glb, &json, sampler["input"].as_u64().unwrap() as usize);
    let keys = glb_floats(&glb, &json, sampler["output"].as_u64().unwrap() as usize);
    assert!((times[1] - 1.0 / 30.0).abs() < 1e-6 && (times[2] - 2.0 / 30.0).abs() < 1e-6);
    let expected = [0.5 * (keys[2] + keys[4]), 0.5 * (keys[3] + keys[5])];
    assert!(
        expected[0] > 0.0,
        "the first target is moving then: {expected:?}"
    );

    let mut world = World::new();
    load_scene(&mut world, path.to_str().unwrap()).unwrap();
    pose_at(&mut world, 0.05);
    let mut q = world.query::<(&MorphWeights, &MeshInstance)>();
    let (weights, instance) = q.iter(&world).next().expect("a morphed instance");
    let (weights, instance) = (weights.0.clone(), *instance);
    for k in 0..2 {
        assert!(
            (weights[k] - expected[k]).abs() < 1e-6,
            "{weights:?} against {expected:?}"
        );
    }
    let primitive = &json["meshes"][0]["primitives"][0];
    let base = glb_floats(
        &glb,
        &json,
        primitive["attributes"]["POSITION"].as_u64().unwrap() as usize,
    );
    let mut by_hand: Vec<Vec3> = base.chunks_exact(3).map(Vec3::from_slice).collect();
    for (k, target) in primitive["targets"].as_array().unwrap().iter().enumerate() {
        let d = glb_floats(&glb, &json, target["POSITION"].as_u64().unwrap() as usize);
        for (p, d) in by_hand.iter_mut().zip(d.chunks_exact(3)) {
            *p += Vec3::from_slice(d) * weights[k];
        }
    }
    let mesh = world.resource::<Meshes>().get(instance.mesh).unwrap();
    assert_eq!(mesh.positions().len(), by_hand.len());
    for (v, (got, want)) in mesh.positions().iter().zip(&by_hand).enumerate() {
        assert!(
            got.abs_diff_eq(*want, 1e-6),
            "vertex {v}: {got} where {want}"
        );
    }
}
