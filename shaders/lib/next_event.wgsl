// Light at a shading point from the scene's lights, the two halves of multiple importance
// sampling with the power heuristic (Veach and Guibas, "Optimally Combining Sampling
// Techniques for Monte Carlo Rendering", SIGGRAPH 1995; Veach, 1997, thesis, chapter 9):
//
// - next-event estimation: every punctual light (or one picked by power when there are more
//   than ALL_PUNCTUAL_LIGHTS_MAX) and one sample of the area-light table (an emissive triangle
//   or the environment, picked by power), each with one shadow ray, the area sample weighted
//   against BRDF sampling;
// - emission_reached: the emission or environment that a BRDF-sampled ray reaches, weighted
//   against the chance that the area-light sample would have produced it.
//
// The environment seen along a ray that leaves the scene is environment_seen.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/bvh.wgsl
#import lib/rng.wgsl
#import lib/frame.wgsl
#import lib/sampling.wgsl
#import lib/brdf.wgsl
#import lib/lights.wgsl
#import lib/environment.wgsl
#import lib/offset.wgsl
#import lib/surface.wgsl
#import lib/features.wgsl

fn scene_environment() -> Environment {
    var e: Environment;
    e.radiance = scene_info.env_radiance;
    e.image = FEATURE_ENVIRONMENT_MAP && scene_info.env_kind == ENV_IMAGE;
    e.black = false;
    e.width = scene_info.env_width;
    e.height = scene_info.env_height;
    e.cos_rotation = scene_info.env_cos_rotation;
    e.sin_rotation = scene_info.env_sin_rotation;
    return e;
}

// Radiance arriving from the environment along world direction dir.
fn environment_seen(dir: vec3<f32>) -> vec3<f32> {
    if !FEATURE_ENVIRONMENT || scene_info.env_kind == ENV_BLACK {
        return vec3<f32>(0.0);
    }
    return environment_radiance(scene_environment(), dir);
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

// The entry of the punctual (or, with `area`, the area) light table of `count` > 0 entries
// that u in [0, 1) picks: the first whose CDF (the running sum of the masses) exceeds u.
fn light_table_pick(u: f32, count: u32, area: bool) -> u32 {
    var lo = 0u;
    var hi = count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        var cdf: f32;
        if area {
            cdf = scene_area_lights[mid].cdf;
        } else {
            cdf = scene_lights[mid].cdf;
        }
        if cdf <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// A punctual light seen from p; a kind the pipeline is specialised without gives none.
fn sample_punctual(light: GpuLight, p: vec3<f32>) -> LightSample {
    if FEATURE_POINT_LIGHTS && light.kind == LIGHT_POINT {
        return sample_point(light.position, light.intensity, light.range, p);
    }
    if FEATURE_SPOT_LIGHTS && light.kind == LIGHT_SPOT {
        return sample_spot(light.position, light.direction, light.intensity, light.inner,
            light.outer, light.range, p);
    }
    if FEATURE_DIRECTIONAL_LIGHTS && light.kind == LIGHT_DIRECTIONAL {
        return sample_directional(light.direction, light.intensity);
    }
    return light_sample_none();
}

// Every punctual light when there are few, else one picked by power (over its probability).
fn punctual_light(s: Shading, rng: ptr<function, Pcg32>) -> vec3<f32> {
    let count = scene_info.light_count;
    let any_kind = FEATURE_POINT_LIGHTS || FEATURE_SPOT_LIGHTS || FEATURE_DIRECTIONAL_LIGHTS;
    var total = vec3<f32>(0.0);
    if count <= ALL_PUNCTUAL_LIGHTS_MAX {
        if any_kind {
            for (var i = 0u; i < count; i++) {
                total += light_contribution(s, sample_punctual(scene_lights[i], s.position)).xyz;
            }
        }
        return total;
    }
    // Drawn whatever the features, so that the random numbers after it stay the same.
    let u = pcg32_next_f32(rng);
    if !any_kind {
        return total;
    }
    let light = scene_lights[light_table_pick(u, count, false)];
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
    let entry = scene_area_lights[light_table_pick(u_pick, count, true)];
    var ls = light_sample_none();
    if entry.instance == NO_INDEX {
        if FEATURE_ENVIRONMENT {
            let es = environment_sample(scene_environment(), u);
            ls = LightSample(es.wi, f32_infinity(), es.radiance, es.pdf, false, es.pdf > 0.0);
        }
    } else if FEATURE_EMISSIVE_TRIANGLES {
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

// The next-event estimate at a shading point: punctual lights and one area-light sample.
fn next_event(s: Shading, rng: ptr<function, Pcg32>) -> vec3<f32> {
    return punctual_light(s, rng) + area_light(s, rng);
}

// The radiance that a ray leaving `source` along world direction wi finds at `hit` (its closest
// hit; a miss reaches the environment): emission where it hits the emitting side of an
// emitter. With `weighted`, the ray was drawn by non-delta BRDF sampling with solid-angle pdf
// `brdf_pdf` and the result carries its power-heuristic weight against area-light sampling
// from `source`; without, weight 1 (delta bounces, and paths that never sample lights).
fn emission_reached(source: vec3<f32>, wi: vec3<f32>, hit: Hit, brdf_pdf: f32, weighted: bool) -> vec3<f32> {
    if hit.instance == BVH_NO_HIT {
        if !FEATURE_ENVIRONMENT || scene_info.env_kind == ENV_BLACK {
            return vec3<f32>(0.0);
        }
        let env = scene_environment();
        var weight = 1.0;
        if weighted {
            weight = power_heuristic(1.0, brdf_pdf, 1.0, scene_info.env_pmf * environment_pdf(env, wi));
        }
        return environment_radiance(env, wi) * weight;
    }
    if !FEATURE_EMISSIVE_TRIANGLES {
        return vec3<f32>(0.0);
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
    if weighted {
        let q = world_triangle_point(t, hit.barycentrics);
        let first = scene_instance_extras[hit.instance].area_first;
        var pmf = 0.0;
        if first != NO_INDEX {
            pmf = scene_area_lights[first + hit.triangle].pmf;
        }
        let light_pdf = pmf * triangle_solid_angle_pdf(t.v0, t.v1, t.v2, source, q);
        weight = power_heuristic(1.0, brdf_pdf, 1.0, light_pdf);
    }
    return emitted * weight;
}
