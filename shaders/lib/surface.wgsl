// Shading points, as chiaro_reference's surface module builds them: the surface the G-buffer
// holds at a pixel, or the surface a ray hits (world position interpolated from the triangle's
// vertices, interpolated and normal-mapped shading normal, textured material, front face
// counter-clockwise and clockwise under a mirroring transform); the world triangles and the
// emission of instances; the origin of a ray leaving a surface (Wachter and Binder, "A Fast
// and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems, 2019, in offset.wgsl).

#import lib/generated.wgsl
#import lib/alpha.wgsl
#import lib/base_color.wgsl
#import lib/bvh.wgsl
#import lib/scene_bindings.wgsl
#import lib/textures.wgsl
#import lib/features.wgsl
#import lib/frame.wgsl
#import lib/brdf.wgsl
#import lib/offset.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/shading_normals.wgsl
#import lib/layer_textures.wgsl

// A point that reflects light: where, its normals (the shading frame's z is the shading
// normal; both on the side the view arrives from), the direction toward the viewer in the
// local frame and the BRDF's parameters.
struct Shading {
    position: vec3<f32>,
    geometric_normal: vec3<f32>,
    frame: Frame,
    wo: vec3<f32>,
    params: SurfaceParams,
}

// The world vertices of a triangle of an instance, reordered (1 <-> 2) under a mirroring
// transform so that the counter-clockwise normal is the front face's.
struct WorldTriangle {
    v0: vec3<f32>,
    v1: vec3<f32>,
    v2: vec3<f32>,
    indices: vec3<u32>,
    mirrored: bool,
}

fn world_triangle(instance: u32, triangle: u32) -> WorldTriangle {
    let record = bvh_load_instance_whole(instance);
    let i = scene_triangle_indices(record.mesh, triangle);
    let m = record.object_to_world;
    let p0 = bvh_transform_point(m, scene_vertex(i.x).position);
    let p1 = bvh_transform_point(m, scene_vertex(i.y).position);
    let p2 = bvh_transform_point(m, scene_vertex(i.z).position);
    let mirrored = scene_instance_extras[instance].mirrored != 0u;
    if mirrored {
        return WorldTriangle(p0, p2, p1, i, true);
    }
    return WorldTriangle(p0, p1, p2, i, false);
}

// The mesh-order barycentrics (of the mesh's vertices 1 and 2) of world point p, projected
// onto the triangle's plane.
fn world_triangle_barycentrics(t: WorldTriangle, p: vec3<f32>) -> vec2<f32> {
    let e1 = select(t.v1, t.v2, t.mirrored) - t.v0;
    let e2 = select(t.v2, t.v1, t.mirrored) - t.v0;
    let d = p - t.v0;
    let d11 = dot(e1, e1);
    let d12 = dot(e1, e2);
    let d22 = dot(e2, e2);
    let det = d11 * d22 - d12 * d12;
    if !(det > 0.0) {
        return vec2<f32>(1.0 / 3.0);
    }
    return vec2<f32>(d22 * dot(d, e1) - d12 * dot(d, e2), d11 * dot(d, e2) - d12 * dot(d, e1))
        / det;
}

// The world point at mesh-order barycentrics b (of the mesh's vertices 1 and 2).
fn world_triangle_point(t: WorldTriangle, b: vec2<f32>) -> vec3<f32> {
    let m1 = select(t.v1, t.v2, t.mirrored);
    let m2 = select(t.v2, t.v1, t.mirrored);
    return t.v0 * (1.0 - b.x - b.y) + m1 * b.x + m2 * b.y;
}

// Emitted radiance of an instance's material at mesh-order barycentrics b.
fn emission_at(instance: u32, indices: vec3<u32>, b: vec2<f32>) -> vec3<f32> {
    let record = bvh_load_instance_whole(instance);
    let material = scene_material(record.material);
    let texel = texture_sample_feature(FEATURE_EMISSIVE_TEXTURES, material.emissive_texture, scene_uvs(indices, b),
        scene_meshes[record.mesh].flags, vec4<f32>(1.0));
    return material.emission * texel.xyz;
}

// The shading point of a covered, shading G-buffer texel seen by `camera`, on triangle
// `triangle` of its instance's mesh (where the extensions' textures are read).
fn gbuffer_shading(g: GbufferSurface, triangle: u32, camera: GpuCamera) -> Shading {
    let record = bvh_load_instance_whole(g.instance);
    let material = scene_material(record.material);
    var s: Shading;
    s.position = g.position;
    s.geometric_normal = g.geometric_normal;
    s.frame = frame_from_normal(g.shading_normal);
    let to_eye = select(normalize(camera.origin - g.position), -camera.forward,
        camera.orthographic != 0u);
    s.wo = frame_to_local(s.frame, to_eye);
    s.params = SurfaceParams(g.base_color, g.metallic, g.roughness, material.f0_dielectric,
        material.specular, material.specular_color, material.clearcoat,
        material.clearcoat_roughness, material.transmission, material.sheen_color,
        material.sheen_roughness, material.absorption,
        volume_eta(material, !g.back_face), vec3<f32>(0.0, 0.0, 1.0));
    let mesh_flags = scene_meshes[record.mesh].flags;
    // The coat's normal differs from the shading normal only where a normal map bends one.
    let coat_normal = FEATURE_CLEARCOAT && FEATURE_NORMAL_MAPS && material.clearcoat > 0.0
        && (mesh_flags & MESH_HAS_TANGENTS) != 0u
        && (material.normal_texture.texture != NO_INDEX
            || material.clearcoat_normal_texture.texture != NO_INDEX);
    if FEATURE_LAYER_TEXTURES || coat_normal {
        let t = world_triangle(g.instance, triangle);
        let b = world_triangle_barycentrics(t, g.position);
        let uvs = scene_uvs(t.indices, b);
        s.params = layer_textured(s.params, material, uvs, mesh_flags);
        if coat_normal {
            let n = interpolated_normals(g.instance, t, b);
            let geometric_front = safe_normalize(cross(t.v1 - t.v0, t.v2 - t.v0),
                vec3<f32>(0.0, 0.0, 1.0));
            let shading_front = mapped_shading_normal(material, mesh_flags, uvs, n.normal,
                n.tangent, t.mirrored, geometric_front);
            s.params.coat_normal = coat_normal_in_frame(material, mesh_flags, uvs, n, t.mirrored,
                geometric_front, shading_front, s.geometric_normal, -to_eye, s.frame);
        }
    }
    return s;
}

// A triangle's world normal (any length) and tangent (the bitangent's sign in w) interpolated
// at mesh-order barycentrics.
struct InterpolatedNormals {
    normal: vec3<f32>,
    tangent: vec4<f32>,
}

fn interpolated_normals(instance: u32, t: WorldTriangle, b: vec2<f32>) -> InterpolatedNormals {
    let record = bvh_load_instance_whole(instance);
    let w = vec3<f32>(1.0 - b.x - b.y, b.x, b.y);
    let v0 = scene_vertex(t.indices.x);
    let v1 = scene_vertex(t.indices.y);
    let v2 = scene_vertex(t.indices.z);
    let normal = v0.normal * w.x + v1.normal * w.y + v2.normal * w.z;
    let tangent = v0.tangent * w.x + v1.tangent * w.y + v2.tangent * w.z;
    // The inverse transpose applied to the normal: the rows of world-to-object as columns.
    let n2o = record.world_to_object;
    var n: InterpolatedNormals;
    n.normal = n2o[0].xyz * normal.x + n2o[1].xyz * normal.y + n2o[2].xyz * normal.z;
    n.tangent = vec4<f32>(bvh_transform_vector(record.object_to_world, tangent.xyz), tangent.w);
    return n;
}

// KHR_materials_clearcoat's coat normal in `frame` (chiaro_reference's surface_at): the
// interpolated normal bent by the coat's own normal map, turned like the shading normal for a
// view travelling along `incoming` (`geometric`: the geometric normal on the viewer's side);
// +z where it is `shading_front` itself (no map bends either) or without a coat.
fn coat_normal_in_frame(
    material: GpuMaterial,
    mesh_flags: u32,
    uvs: vec4<f32>,
    n: InterpolatedNormals,
    mirrored: bool,
    geometric_front: vec3<f32>,
    shading_front: vec3<f32>,
    geometric: vec3<f32>,
    incoming: vec3<f32>,
    frame: Frame,
) -> vec3<f32> {
    if !FEATURE_CLEARCOAT || material.clearcoat <= 0.0 {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    // The coat's own normal texture; the base's normal map does not reach the coat.
    let coat_front = normal_mapped(material.clearcoat_normal_texture,
        material.clearcoat_normal_scale, mesh_flags, uvs, n.normal, n.tangent, mirrored,
        geometric_front);
    if all(coat_front == shading_front) {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    let side = select(-1.0, 1.0, dot(incoming, geometric_front) < 0.0);
    return frame_to_local(frame, facing_normal(geometric, normalize(-incoming), coat_front * side));
}

// KHR_materials_volume's relative IOR across a surface of `material` seen from its front
// (entering: the IOR) or back (leaving: its inverse); 0 for a thin-walled surface
// (chiaro_reference's surface_at).
fn volume_eta(material: GpuMaterial, front_facing: bool) -> f32 {
    if !FEATURE_VOLUMES || (material.flags & MATERIAL_VOLUME) == 0u {
        return 0.0;
    }
    return select(1.0 / material.ior, material.ior, front_facing);
}

// KHR_materials_volume: the transmittance exp(-attenuation d) of the segment from `origin` to
// `hit` along `direction` when it ends on a volume's back face (so it ran inside the medium),
// else 1 (chiaro_reference's radiance).
fn medium_transmittance(origin: vec3<f32>, direction: vec3<f32>, hit: Hit) -> vec3<f32> {
    if !FEATURE_VOLUMES || hit.instance == BVH_NO_HIT {
        return vec3<f32>(1.0);
    }
    let material = scene_material(bvh_load_instance_whole(hit.instance).material);
    if (material.flags & MATERIAL_VOLUME) == 0u {
        return vec3<f32>(1.0);
    }
    let t = world_triangle(hit.instance, hit.triangle);
    if dot(direction, cross(t.v1 - t.v0, t.v2 - t.v0)) <= 0.0 {
        return vec3<f32>(1.0);
    }
    let d = distance(world_triangle_point(t, hit.barycentrics), origin);
    return exp(-material.attenuation * d);
}

// The surface a ray hit; `shades` is false on the back face of a single-sided material
// (which reflects and emits nothing).
struct SurfaceHit {
    shading: Shading,
    shades: bool,
}

// The surface at `hit` of a ray travelling along `direction`.
fn surface_at_hit(direction: vec3<f32>, hit: Hit) -> SurfaceHit {
    let record = bvh_load_instance_whole(hit.instance);
    let material = scene_material(record.material);
    let mesh_flags = scene_meshes[record.mesh].flags;
    let t = world_triangle(hit.instance, hit.triangle);
    let b = hit.barycentrics;
    let w = vec3<f32>(1.0 - b.x - b.y, b.x, b.y);
    let v0 = scene_vertex(t.indices.x);
    let v1 = scene_vertex(t.indices.y);
    let v2 = scene_vertex(t.indices.z);
    let n = interpolated_normals(hit.instance, t, b);
    let uvs = scene_uvs(t.indices, b);
    let geometric_front = safe_normalize(cross(t.v1 - t.v0, t.v2 - t.v0), vec3<f32>(0.0, 0.0, 1.0));
    let shading_front = mapped_shading_normal(material, mesh_flags, uvs, n.normal, n.tangent,
        t.mirrored, geometric_front);
    let normals = orient_normals(geometric_front, shading_front, direction,
        (material.flags & MATERIAL_DOUBLE_SIDED) != 0u);
    let base = material_base_color(material, mesh_flags, uvs, vertex_color_of(v0, v1, v2, w));
    let metallic_roughness = texture_sample_feature(FEATURE_METALLIC_ROUGHNESS_TEXTURES,
        material.metallic_roughness_texture, uvs,
        mesh_flags, vec4<f32>(1.0));
    var s: Shading;
    s.position = world_triangle_point(t, b);
    s.geometric_normal = normals.geometric;
    s.frame = frame_from_normal(normals.shading);
    s.wo = frame_to_local(s.frame, -direction);
    s.params = SurfaceParams(base.xyz,
        clamp(material.metallic * metallic_roughness.z, 0.0, 1.0),
        clamp(material.roughness * metallic_roughness.y, 0.0, 1.0), material.f0_dielectric,
        material.specular, material.specular_color, material.clearcoat,
        material.clearcoat_roughness, material.transmission, material.sheen_color,
        material.sheen_roughness, material.absorption,
        volume_eta(material, dot(direction, geometric_front) < 0.0), vec3<f32>(0.0, 0.0, 1.0));
    s.params = layer_textured(s.params, material, uvs, mesh_flags);
    s.params.coat_normal = coat_normal_in_frame(material, mesh_flags, uvs, n, t.mirrored,
        geometric_front, shading_front, normals.geometric, direction, s.frame);
    return SurfaceHit(s, normals.shades);
}

// The shading-normal rule (chiaro_reference's on_its_side): a reflected direction (local_z
// > 0) must leave on the side the geometric normal (turned towards the viewer) faces, a
// transmitted one (local_z < 0) on the other; on the wrong side it carries nothing, whatever
// the shading normal says: a BSDF sample there ends the path, a light sample counts zero.
fn on_its_side(s: Shading, wi: vec3<f32>, local_z: f32) -> bool {
    let geometric = dot(wi, s.geometric_normal);
    if local_z > 0.0 {
        return geometric > 0.0;
    }
    return local_z < 0.0 && geometric < 0.0;
}

// A ray leaving the shading point along the world direction wi, its origin offset to the side
// of the geometric normal wi points to.
fn leaving_ray(s: Shading, wi: vec3<f32>) -> Ray {
    let side = select(-s.geometric_normal, s.geometric_normal, dot(wi, s.geometric_normal) >= 0.0);
    var ray: Ray;
    ray.origin = offset_ray_origin(s.position, side);
    ray.direction = wi;
    ray.t_min = 0.0;
    return ray;
}
