// Indirect paths from the primary shading point x0, step by step (see indirect.wgsl for the
// estimator): the parameters of the passes that trace them, the next direction by BRDF
// importance sampling or uniformly (naive mode), and one step of a path: next-event estimation
// at its vertex, the ray, the emission it reaches, Russian roulette, the next vertex.
//
// The importing shader declares `params: IndirectParams`.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/bvh.wgsl
#import lib/rng_source.wgsl
#import lib/frame.wgsl
#import lib/sampling.wgsl
#import lib/brdf.wgsl
#import lib/camera.wgsl
#import lib/gbuffer_packing.wgsl
#import lib/gbuffer_inputs.wgsl
#import lib/surface.wgsl
#import lib/next_event.wgsl
#import lib/color.wgsl
#import lib/first_bounce.wgsl

// chiaro_gpu::passes::indirect::IndirectParams.
struct IndirectParams {
    frame: u32,
    seed_lo: u32,
    seed_hi: u32,
    spp: u32,
    bounces: u32,
    naive: u32,
    poison: u32,
    // LIGHT_SAMPLING_POWER or LIGHT_SAMPLING_TREE.
    light_sampling: u32,
    // Most luminance of one path's contribution; 0: off.
    firefly_clamp: f32,
    // 1: Owen-scrambled Sobol draws, `frame` being the sample index; 0: PCG32.
    sampler: u32,
    // Most count M of last frame's resampled-indirect reservoir (restir_gi_initial.wgsl);
    // 0: no temporal reuse.
    gi_history_cap: u32,
    pad: u32,
}

// chiaro_reference's PathSettings::default().russian_roulette_from and its survival floor.
const RUSSIAN_ROULETTE_FROM: u32 = 3u;
const RUSSIAN_ROULETTE_MIN: f32 = 0.05;
// XORed into the frame's seed for the paths' numbers (SplitMix64's second multiplier, as
// (low, high)).
const INDIRECT_SEED: vec2<u32> = vec2<u32>(0x1ce4e5b9u, 0xbf58476du);

// A direction to continue a path in: world direction, weight f cos / pdf, solid-angle pdf.
struct Scatter {
    wi: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    delta: bool,
    valid: bool,
}

// The next direction from s by BRDF importance sampling with `numbers` (lobe choice in x, the
// direction's 2D sample in yz).
fn brdf_scatter(s: Shading, numbers: vec3<f32>) -> Scatter {
    var out: Scatter;
    let bs = brdf_sample(s.params, s.wo, numbers.x, numbers.yz);
    out.wi = frame_to_world(s.frame, bs.wi);
    out.weight = bs.weight;
    out.pdf = bs.pdf;
    out.delta = bs.delta;
    out.valid = bs.valid && on_its_side(s, out.wi, bs.wi.z);
    return out;
}

// The next direction from s, uniform over the hemisphere of its shading normal (naive mode),
// or over the whole sphere for a transmissive surface.
fn uniform_scatter(s: Shading, rng: ptr<function, Rng>) -> Scatter {
    var out: Scatter;
    let u = rng_next_vec2(rng);
    var wi = uniform_hemisphere(u);
    out.pdf = UNIFORM_HEMISPHERE_PDF;
    if FEATURE_TRANSMISSION && s.params.transmission > 0.0 {
        wi = uniform_sphere(u);
        out.pdf = 0.5 * UNIFORM_HEMISPHERE_PDF;
    }
    out.wi = frame_to_world(s.frame, wi);
    out.weight = brdf_eval(s.params, s.wo, wi) * (abs(wi.z) / out.pdf);
    out.delta = false;
    out.valid = on_its_side(s, out.wi, wi.z);
    return out;
}

// The direct pass's BRDF ray from x0, for the first path: the numbers of its direction and
// its hit texel (first_bounce_traced false: trace it).
struct FirstBounce {
    numbers: vec3<f32>,
    texel: vec4<u32>,
}

// A path in flight from the primary shading point x0: the vertex it is at, its throughput, the
// light counted so far and the vertex's depth (x0 is depth 0).
struct Path {
    s: Shading,
    throughput: vec3<f32>,
    total: vec3<f32>,
    depth: u32,
}

// A pixel's path numbers, one PCG32 on the direct pass's stream (pixel index, frame) at the
// seed XOR INDIRECT_SEED, and its first bounce: the numbers of the direct pass's BRDF ray from
// x0 and that ray's hit texel.
struct PathStart {
    rng: Rng,
    first: FirstBounce,
}

fn path_start(index: u32, first_texel: vec4<u32>) -> PathStart {
    let seed = vec2<u32>(params.seed_lo, params.seed_hi);
    let pcg = pcg32_new(seed ^ INDIRECT_SEED, vec2<u32>(index, params.frame));
    return PathStart(rng_new(pcg, params.sampler, seed, index, params.frame, RNG_STREAM_PATHS),
        FirstBounce(first_bounce_numbers(seed, index, params.frame, params.sampler), first_texel));
}

fn path_from(x0: Shading) -> Path {
    return Path(x0, vec3<f32>(1.0), vec3<f32>(0.0), 0u);
}

// One step of `path` from its vertex: next-event estimation there (not at x0), the next
// direction, its ray (with `first_path`, the step from x0 is `first`'s, not in naive mode), the
// emission it reaches and the surface at its hit, which becomes the path's vertex. False when
// the path ends at this step.
fn path_step(path: ptr<function, Path>, rng: ptr<function, Rng>, first_path: bool,
    first: FirstBounce) -> bool {
    let naive = params.naive != 0u;
    let s = (*path).s;
    let depth = (*path).depth;
    if depth > 0u && !naive {
        (*path).total += (*path).throughput * next_event(s, rng);
    }
    let reuse = first_path && depth == 0u && !naive;
    var step: Scatter;
    if naive {
        step = uniform_scatter(s, rng);
    } else {
        // One call site for both the reused and the drawn direction: lavapipe runs every
        // arm of a branch, so two calls cost two BRDF samples.
        var numbers = first.numbers;
        if !reuse {
            numbers = rng_next_choice_vec2(rng);
        }
        step = brdf_scatter(s, numbers);
    }
    if !step.valid {
        return false;
    }
    var throughput = (*path).throughput * step.weight;
    if !vec3_is_finite(throughput) || all(throughput == vec3<f32>(0.0)) {
        return false;
    }
    let ray = leaving_ray(s, step.wi);
    if depth + 1u >= RUSSIAN_ROULETTE_FROM {
        let survive = clamp(max(max(throughput.x, throughput.y), throughput.z),
            RUSSIAN_ROULETTE_MIN, 1.0);
        if rng_next_f32(rng) >= survive {
            return false;
        }
        throughput /= survive;
    }
    (*path).throughput = throughput;
    var hit: Hit;
    if reuse && first_bounce_traced(first.texel) {
        hit = first_bounce_decode(first.texel);
    } else {
        hit = trace_closest(ray, f32_infinity());
    }
    if FEATURE_VOLUMES {
        throughput *= medium_transmittance(s.position, step.wi, hit);
        (*path).throughput = throughput;
    }
    if depth > 0u || naive {
        (*path).total += throughput * emission_reached(s, step.wi, hit, step.pdf,
            !naive && !step.delta);
    }
    if hit.instance == BVH_NO_HIT || depth == params.bounces {
        return false;
    }
    let next = surface_at_hit(step.wi, hit);
    if !next.shades {
        return false;
    }
    (*path).s = next.shading;
    (*path).depth = depth + 1u;
    return true;
}

