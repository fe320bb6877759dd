//! The glTF features chiaro reads, each checked on a small file written by the test:
//! KHR_lights_punctual, cameras, KHR_materials_emissive_strength, KHR_materials_ior,
//! KHR_texture_transform, the `absorption` extra, normal maps without tangents (MikkTSpace),
//! missing normals (flat), strips and fans, points skipped, the automatic camera; and the
//! environment images (.hdr, .exr).

mod common;

use std::io::Cursor;
use std::path::PathBuf;

use base64::Engine;
use bevy_ecs::world::World;
use chiaro::scene::{
    ActiveCamera, AutoCamera, Camera, Environment, EnvironmentSource, Light, LightKind, LightUnits,
    LoadOptions, MaterialId, Materials, MeshId, Meshes, Name, Projection, SceneInfo, Textures,
    load_scene, load_scene_with,
};
use glam::{Vec2, Vec3};
use serde_json::{Value, json};

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!(
        "data:{mime};base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

fn png_2x2() -> Vec<u8> {
    let image = image::RgbaImage::from_fn(2, 2, |x, y| {
        image::Rgba([(x * 255) as u8, (y * 255) as u8, 128, 255])
    });
    let mut out = Cursor::new(Vec::new());
    image.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// One buffer: a unit quad's positions (4), UVs (4), then triangle-list, strip and fan indices.
fn buffer() -> Vec<u8> {
    let positions: [f32; 12] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0];
    let uvs: [f32; 8] = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let strip: [u16; 4] = [0, 1, 3, 2];
    let fan: [u16; 4] = [0, 1, 2, 3];
    let mut out: Vec<u8> = positions
        .iter()
        .chain(&uvs)
        .flat_map(|f| f.to_le_bytes())
        .collect();
    out.extend(
        indices
            .iter()
            .chain(&strip)
            .chain(&fan)
            .flat_map(|i| i.to_le_bytes()),
    );
    out
}

fn scene_json() -> Value {
    let data = buffer();
    json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_texture_transform"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 20.0, "range": 5.0},
            {"type": "spot", "intensity": 10.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
            {"type": "directional", "intensity": 3.0}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3, 4, 5, 6]}],
        "nodes": [
            {"name": "lit quad", "mesh": 0, "translation": [0.0, 0.0, -2.0]},
            {"name": "strip", "mesh": 1},
            {"name": "fan and points", "mesh": 2},
            {"name": "bulb", "translation": [0.0, 2.0, 0.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "spot", "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"name": "sun", "rotation": [-std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2], "extensions": {"KHR_lights_punctual": {"light": 2}}},
            {"name": "eye", "translation": [0.0, 0.0, 3.0], "camera": 0}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 0}, "indices": 3, "mode": 5, "material": 1}]},
            {"primitives": [
                {"attributes": {"POSITION": 0}, "indices": 4, "mode": 6, "material": 1},
                {"attributes": {"POSITION": 0}, "mode": 0}
            ]}
        ],
        "materials": [
            {"name": "textured",
             "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform":
                 {"offset": [0.5, 0.0], "scale": [2.0, 2.0]}}}},
             "normalTexture": {"index": 1, "scale": 0.5},
             "extensions": {"KHR_materials_ior": {"ior": 1.33}},
             "extras": {"absorption": 0.3}},
            {"name": "glowing", "emissiveFactor": [1.0, 0.5, 0.0],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 40.0}}}
        ],
        "textures": [{"source": 0, "sampler": 0}, {"source": 0}],
        "samplers": [{"wrapS": 33071, "magFilter": 9728}],
        "images": [{"uri": data_uri("image/png", &png_2x2())}],
        "buffers": [{"byteLength": data.len(), "uri": data_uri("application/octet-stream", &data)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 28}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "byteOffset": 0, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "byteOffset": 12, "componentType": 5123, "count": 4, "type": "SCALAR"},
            {"bufferView": 2, "byteOffset": 20, "componentType": 5123, "count": 4, "type": "SCALAR"}
        ]
    })
}

/// Adds `names` to the scene's `extensionsUsed`.
fn use_extensions(json: &mut Value, names: &[&str]) {
    let used = json["extensionsUsed"].as_array_mut().expect("a list");
    used.extend(names.iter().map(|n| json!(n)));
}

fn write(name: &str, json: &Value) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("chiaro-features-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(json).unwrap()).unwrap();
    path
}

fn entity_named<'w, C: bevy_ecs::component::Component>(world: &'w mut World, name: &str) -> &'w C {
    let mut query = world.query::<(bevy_ecs::entity::Entity, &Name)>();
    let entity = query
        .iter(world)
        .find(|(_, n)| n.as_str() == name)
        .map(|(e, _)| e);
    world
        .get::<C>(entity.unwrap_or_else(|| panic!("no entity named {name}")))
        .unwrap()
}

/// KHR_lights_punctual's candela and lux become W/sr and W/m^2 at 683 lm/W by default, as
/// Blender's glTF importer reads them; `LightUnits::Unitless` keeps the numbers. A 1000 W
/// Blender point light is exported as 1000 / (4 pi) * 683 cd and must come back as a radiant
/// intensity of 1000 / (4 pi) W/sr, what Blender's point light of 1000 W emits.
#[test]
fn light_intensities_are_photometric_by_default_and_unitless_when_asked() {
    let mut json = scene_json();
    let blender_watts = 1000.0f32;
    let candela = blender_watts / (4.0 * std::f32::consts::PI) * 683.0;
    json["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = json!(candela);
    let path = write("light_units.gltf", &json);
    let read = |units: LightUnits| {
        let mut world = World::new();
        let options = LoadOptions {
            light_units: units,
            ..LoadOptions::default()
        };
        load_scene_with(&mut world, path.to_str().unwrap(), &options).unwrap();
        let bulb = entity_named::<Light>(&mut world, "bulb").intensity;
        let spot = entity_named::<Light>(&mut world, "spot").intensity;
        let sun = entity_named::<Light>(&mut world, "sun").intensity;
        (bulb, spot, sun)
    };
    let (bulb, spot, sun) = read(LightUnits::default());
    let watts_per_sr = blender_watts / (4.0 * std::f32::consts::PI);
    assert!(
        (bulb - watts_per_sr).abs() <= 1e-5 * watts_per_sr,
        "{bulb} W/sr from {candela} cd, not {watts_per_sr}"
    );
    assert_eq!((spot, sun), (10.0 / 683.0, 3.0 / 683.0));
    assert_eq!(read(LightUnits::Unitless), (candela, 10.0, 3.0));
}

#[test]
fn lights_camera_and_material_extensions_are_read() {
    let path = write("features.gltf", &scene_json());
    let mut world = World::new();
    let spawned = load_scene(&mut world, path.to_str().unwrap()).unwrap();
    assert_eq!(spawned.repairs.len(), 1, "{:?}", spawned.repairs);
    assert_eq!(spawned.repairs[0].element, "mesh 2 primitive 1");
    assert_eq!(
        spawned.repairs[0].action,
        "skipped: Points primitives are not surfaces"
    );

    let bulb = *entity_named::<Light>(&mut world, "bulb");
    assert_eq!(bulb.kind, LightKind::Point);
    assert_eq!(
        (bulb.color, bulb.intensity, bulb.range),
        (Vec3::new(1.0, 0.5, 0.25), 20.0 / 683.0, Some(5.0))
    );
    let spot = *entity_named::<Light>(&mut world, "spot");
    assert_eq!(
        spot.kind,
        LightKind::Spot {
            inner_cone_angle: 0.2,
            outer_cone_angle: 0.6
        }
    );
    assert_eq!(
        entity_named::<Light>(&mut world, "sun").kind,
        LightKind::Directional
    );

    let camera = world.resource::<ActiveCamera>().0;
    assert!(world.get::<AutoCamera>(camera).is_none());
    assert_eq!(
        world.get::<Camera>(camera).unwrap().projection,
        Projection::Perspective {
            yfov: 0.8,
            aspect_ratio: Some(1.5),
            znear: 0.1,
            zfar: None
        }
    );

    let materials = world.resource::<Materials>();
    let textured = materials.get(MaterialId(0)).unwrap();
    assert_eq!(
        (textured.ior, textured.absorption, textured.normal_scale),
        (1.33, 0.3, 0.5)
    );
    let base = textured.base_color_texture.unwrap();
    assert_eq!(
        base.transform.transform_point2(Vec2::new(1.0, 1.0)),
        Vec2::new(2.5, 2.0)
    );
    assert_eq!(
        base.sampler.wrap_u,
        chiaro::scene::material::WrapMode::ClampToEdge
    );
    assert_eq!(
        base.sampler.mag_filter,
        chiaro::scene::material::Filter::Nearest
    );
    let glowing = materials.get(MaterialId(1)).unwrap();
    assert_eq!(glowing.emitted_radiance(), Vec3::new(40.0, 20.0, 0.0));

    // The same image serves an sRGB slot and a linear slot: decoded once per colour space.
    let textures = world.resource::<Textures>();
    assert_eq!(textures.len(), 2);
    assert_eq!(
        textures.get(chiaro::scene::TextureId(0)).unwrap().rgba8[..4],
        [0, 0, 128, 255]
    );

    // The normal-mapped quad got MikkTSpace tangents; without normals in the file, flat normals.
    let meshes = world.resource::<Meshes>();
    let quad = meshes.get(MeshId(0)).unwrap();
    let tangents = quad
        .tangents()
        .expect("tangents generated for the normal map");
    assert!(
        tangents
            .iter()
            .all(|t| t.truncate().abs_diff_eq(Vec3::X, 1e-5))
    );
    assert!(quad.normals().iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)));
    // Strip of 4 and fan of 4: two triangles each, all facing +Z like the list.
    for id in [1, 2] {
        let mesh = meshes.get(MeshId(id)).unwrap();
        assert_eq!(mesh.triangle_count(), 2);
        assert!(
            mesh.normals().iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)),
            "mesh {id}"
        );
    }
    let info = SceneInfo::gather(&mut world);
    assert_eq!(
        (info.instances, info.triangles, info.emissive_triangles),
        (3, 6, 4)
    );
}

#[test]
fn a_scene_without_camera_gets_one_framing_its_bounds() {
    let mut json = scene_json();
    json["nodes"][6] = json!({"name": "no camera here"});
    let path = write("no-camera.gltf", &json);
    let mut world = World::new();
    load_scene(&mut world, path.to_str().unwrap()).unwrap();
    let info = SceneInfo::gather(&mut world);
    let camera = info.camera.unwrap();
    assert!(camera.automatic);
    assert!(camera.forward.abs_diff_eq(Vec3::NEG_Z, 1e-6));
    let center = info.bounds.center();
    assert!((camera.position.truncate() - center.truncate()).length() < 1e-5);
    let radius = 0.5 * info.bounds.size().length();
    let half_fov = (radius / (camera.position.z - center.z)).asin();
    assert!((half_fov - chiaro::scene::framing::AUTO_YFOV / 2.0).abs() < 1e-4);
}

#[test]
fn required_extension_chiaro_lacks_is_refused() {
    let mut json = scene_json();
    json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    json["extensionsUsed"]
        .as_array_mut()
        .unwrap()
        .push(json!("KHR_draco_mesh_compression"));
    let path = write("draco.gltf", &json);
    let err = load_scene(&mut World::new(), path.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        err.ends_with(
            "requires extension KHR_draco_mesh_compression, which chiaro does not support"
        ),
        "{err}"
    );
}

#[test]
fn shared_hdr_environment_loads() {
    let path = common::shared_dir("scenes").join("qwantani_afternoon_puresky_1k.hdr");
    let (env, repairs) = Environment::from_file(&path, 2.0).unwrap();
    assert!(repairs.is_empty());
    let EnvironmentSource::Equirect(image) = &env.source else {
        panic!("expected an image")
    };
    assert_eq!((image.width, image.height), (1024, 512));
    let mean = env.mean_radiance();
    assert!(mean.is_finite() && mean.min_element() > 0.0, "{mean}");
}

#[test]
fn exr_environment_loads_and_non_finite_texels_are_zeroed() {
    let mut image = image::Rgb32FImage::from_pixel(8, 4, image::Rgb([0.5, 1.0, 2.0]));
    image.put_pixel(3, 1, image::Rgb([f32::NAN, 1.0, 1.0]));
    image.put_pixel(4, 2, image::Rgb([-1.0, 1.0, 1.0]));
    let path = std::env::temp_dir().join(format!("chiaro-env-{}.exr", std::process::id()));
    image.save(&path).unwrap();
    let (env, repairs) = Environment::from_file(&path, 1.0).unwrap();
    assert_eq!(repairs.len(), 1);
    assert_eq!(
        repairs[0].action,
        "set 2 non-finite or negative texels to zero"
    );
    let EnvironmentSource::Equirect(loaded) = &env.source else {
        panic!("expected an image")
    };
    assert_eq!(loaded.texels[0], Vec3::new(0.5, 1.0, 2.0));
    assert_eq!(loaded.texels[8 + 3], Vec3::ZERO);
}

#[test]
fn required_gpu_instancing_is_read() {
    let mut json = scene_json();
    let data = buffer();
    let offsets: Vec<u8> = [0.0f32, 0.0, 0.0, 5.0, 0.0, 0.0, 10.0, 0.0, 0.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let mut all = data.clone();
    all.extend(&offsets);
    json["buffers"][0] =
        json!({"byteLength": all.len(), "uri": data_uri("application/octet-stream", &all)});
    json["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": 0, "byteOffset": data.len(), "byteLength": 36}));
    json["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"}));
    json["extensionsRequired"] = json!(["EXT_mesh_gpu_instancing"]);
    json["nodes"][1]["extensions"] =
        json!({"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": 5}}});
    let path = write("gpu-instancing.gltf", &json);
    let mut world = World::new();
    load_scene(&mut world, path.to_str().unwrap()).unwrap();
    let info = SceneInfo::gather(&mut world);
    // The strip node now draws its mesh three times, 5 units apart; the mesh is stored once.
    assert_eq!((info.instances, info.meshes), (5, 3));
    assert!((info.bounds.max.x - 11.0).abs() < 1e-6, "{:?}", info.bounds);
}

#[test]
fn material_extension_factors_are_read_and_bad_ones_repaired() {
    let mut json = scene_json();
    json["materials"][0]["extensions"]["KHR_materials_specular"] = json!({
        "specularFactor": 0.25, "specularColorFactor": [2.0, 1.0, 0.5],
        "specularTexture": {"index": 0}
    });
    json["materials"][0]["extensions"]["KHR_materials_clearcoat"] =
        json!({"clearcoatFactor": 0.75, "clearcoatRoughnessFactor": 0.3});
    json["materials"][0]["extensions"]["KHR_materials_sheen"] =
        json!({"sheenColorFactor": [0.5, 1.5, 0.25], "sheenRoughnessFactor": 0.4});
    json["materials"][0]["extensions"]["KHR_materials_transmission"] =
        json!({"transmissionFactor": 0.6});
    json["materials"][0]["extensions"]["KHR_materials_volume"] = json!({
        "thicknessFactor": 0.5, "attenuationColor": [0.5, 0.25, 1.0], "attenuationDistance": 2.0
    });
    json["materials"][1]["extensions"]["KHR_materials_transmission"] =
        json!({"transmissionFactor": 0.5});
    json["materials"][1]["extensions"]["KHR_materials_volume"] = json!({
        "thicknessFactor": 0.1, "attenuationColor": [0.0, 0.5, 2.0], "attenuationDistance": -1
    });
    json["materials"][1]["extensions"]["KHR_materials_clearcoat"] =
        json!({"clearcoatFactor": 4.0, "clearcoatRoughnessFactor": "rough"});
    use_extensions(
        &mut json,
        &[
            "KHR_materials_specular",
            "KHR_materials_clearcoat",
            "KHR_materials_sheen",
            "KHR_materials_transmission",
            "KHR_materials_volume",
        ],
    );
    let path = write("extensions.gltf", &json);
    let mut world = World::new();
    let spawned = load_scene(&mut world, path.to_str().unwrap()).unwrap();
    let materials = world.resource::<chiaro_scene::Materials>();
    let named = |name: &str| {
        materials
            .iter()
            .find(|(_, m)| m.name == name)
            .map(|(_, m)| m.clone())
            .unwrap()
    };
    let textured = named("textured");
    assert_eq!(
        (textured.specular, textured.specular_color),
        (0.25, Vec3::new(2.0, 1.0, 0.5))
    );
    assert_eq!(
        (textured.clearcoat, textured.clearcoat_roughness),
        (0.75, 0.3)
    );
    assert_eq!(
        (
            textured.sheen_color,
            textured.sheen_roughness,
            textured.transmission
        ),
        (Vec3::new(0.5, 1.0, 0.25), 0.4, 0.6)
    );
    assert!(textured.shades_both_sides());
    let volume = textured.volume.expect("a volume");
    assert_eq!(
        (volume.attenuation_color, volume.attenuation_distance),
        (Vec3::new(0.5, 0.25, 1.0), 2.0)
    );
    let sigma = volume.attenuation_coefficient();
    assert!(
        (sigma - Vec3::new(0.5f32.ln(), 0.25f32.ln(), 0.0) / -2.0)
            .abs()
            .max_element()
            < 1e-6
    );
    let glowing = named("glowing");
    assert_eq!(glowing.volume, Some(chiaro_scene::Volume::default()));
    assert_eq!(
        (
            glowing.specular,
            glowing.clearcoat,
            glowing.clearcoat_roughness
        ),
        (1.0, 1.0, 0.0)
    );
    let actions: Vec<&str> = spawned.repairs.iter().map(|r| r.action.as_str()).collect();
    for expected in [
        "clear coat factor 4 clamped to [0, 1]",
        "clear coat roughness \"rough\" is not a number: the default is used",
        "sheen colour [0.5, 1.5, 0.25] clamped to [0, 1]",
        "attenuation colour [0.0,0.5,2.0] is not three numbers in (0, 1]: white used",
        "attenuation distance -1 is not a number > 0: no attenuation",
    ] {
        assert!(
            actions.contains(&expected),
            "{expected:?} not in {actions:?}"
        );
    }
}

/// The material extensions' textures are read, each in its colour space (the colour textures
/// sRGB, the rest linear), with its UV set and KHR_texture_transform; the clear coat's normal
/// texture with its scale, the mesh given tangents for its UV set though the base has no normal
/// map; one that names no texture of the file gets a repair line.
#[test]
fn material_extension_textures_are_read_in_their_colour_spaces() {
    let mut json = scene_json();
    json["materials"][0]
        .as_object_mut()
        .unwrap()
        .remove("normalTexture");
    let ext = &mut json["materials"][0]["extensions"];
    ext["KHR_materials_specular"] = json!({
        "specularTexture": {"index": 1},
        "specularColorTexture": {"index": 1, "texCoord": 1}
    });
    ext["KHR_materials_clearcoat"] = json!({
        "clearcoatFactor": 1.0,
        "clearcoatTexture": {"index": 1},
        "clearcoatRoughnessTexture": {"index": 1, "extensions": {"KHR_texture_transform":
            {"offset": [0.25, 0.0]}}},
        "clearcoatNormalTexture": {"index": 1, "scale": 0.5}
    });
    ext["KHR_materials_sheen"] = json!({
        "sheenColorFactor": [1.0, 1.0, 1.0],
        "sheenColorTexture": {"index": 1},
        "sheenRoughnessTexture": {"index": 7}
    });
    ext["KHR_materials_transmission"] =
        json!({"transmissionFactor": 1.0, "transmissionTexture": {"index": 1}});
    use_extensions(
        &mut json,
        &[
            "KHR_materials_specular",
            "KHR_materials_clearcoat",
            "KHR_materials_sheen",
            "KHR_materials_transmission",
        ],
    );
    let path = write("extension_textures.gltf", &json);
    let mut world = World::new();
    let spawned = load_scene(&mut world, path.to_str().unwrap()).unwrap();
    let materials = world.resource::<chiaro_scene::Materials>();
    let textures = world.resource::<chiaro_scene::Textures>();
    let material = materials
        .iter()
        .find(|(_, m)| m.name == "textured")
        .map(|(_, m)| m.clone())
        .unwrap();
    let layers = material.layer_textures;
    let space = |slot: Option<chiaro_scene::TextureRef>| {
        let slot = slot.expect("a texture");
        textures.get(slot.texture).unwrap().color_space
    };
    use chiaro_scene::ColorSpace::{Linear, Srgb};
    assert_eq!(space(layers.specular), Linear);
    assert_eq!(space(layers.specular_color), Srgb);
    assert_eq!(space(layers.clearcoat), Linear);
    assert_eq!(space(layers.clearcoat_roughness), Linear);
    assert_eq!(space(layers.transmission), Linear);
    assert_eq!(space(layers.sheen_color), Srgb);
    assert_eq!(layers.sheen_roughness, None, "texture 7 does not exist");
    assert_eq!(layers.specular_color.unwrap().uv_set, 1);
    assert_eq!(
        layers.clearcoat_roughness.unwrap().transform.translation,
        glam::Vec2::new(0.25, 0.0)
    );
    assert_eq!(space(material.clearcoat_normal_texture), Linear);
    assert_eq!(material.clearcoat_normal_scale, 0.5);
    assert_eq!(material.normal_texture, None);
    let meshes = world.resource::<chiaro_scene::Meshes>();
    assert!(
        meshes.iter().any(|(_, m)| m.tangents().is_some()),
        "the coat's normal map needs the textured quad's tangents"
    );
    let actions: Vec<&str> = spawned.repairs.iter().map(|r| r.action.as_str()).collect();
    let expected = "sheenRoughnessTexture {\"index\":7} names no texture of the file: its factor alone is used";
    assert!(
        actions.contains(&expected),
        "{expected:?} not in {actions:?}"
    );
    let about_textures = actions.iter().filter(|a| a.contains("Texture")).count();
    assert_eq!(about_textures, 1, "{actions:?}");
}
