// Direct light per pixel of the G-buffer, one frame's estimate of the light the surface seen
// reflects (its own emission is the composite's to add): every
// punctual light (or one picked by power when there are more than ALL_PUNCTUAL_LIGHTS_MAX),
// one area-light sample (an emissive triangle or the environment, picked by power) and one
// BRDF sample, the last two combined by multiple importance sampling with the power
// heuristic (Veach and Guibas, "Optimally Combining Sampling Techniques for Monte Carlo
// Rendering", SIGGRAPH 1995). Each light sample casts one shadow ray from an origin offset
// along the geometric normal (Wachter and Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems, 2019). Where the camera sees no surface, the
// environment along the camera ray. The same estimate as chiaro_reference with direct_only.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/alpha.wgsl
#import lib/bvh.wgsl
#import lib/rng.wgsl
#import lib/frame.wgsl
#import lib/sampling.wgsl
#import lib/brdf.wgsl
#import lib/lights.wgsl
#import lib/environment.wgsl
#import lib/offset.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl

// chiaro_gpu::passes::direct::DirectParams.
struct DirectParams {
    frame: u32,
    seed_lo: u32,
    seed_hi: u32,
    // 0 in naive mode: no light sampling, covered pixels reflect nothing here.
    lights: u32,
}

@group(1) @binding(0) var gbuffer_position: texture_2d<u32>;
@group(1) @binding(1) var gbuffer_surface: texture_2d<u32>;
@group(1) @binding(2) var gbuffer_emission: texture_2d<u32>;
@group(1) @binding(3) var<uniform> camera: GpuCamera;
@group(1) @binding(4) var<uniform> params: DirectParams;
@group(1) @binding(5) var direct_out: texture_storage_2d<rgba32float, write>;

fn scene_environment() -> Environment {
    var e: Environment;
    e.radiance = scene_info.env_radiance;
    e.image = scene_info.env_kind == ENV_IMAGE;
    e.black = false;
    e.width = scene_info.env_width;
    e.height = scene_info.env_height;
    e.cos_rotation = scene_info.env_cos_rotation;
    e.sin_rotation = scene_info.env_sin_rotation;
    return e;
}

fn environment_seen(dir: vec3<f32>) -> vec3<f32> {
    if scene_info.env_kind == ENV_BLACK {
        return vec3<f32>(0.0);
    }
    return environment_radiance(scene_environment(), dir);
}

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
    let record = bvh_instances[instance];
    let i = scene_triangle_indices(record.mesh, triangle);
    let m = record.object_to_world;
    let p0 = bvh_transform_point(m, scene_vertices[i.x].position);
    let p1 = bvh_transform_point(m, scene_vertices[i.y].position);
    let p2 = bvh_transform_point(m, scene_vertices[i.z].position);
    let mirrored = scene_instance_extras[instance].mirrored != 0u;
    if mirrored {
        return WorldTriangle(p0, p2, p1, i, true);
    }
    return WorldTriangle(p0, p1, p2, i, false);
}

// Emitted radiance of an instance's material at mesh-order barycentrics b.
fn emission_at(instance: u32, indices: vec3<u32>, b: vec2<f32>) -> vec3<f32> {
    let record = bvh_instances[instance];
    let material = scene_materials[record.material];
    let texel = texture_sample_slot(material.emissive_texture, scene_uvs(indices, b),
        scene_meshes[record.mesh].flags, vec4<f32>(1.0));
    return material.emission * texel.xyz;
}

// Whether nothing blocks the segment from the shading point toward wi (distance may be inf).
fn unoccluded(s: Shading, wi: vec3<f32>, distance: f32) -> bool {
    var ray: Ray;
    ray.origin = offset_ray_origin(s.position, s.geometric_normal);
    ray.direction = wi;
    ray.t_min = 0.0;
    let t_max = select(f32_infinity(), distance * SHADOW_RAY_REACH, f32_is_finite(distance));
    return !trace_any(ray, t_max);
}

// f cos Li of a light sample that reaches the point, 0 when rejected or occluded; the BRDF
// pdf of its direction in w.
fn light_contribution(s: Shading, ls: LightSample) -> vec4<f32> {
    if !ls.valid {
        return vec4<f32>(0.0);
    }
    let wi = frame_to_local(s.frame, ls.wi);
    if wi.z <= 0.0 || dot(ls.wi, s.geometric_normal) <= 0.0 || all(ls.radiance == vec3<f32>(0.0)) {
        return vec4<f32>(0.0);
    }
    let f = brdf_eval(s.params, s.wo, wi) * wi.z;
    if all(f == vec3<f32>(0.0)) || !unoccluded(s, ls.wi, ls.distance) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(f * ls.radiance, brdf_pdf(s.params, s.wo, wi));
}

fn sample_punctual(light: GpuLight, p: vec3<f32>) -> LightSample {
    if light.kind == LIGHT_POINT {
        return sample_point(light.position, light.intensity, light.range, p);
    }
    if light.kind == LIGHT_SPOT {
        return sample_spot(light.position, light.direction, light.intensity, light.inner,
            light.outer, light.range, p);
    }
    return sample_directional(light.direction, light.intensity);
}

// Every punctual light when there are few, else one picked by power (over its probability).
fn punctual_light(s: Shading, rng: ptr<function, Pcg32>) -> vec3<f32> {
    let count = scene_info.light_count;
    var total = vec3<f32>(0.0);
    if count <= ALL_PUNCTUAL_LIGHTS_MAX {
        for (var i = 0u; i < count; i++) {
            total += light_contribution(s, sample_punctual(scene_lights[i], s.position)).xyz;
        }
        return total;
    }
    let u = pcg32_next_f32(rng);
    var lo = 0u;
    var hi = count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if scene_lights[mid].cdf <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let light = scene_lights[lo];
    return light_contribution(s, sample_punctual(light, s.position)).xyz / light.pmf;
}

// One sample of the area-light table, weighted against BRDF sampling.
fn area_light(s: Shading, rng: ptr<function, Pcg32>) -> vec3<f32> {
    let count = scene_info.area_count;
    let u_pick = pcg32_next_f32(rng);
    let u = pcg32_next_vec2(rng);
    if count == 0u {
        return vec3<f32>(0.0);
    }
    var lo = 0u;
    var hi = count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if scene_area_lights[mid].cdf <= u_pick {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let entry = scene_area_lights[lo];
    var ls: LightSample;
    if entry.instance == NO_INDEX {
        let es = environment_sample(scene_environment(), u);
        ls = LightSample(es.wi, f32_infinity(), es.radiance, es.pdf, false, es.pdf > 0.0);
    } else {
        let t = world_triangle(entry.instance, entry.triangle);
        let b = uniform_triangle(u);
        let mesh_b = select(b, b.yx, t.mirrored);
        let material = scene_materials[bvh_instances[entry.instance].material];
        let two_sided = (material.flags & MATERIAL_DOUBLE_SIDED) != 0u;
        ls = sample_triangle(t.v0, t.v1, t.v2, emission_at(entry.instance, t.indices, mesh_b),
            two_sided, s.position, u);
    }
    let c = light_contribution(s, ls);
    if all(c.xyz == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let light_pdf = entry.pmf * ls.pdf;
    return c.xyz * power_heuristic(1.0, light_pdf, 1.0, c.w) / light_pdf;
}

// One BRDF sample: the emission or environment it reaches, weighted against light sampling.
fn brdf_light(s: Shading, rng: ptr<function, Pcg32>) -> vec3<f32> {
    let u_lobe = pcg32_next_f32(rng);
    let u = pcg32_next_vec2(rng);
    let bs = brdf_sample(s.params, s.wo, u_lobe, u);
    if !bs.valid || !vec3_is_finite(bs.weight) || all(bs.weight == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let wi = frame_to_world(s.frame, bs.wi);
    let side = select(-s.geometric_normal, s.geometric_normal, dot(wi, s.geometric_normal) >= 0.0);
    var ray: Ray;
    ray.origin = offset_ray_origin(s.position, side);
    ray.direction = wi;
    ray.t_min = 0.0;
    let hit = trace_closest(ray, f32_infinity());
    if hit.instance == BVH_NO_HIT {
        if scene_info.env_kind == ENV_BLACK {
            return vec3<f32>(0.0);
        }
        let env = scene_environment();
        var weight = 1.0;
        if !bs.delta {
            weight = power_heuristic(1.0, bs.pdf, 1.0, scene_info.env_pmf * environment_pdf(env, wi));
        }
        return bs.weight * environment_radiance(env, wi) * weight;
    }
    let record = bvh_instances[hit.instance];
    let material = scene_materials[record.material];
    if all(material.emission == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let t = world_triangle(hit.instance, hit.triangle);
    let front = cross(t.v1 - t.v0, t.v2 - t.v0);
    let front_facing = dot(wi, front) < 0.0;
    if !front_facing && (material.flags & MATERIAL_DOUBLE_SIDED) == 0u {
        return vec3<f32>(0.0);
    }
    let emitted = emission_at(hit.instance, t.indices, hit.barycentrics);
    var weight = 1.0;
    if !bs.delta {
        // The hit point from the vertices in mesh order.
        let b = hit.barycentrics;
        let m1 = select(t.v1, t.v2, t.mirrored);
        let m2 = select(t.v2, t.v1, t.mirrored);
        let q = t.v0 * (1.0 - b.x - b.y) + m1 * b.x + m2 * b.y;
        let first = scene_instance_extras[hit.instance].area_first;
        var pmf = 0.0;
        if first != NO_INDEX {
            pmf = scene_area_lights[first + hit.triangle].pmf;
        }
        let light_pdf = pmf * triangle_solid_angle_pdf(t.v0, t.v1, t.v2, s.position, q);
        weight = power_heuristic(1.0, bs.pdf, 1.0, light_pdf);
    }
    return bs.weight * emitted * weight;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(direct_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    var texels: GbufferTexels;
    texels.position = textureLoad(gbuffer_position, pixel, 0);
    texels.surface = textureLoad(gbuffer_surface, pixel, 0);
    texels.emission = textureLoad(gbuffer_emission, pixel, 0);
    if !gbuffer_covered(texels) {
        let ray = camera_ray(camera, vec2<f32>(id.xy) + camera.jitter);
        textureStore(direct_out, pixel, vec4<f32>(environment_seen(ray.direction), 1.0));
        return;
    }
    let g = gbuffer_unpack(texels);
    var radiance = vec3<f32>(0.0);
    if g.shades && params.lights != 0u {
        let material = scene_materials[bvh_instances[g.instance].material];
        var s: Shading;
        s.position = g.position;
        s.geometric_normal = g.geometric_normal;
        s.frame = frame_from_normal(g.shading_normal);
        let to_eye = select(normalize(camera.origin - g.position), -camera.forward,
            camera.orthographic != 0u);
        s.wo = frame_to_local(s.frame, to_eye);
        s.params = SurfaceParams(g.base_color, g.metallic, g.roughness, material.f0_dielectric,
            material.absorption);
        let index = id.y * size.x + id.x;
        var rng = pcg32_new(vec2<u32>(params.seed_lo, params.seed_hi), vec2<u32>(index, params.frame));
        radiance += punctual_light(s, &rng);
        radiance += area_light(s, &rng);
        radiance += brdf_light(s, &rng);
    }
    textureStore(direct_out, pixel, vec4<f32>(radiance, 1.0));
}
