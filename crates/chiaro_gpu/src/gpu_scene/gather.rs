//! The scene's data flattened into the GPU records of [`super::layout`]: meshes, materials,
//! textures, punctual lights, the area-light table and the environment.

use std::f32::consts::PI;
use std::ops::Range;

use chiaro_bvh::SceneBvh;
use chiaro_scene::material::{Filter, WrapMode};
use chiaro_scene::{
    AlphaMode, ColorSpace, Environment, EnvironmentSource, GlobalTransform, Light, LightKind,
    Material, Materials, Meshes, TextureRef, Textures,
};
use chiaro_shading::color::luminance;
use chiaro_shading::light_tree::LightBounds;
use glam::{Vec3, Vec4};

use super::layout::*;

/// The runs of consecutive instances that draw the same mesh, given each instance's mesh in
/// order: (mesh, instance range), one instanced G-buffer draw each.
pub fn mesh_runs(meshes: impl Iterator<Item = u32>) -> Vec<(u32, Range<u32>)> {
    let mut runs: Vec<(u32, Range<u32>)> = Vec::new();
    for (i, mesh) in (0u32..).zip(meshes) {
        match runs.last_mut() {
            Some((last, range)) if *last == mesh => range.end = i + 1,
            _ => runs.push((mesh, i..i + 1)),
        }
    }
    runs
}

/// A linear RGBA colour in [0, 1] as four unorm16 in two words (WGSL's `pack2x16unorm` of
/// (r, g) and of (b, a)).
pub fn pack_color(color: Vec4) -> [u32; 2] {
    let unorm = |x: f32| (x.clamp(0.0, 1.0) * 65535.0).round() as u32;
    let c = color.to_array().map(unorm);
    [c[0] | (c[1] << 16), c[2] | (c[3] << 16)]
}

/// Vertices, indices (global vertex indices) and the per-mesh table.
pub fn meshes(meshes: &Meshes) -> (Vec<GpuVertex>, Vec<u32>, Vec<GpuMesh>) {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let mut table = Vec::new();
    for (_, mesh) in meshes.iter() {
        let vertex_base = vertices.len() as u32;
        let uv0 = mesh.uv(0);
        let uv1 = mesh.uv(1);
        let tangents = mesh.tangents();
        let colors = mesh.colors();
        let flags = bit(uv0.is_some(), MESH_HAS_UV0)
            | bit(uv1.is_some(), MESH_HAS_UV1)
            | bit(tangents.is_some(), MESH_HAS_TANGENTS);
        for (i, (p, n)) in mesh.positions().iter().zip(mesh.normals()).enumerate() {
            let uv = uv0.map_or([0.0; 2], |uv| uv[i].to_array());
            vertices.push(GpuVertex {
                position: p.to_array(),
                u0: uv[0],
                normal: n.to_array(),
                v0: uv[1],
                tangent: tangents.map_or([0.0; 4], |t| t[i].to_array()),
                uv1: uv1.map_or([0.0; 2], |uv| uv[i].to_array()),
                color: pack_color(colors.map_or(Vec4::ONE, |c| c[i])),
            });
        }
        table.push(GpuMesh {
            index_base: indices.len() as u32,
            vertex_base,
            triangle_count: mesh.triangle_count() as u32,
            flags,
        });
        indices.extend(mesh.indices().iter().map(|i| i + vertex_base));
    }
    (vertices, indices, table)
}

/// `flag` when `set`, else 0.
fn bit(set: bool, flag: u32) -> u32 {
    if set { flag } else { 0 }
}

fn wrap_bits(mode: WrapMode) -> u32 {
    match mode {
        WrapMode::Repeat => 0,
        WrapMode::MirroredRepeat => 1,
        WrapMode::ClampToEdge => 2,
    }
}

fn slot(slot: &Option<TextureRef>) -> GpuTextureSlot {
    let Some(t) = slot else {
        return GpuTextureSlot::default();
    };
    let m = t.transform.matrix2;
    GpuTextureSlot {
        texture: t.texture.0,
        uv_set: t.uv_set,
        sampler: wrap_bits(t.sampler.wrap_u)
            | (wrap_bits(t.sampler.wrap_v) << 2)
            | bit(t.sampler.mag_filter == Filter::Nearest, SAMPLER_NEAREST),
        pad: 0,
        transform_m: [m.x_axis.x, m.x_axis.y, m.y_axis.x, m.y_axis.y],
        transform_t: [
            t.transform.translation.x,
            t.transform.translation.y,
            0.0,
            0.0,
        ],
    }
}

/// One material's record.
pub fn material(m: &Material) -> GpuMaterial {
    let (mask, cutoff) = match m.alpha_mode {
        AlphaMode::Mask { cutoff } => (MATERIAL_ALPHA_MASK, cutoff),
        AlphaMode::Blend => (MATERIAL_ALPHA_BLEND, 0.0),
        AlphaMode::Opaque => (0, 0.0),
    };
    GpuMaterial {
        base_color: m.base_color.to_array(),
        emission: m.emitted_radiance().to_array(),
        alpha_cutoff: cutoff,
        metallic: m.metallic,
        roughness: m.roughness,
        f0_dielectric: m.dielectric_f0(),
        absorption: m.absorption,
        normal_scale: m.normal_scale,
        flags: mask
            | bit(m.shades_both_sides(), MATERIAL_DOUBLE_SIDED)
            | bit(m.volume.is_some(), MATERIAL_VOLUME),
        specular: m.specular,
        clearcoat: m.clearcoat,
        specular_color: m.specular_color.to_array(),
        clearcoat_roughness: m.clearcoat_roughness,
        sheen_color: m.sheen_color.to_array(),
        sheen_roughness: m.sheen_roughness,
        transmission: m.transmission,
        ior: m.ior,
        clearcoat_normal_scale: m.clearcoat_normal_scale,
        pad1: 0,
        attenuation: m
            .volume
            .map_or(Vec3::ZERO, |v| v.attenuation_coefficient())
            .to_array(),
        pad2: 0,
        base_color_texture: slot(&m.base_color_texture),
        metallic_roughness_texture: slot(&m.metallic_roughness_texture),
        normal_texture: slot(&m.normal_texture),
        emissive_texture: slot(&m.emissive_texture),
        specular_texture: slot(&m.layer_textures.specular),
        specular_color_texture: slot(&m.layer_textures.specular_color),
        clearcoat_texture: slot(&m.layer_textures.clearcoat),
        clearcoat_roughness_texture: slot(&m.layer_textures.clearcoat_roughness),
        transmission_texture: slot(&m.layer_textures.transmission),
        sheen_color_texture: slot(&m.layer_textures.sheen_color),
        sheen_roughness_texture: slot(&m.layer_textures.sheen_roughness),
        clearcoat_normal_texture: slot(&m.clearcoat_normal_texture),
    }
}

/// Every material's record, indexed by material id.
pub fn materials(materials: &Materials) -> Vec<GpuMaterial> {
    materials.iter().map(|(_, m)| material(m)).collect()
}

/// The texel atlas (one packed RGBA8 texel per `u32`) and the per-texture table.
pub fn textures(textures: &Textures) -> (Vec<u32>, Vec<GpuTextureInfo>) {
    let mut texels = Vec::new();
    let mut table = Vec::new();
    for (_, t) in textures.iter() {
        table.push(GpuTextureInfo {
            offset: texels.len() as u32,
            width: t.width,
            height: t.height,
            srgb: u32::from(t.color_space == ColorSpace::Srgb),
        });
        texels.extend(
            t.rgba8
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
        );
    }
    (texels, table)
}

/// A CDF over `weights` (entry i holds the sum up to and including i, over the total) and
/// each entry's probability; empty when the weights sum to zero.
fn cdf(weights: &[f64]) -> Vec<(f32, f32)> {
    let total: f64 = weights.iter().sum();
    if total <= 0.0 || !total.is_finite() {
        return Vec::new();
    }
    let mut running = 0.0;
    let last_positive = weights.iter().rposition(|&w| w > 0.0).unwrap_or(0);
    weights
        .iter()
        .enumerate()
        .map(|(i, &w)| {
            running += w;
            let c = if i >= last_positive {
                1.0
            } else {
                (running / total) as f32
            };
            (c, (w / total) as f32)
        })
        .collect()
}

/// The punctual lights with their power-proportional selection CDF (powers as the CPU
/// reference's light table defines them; `radius` is the scene's bounding radius), the light
/// tree's bounds of each (`None` for directional lights, which no tree holds) and the
/// directional lights' share of the power.
pub fn lights<'a>(
    all: impl Iterator<Item = (&'a Light, &'a GlobalTransform)>,
    radius: f32,
) -> (Vec<GpuLight>, Vec<Option<LightBounds>>, f32) {
    let mut out = Vec::new();
    let mut powers = Vec::new();
    let mut bounds = Vec::new();
    for (light, global) in all {
        let intensity = light.radiant_intensity();
        let axis = global
            .transform_vector(Vec3::NEG_Z)
            .normalize_or(Vec3::NEG_Z);
        let position = global.translation();
        let mut record = GpuLight {
            position: position.to_array(),
            direction: axis.to_array(),
            range: light.range.unwrap_or(f32::INFINITY),
            intensity: intensity.to_array(),
            ..GpuLight::default()
        };
        let (power, extent) = match light.kind {
            LightKind::Point => {
                record.kind = LIGHT_POINT;
                let power = 4.0 * PI * luminance(intensity);
                (power, Some(LightBounds::point(position, power)))
            }
            LightKind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                record.kind = LIGHT_SPOT;
                record.inner = inner_cone_angle;
                record.outer = outer_cone_angle;
                let power = 2.0
                    * PI
                    * (1.0 - (0.5 * (inner_cone_angle + outer_cone_angle)).cos())
                    * luminance(intensity);
                let extent = LightBounds::spot(position, axis, outer_cone_angle, power);
                (power, Some(extent))
            }
            LightKind::Directional => {
                record.kind = LIGHT_DIRECTIONAL;
                (PI * radius * radius * luminance(intensity), None)
            }
        };
        if power > 0.0 && power.is_finite() {
            out.push(record);
            powers.push(f64::from(power));
            bounds.push(extent);
        }
    }
    for (light, (c, p)) in out.iter_mut().zip(cdf(&powers)) {
        light.cdf = c;
        light.pmf = p;
    }
    let directional: Vec<f64> = powers
        .iter()
        .zip(&bounds)
        .map(|(&p, b)| if b.is_none() { p } else { 0.0 })
        .collect();
    for (light, (c, _)) in out.iter_mut().zip(cdf(&directional)) {
        light.directional_cdf = c;
    }
    let total: f64 = powers.iter().sum();
    let share = if total > 0.0 {
        (directional.iter().sum::<f64>() / total) as f32
    } else {
        0.0
    };
    (out, bounds, share)
}

/// The scene's bounding radius (1 when empty), as the CPU reference computes it.
pub fn scene_radius(bvh: &SceneBvh) -> f32 {
    let bounds = bvh.bounds();
    if bounds.is_empty() {
        1.0
    } else {
        (0.5 * bounds.size().length()).max(1e-3)
    }
}

/// The area-light table (every emissive triangle of every instance, then the environment unless
/// it is constant: [`Environment::light_sampling_radiance`]),
/// each instance's first entry ([`NO_INDEX`] when it does not emit), the environment's
/// probability, and the light tree's bounds of each triangle (entries `0..n` of the table, in
/// its order: front faces as the CPU reference orients them).
pub fn area_lights(
    bvh: &SceneBvh,
    meshes: &Meshes,
    materials: &Materials,
    environment: &Environment,
) -> (Vec<GpuAreaLight>, Vec<u32>, f32, Vec<LightBounds>) {
    let mut entries = Vec::new();
    let mut powers = Vec::new();
    let mut bounds = Vec::new();
    let mut first = vec![NO_INDEX; bvh.instances().len()];
    for (index, record) in bvh.instances().iter().enumerate() {
        let (Some(mesh), Some(material)) =
            (meshes.get(record.mesh), materials.get(record.material))
        else {
            continue;
        };
        let radiance = luminance(material.emitted_radiance());
        if radiance <= 0.0 {
            continue;
        }
        first[index] = entries.len() as u32;
        let sides = if material.shades_both_sides() {
            2.0
        } else {
            1.0
        };
        let mirrored = record.world.matrix3.determinant() < 0.0;
        for triangle in 0..mesh.triangle_count() as u32 {
            let v = bvh
                .world_triangle(index as u32, triangle)
                .map(|[a, b, c]| if mirrored { [a, c, b] } else { [a, b, c] })
                .unwrap_or([Vec3::ZERO; 3]);
            let power = PI * sides * radiance * 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length();
            entries.push(GpuAreaLight {
                instance: index as u32,
                triangle,
                ..GpuAreaLight::default()
            });
            powers.push(f64::from(power));
            bounds.push(LightBounds::triangle(
                v,
                power,
                material.shades_both_sides(),
            ));
        }
    }
    let radius = scene_radius(bvh);
    let env_power =
        4.0 * PI * PI * radius * radius * luminance(environment.light_sampling_radiance());
    if env_power > 0.0 && env_power.is_finite() {
        entries.push(GpuAreaLight {
            instance: NO_INDEX,
            ..GpuAreaLight::default()
        });
        powers.push(f64::from(env_power));
    }
    let table = cdf(&powers);
    if table.is_empty() {
        return (Vec::new(), vec![NO_INDEX; first.len()], 0.0, Vec::new());
    }
    for (e, (c, p)) in entries.iter_mut().zip(table) {
        e.cdf = c;
        e.pmf = p;
    }
    let env_pmf = entries
        .last()
        .filter(|e| e.instance == NO_INDEX)
        .map_or(0.0, |e| e.pmf);
    (entries, first, env_pmf, bounds)
}

/// chiaro_shading's `Distribution1D` over `weights` as its arrays: the CDF (`n + 1` entries,
/// 0 first, 1 from the last positive weight on) and the masses; `None` when the weights sum
/// to zero.
fn distribution_1d(weights: &[f32]) -> Option<(Vec<f32>, Vec<f32>)> {
    let total: f64 = weights.iter().map(|&w| f64::from(w)).sum();
    if total <= 0.0 || !(total as f32).is_finite() {
        return None;
    }
    let mut cdf = Vec::with_capacity(weights.len() + 1);
    cdf.push(0.0);
    let mut running = 0.0f64;
    for &w in weights {
        running += f64::from(w);
        cdf.push((running / total) as f32);
    }
    let last_positive = weights.iter().rposition(|&w| w > 0.0).unwrap_or(0);
    for c in &mut cdf[last_positive + 1..] {
        *c = 1.0;
    }
    let inv_total = 1.0 / total;
    let pmf = weights
        .iter()
        .map(|&w| (f64::from(w) * inv_total) as f32)
        .collect();
    Some((cdf, pmf))
}

/// `values` four to a texel, the last texel padded with zeros.
pub(super) fn four_to_a_texel<T: Copy + Default>(values: &[T]) -> Vec<[T; 4]> {
    values
        .chunks(4)
        .map(|c| std::array::from_fn(|k| c.get(k).copied().unwrap_or_default()))
        .collect()
}

/// The environment: its texels (radiance x strength, `w` zero), its importance table and the
/// header fields of [`GpuSceneInfo`]. The table holds chiaro_shading's `Distribution2D` over
/// luminance x sin(theta) as arrays, for a `width` w x `height` h image: the marginal CDF
/// (h + 1 entries) at 0, the marginal masses (h) at h + 1, the conditional CDFs (w + 1 per
/// row) at 2h + 1, then the conditional masses (w per row) at 2h + 1 + h (w + 1); entry `i` is
/// component `i % 4` of texel `i / 4` (the last texel padded with zeros).
pub fn environment(
    environment: &Environment,
    info: &mut GpuSceneInfo,
) -> (Vec<[f32; 4]>, Vec<[f32; 4]>) {
    let strength = if environment.strength.is_finite() && environment.strength > 0.0 {
        environment.strength
    } else {
        0.0
    };
    let rotation = if environment.rotation.is_finite() {
        environment.rotation
    } else {
        0.0
    };
    let (s, c) = rotation.sin_cos();
    info.env_cos_rotation = c;
    info.env_sin_rotation = s;
    let sanitize = |v: Vec3| {
        Vec3::from_array(
            v.to_array()
                .map(|x| if x.is_finite() && x > 0.0 { x } else { 0.0 }),
        )
    };
    match &environment.source {
        EnvironmentSource::Constant(radiance) => {
            let radiance = sanitize(*radiance) * strength;
            info.env_radiance = radiance.to_array();
            info.env_kind = if radiance.max_element() > 0.0 {
                ENV_CONSTANT
            } else {
                ENV_BLACK
            };
            (Vec::new(), Vec::new())
        }
        EnvironmentSource::Equirect(image) => {
            let (w, h) = (image.width as usize, image.height as usize);
            let texels: Vec<Vec3> = image
                .texels
                .iter()
                .map(|&t| sanitize(t) * strength)
                .collect();
            let weights: Vec<f32> = texels
                .iter()
                .enumerate()
                .map(|(i, &t)| {
                    let theta = ((i / w.max(1)) as f32 + 0.5) / h as f32 * PI;
                    luminance(t) * theta.sin()
                })
                .collect();
            let packed = texels.iter().map(|t| t.extend(0.0).to_array()).collect();
            info.env_width = w as u32;
            info.env_height = h as u32;
            info.env_kind = ENV_BLACK;
            if w == 0 || h == 0 || texels.len() != w * h {
                return (Vec::new(), Vec::new());
            }
            let uniform = vec![1.0; w];
            let mut row_sums = Vec::with_capacity(h);
            let mut cdfs = Vec::with_capacity(h * (w + 1));
            let mut pmfs = Vec::with_capacity(h * w);
            for row in weights.chunks_exact(w) {
                row_sums.push(row.iter().map(|&x| f64::from(x)).sum::<f64>() as f32);
                let (cdf, pmf) = distribution_1d(row)
                    .or_else(|| distribution_1d(&uniform))
                    .expect("a uniform row has weight");
                cdfs.extend(cdf);
                pmfs.extend(pmf);
            }
            let Some((marginal_cdf, marginal_pmf)) = distribution_1d(&row_sums) else {
                return (packed, Vec::new());
            };
            info.env_kind = ENV_IMAGE;
            let mut table = marginal_cdf;
            table.extend(marginal_pmf);
            table.extend(cdfs);
            table.extend(pmfs);
            (packed, four_to_a_texel(&table))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn consecutive_instances_of_one_mesh_share_a_draw() {
        let runs = mesh_runs([4, 4, 4, 1, 4, 4, 2].into_iter());
        assert_eq!(runs, vec![(4, 0..3), (1, 3..4), (4, 4..6), (2, 6..7)]);
        assert!(mesh_runs(std::iter::empty()).is_empty());
    }

    #[test]
    fn colours_pack_as_unorm16_red_low() {
        assert_eq!(pack_color(Vec4::ONE), [u32::MAX; 2]);
        assert_eq!(
            pack_color(Vec4::new(1.0, 0.0, 0.5, 2.0)),
            [0x0000_ffff, 0xffff_8000]
        );
    }

    #[test]
    fn four_values_to_a_texel_in_order_the_last_padded() {
        let values: Vec<f32> = (1..=6).map(|i| i as f32).collect();
        assert_eq!(
            four_to_a_texel(&values),
            vec![[1.0, 2.0, 3.0, 4.0], [5.0, 6.0, 0.0, 0.0]]
        );
        assert_eq!(four_to_a_texel(&values[..4]).len(), 1);
        assert!(four_to_a_texel::<f32>(&[]).is_empty());
    }

    #[test]
    fn distribution_matches_chiaro_shading() {
        let weights = [0.5, 0.0, 2.0, 1.5, 0.0];
        let d = chiaro_shading::distribution::Distribution1D::new(&weights).unwrap();
        let (cdf, pmf) = distribution_1d(&weights).unwrap();
        assert_eq!(cdf.len(), 6);
        for (i, p) in pmf.iter().enumerate() {
            assert_eq!(*p, d.pmf(i));
        }
        for u in [0.0, 0.1, 0.2, 0.5, 0.9, 0.999] {
            let (index, _) = d.sample(u);
            // The CPU picks the largest index whose CDF entry is at most u.
            let mine = cdf[1..weights.len()].partition_point(|&c| c <= u);
            assert_eq!(index, mine, "u = {u}");
        }
        assert!(distribution_1d(&[0.0]).is_none());
    }

    #[test]
    fn cdf_ends_at_one_and_skips_trailing_zeros() {
        let t = cdf(&[1.0, 3.0, 0.0]);
        assert_eq!(t.iter().map(|e| e.0).collect::<Vec<_>>(), [0.25, 1.0, 1.0]);
        assert_eq!(t.iter().map(|e| e.1).collect::<Vec<_>>(), [0.25, 0.75, 0.0]);
        assert!(cdf(&[0.0, 0.0]).is_empty());
    }
}
