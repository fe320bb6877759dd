//! COLOR_0 vertex colours: read as floats, normalized unsigned bytes or normalized unsigned
//! shorts, RGB or RGBA, checked like every accessor; and rendered as glTF 2.0 says (they
//! multiply the base colour and its alpha), the GPU agreeing with the CPU reference.

mod common;

use bevy_ecs::world::World;
use chiaro::scene::{Environment, Meshes, Transform};
use common::hand_made::{EmbeddedBuffer, QUAD, load, write};
use glam::{Quat, Vec3, Vec4};
use serde_json::{Value, json};

/// Colours of the quad's four corners, as the tests write them.
const CORNERS: [[f32; 4]; 4] = [
    [1.0, 0.0, 0.2, 0.5],
    [0.0, 1.0, 0.4, 1.0],
    [0.25, 0.5, 1.0, 0.0],
    [1.0, 1.0, 1.0, 1.0],
];

/// A file of the unit quad whose COLOR_0 is `data` (`kind`, `component`, `normalized`).
fn colored_quad(data: &[u8], kind: &str, component: u32, normalized: bool) -> Value {
    let mut buffer = EmbeddedBuffer::default();
    let position = buffer.positions(&QUAD);
    let color = buffer.add(data, 4, kind, component, normalized);
    let indices = buffer.indices(&[0, 1, 2, 0, 2, 3]);
    let mut gltf = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position, "COLOR_0": color},
            "indices": indices}]}],
    });
    buffer.finish(&mut gltf);
    gltf
}

/// The colour of each of the mesh's vertices, by the quad corner at its position.
fn colors_by_corner(world: &World) -> [Vec4; 4] {
    let mesh = world.resource::<Meshes>().iter().next().unwrap().1;
    let colors = mesh.colors().expect("the mesh has colours");
    let mut found = [None; 4];
    for (p, c) in mesh.positions().iter().zip(colors) {
        let corner = QUAD.iter().position(|q| Vec3::from(*q) == *p).unwrap();
        assert!(
            found[corner].is_none_or(|f| f == *c),
            "one corner, two colours"
        );
        found[corner] = Some(*c);
    }
    found.map(Option::unwrap)
}

fn load_quad(test: &str, gltf: &Value) -> World {
    let (world, result) = load(&write(test, "quad.gltf", gltf));
    let spawned = result.unwrap();
    assert!(spawned.repairs.is_empty(), "{:?}", spawned.repairs);
    world
}

#[test]
fn float_rgb_colours_are_read_with_alpha_one() {
    let floats: Vec<f32> = CORNERS.iter().flat_map(|c| c[..3].to_vec()).collect();
    let data: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    let world = load_quad("color-f32", &colored_quad(&data, "VEC3", 5126, false));
    for (got, want) in colors_by_corner(&world).iter().zip(CORNERS) {
        assert_eq!(*got, Vec4::new(want[0], want[1], want[2], 1.0));
    }
}

#[test]
fn normalized_byte_rgba_colours_are_read() {
    let data: Vec<u8> = CORNERS
        .iter()
        .flatten()
        .map(|&c| (c * 255.0).round() as u8)
        .collect();
    let world = load_quad("color-u8", &colored_quad(&data, "VEC4", 5121, true));
    for (got, want) in colors_by_corner(&world).iter().zip(CORNERS) {
        let want = Vec4::from(want.map(|c| (c * 255.0).round() / 255.0));
        assert!(got.abs_diff_eq(want, 1e-6), "{got} against {want}");
    }
}

#[test]
fn normalized_short_colours_are_read_rgb_and_rgba() {
    let unorm16 = |c: f32| (c * 65535.0).round() as u16;
    for (kind, components) in [("VEC3", 3), ("VEC4", 4)] {
        let data: Vec<u8> = CORNERS
            .iter()
            .flat_map(|c| c[..components].to_vec())
            .flat_map(|c| unorm16(c).to_le_bytes())
            .collect();
        let world = load_quad("color-u16", &colored_quad(&data, kind, 5123, true));
        for (got, want) in colors_by_corner(&world).iter().zip(CORNERS) {
            let mut want = Vec4::from(want.map(|c| f32::from(unorm16(c)) / 65535.0));
            if components == 3 {
                want.w = 1.0;
            }
            assert!(got.abs_diff_eq(want, 1e-6), "{kind}: {got} against {want}");
        }
    }
}

#[test]
fn colours_of_a_wrong_format_are_refused_by_name() {
    let bytes = [0u8; 32];
    let cases = [
        (
            "VEC4",
            5121,
            false,
            "4 components of U8 where 4 of F32 or normalized U8/U16",
        ),
        (
            "VEC2",
            5126,
            false,
            "a colour of 2 components where 3 (RGB) or 4 (RGBA)",
        ),
    ];
    for (kind, component, normalized, fault) in cases {
        let gltf = colored_quad(&bytes, kind, component, normalized);
        let path = write("color-refused", "quad.gltf", &gltf);
        let (_, result) = load(&path);
        let Err(error) = result else {
            panic!("{kind} {component} loaded")
        };
        let text = error.to_string();
        assert_eq!(
            error.element.as_deref(),
            Some("mesh 0 primitive 0"),
            "{text}"
        );
        assert!(text.contains("quad.gltf"), "{text}");
        assert!(
            text.contains("accessor 1") && text.contains(fault),
            "{text}"
        );
    }
}

#[test]
fn non_finite_colours_are_repaired_with_a_warning() {
    let mut floats: Vec<f32> = CORNERS.iter().flat_map(|c| c[..3].to_vec()).collect();
    floats[4] = f32::NAN;
    let data: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    let (world, result) = load(&write(
        "color-nan",
        "quad.gltf",
        &colored_quad(&data, "VEC3", 5126, false),
    ));
    let repairs = result.unwrap().repairs;
    assert_eq!(repairs.len(), 1, "{repairs:?}");
    assert!(
        repairs[0]
            .to_string()
            .contains("non-finite components of 1 vertex colours")
    );
    assert_eq!(colors_by_corner(&world)[1], Vec4::new(0.0, 1.0, 0.4, 1.0));
}

/// A floor coloured red, green, blue and white at its corners (unorm16 RGB), and in front of
/// it a wall whose vertex alpha falls from 1 on the right to 0 on the left (unorm8 RGBA) under
/// an alpha mask of cutoff 0.5, so its left half is a hole for camera, shadow and indirect rays;
/// lit by a sun (its shadow falls on the floor) and a grey sky. Without `colors` the file has
/// no COLOR_0 (a white floor, an opaque wall).
fn colored_scene(colors: bool) -> World {
    let mut buffer = EmbeddedBuffer::default();
    let floor = buffer.positions(&[
        [-1.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 0.0, -1.0],
        [-1.0, 0.0, -1.0],
    ]);
    let floor_colors: Vec<u8> = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0; 3]]
        .iter()
        .flatten()
        .flat_map(|&c: &f32| ((c * 65535.0) as u16).to_le_bytes())
        .collect();
    let floor_colors = buffer.add(&floor_colors, 4, "VEC3", 5123, true);
    let wall = buffer.positions(&[
        [-0.6, 0.0, -0.2],
        [0.6, 0.0, -0.2],
        [0.6, 0.9, -0.2],
        [-0.6, 0.9, -0.2],
    ]);
    let wall_colors = buffer.add(
        &[
            255, 230, 0, 0, 255, 230, 0, 255, 255, 230, 0, 255, 255, 230, 0, 0,
        ],
        4,
        "VEC4",
        5121,
        true,
    );
    let indices = buffer.indices(&[0, 1, 2, 0, 2, 3]);
    let sun = Quat::from_rotation_arc(Vec3::NEG_Z, Vec3::new(-0.4, -1.0, -0.6).normalize());
    let eye = Transform::looking_at(Vec3::new(0.3, 1.3, 2.2), Vec3::new(0.0, 0.25, 0.0), Vec3::Y);
    let mut gltf = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 2.0}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"name": "floor", "mesh": 0},
            {"name": "wall", "mesh": 1},
            {"name": "sun", "rotation": sun.to_array(),
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "eye", "camera": 0, "translation": eye.translation.to_array(),
             "rotation": eye.rotation.to_array()}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05,
            "aspectRatio": 1.0}}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": floor, "COLOR_0": floor_colors},
                "indices": indices, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": wall, "COLOR_0": wall_colors},
                "indices": indices, "material": 1}]}
        ],
        "materials": [
            {"name": "floor", "pbrMetallicRoughness": {"metallicFactor": 0.0,
                "roughnessFactor": 0.8, "baseColorFactor": [0.9, 0.9, 0.9, 1.0]}},
            {"name": "wall", "alphaMode": "MASK", "doubleSided": true,
             "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.6}}
        ]
    });
    buffer.finish(&mut gltf);
    if !colors {
        for mesh in 0..2 {
            let attributes = &mut gltf["meshes"][mesh]["primitives"][0]["attributes"];
            attributes.as_object_mut().unwrap().remove("COLOR_0");
        }
    }
    let (mut world, result) = load(&write("color-scene", "scene.gltf", &gltf));
    let spawned = result.unwrap();
    assert!(spawned.repairs.is_empty(), "{:?}", spawned.repairs);
    world.insert_resource(Environment::constant(Vec3::splat(0.4)));
    world
}

/// relMSE of the GPU reference mode against the CPU reference on [`colored_scene`], 32x32:
/// below 3 x their combined own noise. And the colours matter: the same scene without them
/// (white floor, opaque wall) is far from the reference, so a renderer ignoring COLOR_0 fails.
#[test]
fn vertex_coloured_scene_matches_the_reference_on_the_gpu() {
    let mut world = colored_scene(true);
    let Some(result) = common::parity::gpu_and_cpu_references(&mut world, 32, 256, 64) else {
        return;
    };
    let bound = result.bound();
    eprintln!(
        "vertex colours: relMSE {:.3e}, bound {bound:.3e} (GPU noise {:.2e}, CPU noise {:.2e})",
        result.error, result.gpu_noise, result.cpu_noise
    );
    assert!(
        result.error < bound,
        "relMSE {:.3e} against {bound:.3e}",
        result.error
    );

    // Without colours (as before COLOR_0 was read): far from the reference.
    let mut plain = colored_scene(false);
    let plain_cpu = chiaro::reference::render_world(
        &mut plain,
        &chiaro::reference::RenderSettings {
            width: 32,
            height: 32,
            spp: 64,
            seed: 7,
            sampler: chiaro_reference::Sampler::default(),
            threads: None,
            path: chiaro::reference::PathSettings::default(),
        },
        false,
    )
    .unwrap();
    let ignored = common::parity::rel_mse_01(&plain_cpu.image, &result.cpu);
    eprintln!("without colours: relMSE {ignored:.3e}");
    assert!(ignored > 20.0 * bound, "{ignored:.3e} against {bound:.3e}");
}
