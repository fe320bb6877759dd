// Light at a shading point from the scene's lights, the two halves of multiple importance
// sampling with the power heuristic (Veach and Guibas, "Optimally Combining Sampling
// Techniques for Monte Carlo Rendering", SIGGRAPH 1995; Veach, 1997, thesis, chapter 9):
//
// - next-event estimation, each light sample with one shadow ray, an area-light sample
//   weighted against BRDF sampling: at the primary surface (the direct pass), every punctual
//   light (or one picked when there are more than ALL_PUNCTUAL_LIGHTS_MAX) and one sample of
//   the area-light table (an emissive triangle or the environment); at the path's further
//   vertices (next_event), one light, a punctual light or an area-light sample;
// - emission_reached: the emission or environment that a BRDF-sampled ray reaches, weighted
//   against the chance that the area-light sampling would have produced it.
//
// A light is picked by power alone, or, when the importer's light_tree_sampling() says so,
// through the light trees (lib/light_tree.wgsl) by its importance to the shading point (its
// position and shading normal, as chiaro_reference's light table): the environment keeps its
// power share of the area table and the directional lights theirs of the punctual lights, the
// rest is the tree's walk. A constant environment is not in the area table (BRDF rays find it;
// chiaro_scene's Environment::light_sampling_radiance). The importer defines
//     fn light_tree_sampling() -> bool
//
// The environment seen along a ray that leaves the scene is environment_seen.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/bvh.wgsl
#import lib/rng_source.wgsl
#import lib/frame.wgsl
#import lib/sampling.wgsl
#import lib/brdf.wgsl
#import lib/lights.wgsl
#import lib/environment.wgsl
#import lib/offset.wgsl
#import lib/surface.wgsl
#import lib/features.wgsl
#import lib/light_tree.wgsl
#import lib/color.wgsl

// Whether lights are picked through the light trees: the importer asks for it, and the pipeline
// is specialised with trees to pick from (without, the trees' code is compiled out, which
// lavapipe would otherwise run, masked, at every light sample).
fn light_trees_picking() -> bool {
    return FEATURE_LIGHT_TREES && light_tree_sampling();
}

// The CDFs light_table_pick searches: the punctual lights' by power, the area table's, and the
// directional lights' among themselves (GpuLight::directional_cdf).
const TABLE_PUNCTUAL: u32 = 0u;
const TABLE_AREA: u32 = 1u;
const TABLE_DIRECTIONAL: u32 = 2u;

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
    let t_max = select(f32_infinity(), distance * SHADOW_RAY_REACH, f32_is_finite(distance));
    return !trace_any(leaving_ray(s, wi), t_max);
}

// f cos Li of a light sample before its shadow ray, and the BRDF pdf of its direction in w;
// 0 when the sample is invalid, below either horizon, black, or not reflected.
fn light_unoccluded_value(s: Shading, ls: LightSample) -> vec4<f32> {
    if !ls.valid {
        return vec4<f32>(0.0);
    }
    let wi = frame_to_local(s.frame, ls.wi);
    if !on_its_side(s, ls.wi, wi.z) || all(ls.radiance == vec3<f32>(0.0)) {
        return vec4<f32>(0.0);
    }
    let f = brdf_eval(s.params, s.wo, wi) * abs(wi.z);
    if all(f == vec3<f32>(0.0)) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(f * ls.radiance, brdf_pdf(s.params, s.wo, wi));
}

// f cos Li of a light sample that reaches the point, 0 when rejected or occluded; the BRDF
// pdf of its direction in w.
fn light_contribution(s: Shading, ls: LightSample) -> vec4<f32> {
    let c = light_unoccluded_value(s, ls);
    if all(c.xyz == vec3<f32>(0.0)) || !unoccluded(s, ls.wi, ls.distance) {
        return vec4<f32>(0.0);
    }
    return c;
}

// The entry of the light table of `count` > 0 entries that u in [0, 1) picks: the first whose
// CDF `table` (the running sum of the masses) exceeds u.
fn light_table_pick(u: f32, count: u32, table: u32) -> u32 {
    var lo = 0u;
    var hi = count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        var cdf: f32;
        if table == TABLE_AREA {
            cdf = scene_area_light(mid).cdf;
        } else if table == TABLE_DIRECTIONAL {
            cdf = scene_light(mid).directional_cdf;
        } else {
            cdf = scene_light(mid).cdf;
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

// Whether punctual_light evaluates every punctual light (so its estimate has no sampling
// noise) rather than one picked at random.
fn punctual_lights_all_evaluated() -> bool {
    return scene_info.light_count <= ALL_PUNCTUAL_LIGHTS_MAX;
}

// A punctual light picked with the number u, and the probability of the pick: by power, or a
// directional light by power with their share and else a point or spot light by the tree.
struct PunctualPick {
    light: u32,
    pmf: f32,
}

fn punctual_pick(s: Shading, u: f32) -> PunctualPick {
    let count = scene_info.light_count;
    let share = scene_info.directional_share;
    if !light_trees_picking() || scene_info.punctual_tree == NO_INDEX {
        let first = light_table_pick(u, count, TABLE_PUNCTUAL);
        return PunctualPick(first, scene_light(first).pmf);
    }
    if u < share {
        let first = light_table_pick(min(u / share, ONE_MINUS_EPSILON), count, TABLE_DIRECTIONAL);
        return PunctualPick(first, scene_light(first).pmf);
    }
    let u_tree = clamp((u - share) / (1.0 - share), 0.0, ONE_MINUS_EPSILON);
    let pick = light_tree_pick(scene_info.punctual_tree, s.position, s.frame.normal, u_tree);
    return PunctualPick(pick.light, (1.0 - share) * pick.pmf);
}

// The punctual lights [first, first + n) to evaluate, their sum to be divided by pmf: every one
// when there are few, else the one that u picks (punctual_pick); none when the pipeline is
// specialised without any punctual kind.
struct PunctualRange {
    first: u32,
    n: u32,
    pmf: f32,
}

fn punctual_range(s: Shading, u: f32) -> PunctualRange {
    var range = PunctualRange(0u, scene_info.light_count, 1.0);
    if !punctual_lights_all_evaluated() {
        let pick = punctual_pick(s, u);
        range = PunctualRange(pick.light, 1u, pick.pmf);
    }
    if !(FEATURE_POINT_LIGHTS || FEATURE_SPOT_LIGHTS || FEATURE_DIRECTIONAL_LIGHTS) {
        range.n = 0u;
    }
    return range;
}

// Every punctual light when there are few, else one picked, over its probability
// (punctual_range). Either way one loop casts the shadow rays (lib/bvh.wgsl says why lavapipe
// wants each trace in one place).
fn punctual_light(s: Shading, rng: ptr<function, Rng>) -> vec3<f32> {
    var u = 0.0;
    if !punctual_lights_all_evaluated() {
        // Drawn whatever the features, so that the random numbers after it stay the same.
        u = rng_next_f32(rng);
    }
    let range = punctual_range(s, u);
    var total = vec3<f32>(0.0);
    for (var i = 0u; i < range.n; i++) {
        total += light_contribution(s, sample_punctual(scene_light(range.first + i), s.position)).xyz;
    }
    return total / range.pmf;
}

// One sample of the area-light table (an emissive triangle or the environment), not yet
// traced, and the probability of its entry: the entry picked by power, or the environment (the
// last entry) with its share and else a triangle by the tree. No sample (valid false) when the
// table is empty.
struct AreaSample {
    sample: LightSample,
    pmf: f32,
}

fn area_light_sample(s: Shading, rng: ptr<function, Rng>) -> AreaSample {
    let numbers = rng_next_choice_vec2(rng);
    let pick = area_light_pick(s, numbers.x);
    let u = numbers.yz;
    if pick.pmf == 0.0 {
        return AreaSample(light_sample_none(), 1.0);
    }
    return AreaSample(area_light_at(s, pick.entry, u), pick.pmf);
}

// An entry of the area-light table picked with the number u_pick, and the probability of the
// pick (0: the table is empty).
struct AreaPick {
    entry: u32,
    pmf: f32,
}

fn area_light_pick(s: Shading, u_pick: f32) -> AreaPick {
    let count = scene_info.area_count;
    if count == 0u {
        return AreaPick(0u, 0.0);
    }
    let share = scene_info.env_pmf;
    var index: u32;
    var pmf: f32;
    if !light_trees_picking() || scene_info.area_tree == NO_INDEX {
        index = light_table_pick(u_pick, count, TABLE_AREA);
        pmf = scene_area_light(index).pmf;
    } else if u_pick < share {
        index = count - 1u;
        pmf = share;
    } else {
        let u_tree = clamp((u_pick - share) / (1.0 - share), 0.0, ONE_MINUS_EPSILON);
        let pick = light_tree_pick(scene_info.area_tree, s.position, s.frame.normal, u_tree);
        index = pick.light;
        pmf = (1.0 - share) * pick.pmf;
    }
    return AreaPick(index, pmf);
}

// The point of area-light table entry `index` that the numbers u draw (an emissive triangle's
// point, or an environment direction), seen from the shading point: the same sample from every
// point that asks with the same numbers (how resampled reservoirs name their sample).
fn area_light_at(s: Shading, index: u32, u: vec2<f32>) -> LightSample {
    let entry = scene_area_light(index);
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
        let material = scene_material(bvh_load_instance_whole(entry.instance).material);
        let two_sided = (material.flags & MATERIAL_DOUBLE_SIDED) != 0u;
        let radiance = emission_at(entry.instance, t.indices, mesh_b)
            * emitter_coverage(entry.instance, t.indices, mesh_b);
        ls = sample_triangle(t.v0, t.v1, t.v2, radiance, two_sided, s.position, u);
    }
    return ls;
}

// One sample of the area-light table, weighted against BRDF sampling.
fn area_light(s: Shading, rng: ptr<function, Rng>) -> vec3<f32> {
    let area = area_light_sample(s, rng);
    let c = light_contribution(s, area.sample);
    if all(c.xyz == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let light_pdf = area.pmf * area.sample.pdf;
    return c.xyz * power_heuristic(1.0, light_pdf, 1.0, c.w) / light_pdf;
}

// f cos Li of a light sample over the probability `pick_pmf` of its light (an area sample's
// also over its solid-angle pdf, and weighted against BRDF sampling), before its shadow ray;
// 0 when rejected.
fn light_unshadowed(s: Shading, ls: LightSample, pick_pmf: f32) -> vec3<f32> {
    let c = light_unoccluded_value(s, ls);
    let f = c.xyz / pick_pmf;
    if ls.delta || all(f == vec3<f32>(0.0)) {
        return f;
    }
    return f * power_heuristic(1.0, pick_pmf * ls.pdf, 1.0, c.w) / ls.pdf;
}

// The next-event estimate at a path vertex beyond x0, with one shadow ray. Its candidates are
// what the direct pass sums (one area-light sample, and every punctual light, or one picked
// when there are more than ALL_PUNCTUAL_LIGHTS_MAX), each valued before its shadow ray
// (light_unshadowed); one is picked in proportion to the luminance of its value (weighted
// reservoir sampling with one number, rescaled at each candidate), traced, and counted over
// the probability of the pick: where every candidate is visible the estimate is their sum, as
// the direct pass's is, and only the visibility of the ones not picked is left to chance.
// Unbiased, because a candidate is picked with nonzero probability wherever its value is
// nonzero. The MIS weights are the direct pass's (emission_reached's counterpart is the area
// sample as if always taken, so the two weights of a path still sum to 1). lavapipe runs every
// block whatever its lanes decide, so one trace for all candidates is what saves the rays.
fn next_event(s: Shading, rng: ptr<function, Rng>) -> vec3<f32> {
    var u = rng_next_f32(rng);
    let u_punctual = rng_next_f32(rng);
    let area = area_light_sample(s, rng);
    var chosen_ls = area.sample;
    var chosen = light_unshadowed(s, area.sample, area.pmf);
    var total = luminance(chosen);
    let range = punctual_range(s, u_punctual);
    for (var i = 0u; i < range.n; i++) {
        let ls = sample_punctual(scene_light(range.first + i), s.position);
        let value = light_unshadowed(s, ls, range.pmf);
        let w = luminance(value);
        if w > 0.0 {
            total += w;
            let p = w / total;
            if u < p {
                chosen = value;
                chosen_ls = ls;
                u = u / p;
            } else {
                u = (u - p) / (1.0 - p);
            }
        }
    }
    if !(total > 0.0) || !f32_is_finite(total) || !unoccluded(s, chosen_ls.wi, chosen_ls.distance) {
        return vec3<f32>(0.0);
    }
    return chosen * (total / luminance(chosen));
}

// The radiance that a ray leaving shading point `source` along world direction wi finds at
// `hit` (its closest hit; a miss reaches the environment): emission where it hits the
// emitting side of an emitter. With `weighted`, the ray was drawn by non-delta BRDF sampling
// with solid-angle pdf `brdf_pdf` and the result carries its power-heuristic weight against
// area-light sampling from `source`; without, weight 1 (delta bounces, and paths that never
// sample lights).
fn emission_reached(source: Shading, wi: vec3<f32>, hit: Hit, brdf_pdf: f32, weighted: bool) -> vec3<f32> {
    return emission_reached_weighing(source, wi, hit, brdf_pdf,
        select(REACHED_UNWEIGHTED, REACHED_MIS, weighted));
}

// How emission_reached_weighing weighs what a BRDF-sampled ray reaches: by 1; by the power
// heuristic against area-light sampling; or by 1 where area-light sampling cannot produce it
// and 0 where it can (the direct pass with resampled area light, lib/reservoir.wgsl, whose
// reservoirs carry all the light the area table can reach).
const REACHED_UNWEIGHTED: u32 = 0u;
const REACHED_MIS: u32 = 1u;
const REACHED_UNSAMPLED: u32 = 2u;

// The weight of a BRDF sample of pdf brdf_pdf against area-light sampling of pdf light_pdf.
fn reached_weight(weighing: u32, brdf_pdf: f32, light_pdf: f32) -> f32 {
    if weighing == REACHED_MIS {
        return power_heuristic(1.0, brdf_pdf, 1.0, light_pdf);
    }
    if weighing == REACHED_UNSAMPLED {
        return select(1.0, 0.0, light_pdf > 0.0);
    }
    return 1.0;
}

// emission_reached, weighed as `weighing` says.
fn emission_reached_weighing(source: Shading, wi: vec3<f32>, hit: Hit, brdf_pdf: f32, weighing: u32) -> vec3<f32> {
    let weighted = weighing != REACHED_UNWEIGHTED;
    if hit.instance == BVH_NO_HIT {
        if !FEATURE_ENVIRONMENT || scene_info.env_kind == ENV_BLACK {
            return vec3<f32>(0.0);
        }
        let env = scene_environment();
        var weight = 1.0;
        if weighted {
            let light_pdf = scene_info.env_pmf * environment_pdf(env, wi);
            weight = reached_weight(weighing, brdf_pdf, light_pdf);
        }
        return environment_radiance(env, wi) * weight;
    }
    if !FEATURE_EMISSIVE_TRIANGLES {
        return vec3<f32>(0.0);
    }
    let record = bvh_load_instance_whole(hit.instance);
    let material = scene_material(record.material);
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
        if first != NO_INDEX && light_trees_picking() && scene_info.area_tree != NO_INDEX {
            let leaf = scene_info.area_leaves + first + hit.triangle;
            pmf = (1.0 - scene_info.env_pmf)
                * light_tree_pmf(leaf, source.position, source.frame.normal);
        } else if first != NO_INDEX {
            pmf = scene_area_light(first + hit.triangle).pmf;
        }
        let light_pdf = pmf * triangle_solid_angle_pdf(t.v0, t.v1, t.v2, source.position, q);
        weight = reached_weight(weighing, brdf_pdf, light_pdf);
    }
    return emitted * weight;
}
