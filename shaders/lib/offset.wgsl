// Origins of secondary rays that cannot hit the surface they leave: Wächter and Binder, "A Fast
// and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems, chapter 6, 2019.
// Mirrors chiaro_bvh::offset_ray_origin.

#import lib/generated.wgsl
#import lib/float.wgsl

fn offset_coordinate(p: f32, n: f32) -> f32 {
    if abs(p) < OFFSET_ORIGIN {
        return p + OFFSET_FLOAT_SCALE * n;
    }
    // Truncation toward zero, like Rust's `as i32` (|n| <= 1 keeps it in range).
    let ulps = i32(OFFSET_INT_SCALE * n);
    // Moving the bits of a negative number up moves it down: flip the step's sign.
    let step = select(ulps, -ulps, p < 0.0);
    let moved = bitcast<f32>(u32(bitcast<i32>(p) + step));
    return select(p, moved, f32_is_finite(moved));
}

// Moves the surface point p off its surface along the unit geometric normal (pointing to the
// side the new ray leaves from): 256 n ulps per coordinate, or n / 65536 for coordinates
// closer to zero than 1/32. Non-finite input returns p unchanged.
fn offset_ray_origin(p: vec3<f32>, geometric_normal: vec3<f32>) -> vec3<f32> {
    if !vec3_is_finite(p) || !vec3_is_finite(geometric_normal) {
        return p;
    }
    return vec3<f32>(
        offset_coordinate(p.x, geometric_normal.x),
        offset_coordinate(p.y, geometric_normal.y),
        offset_coordinate(p.z, geometric_normal.z),
    );
}
