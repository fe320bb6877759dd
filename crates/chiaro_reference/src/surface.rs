//! What a ray hit: position, normals (geometric, interpolated, normal-mapped), UVs, and the
//! material evaluated there (textures included), in the form the BRDF and the lights take.
//!
//! Conventions: a triangle's front face is counter-clockwise, reversed when the instance's world
//! matrix has a negative determinant (glTF's rule). A back face of a single-sided material
//! absorbs everything (as a rasterizer culling it would show nothing behind it either). A
//! KHR_materials_volume mesh is a medium behind its front faces: a ray that hits a back face
//! has crossed it, and its transmission refracts into or out of it by the IOR.

use chiaro_bvh::{Hit, Ray};
use chiaro_scene::{AlphaMode, Material, Mesh};
use chiaro_shading::brdf::SurfaceParams;
use chiaro_shading::coverage;
use chiaro_shading::frame::Frame;
use chiaro_shading::shading_normal::valid_reflection_normal;
use glam::{Vec2, Vec3, Vec4};

use crate::scene::RenderScene;
use crate::texture_sampling::sample_slot;

/// The shading data at a hit.
#[derive(Clone, Debug)]
pub struct SurfaceHit {
    /// World position.
    pub position: Vec3,
    /// Unit geometric normal on the side the ray arrived from.
    pub geometric_normal: Vec3,
    /// Shading frame (interpolated and normal-mapped normal), on the same side.
    pub frame: Frame,
    /// False for the back face of a single-sided material: nothing is reflected or emitted.
    pub shades: bool,
    /// The BRDF parameters there.
    pub params: SurfaceParams,
    /// Radiance emitted toward the ray's origin.
    pub emission: Vec3,
    /// The attenuation coefficient of the medium the ray crossed to get here: a
    /// KHR_materials_volume's when the ray hit its back face from inside, else zero.
    pub medium: Vec3,
    /// The attenuation coefficient on the far side of the surface from the ray: a
    /// KHR_materials_volume's when the ray hit its front face from outside, else zero.
    pub far_medium: Vec3,
}

/// The three world-space vertices of `triangle` of `mesh` under `world`, reordered so that
/// their counter-clockwise normal is the front face's even under a mirroring transform.
pub fn world_triangle(mesh: &Mesh, triangle: u32, world: &glam::Affine3A) -> [Vec3; 3] {
    let i = triangle as usize * 3;
    let idx = &mesh.indices()[i..i + 3];
    let p = [0, 1, 2].map(|k| world.transform_point3(mesh.positions()[idx[k] as usize]));
    if world.matrix3.determinant() < 0.0 {
        [p[0], p[2], p[1]]
    } else {
        p
    }
}

fn interpolate<T>(values: &[T], idx: &[u32], b: Vec3) -> T
where
    T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    values[idx[0] as usize] * b.x + values[idx[1] as usize] * b.y + values[idx[2] as usize] * b.z
}

/// The UVs (sets 0 and 1) at barycentrics `b` of `triangle`.
pub fn uvs_at(mesh: &Mesh, triangle: u32, b: Vec3) -> [Option<Vec2>; 2] {
    let i = triangle as usize * 3;
    let idx = &mesh.indices()[i..i + 3];
    [
        mesh.uv(0).map(|uv| interpolate(uv, idx, b)),
        mesh.uv(1).map(|uv| interpolate(uv, idx, b)),
    ]
}

/// The vertex colour at barycentrics `b` of `triangle`: white and opaque without colours.
pub fn vertex_color_at(mesh: &Mesh, triangle: u32, b: Vec3) -> Vec4 {
    let i = triangle as usize * 3;
    mesh.colors()
        .map_or(Vec4::ONE, |c| interpolate(c, &mesh.indices()[i..i + 3], b))
}

/// The base colour and alpha of `material` at barycentrics `b` of `triangle` of `mesh`, with UVs
/// `uvs` there: factor x texture x vertex colour (glTF 2.0's base colour).
pub fn base_color_at(
    scene: &RenderScene,
    material: &Material,
    mesh: &Mesh,
    triangle: u32,
    b: Vec3,
    uvs: [Option<Vec2>; 2],
) -> Vec4 {
    let texture = material
        .base_color_texture
        .as_ref()
        .and_then(|slot| sample_slot(scene.textures, slot, uvs))
        .unwrap_or(Vec4::ONE);
    material.base_color * texture * vertex_color_at(mesh, triangle, b)
}

fn barycentrics(hit: &Hit) -> Vec3 {
    Vec3::new(
        1.0 - hit.barycentrics.x - hit.barycentrics.y,
        hit.barycentrics.x,
        hit.barycentrics.y,
    )
}

/// Emitted radiance of `material` at UVs `uvs` (factor x strength x emissive texture).
pub fn emission_at(scene: &RenderScene, material: &Material, uvs: [Option<Vec2>; 2]) -> Vec3 {
    let texture = material
        .emissive_texture
        .as_ref()
        .and_then(|slot| sample_slot(scene.textures, slot, uvs))
        .map_or(Vec3::ONE, |t| t.truncate());
    material.emitted_radiance() * texture
}

/// Whether candidate `hit` of `ray` stops it: false where an alpha-masked material is cut
/// away; for an alpha-blended one, true with probability alpha, decided by the coverage number
/// of the ray and triangle (`chiaro_shading::coverage`).
pub fn stops_ray(scene: &RenderScene, ray: &Ray, hit: &Hit) -> bool {
    let record = &scene.bvh.instances()[hit.instance as usize];
    let Some(material) = scene.materials.get(record.material) else {
        return true;
    };
    if material.alpha_mode == AlphaMode::Opaque {
        return true;
    }
    let Some(mesh) = scene.meshes.get(record.mesh) else {
        return true;
    };
    let b = barycentrics(hit);
    let uvs = uvs_at(mesh, hit.triangle, b);
    let alpha = base_color_at(scene, material, mesh, hit.triangle, b, uvs).w;
    match material.alpha_mode {
        AlphaMode::Mask { cutoff } => alpha >= cutoff,
        _ => coverage::stops(
            alpha,
            coverage::ray_number(ray.origin, ray.direction, hit.instance, hit.triangle),
        ),
    }
}

/// The coverage a light sample on an alpha-blended emitter is weighted by: alpha there (the
/// share of rays it stops, so of the rays that see its emission); 1 for other materials.
pub fn emitter_coverage(
    scene: &RenderScene,
    material: &Material,
    mesh: &Mesh,
    triangle: u32,
    b: Vec3,
) -> f32 {
    if material.alpha_mode != AlphaMode::Blend {
        return 1.0;
    }
    let uvs = uvs_at(mesh, triangle, b);
    base_color_at(scene, material, mesh, triangle, b, uvs)
        .w
        .clamp(0.0, 1.0)
}

/// Tangent-space normal mapping at one point: glTF 2.0's normal textures (the base's and
/// KHR_materials_clearcoat's) in the frame of the interpolated normal and tangent.
struct NormalMap<'a> {
    scene: &'a RenderScene<'a>,
    uvs: [Option<Vec2>; 2],
    /// The unit interpolated normal, front side, world space.
    interpolated: Vec3,
    /// The world tangent and the bitangent's sign (the mirroring transform's included), when
    /// the mesh has tangents.
    tangent: Option<(Vec3, f32)>,
}

impl NormalMap<'_> {
    /// The interpolated normal bent by the texture in `slot` with XY scaled by `scale`; the
    /// interpolated normal itself without a texture, a texel or tangents.
    fn apply(&self, slot: &Option<chiaro_scene::TextureRef>, scale: f32) -> Vec3 {
        let n = self.interpolated;
        let (Some(slot), Some((tangent, sign))) = (slot, self.tangent) else {
            return n;
        };
        let Some(texel) = sample_slot(self.scene.textures, slot, self.uvs) else {
            return n;
        };
        let tangent = (tangent - n * n.dot(tangent)).normalize_or_zero();
        if tangent == Vec3::ZERO {
            return n;
        }
        let bitangent = n.cross(tangent) * sign;
        let m = (texel.truncate() * 2.0 - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
        (tangent * m.x + bitangent * m.y + n * m.z).normalize_or(n)
    }
}

/// A shading normal (already turned to the viewer's side of the surface) made usable: the
/// geometric normal where it faces away from `view`, then turned so that the mirror
/// reflection of `view` leaves the surface ([`valid_reflection_normal`]).
fn facing_normal(geometric: Vec3, view: Vec3, normal: Vec3) -> Vec3 {
    let normal = if normal.dot(view) <= 0.0 {
        geometric
    } else {
        normal
    };
    valid_reflection_normal(geometric, view, normal)
}

/// Evaluates the surface at `hit` of `ray`.
pub fn surface_at(scene: &RenderScene, ray: &Ray, hit: &Hit) -> SurfaceHit {
    let record = &scene.bvh.instances()[hit.instance as usize];
    let mesh = scene
        .meshes
        .get(record.mesh)
        .expect("the BVH only holds stored meshes");
    let material = scene
        .materials
        .get(record.material)
        .unwrap_or(&scene.default_material);
    let b = barycentrics(hit);
    let i = hit.triangle as usize * 3;
    let idx = &mesh.indices()[i..i + 3];
    // Interpolated from the vertices, not origin + t * direction: far from the ray's origin the
    // latter can land further from the surface than the secondary-ray offset reaches.
    let position = scene
        .bvh
        .hit_point(hit)
        .unwrap_or(ray.origin + ray.direction * hit.t);

    let v = world_triangle(mesh, hit.triangle, &record.world);
    let geometric_front = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or(Vec3::Z);
    let front_facing = ray.direction.dot(geometric_front) < 0.0;
    let normal_matrix = record.inverse.matrix3.transpose();
    let interpolated_front =
        (normal_matrix * interpolate(mesh.normals(), idx, b)).normalize_or(geometric_front);

    let uvs = uvs_at(mesh, hit.triangle, b);
    let sample = |slot: &Option<chiaro_scene::TextureRef>| {
        slot.as_ref()
            .and_then(|s| sample_slot(scene.textures, s, uvs))
            .unwrap_or(Vec4::ONE)
    };
    let tangent = mesh.tangents().map(|tangents| {
        let t = interpolate(tangents, idx, b);
        let sign = t.w.signum() * record.world.matrix3.determinant().signum();
        (record.world.matrix3 * t.truncate(), sign)
    });
    let normal_map = NormalMap {
        scene,
        uvs,
        interpolated: interpolated_front,
        tangent,
    };
    let shading_front = normal_map.apply(&material.normal_texture, material.normal_scale);

    let side = if front_facing { 1.0 } else { -1.0 };
    let geometric_normal = geometric_front * side;
    let view = -ray.direction;
    let shading_normal = facing_normal(geometric_normal, view, shading_front * side);
    let frame = Frame::from_normal(shading_normal);
    // KHR_materials_clearcoat: the coat takes its own normal map, or the interpolated normal
    // (the base's normal map does not reach it).
    let coat_front = normal_map.apply(
        &material.clearcoat_normal_texture,
        material.clearcoat_normal_scale,
    );
    let coat_normal = if material.clearcoat <= 0.0 || coat_front == shading_front {
        Vec3::Z
    } else {
        frame.to_local(facing_normal(geometric_normal, view, coat_front * side))
    };
    let shades = front_facing || material.shades_both_sides();

    let base = base_color_at(scene, material, mesh, hit.triangle, b, uvs);
    let metallic_roughness = sample(&material.metallic_roughness_texture);
    // The extensions' textures multiply their factors, each in the channel its extension names.
    let layers = &material.layer_textures;
    let params = SurfaceParams {
        base_color: base.truncate(),
        metallic: (material.metallic * metallic_roughness.z).clamp(0.0, 1.0),
        roughness: (material.roughness * metallic_roughness.y).clamp(0.0, 1.0),
        f0_dielectric: material.dielectric_f0(),
        specular: material.specular * sample(&layers.specular).w,
        specular_color: material.specular_color * sample(&layers.specular_color).truncate(),
        clearcoat: material.clearcoat * sample(&layers.clearcoat).x,
        clearcoat_roughness: material.clearcoat_roughness * sample(&layers.clearcoat_roughness).y,
        transmission: material.transmission * sample(&layers.transmission).x,
        sheen_color: material.sheen_color * sample(&layers.sheen_color).truncate(),
        sheen_roughness: material.sheen_roughness * sample(&layers.sheen_roughness).w,
        absorption: material.absorption,
        eta: match material.volume {
            Some(_) if front_facing => material.ior,
            Some(_) => 1.0 / material.ior,
            None => 0.0,
        },
        coat_normal,
    };
    let interior = material
        .volume
        .map_or(Vec3::ZERO, |volume| volume.attenuation_coefficient());
    let (medium, far_medium) = if front_facing {
        (Vec3::ZERO, interior)
    } else {
        (interior, Vec3::ZERO)
    };
    let emission = if shades {
        emission_at(scene, material, uvs)
    } else {
        Vec3::ZERO
    };
    SurfaceHit {
        position,
        geometric_normal,
        frame,
        shades,
        params,
        emission,
        medium,
        far_medium,
    }
}

#[cfg(test)]
mod coat_normal_tests;
