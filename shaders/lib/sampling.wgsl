// Warps from uniform numbers to directions and points, and the power heuristic. Mirrors
// chiaro_shading::sampling; every function takes its uniform numbers as arguments.
//
// - Shirley and Chiu, 1997, "A Low Distortion Map Between Disk and Square" (concentric_disk).
// - Malley's method for the cosine-weighted hemisphere (cosine_hemisphere).
// - Heitz, 2019, "A Low-Distortion Map Between Triangle and Square" (uniform_triangle).
// - Veach and Guibas, 1995, "Optimally Combining Sampling Techniques for Monte Carlo
//   Rendering" (power_heuristic, beta = 2).

#import lib/generated.wgsl
#import lib/float.wgsl

// The unit square to the unit disk, area-preserving up to a constant.
fn concentric_disk(u: vec2<f32>) -> vec2<f32> {
    let a = 2.0 * u.x - 1.0;
    let b = 2.0 * u.y - 1.0;
    if a == 0.0 && b == 0.0 {
        return vec2<f32>(0.0);
    }
    var r: f32;
    var phi: f32;
    if abs(a) > abs(b) {
        r = a;
        phi = FRAC_PI_4 * (b / a);
    } else {
        r = b;
        phi = FRAC_PI_2 - FRAC_PI_4 * (a / b);
    }
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

// A cosine-weighted direction on the hemisphere z >= 0; pdf cos / pi.
fn cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let d = concentric_disk(u);
    let z = sqrt(max(1.0 - dot(d, d), 0.0));
    return vec3<f32>(d.x, d.y, z);
}

// The pdf of cosine_hemisphere for a direction with this cosine: cos / pi, 0 for cos <= 0.
fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    return f32_max_zero(cos_theta) * INV_PI;
}

// A uniform direction on the hemisphere z >= 0; pdf UNIFORM_HEMISPHERE_PDF.
fn uniform_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let z = u.x;
    let r = sqrt(max(1.0 - z * z, 0.0));
    let phi = TAU * u.y;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

// A uniform direction on the unit sphere; pdf UNIFORM_SPHERE_PDF.
fn uniform_sphere(u: vec2<f32>) -> vec3<f32> {
    let z = 1.0 - 2.0 * u.x;
    let r = sqrt(max(1.0 - z * z, 0.0));
    let phi = TAU * u.y;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

// A uniform point on a triangle as barycentrics (b1, b2) of vertices 1 and 2.
fn uniform_triangle(u: vec2<f32>) -> vec2<f32> {
    if u.y > u.x {
        let s = 0.5 * u.x;
        return vec2<f32>(s, u.y - s);
    }
    let t = 0.5 * u.y;
    return vec2<f32>(u.x - t, t);
}

// The MIS weight of a sample of strategy f (nf samples, pdf f_pdf) against strategy g, with the
// same defined answers as the Rust: negative or NaN products count as 0; both 0 gives 0; f
// infinite gives 1 (1/2 when g is infinite too); g infinite and f finite gives 0.
fn power_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    let f = f32_max_zero(nf * f_pdf);
    let g = f32_max_zero(ng * g_pdf);
    if f == g {
        return select(0.5, 0.0, f == 0.0);
    }
    if f > g {
        if f32_is_infinite(f) {
            return 1.0;
        }
        let r = g / f;
        return 1.0 / (1.0 + r * r);
    }
    if f32_is_infinite(g) {
        return 0.0;
    }
    let r = f / g;
    let r2 = r * r;
    return r2 / (1.0 + r2);
}
