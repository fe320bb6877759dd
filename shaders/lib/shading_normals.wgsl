// A surface's normals as chiaro_reference's surface_at decides them, shared by the G-buffer
// (raster) and by surfaces found by rays: the normal map in the interpolated tangent frame
// (glTF 2.0 tangent-space normal textures, with normal_scale), then both normals turned to the
// side the view arrives from, the shading normal replaced by the geometric one where it faces
// away from the viewer. A back face of a single-sided material does not shade.

#import lib/generated.wgsl
#import lib/scene_bindings.wgsl
#import lib/textures.wgsl
#import lib/features.wgsl

// v / |v|, or `fallback` when the length is zero or not finite.
fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    return select(fallback, v / l, l > 0.0 && l < 3.0e38);
}

// The unit front-side shading normal: `interpolated` (world, any length; `geometric_front`
// where it degenerates) bent by the material's normal texture at `uvs` when the mesh has
// tangents. `tangent` is the world tangent with the bitangent sign in w; `mirrored` when the
// instance's transform mirrors.
fn mapped_shading_normal(
    material: GpuMaterial,
    mesh_flags: u32,
    uvs: vec4<f32>,
    interpolated: vec3<f32>,
    tangent: vec4<f32>,
    mirrored: bool,
    geometric_front: vec3<f32>,
) -> vec3<f32> {
    return normal_mapped(material.normal_texture, material.normal_scale, mesh_flags, uvs,
        interpolated, tangent, mirrored, geometric_front);
}

// `interpolated` (unit where it can be; `geometric_front` where it degenerates) bent by the
// tangent-space normal texture `slot` with XY scaled by `scale`, when the mesh has tangents.
fn normal_mapped(
    slot: GpuTextureSlot,
    scale: f32,
    mesh_flags: u32,
    uvs: vec4<f32>,
    interpolated: vec3<f32>,
    tangent: vec4<f32>,
    mirrored: bool,
    geometric_front: vec3<f32>,
) -> vec3<f32> {
    let n = safe_normalize(interpolated, geometric_front);
    if !FEATURE_NORMAL_MAPS || slot.texture == NO_INDEX
        || (mesh_flags & MESH_HAS_TANGENTS) == 0u {
        return n;
    }
    // Alpha -1 marks a lookup that found no texel (missing UV set or texture).
    let texel = texture_sample_slot(slot, uvs, mesh_flags, vec4<f32>(-1.0));
    let t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), vec3<f32>(0.0));
    if texel.w < 0.0 || all(t == vec3<f32>(0.0)) {
        return n;
    }
    let mirror = select(1.0, -1.0, mirrored);
    let bitangent = cross(n, t) * sign(tangent.w) * mirror;
    let m = (texel.xyz * 2.0 - 1.0) * vec3<f32>(scale, scale, 1.0);
    return safe_normalize(t * m.x + bitangent * m.y + n * m.z, n);
}

// Normals turned toward the viewer, and whether the surface shades.
struct OrientedNormals {
    geometric: vec3<f32>,
    shading: vec3<f32>,
    shades: bool,
}

// Both front-side unit normals turned to the side `incoming` (the direction of travel of the
// view ray) arrives from.
fn orient_normals(
    geometric_front: vec3<f32>,
    shading_front: vec3<f32>,
    incoming: vec3<f32>,
    double_sided: bool,
) -> OrientedNormals {
    let front_facing = dot(incoming, geometric_front) < 0.0;
    let side = select(-1.0, 1.0, front_facing);
    var o: OrientedNormals;
    o.geometric = geometric_front * side;
    o.shading = facing_normal(o.geometric, normalize(-incoming), shading_front * side);
    o.shades = front_facing || double_sided;
    return o;
}

// A normal already turned to the viewer's side made usable (chiaro_reference's
// facing_normal): the geometric normal where it faces away from `view`, then turned so that
// the mirror reflection of `view` leaves the surface (valid_reflection_normal).
fn facing_normal(geometric: vec3<f32>, view: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    let n = select(normal, geometric, dot(normal, view) <= 0.0);
    return valid_reflection_normal(geometric, view, n);
}

// chiaro_shading::shading_normal::valid_reflection_normal: `shading` turned towards `geometric`
// in the plane they span, just far enough that the mirror reflection of `view` leaves the
// surface at a cosine of at least min(0.9 geometric.view, MIN_REFLECTION_COSINE) (as Blender
// Cycles' ensure_valid_specular_reflection does); `shading` itself when it already does.
fn valid_reflection_normal(geometric: vec3<f32>, view: vec3<f32>, shading: vec3<f32>) -> vec3<f32> {
    let v_z = dot(view, geometric);
    let threshold = min(0.9 * v_z, MIN_REFLECTION_COSINE);
    let reflected_z = 2.0 * dot(shading, view) * dot(shading, geometric) - v_z;
    if reflected_z >= threshold {
        return shading;
    }
    let tangential = shading - geometric * dot(shading, geometric);
    let length = length(tangential);
    if !(length > 0.0) {
        return geometric;
    }
    let x = tangential / length;
    let v_x = dot(view, x);
    let amplitude = sqrt(v_z * v_z + v_x * v_x);
    if !(amplitude > 0.0) {
        return geometric;
    }
    let b = atan2(v_x, v_z);
    let angle = 2.0 * atan2(dot(shading, x), dot(shading, geometric));
    let reach = acos(clamp(threshold / amplitude, -1.0, 1.0));
    let side = select(-1.0, 1.0, angle >= b);
    let half = 0.5 * (b + side * reach);
    return safe_normalize(geometric * cos(half) + x * sin(half), geometric);
}
