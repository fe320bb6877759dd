//! Lights: sampling an incident direction at a shading point `p` (world space), and the pdfs MIS
//! needs when a BRDF-sampled ray finds an emitter instead.
//!
//! - Punctual lights after KHR_lights_punctual (Khronos glTF extension specification): point and
//!   spot lights with inverse-square falloff, the extension's recommended smooth range window
//!   and spot cone falloff; directional lights. These are delta lights: `pdf` is 1 and `radiance`
//!   holds what reaches `p` (intensity / distance^2 with the falloffs, or illuminance).
//! - Triangle area lights: a uniformly sampled point ([`crate::sampling::uniform_triangle`]) with
//!   the area pdf converted to solid angle, dist^2 / (|cos_light| area) (Pharr, Jakob and Humphreys,
//!   2016, "Physically Based Rendering", 3rd ed., section 14.2.2).
//! - The environment ([`EnvironmentLight`]): an equirectangular image importance-sampled by
//!   luminance x sin(theta), or a constant colour.
//!
//! Defined answers: a shading point at a light's position, outside its range, behind a one-sided
//! emitter or on a degenerate (zero-area) triangle gets `None`; nothing here returns NaN or
//! infinity for finite inputs.

use glam::{Vec2, Vec3};

use crate::sampling::uniform_triangle;

mod environment;

pub use environment::{EnvironmentLight, MIN_SIN_THETA};

/// Distances below this (1e-6, a micrometre in metres) are raised to it in the inverse-square
/// falloff of point and spot lights, so a shading point next to a light gets a large but finite
/// irradiance.
pub const MIN_PUNCTUAL_DISTANCE: f32 = 1e-6;

/// The smallest `cos(inner) - cos(outer)` the spot falloff divides by (KHR_lights_punctual's
/// recommended 0.001): narrower transitions become a steep ramp, not a division by zero.
pub const MIN_SPOT_COS_DIFFERENCE: f32 = 0.001;

/// An incident direction toward a light and what arrives along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light (world space).
    pub wi: Vec3,
    /// Distance to the sampled point of the light; `f32::INFINITY` for directional and
    /// environment lights.
    pub distance: f32,
    /// Incident radiance for area and environment lights; for delta lights the incident
    /// irradiance-equivalent (intensity / distance^2 with falloffs, or the illuminance), so that
    /// the contribution is `f * cos * radiance` for both.
    pub radiance: Vec3,
    /// Solid-angle pdf of `wi`; 1 for delta lights.
    pub pdf: f32,
    /// True for point, spot and directional lights, which a BRDF-sampled ray can never hit.
    pub delta: bool,
}

/// KHR_lights_punctual's recommended range window: clamp(1 - (d / range)^4, 0, 1); 1 without a
/// range. A range that is not positive (0, negative, NaN) reaches nothing: 0.
pub fn range_window(distance: f32, range: Option<f32>) -> f32 {
    match range {
        None => 1.0,
        Some(r) if r > 0.0 => {
            let x = distance / r;
            let x2 = x * x;
            (1.0 - x2 * x2).clamp(0.0, 1.0)
        }
        Some(_) => 0.0,
    }
}

/// KHR_lights_punctual's recommended spot cone falloff for `cos_angle`, the cosine between the
/// spot's axis and the direction from the light to the point: with
/// scale = 1 / max(0.001, cos(inner) - cos(outer)) and offset = -cos(outer) scale,
/// saturate(cos_angle scale + offset)^2. `inner` and `outer` are half-angles in radians. It is 1
/// inside the inner cone (when cos(inner) - cos(outer) >= 0.001), 0 outside the outer cone, and
/// rises monotonically (smoothly, quadratically) between.
pub fn spot_falloff(cos_angle: f32, inner: f32, outer: f32) -> f32 {
    let cos_outer = outer.cos();
    let scale = 1.0 / (inner.cos() - cos_outer).max(MIN_SPOT_COS_DIFFERENCE);
    let offset = -cos_outer * scale;
    let t = (cos_angle * scale + offset).clamp(0.0, 1.0);
    t * t
}

/// Direction and distance from `p` to `target`; None when they coincide (or are not finite).
/// The offset is divided by its largest component before its length is taken, so tiny offsets
/// (1e-30) do not underflow to a zero length.
fn toward(p: Vec3, target: Vec3) -> Option<(Vec3, f32)> {
    let d = target - p;
    let largest = d.abs().max_element();
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let scaled = d / largest;
    let length = scaled.length();
    let distance = length * largest;
    if !distance.is_finite() {
        return None;
    }
    Some((scaled / length, distance))
}

/// Irradiance-equivalent of a point-like emitter of `intensity` at `distance`, with the range
/// window; None when the window is 0.
fn punctual(intensity: Vec3, distance: f32, range: Option<f32>) -> Option<Vec3> {
    let window = range_window(distance, range);
    if window <= 0.0 {
        return None;
    }
    let d = distance.max(MIN_PUNCTUAL_DISTANCE);
    Some(intensity * (window / (d * d)))
}

/// A point light of `intensity` (W/sr, linear RGB) at `position`, seen from `p`: radiance =
/// intensity window / distance^2, pdf 1, delta. None when `p` is at the light or out of range.
pub fn sample_point(
    position: Vec3,
    intensity: Vec3,
    range: Option<f32>,
    p: Vec3,
) -> Option<LightSample> {
    let (wi, distance) = toward(p, position)?;
    let radiance = punctual(intensity, distance, range)?;
    Some(LightSample {
        wi,
        distance,
        radiance,
        pdf: 1.0,
        delta: true,
    })
}

/// A spot light at `position` pointing along the unit `axis`, with cone half-angles `inner_cone`
/// and `outer_cone` (radians): the point light's radiance times [`spot_falloff`] of the angle
/// between `axis` and the direction from the light to `p`. None when `p` is at the light, out of
/// range, or outside the outer cone.
pub fn sample_spot(
    position: Vec3,
    axis: Vec3,
    intensity: Vec3,
    inner_cone: f32,
    outer_cone: f32,
    range: Option<f32>,
    p: Vec3,
) -> Option<LightSample> {
    let (wi, distance) = toward(p, position)?;
    let falloff = spot_falloff(axis.dot(-wi), inner_cone, outer_cone);
    if falloff <= 0.0 {
        return None;
    }
    let radiance = punctual(intensity * falloff, distance, range)?;
    Some(LightSample {
        wi,
        distance,
        radiance,
        pdf: 1.0,
        delta: true,
    })
}

/// A directional light whose light travels along `travel_direction` (any length), of
/// `illuminance` (W/m^2, linear RGB): wi = -travel_direction normalized, infinitely far, delta.
/// A zero or non-finite direction has no defined source: radiance 0, wi = +Y.
pub fn sample_directional(travel_direction: Vec3, illuminance: Vec3) -> LightSample {
    let (wi, radiance) = match (-travel_direction).try_normalize() {
        Some(wi) => (wi, illuminance),
        None => (Vec3::Y, Vec3::ZERO),
    };
    LightSample {
        wi,
        distance: f32::INFINITY,
        radiance,
        pdf: 1.0,
        delta: true,
    }
}

/// Area of a triangle and its unit geometric normal (v1 - v0) x (v2 - v0), normalized; None when
/// the area is zero or not finite.
pub fn triangle_area_normal(v: [Vec3; 3]) -> Option<(f32, Vec3)> {
    let cross = (v[1] - v[0]).cross(v[2] - v[0]);
    let twice_area = cross.length();
    if !(twice_area > 0.0 && twice_area.is_finite()) {
        return None;
    }
    Some((0.5 * twice_area, cross / twice_area))
}

/// Converts an area pdf 1 / `area` at a point seen from `p` along unit `wi` at `distance` to
/// solid angle: distance^2 / (|cos_light| area). None when edge-on or when the result is not a
/// finite number (a tiny triangle seen exactly edge-on).
fn area_to_solid_angle(area: f32, normal: Vec3, wi: Vec3, distance: f32) -> Option<f32> {
    let cos_light = normal.dot(wi).abs();
    let pdf = distance * distance / (cos_light * area);
    (pdf > 0.0 && pdf <= f32::MAX).then_some(pdf)
}

/// Samples a point uniformly on the triangle `v` (by `u`, [`uniform_triangle`]) emitting radiance
/// `emitted`, seen from `p`; pdf in solid angle (dist^2 / (|cos_light| area)). The emitting side is
/// the one the geometric normal (v1 - v0) x (v2 - v0) faces, or both when `two_sided`. None for a
/// degenerate triangle, a point seen from the non-emitting side or edge-on, or `p` on the triangle.
pub fn sample_triangle(
    v: [Vec3; 3],
    emitted: Vec3,
    two_sided: bool,
    p: Vec3,
    u: Vec2,
) -> Option<LightSample> {
    let (area, normal) = triangle_area_normal(v)?;
    let (b1, b2) = uniform_triangle(u);
    let q = v[0] + (v[1] - v[0]) * b1 + (v[2] - v[0]) * b2;
    let (wi, distance) = toward(p, q)?;
    // The light leaves q toward p along -wi: the front face emits when normal . (-wi) > 0.
    if !two_sided && normal.dot(wi) >= 0.0 {
        return None;
    }
    let pdf = area_to_solid_angle(area, normal, wi, distance)?;
    Some(LightSample {
        wi,
        distance,
        radiance: emitted,
        pdf,
        delta: false,
    })
}

/// The solid-angle pdf with which [`sample_triangle`] would produce the point `q` (on the
/// triangle `v`) from `p`: dist^2 / (|cos_light| area). For MIS when a BRDF-sampled ray hits the
/// emitter. It ignores which side emits (a one-sided emitter seen from behind emits nothing, so
/// its weight does not matter). 0 for a degenerate triangle, `q == p`, or an edge-on view.
pub fn triangle_solid_angle_pdf(v: [Vec3; 3], p: Vec3, q: Vec3) -> f32 {
    let Some((area, normal)) = triangle_area_normal(v) else {
        return 0.0;
    };
    let Some((wi, distance)) = toward(p, q) else {
        return 0.0;
    };
    area_to_solid_angle(area, normal, wi, distance).unwrap_or(0.0)
}

#[cfg(test)]
mod tests;
