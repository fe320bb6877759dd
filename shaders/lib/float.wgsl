// Bit-level tests and special values of IEEE 754 binary32.
//
// WGSL has no isNan or isInf, and an implementation may assume that arithmetic produces neither,
// so these inspect the bits (IEEE 754-2019, section 3.4: exponent all ones is infinity or NaN).
// Rust counterparts: f32::is_nan, f32::is_infinite, f32::is_finite, f32::INFINITY.

const F32_EXPONENT_MASK: u32 = 0x7f800000u;
const F32_ABS_MASK: u32 = 0x7fffffffu;
// The smallest positive normal value (Rust's f32::MIN_POSITIVE).
const F32_MIN_POSITIVE: f32 = 1.17549435e-38;

// +infinity, built at run time (a constant expression may not overflow).
fn f32_infinity() -> f32 {
    return bitcast<f32>(F32_EXPONENT_MASK);
}

fn f32_is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & F32_ABS_MASK) > F32_EXPONENT_MASK;
}

fn f32_is_infinite(x: f32) -> bool {
    return (bitcast<u32>(x) & F32_ABS_MASK) == F32_EXPONENT_MASK;
}

fn f32_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & F32_EXPONENT_MASK) != F32_EXPONENT_MASK;
}

fn vec3_is_finite(v: vec3<f32>) -> bool {
    return f32_is_finite(v.x) && f32_is_finite(v.y) && f32_is_finite(v.z);
}

// max(x, 0) that maps NaN to 0, like Rust's f32::max (which returns the non-NaN operand);
// WGSL's max leaves the result of a NaN operand indeterminate.
fn f32_max_zero(x: f32) -> f32 {
    return select(0.0, x, x > 0.0);
}
