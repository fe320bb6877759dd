// The environment light: a constant colour or an equirectangular image importance-sampled by
// luminance x sin(theta). Mirrors chiaro_shading::lights::EnvironmentLight (whose module
// documentation states the equirectangular convention) and chiaro_shading::distribution.
//
// - Pharr, Jakob and Humphreys, 2016, "Physically Based Rendering", 3rd ed., sections 13.6.7
//   (2D distributions by marginal and conditional CDFs) and 14.2.4 (environment sampling, the
//   solid-angle pdf pmf width height / (2 pi^2 sin(theta))).
//
// The image and its tables live wherever the importing module keeps them; it defines
//     fn env_texel(column: u32, row: u32) -> vec3<f32>        // radiance, strength applied
//     fn env_marginal_cdf(i: u32) -> f32                     // height + 1 entries
//     fn env_marginal_pmf(row: u32) -> f32                   // Distribution1D::pmf
//     fn env_conditional_cdf(row: u32, i: u32) -> f32        // width + 1 entries per row
//     fn env_conditional_pmf(row: u32, column: u32) -> f32
// (the CDFs and masses exactly as chiaro_shading's Distribution2D holds them).

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/sampling.wgsl

// What the environment is (chiaro_gpu's GpuSceneInfo carries these fields).
struct Environment {
    // Constant radiance (used when `image` is false).
    radiance: vec3<f32>,
    // True for an image; its tables must then be present unless `black` is set.
    image: bool,
    // True for an image without any radiance (no distribution): sampled uniformly.
    black: bool,
    width: u32,
    height: u32,
    cos_rotation: f32,
    sin_rotation: f32,
}

// A sampled direction toward the environment, the radiance from it and its solid-angle pdf.
struct EnvironmentSample {
    wi: vec3<f32>,
    radiance: vec3<f32>,
    pdf: f32,
}

// World direction -> image frame (undo the rotation about +Y).
fn environment_to_image(env: Environment, d: vec3<f32>) -> vec3<f32> {
    let c = env.cos_rotation;
    let s = env.sin_rotation;
    return vec3<f32>(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

// Image frame -> world direction (apply the rotation about +Y).
fn environment_to_world(env: Environment, d: vec3<f32>) -> vec3<f32> {
    let c = env.cos_rotation;
    let s = env.sin_rotation;
    return vec3<f32>(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// floor(x) as an index in 0..n, saturating like Rust's `as usize` (NaN and negatives give 0).
fn environment_index(x: f32, n: u32) -> u32 {
    if !(x > 0.0) {
        return 0u;
    }
    return min(u32(min(x, 4294967040.0)), n - 1u);
}

// (column, row) of the texel an image-frame unit direction falls in, and sin(theta) there.
struct EnvironmentTexel {
    column: u32,
    row: u32,
    sin_theta: f32,
}

// atan2 with IEEE 754's answers at the origin (atan2(+-0, +0) = +-0, atan2(+-0, -0) = +-pi),
// as Rust's f32::atan2 gives them; WGSL leaves atan2(0, 0) undefined. The poles need it.
fn environment_atan2(y: f32, x: f32) -> f32 {
    if x == 0.0 && y == 0.0 {
        let angle = select(0.0, PI, (bitcast<u32>(x) & 0x80000000u) != 0u);
        return bitcast<f32>(bitcast<u32>(angle) | (bitcast<u32>(y) & 0x80000000u));
    }
    return atan2(y, x);
}

fn environment_texel_of(d: vec3<f32>, width: u32, height: u32) -> EnvironmentTexel {
    let u = 0.5 + environment_atan2(d.z, d.x) / TAU;
    let sin_theta = sqrt(d.x * d.x + d.z * d.z);
    let v = atan2(sin_theta, d.y) / PI;
    return EnvironmentTexel(environment_index(u * f32(width), width), environment_index(v * f32(height), height), sin_theta);
}

// glam's try_normalize, or +Y for a zero or non-finite direction.
fn environment_direction(dir: vec3<f32>) -> vec3<f32> {
    let reciprocal = 1.0 / length(dir);
    if f32_is_finite(reciprocal) && reciprocal > 0.0 {
        return dir * reciprocal;
    }
    return vec3<f32>(0.0, 1.0, 0.0);
}

// Radiance arriving from world direction `dir` (any length): the nearest texel, or the constant.
fn environment_radiance(env: Environment, dir: vec3<f32>) -> vec3<f32> {
    if !env.image {
        return env.radiance;
    }
    let d = environment_to_image(env, environment_direction(dir));
    let t = environment_texel_of(d, env.width, env.height);
    return env_texel(t.column, t.row);
}

// pmf width height / (2 pi^2 sin(theta)), sin(theta) at least MIN_SIN_THETA.
fn environment_solid_angle_pdf(pmf: f32, width: u32, height: u32, sin_theta: f32) -> f32 {
    return pmf * (f32(width) * f32(height)) / (2.0 * PI * PI * max(sin_theta, MIN_SIN_THETA));
}

// Distribution1D::sample_remapped over a CDF of n + 1 entries: (index, remapped u) as
// (bits of the index, remapped). `row` selects a conditional CDF; the marginal when `marginal`.
fn environment_sample_cdf(u_in: f32, n: u32, marginal: bool, row: u32) -> vec2<f32> {
    var u = clamp(u_in, 0.0, ONE_MINUS_EPSILON);
    if f32_is_nan(u_in) {
        u = 0.0;
    }
    // The largest index in 0..n whose CDF entry is <= u (a partition point of cdf[1..n]).
    var lo = 0u;
    var hi = n - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        var c: f32;
        if marginal {
            c = env_marginal_cdf(1u + mid);
        } else {
            c = env_conditional_cdf(row, 1u + mid);
        }
        if c <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    var c_lo: f32;
    var c_hi: f32;
    if marginal {
        c_lo = env_marginal_cdf(lo);
        c_hi = env_marginal_cdf(lo + 1u);
    } else {
        c_lo = env_conditional_cdf(row, lo);
        c_hi = env_conditional_cdf(row, lo + 1u);
    }
    let width = c_hi - c_lo;
    var remapped = 0.0;
    if width > 0.0 {
        remapped = clamp((u - c_lo) / width, 0.0, ONE_MINUS_EPSILON);
    }
    return vec2<f32>(bitcast<f32>(lo), remapped);
}

// Samples a world direction toward the environment; the pdf is always positive and finite.
fn environment_sample(env: Environment, u: vec2<f32>) -> EnvironmentSample {
    if !env.image {
        return EnvironmentSample(uniform_sphere(u), env.radiance, UNIFORM_SPHERE_PDF);
    }
    if env.black {
        return EnvironmentSample(uniform_sphere(u), vec3<f32>(0.0), UNIFORM_SPHERE_PDF);
    }
    let r = environment_sample_cdf(u.y, env.height, true, 0u);
    let row = bitcast<u32>(r.x);
    let c = environment_sample_cdf(u.x, env.width, false, row);
    let column = bitcast<u32>(c.x);
    let pmf = env_marginal_pmf(row) * env_conditional_pmf(row, column);
    let u_img = (f32(column) + c.y) / f32(env.width);
    let v_img = (f32(row) + r.y) / f32(env.height);
    let phi = TAU * (u_img - 0.5);
    let theta = PI * v_img;
    let sin_theta = sin(theta);
    let d = vec3<f32>(sin_theta * cos(phi), cos(theta), sin_theta * sin(phi));
    let pdf = environment_solid_angle_pdf(pmf, env.width, env.height, sin_theta);
    return EnvironmentSample(environment_to_world(env, d), env_texel(column, row), pdf);
}

// The solid-angle pdf with which environment_sample produces world direction `dir`.
fn environment_pdf(env: Environment, dir: vec3<f32>) -> f32 {
    if !env.image || env.black {
        return UNIFORM_SPHERE_PDF;
    }
    let d = environment_to_image(env, environment_direction(dir));
    let t = environment_texel_of(d, env.width, env.height);
    let pmf = env_marginal_pmf(t.row) * env_conditional_pmf(t.row, t.column);
    return environment_solid_angle_pdf(pmf, env.width, env.height, t.sin_theta);
}
