// The watertight ray/triangle test of Woop, Benthin and Wald, "Watertight Ray/Triangle
// Intersection", Journal of Computer Graphics Techniques 2(1), 2013. Mirrors
// chiaro_bvh::watertight::WatertightRay.
//
// The ray's largest direction component becomes z, the other two are sheared away, and the hit
// is decided by the signs of three 2D edge functions. Where an edge function rounds to exactly
// zero the Rust recomputes all three in double precision; WGSL has no f64, so they are
// recomputed here from exact products (Dekker, 1971, "A floating-point technique for extending
// the available precision": each product split into its rounded value and exact error, the
// halves of each operand cut by masking the low 12 significand bits), which gives the same
// sign and, to within an ulp, the same value.

// A ray prepared for the watertight test.
struct WatertightRay {
    origin: vec3<f32>,
    kx: u32,
    ky: u32,
    kz: u32,
    // Shear: d[kx] / d[kz], d[ky] / d[kz], 1 / d[kz].
    shear: vec3<f32>,
}

// A triangle hit: t in units of the ray's direction, barycentrics of vertices 1 and 2.
struct TriangleHit {
    t: f32,
    b1: f32,
    b2: f32,
    found: bool,
}

// Prepares a ray; `direction` must be finite with a non-zero component.
fn watertight_ray_new(origin: vec3<f32>, direction: vec3<f32>) -> WatertightRay {
    let a = abs(direction);
    var kz = 2u;
    if a.x > a.y {
        if a.x > a.z {
            kz = 0u;
        }
    } else if a.y > a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    // Swapped to keep the winding independent of the direction's sign.
    if direction[kz] < 0.0 {
        let swap = kx;
        kx = ky;
        ky = swap;
    }
    var r: WatertightRay;
    r.origin = origin;
    r.kx = kx;
    r.ky = ky;
    r.kz = kz;
    r.shear = vec3<f32>(direction[kx] / direction[kz], direction[ky] / direction[kz], 1.0 / direction[kz]);
    return r;
}

// The high half of x: its top 12 significand bits (exact to multiply by another such half).
fn watertight_split_high(x: f32) -> f32 {
    return bitcast<f32>(bitcast<u32>(x) & 0xfffff000u);
}

// a * b as (rounded product, exact error): Dekker's product with a bit-mask split.
fn watertight_two_product(a: f32, b: f32) -> vec2<f32> {
    let p = a * b;
    let a_hi = watertight_split_high(a);
    let a_lo = a - a_hi;
    let b_hi = watertight_split_high(b);
    let b_lo = b - b_hi;
    let error = ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo;
    return vec2<f32>(p, error);
}

// a * b - c * d from exact products, rounded once more at the end.
fn watertight_exact_difference(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let ab = watertight_two_product(a, b);
    let cd = watertight_two_product(c, d);
    // Knuth's two-sum of ab.x and -cd.x.
    let s = ab.x - cd.x;
    let bb = s - ab.x;
    let sum_error = (ab.x - (s - bb)) + (-cd.x - bb);
    return s + (sum_error + (ab.y - cd.y));
}

// The hit of triangle (v0, v1, v2), either side, for t in the open interval (t_min, t_max).
fn watertight_intersect(
    ray: WatertightRay,
    v0: vec3<f32>,
    v1: vec3<f32>,
    v2: vec3<f32>,
    t_min: f32,
    t_max: f32,
) -> TriangleHit {
    var hit: TriangleHit;
    hit.found = false;
    let a = v0 - ray.origin;
    let b = v1 - ray.origin;
    let c = v2 - ray.origin;
    let ax = a[ray.kx] - ray.shear.x * a[ray.kz];
    let ay = a[ray.ky] - ray.shear.y * a[ray.kz];
    let bx = b[ray.kx] - ray.shear.x * b[ray.kz];
    let by = b[ray.ky] - ray.shear.y * b[ray.kz];
    let cx = c[ray.kx] - ray.shear.x * c[ray.kz];
    let cy = c[ray.ky] - ray.shear.y * c[ray.kz];

    var u = cx * by - cy * bx;
    var v = ax * cy - ay * cx;
    var w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        u = watertight_exact_difference(cx, by, cy, bx);
        v = watertight_exact_difference(ax, cy, ay, cx);
        w = watertight_exact_difference(bx, ay, by, ax);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return hit;
    }
    let det = u + v + w;
    if det == 0.0 {
        return hit;
    }
    let az = ray.shear.z * a[ray.kz];
    let bz = ray.shear.z * b[ray.kz];
    let cz = ray.shear.z * c[ray.kz];
    let inv_det = 1.0 / det;
    let t = (u * az + v * bz + w * cz) * inv_det;
    if t > t_min && t < t_max {
        hit.t = t;
        hit.b1 = v * inv_det;
        hit.b2 = w * inv_det;
        hit.found = true;
    }
    return hit;
}
