// Light sampling at a shading point p (world space) and the pdfs MIS needs. Mirrors
// chiaro_shading::lights (the environment lives in environment.wgsl).
//
// - Punctual lights after KHR_lights_punctual (Khronos glTF extension specification):
//   inverse-square falloff, the recommended smooth range window and spot cone falloff;
//   directional lights. Delta lights: pdf 1, radiance = what reaches p.
// - Triangle area lights: a uniform point (Heitz, 2019, "A Low-Distortion Map Between Triangle
//   and Square") with the area pdf converted to solid angle, dist^2 / (|cos_light| area)
//   (Pharr, Jakob and Humphreys, 2016, "Physically Based Rendering", 3rd ed., section 14.2.2).
// - power_heuristic is in sampling.wgsl.
//
// A light range is an f32 here: +infinity means "no range" (the Rust's None, which gives the
// same window), a range that is not positive (0, negative, NaN) reaches nothing.

#import lib/generated.wgsl
#import lib/float.wgsl
#import lib/sampling.wgsl

// An incident direction toward a light and what arrives along it. `valid` is false where the
// Rust returns None (the other fields are then zero).
struct LightSample {
    wi: vec3<f32>,
    // Distance to the sampled point; +infinity for directional lights.
    distance: f32,
    radiance: vec3<f32>,
    // Solid-angle pdf; 1 for delta lights.
    pdf: f32,
    delta: bool,
    valid: bool,
}

fn light_sample_none() -> LightSample {
    return LightSample(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), 0.0, false, false);
}

// KHR_lights_punctual's range window clamp(1 - (d / range)^4, 0, 1).
fn range_window(distance: f32, range: f32) -> f32 {
    if !(range > 0.0) {
        return 0.0;
    }
    let x = distance / range;
    let x2 = x * x;
    return clamp(1.0 - x2 * x2, 0.0, 1.0);
}

// KHR_lights_punctual's spot cone falloff for the cosine between the axis and the direction
// from the light to the point; inner and outer are half-angles in radians.
fn spot_falloff(cos_angle: f32, inner: f32, outer: f32) -> f32 {
    let cos_outer = cos(outer);
    let scale = 1.0 / max(cos(inner) - cos_outer, MIN_SPOT_COS_DIFFERENCE);
    let offset = -cos_outer * scale;
    let t = clamp(cos_angle * scale + offset, 0.0, 1.0);
    return t * t;
}

// Direction (xyz) and distance (w) from p to the point `to`; w = 0 when they coincide or the result is
// not finite. The offset is scaled by its largest component before its length is taken.
fn light_toward(p: vec3<f32>, to: vec3<f32>) -> vec4<f32> {
    let d = to - p;
    let a = abs(d);
    let largest = max(max(a.x, a.y), a.z);
    if !(largest > 0.0 && f32_is_finite(largest)) {
        return vec4<f32>(0.0);
    }
    let scaled = d / largest;
    let len = length(scaled);
    let distance = len * largest;
    if !f32_is_finite(distance) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(scaled / len, distance);
}

// What a point-like emitter of `intensity` delivers at `distance` with the range window; w = 0
// when the window is 0 (xyz then meaningless).
fn light_punctual(intensity: vec3<f32>, distance: f32, range: f32) -> vec4<f32> {
    let window = range_window(distance, range);
    if window <= 0.0 {
        return vec4<f32>(0.0);
    }
    let d = max(distance, MIN_PUNCTUAL_DISTANCE);
    return vec4<f32>(intensity * (window / (d * d)), 1.0);
}

// A point light of `intensity` (W/sr) at `position`, seen from p.
fn sample_point(position: vec3<f32>, intensity: vec3<f32>, range: f32, p: vec3<f32>) -> LightSample {
    let toward = light_toward(p, position);
    if toward.w == 0.0 {
        return light_sample_none();
    }
    let radiance = light_punctual(intensity, toward.w, range);
    if radiance.w == 0.0 {
        return light_sample_none();
    }
    return LightSample(toward.xyz, toward.w, radiance.xyz, 1.0, true, true);
}

// A spot light at `position` along the unit `axis` with cone half-angles (radians).
fn sample_spot(
    position: vec3<f32>,
    axis: vec3<f32>,
    intensity: vec3<f32>,
    inner_cone: f32,
    outer_cone: f32,
    range: f32,
    p: vec3<f32>,
) -> LightSample {
    let toward = light_toward(p, position);
    if toward.w == 0.0 {
        return light_sample_none();
    }
    let falloff = spot_falloff(dot(axis, -toward.xyz), inner_cone, outer_cone);
    if falloff <= 0.0 {
        return light_sample_none();
    }
    let radiance = light_punctual(intensity * falloff, toward.w, range);
    if radiance.w == 0.0 {
        return light_sample_none();
    }
    return LightSample(toward.xyz, toward.w, radiance.xyz, 1.0, true, true);
}

// A directional light whose light travels along `travel_direction` (any length), of
// `illuminance` (W/m^2). A zero or non-finite direction: radiance 0, wi = +Y.
fn sample_directional(travel_direction: vec3<f32>, illuminance: vec3<f32>) -> LightSample {
    // glam's try_normalize: the reciprocal length must be finite and positive.
    let reciprocal = 1.0 / length(travel_direction);
    if f32_is_finite(reciprocal) && reciprocal > 0.0 {
        return LightSample(-travel_direction * reciprocal, f32_infinity(), illuminance, 1.0, true, true);
    }
    return LightSample(vec3<f32>(0.0, 1.0, 0.0), f32_infinity(), vec3<f32>(0.0), 1.0, true, true);
}

// The unit geometric normal (v1 - v0) x (v2 - v0) (xyz) and the area (w) of a triangle; w = 0
// when the area is zero or not finite.
fn triangle_area_normal(v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>) -> vec4<f32> {
    let c = cross(v1 - v0, v2 - v0);
    let twice_area = length(c);
    if !(twice_area > 0.0 && f32_is_finite(twice_area)) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(c / twice_area, 0.5 * twice_area);
}

// Area pdf 1 / area at a point seen along unit wi at `distance`, in solid angle; 0 when
// edge-on or not a finite number.
fn light_area_to_solid_angle(area: f32, normal: vec3<f32>, wi: vec3<f32>, distance: f32) -> f32 {
    let cos_light = abs(dot(normal, wi));
    let pdf = distance * distance / (cos_light * area);
    return select(0.0, pdf, pdf > 0.0 && f32_is_finite(pdf));
}

// A uniform point of the triangle (v0, v1, v2) emitting `emitted`, seen from p; the front face
// ((v1 - v0) x (v2 - v0)) emits, or both faces when two_sided.
fn sample_triangle(
    v0: vec3<f32>,
    v1: vec3<f32>,
    v2: vec3<f32>,
    emitted: vec3<f32>,
    two_sided: bool,
    p: vec3<f32>,
    u: vec2<f32>,
) -> LightSample {
    let area_normal = triangle_area_normal(v0, v1, v2);
    if area_normal.w == 0.0 {
        return light_sample_none();
    }
    let b = uniform_triangle(u);
    let q = v0 + (v1 - v0) * b.x + (v2 - v0) * b.y;
    let toward = light_toward(p, q);
    if toward.w == 0.0 {
        return light_sample_none();
    }
    if !two_sided && dot(area_normal.xyz, toward.xyz) >= 0.0 {
        return light_sample_none();
    }
    let pdf = light_area_to_solid_angle(area_normal.w, area_normal.xyz, toward.xyz, toward.w);
    if pdf == 0.0 {
        return light_sample_none();
    }
    return LightSample(toward.xyz, toward.w, emitted, pdf, false, true);
}

// The solid-angle pdf with which sample_triangle would produce the point q from p (for MIS);
// 0 for a degenerate triangle, q == p or an edge-on view.
fn triangle_solid_angle_pdf(v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, p: vec3<f32>, q: vec3<f32>) -> f32 {
    let area_normal = triangle_area_normal(v0, v1, v2);
    if area_normal.w == 0.0 {
        return 0.0;
    }
    let toward = light_toward(p, q);
    if toward.w == 0.0 {
        return 0.0;
    }
    return light_area_to_solid_angle(area_normal.w, area_normal.xyz, toward.xyz, toward.w);
}
