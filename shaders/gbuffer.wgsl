// The G-buffer: the scene rasterized in indexed draws over the raster lists
// (chiaro_gpu::gpu_scene::raster: each triangle starts at a vertex of its own, which carries the
// triangle's face), one instanced draw per run of consecutive instances of one mesh
// (instance_index is the instance's index in bvh_instances). The vertex stage's inputs are
// vertex buffers (chiaro_gpu::passes::gbuffer::VERTEX_LAYOUTS), not storage loads, which
// lavapipe runs lane by lane, one word at a time.
// Per pixel: world position, geometric and shading normals (octahedral, Cigolle et al., "A
// Survey of Efficient Representations for Independent Unit Vectors", JCGT 3(2), 2014), base
// colour (factor x texture x vertex colour), metallic, roughness, emission, instance id, the
// motion vector and the triangle's number in its mesh; depth in the depth attachment.
// Alpha-masked texels are discarded, and
// alpha-blended fragments with probability 1 - alpha (stochastic coverage, coverage.wgsl),
// the number hashed from the pixel, the frame's camera.frame_seed, the instance and the depth,
// so the frames that accumulate see every fragment in proportion to its alpha. Surfaces are shaded as chiaro_reference's
// surface_at: the front face is counter-clockwise (clockwise under a mirroring transform), a
// back face of a single-sided material does not shade, normal maps use the interpolated
// tangent frame. The geometric normal is the triangle's face (the cross product of its
// object-space edges) taken to world space as a normal is.

#import lib/generated.wgsl
#import lib/bvh_bindings.wgsl
#import lib/scene_bindings.wgsl
#import lib/textures.wgsl
#import lib/base_color.wgsl
#import lib/coverage.wgsl
#import lib/features.wgsl
#import lib/shading_normals.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl

@group(1) @binding(0) var<storage, read> camera: GpuCamera;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uvs: vec4<f32>,
    @location(4) @interpolate(flat) instance: u32,
    @location(5) previous_clip: vec4<f32>,
    // The triangle's front side in world space, not unit (from its first vertex, the provoking
    // one).
    @location(6) @interpolate(flat) face: vec3<f32>,
    // The vertex colour (white without FEATURE_VERTEX_COLORS).
    @location(7) color: vec4<f32>,
    // The triangle's number in its mesh (from its first vertex).
    @location(8) @interpolate(flat) triangle: u32,
}

fn transform_point(m: array<vec4<f32>, 3>, p: vec3<f32>) -> vec3<f32> {
    let q = vec4<f32>(p, 1.0);
    return vec3<f32>(dot(m[0], q), dot(m[1], q), dot(m[2], q));
}

fn transform_vector(m: array<vec4<f32>, 3>, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(m[0].xyz, v), dot(m[1].xyz, v), dot(m[2].xyz, v));
}

// The inverse transpose of the object-to-world matrix applied to a normal: the rows of
// world-to-object as columns.
fn transform_normal(world_to_object: array<vec4<f32>, 3>, n: vec3<f32>) -> vec3<f32> {
    return world_to_object[0].xyz * n.x + world_to_object[1].xyz * n.y + world_to_object[2].xyz * n.z;
}

// A raster vertex (chiaro_gpu::gpu_scene::RasterVertex): its scene vertex, the face of the
// triangle that starts at it (object space), and its instance's transforms (rows of 3x4
// matrices).
struct VertexIn {
    @location(0) position_u0: vec4<f32>,
    @location(1) normal_v0: vec4<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv1: vec2<f32>,
    @location(4) face: vec3<f32>,
    @location(5) world_to_object_0: vec4<f32>,
    @location(6) world_to_object_1: vec4<f32>,
    @location(7) world_to_object_2: vec4<f32>,
    @location(8) object_to_world_0: vec4<f32>,
    @location(9) object_to_world_1: vec4<f32>,
    @location(10) object_to_world_2: vec4<f32>,
    @location(11) previous_object_to_world_0: vec4<f32>,
    @location(12) previous_object_to_world_1: vec4<f32>,
    @location(13) previous_object_to_world_2: vec4<f32>,
    @location(14) color: vec4<f32>,
    @location(15) triangle: u32,
}

@vertex
fn vs_main(v: VertexIn, @builtin(instance_index) instance: u32) -> VertexOut {
    let m = array<vec4<f32>, 3>(v.object_to_world_0, v.object_to_world_1, v.object_to_world_2);
    let world_to_object = array<vec4<f32>, 3>(v.world_to_object_0, v.world_to_object_1,
        v.world_to_object_2);
    let previous_to_world = array<vec4<f32>, 3>(v.previous_object_to_world_0,
        v.previous_object_to_world_1, v.previous_object_to_world_2);
    let position = v.position_u0.xyz;
    let world = transform_point(m, position);
    let previous = transform_point(previous_to_world, position);
    var out: VertexOut;
    out.clip = camera.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = transform_normal(world_to_object, v.normal_v0.xyz);
    out.tangent = vec4<f32>(transform_vector(m, v.tangent.xyz), v.tangent.w);
    out.uvs = vec4<f32>(v.position_u0.w, v.normal_v0.w, v.uv1);
    out.instance = instance;
    out.previous_clip = camera.previous_view_proj * vec4<f32>(previous, 1.0);
    // The inverse transpose keeps the object-space front side in front under a mirroring
    // transform, as chiaro_reference's surface_at does.
    out.face = transform_normal(world_to_object, v.face);
    out.color = select(vec4<f32>(1.0), v.color, FEATURE_VERTEX_COLORS);
    out.triangle = v.triangle;
    return out;
}

// Most rounding error (in radians, about) at which the plane of the position's screen-space
// slopes is trusted to check the flat face.
const SLOPE_TRUST: f32 = 0.01;
// Least |cos| between the flat face and the slopes' plane at which the flat face is the
// fragment's own triangle's.
const FACE_AGREEMENT: f32 = 0.99;

// The fragment's triangle's front side (unit): the flat face from its first vertex, checked
// against the plane in which the world position's screen-space slopes `dx`, `dy` lie. A driver
// may hand a triangle the flat attributes of another vertex (llvmpipe's GL, Mesa 22.3, did for
// one triangle of builtin:instances), so where the slopes are precise enough to tell (their
// rounding, f32 epsilon times the position's size over the slopes', below SLOPE_TRUST) and the
// two disagree (|cos| below FACE_AGREEMENT), the slopes' plane is taken, on the side of the
// flat face or, where that is zero or nearly perpendicular, of the interpolated normal.
// Elsewhere the flat face stands: it is exact.
fn checked_face(flat: vec3<f32>, world: vec3<f32>, dx: vec3<f32>, dy: vec3<f32>,
    interpolated: vec3<f32>) -> vec3<f32> {
    let face = safe_normalize(flat, vec3<f32>(0.0));
    let slopes = cross(dx, dy);
    let largest = max(max(abs(world.x), abs(world.y)), abs(world.z));
    let rounding = F32_EPSILON * largest / min(length(dx), length(dy));
    if !(rounding < SLOPE_TRUST) || dot(slopes, slopes) == 0.0 {
        return safe_normalize(flat, vec3<f32>(0.0, 0.0, 1.0));
    }
    let plane = normalize(slopes);
    let agreement = dot(face, plane);
    if abs(agreement) >= FACE_AGREEMENT {
        return face;
    }
    let side = select(interpolated, face, abs(agreement) > 0.1);
    return select(plane, -plane, dot(plane, side) < 0.0);
}

struct GbufferOut {
    @location(0) position: vec4<u32>,
    @location(1) surface: vec4<u32>,
    @location(2) emission: vec4<u32>,
    // lib/gbuffer_packing.wgsl's motion_pack.
    @location(3) motion: u32,
    @location(4) triangle: u32,
}

@fragment
fn fs_main(in: VertexOut) -> GbufferOut {
    // Taken first, in uniform control flow (before any discard).
    let dx = dpdx(in.world);
    let dy = dpdy(in.world);
    let record = bvh_load_instance_whole(in.instance);
    let material = scene_material(record.material);
    let mesh_flags = scene_meshes[record.mesh].flags;
    let base = material_base_color(material, mesh_flags, in.uvs, in.color);
    if FEATURE_ALPHA_MASKS && (material.flags & MATERIAL_ALPHA_MASK) != 0u && !(base.w >= material.alpha_cutoff) {
        discard;
    }
    if FEATURE_ALPHA_BLEND && (material.flags & MATERIAL_ALPHA_BLEND) != 0u {
        let u = coverage_fragment_number(vec2<u32>(in.clip.xy), camera.frame_seed, in.instance,
            in.clip.z);
        if !coverage_stops(base.w, u) {
            discard;
        }
    }
    let view = in.world - camera.origin;
    let incoming = select(view, camera.forward, camera.orthographic != 0u);
    let geometric_front = checked_face(in.face, in.world, dx, dy, in.normal);
    let mirrored = scene_instance_extras[in.instance].mirrored != 0u;
    let shading_front = mapped_shading_normal(material, mesh_flags, in.uvs, in.normal, in.tangent,
        mirrored, geometric_front);
    let normals = orient_normals(geometric_front, shading_front, incoming,
        (material.flags & MATERIAL_DOUBLE_SIDED) != 0u);
    let shades = normals.shades;
    let metallic_roughness = texture_sample_feature(FEATURE_METALLIC_ROUGHNESS_TEXTURES,
        material.metallic_roughness_texture, in.uvs, mesh_flags, vec4<f32>(1.0));
    var emission = vec3<f32>(0.0);
    if shades {
        emission = material.emission * texture_sample_feature(FEATURE_EMISSIVE_TEXTURES,
            material.emissive_texture, in.uvs, mesh_flags, vec4<f32>(1.0)).xyz;
    }
    var surface: GbufferSurface;
    surface.position = in.world;
    surface.geometric_normal = normals.geometric;
    surface.shading_normal = normals.shading;
    surface.base_color = base.xyz;
    surface.metallic = clamp(material.metallic * metallic_roughness.z, 0.0, 1.0);
    surface.roughness = clamp(material.roughness * metallic_roughness.y, 0.0, 1.0);
    surface.shades = shades;
    surface.back_face = dot(incoming, geometric_front) >= 0.0;
    surface.emission = emission;
    surface.instance = in.instance;
    let packed = gbuffer_pack(surface);
    var out: GbufferOut;
    out.position = packed.position;
    out.surface = packed.surface;
    out.emission = packed.emission;
    out.triangle = in.triangle;
    // Where this point was in the previous frame, in pixels, minus where it is now.
    let now = camera.unjittered_view_proj * vec4<f32>(in.world, 1.0);
    let size = vec2<f32>(camera.width, camera.height);
    let to_pixel = vec2<f32>(0.5, -0.5) * size;
    out.motion = motion_pack((in.previous_clip.xy / in.previous_clip.w - now.xy / now.w) * to_pixel);
    return out;
}
