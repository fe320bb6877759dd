// Stochastic coverage (glTF alpha mode BLEND): a surface of alpha a stops a ray with
// probability a, else the ray passes straight through. Mirrors chiaro_shading::coverage bit
// for bit (its docs give the rule and why the numbers are hashes): Jarzynski and Olano's PCG
// hash, "Hash Functions for GPU Rendering", JCGT 9(3), 2020, chained over the words.

// 2^-24 exactly.
const COVERAGE_TWO_POW_MINUS_24: f32 = 5.9604644775390625e-8;

fn coverage_pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The top 24 bits of a hash as a uniform number in [0, 1), exact.
fn coverage_unit_float(hash: u32) -> f32 {
    return f32(hash >> 8u) * COVERAGE_TWO_POW_MINUS_24;
}

// chiaro_shading::coverage::ray_number.
fn coverage_ray_number(origin: vec3<f32>, direction: vec3<f32>, instance: u32, triangle: u32) -> f32 {
    let o = bitcast<vec3<u32>>(origin);
    let d = bitcast<vec3<u32>>(direction);
    var h = coverage_pcg_hash(o.x);
    h = coverage_pcg_hash(h ^ o.y);
    h = coverage_pcg_hash(h ^ o.z);
    h = coverage_pcg_hash(h ^ d.x);
    h = coverage_pcg_hash(h ^ d.y);
    h = coverage_pcg_hash(h ^ d.z);
    h = coverage_pcg_hash(h ^ instance);
    h = coverage_pcg_hash(h ^ triangle);
    return coverage_unit_float(h);
}

// chiaro_shading::coverage::fragment_number.
fn coverage_fragment_number(pixel: vec2<u32>, frame_seed: u32, instance: u32, depth: f32) -> f32 {
    var h = coverage_pcg_hash(pixel.x);
    h = coverage_pcg_hash(h ^ pixel.y);
    h = coverage_pcg_hash(h ^ frame_seed);
    h = coverage_pcg_hash(h ^ instance);
    h = coverage_pcg_hash(h ^ bitcast<u32>(depth));
    return coverage_unit_float(h);
}

// chiaro_shading::coverage::stops.
fn coverage_stops(alpha: f32, u: f32) -> bool {
    return u < alpha;
}
