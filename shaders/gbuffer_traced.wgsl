// The G-buffer traced instead of rasterized (FrameSettings::primary = Traced): one camera ray
// per pixel through the frame's sub-pixel point, cast through the BVHs (bvh.wgsl), its closest
// accepted hit (instance, triangle, barycentrics: the visibility buffer) turned into the
// raster pass's texels. The attributes are those of a ray's hit in the other passes
// (surface.wgsl's surface_at_hit, emission_at): world position interpolated from the
// triangle's vertices, the geometric normal its face's, the interpolated and normal-mapped
// shading normal, the textured material. Alpha masks are holes and blended surfaces are
// covered with probability alpha, decided by the ray's coverage number (alpha.wgsl), where the
// raster pass hashes the fragment's. The near plane clips as the raster's does. A pixel whose
// ray hits nothing gets the raster pass's clear value, zero.

#import lib/generated.wgsl
#import lib/frame.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/surface.wgsl

@group(1) @binding(0) var<storage, read> camera: GpuCamera;
@group(1) @binding(1) var out_position: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(2) var out_surface: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(3) var out_emission: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(4) var out_motion: texture_storage_2d<r32uint, write>;
@group(1) @binding(5) var out_triangle: texture_storage_2d<r32uint, write>;

// The distance along `direction` (unit) at which a ray from the camera crosses the near plane.
fn near_distance(direction: vec3<f32>) -> f32 {
    if camera.orthographic != 0u {
        return camera.near;
    }
    return camera.near / max(dot(direction, camera.forward), 1e-6);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if f32(id.x) >= camera.width || f32(id.y) >= camera.height {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let primary = camera_ray(camera, vec2<f32>(id.xy) + camera.jitter);
    let hit = trace_closest(Ray(primary.origin, near_distance(primary.direction),
        primary.direction), f32_infinity());
    if hit.instance == BVH_NO_HIT {
        textureStore(out_position, pixel, vec4<u32>(0u));
        textureStore(out_surface, pixel, vec4<u32>(0u));
        textureStore(out_emission, pixel, vec4<u32>(0u));
        textureStore(out_motion, pixel, vec4<u32>(0u));
        textureStore(out_triangle, pixel, vec4<u32>(0u));
        return;
    }
    let seen = surface_at_hit(primary.direction, hit);
    let s = seen.shading;
    let t = world_triangle(hit.instance, hit.triangle);
    var surface: GbufferSurface;
    surface.position = s.position;
    surface.geometric_normal = s.geometric_normal;
    surface.shading_normal = s.frame.normal;
    surface.base_color = s.params.base_color;
    surface.metallic = s.params.metallic;
    surface.roughness = s.params.roughness;
    surface.shades = seen.shades;
    surface.back_face = dot(primary.direction, cross(t.v1 - t.v0, t.v2 - t.v0)) >= 0.0;
    surface.emission = select(vec3<f32>(0.0), emission_at(hit.instance, t.indices,
        hit.barycentrics), seen.shades);
    surface.instance = hit.instance;
    let packed = gbuffer_pack(surface);
    textureStore(out_position, pixel, packed.position);
    textureStore(out_surface, pixel, packed.surface);
    textureStore(out_emission, pixel, packed.emission);
    textureStore(out_triangle, pixel, vec4<u32>(hit.triangle, 0u, 0u, 0u));
    // Where this point was in the previous frame, in pixels, minus where it is now: its
    // object-space point carried by the instance's previous transform.
    let b = hit.barycentrics;
    let w = vec3<f32>(1.0 - b.x - b.y, b.x, b.y);
    let object = scene_vertex(t.indices.x).position * w.x + scene_vertex(t.indices.y).position * w.y
        + scene_vertex(t.indices.z).position * w.z;
    let previous = bvh_transform_point(scene_instance_extras[hit.instance].previous_object_to_world,
        object);
    let now = camera.unjittered_view_proj * vec4<f32>(s.position, 1.0);
    let before = camera.previous_view_proj * vec4<f32>(previous, 1.0);
    let to_pixel = vec2<f32>(0.5, -0.5) * vec2<f32>(camera.width, camera.height);
    let motion = (before.xy / before.w - now.xy / now.w) * to_pixel;
    textureStore(out_motion, pixel, vec4<u32>(motion_pack(motion), 0u, 0u, 0u));
}
