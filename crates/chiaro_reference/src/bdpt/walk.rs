//! The two subpaths: one from the camera, one from a light picked by power, each a random walk
//! that importance-samples the BSDF and records, at every vertex, the area densities MIS needs.

use std::f32::consts::{PI, TAU};

use chiaro_bvh::{Ray, offset_ray_origin};
use chiaro_shading::brdf;
use chiaro_shading::frame::Frame;
use chiaro_shading::lights::{range_window, spot_falloff, triangle_area_normal};
use chiaro_shading::sampling::{
    UNIFORM_SPHERE_PDF, concentric_disk, cosine_hemisphere, uniform_sphere, uniform_triangle,
};
use glam::{Vec2, Vec3};

use super::vertex::{Vertex, VertexKind, bsdf_pdf, importance_factor};
use crate::integrator::{leaving_origin, triangle_emission};
use crate::light_table::LightEntry;
use crate::random::RandomSource;
use crate::scene::RenderScene;
use crate::surface::surface_at;

/// Which way a subpath carries light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Transport {
    /// From the camera: radiance.
    Radiance,
    /// From a light: importance.
    Importance,
}

/// Russian roulette for subpaths: from which surface vertex it may end them.
pub struct Roulette(pub Option<u32>);

/// Extends `path` along `ray`, whose direction was drawn with solid-angle pdf `pdf` from the
/// last vertex, with throughput `beta`, by at most `max_vertices` surface vertices (a camera
/// path that escapes adds an environment vertex).
#[allow(clippy::too_many_arguments)]
fn random_walk(
    scene: &RenderScene,
    rng: &mut impl RandomSource,
    mut ray: Ray,
    mut beta: Vec3,
    mut pdf: f32,
    transport: Transport,
    max_vertices: u32,
    roulette: &Roulette,
    path: &mut Vec<Vertex>,
) {
    let mut pushed = 0;
    // Roulette weighs the throughput against the walk's start: a light path's is in the
    // light's units, far from 1.
    let start = beta.max_element().max(f32::MIN_POSITIVE);
    while pushed < max_vertices {
        let Some(found) = scene.closest_hit(&ray) else {
            if transport == Transport::Radiance {
                let mut v = Vertex::new(
                    VertexKind::Environment,
                    ray.origin + ray.direction,
                    Vec3::ZERO,
                    beta,
                );
                v.direction = ray.direction;
                v.pdf_fwd = pdf;
                path.push(v);
            }
            return;
        };
        let si = surface_at(scene, &ray, &found);
        if si.medium != Vec3::ZERO {
            beta *= (-si.medium * found.t * ray.direction.length()).exp();
        }
        let light = if transport == Transport::Radiance && si.emission != Vec3::ZERO {
            scene.lights.triangle_index(found.instance, found.triangle)
        } else {
            None
        };
        let (position, normal, shades) = (si.position, si.geometric_normal, si.shades);
        let frame = si.frame;
        let params = si.params;
        let mut v = Vertex::new(
            VertexKind::Surface {
                hit: Box::new(si),
                light,
            },
            position,
            normal,
            beta,
        );
        let previous = path.last().expect("a walk starts from a vertex");
        v.pdf_fwd = previous.convert_density(scene, pdf, &v);
        path.push(v);
        pushed += 1;
        if !shades || pushed == max_vertices {
            return;
        }
        let wo = -ray.direction;
        let Some(sample) =
            brdf::sample(&params, frame.to_local(wo), rng.next_f32(), rng.next_vec2())
        else {
            return;
        };
        let wi = frame.to_world(sample.wi);
        let n = path.len();
        let hit = path[n - 1].hit().expect("just pushed");
        // The shading-normal rule (as the path tracer's): no crossing on the wrong side.
        if (sample.wi.z > 0.0) != (wi.dot(hit.geometric_normal) > 0.0) {
            return;
        }
        let mut weight = sample.weight;
        if transport == Transport::Importance {
            weight *= importance_factor(hit, wo, wi);
        }
        beta *= weight;
        if !beta.is_finite() || beta == Vec3::ZERO {
            return;
        }
        let reverse = if sample.delta {
            0.0
        } else {
            bsdf_pdf(hit, wi, wo)
        };
        pdf = if sample.delta { 0.0 } else { sample.pdf };
        let origin = leaving_origin(hit, wi);
        path[n - 1].delta = sample.delta;
        path[n - 2].pdf_rev = path[n - 1].convert_density(scene, reverse, &path[n - 2]);
        ray = Ray {
            origin,
            direction: wi,
            t_min: 0.0,
            t_max: f32::INFINITY,
        };
        if let Some(from) = roulette.0
            && pushed >= from
        {
            let survive = (beta.max_element() / start).clamp(0.05, 1.0);
            if rng.next_f32() >= survive {
                return;
            }
            beta /= survive;
        }
    }
}

/// The camera subpath through pixel (x, y) at `jitter` within it: the eye, then up to
/// `max_vertices` surface vertices (the last an environment vertex where it escapes).
pub fn camera_subpath(
    scene: &RenderScene,
    (x, y): (u32, u32),
    jitter: Vec2,
    rng: &mut impl RandomSource,
    max_vertices: u32,
    roulette: &Roulette,
    path: &mut Vec<Vertex>,
) {
    path.clear();
    let ray = scene.camera.ray(x, y, jitter);
    path.push(Vertex::new(
        VertexKind::Camera,
        scene.camera.eye(),
        Vec3::ZERO,
        Vec3::ONE,
    ));
    let pdf = scene.camera.direction_pdf(ray.direction);
    random_walk(
        scene,
        rng,
        ray,
        Vec3::ONE,
        pdf,
        Transport::Radiance,
        max_vertices,
        roulette,
        path,
    );
}

/// A point on the disk of radius `radius` centred on `centre`, perpendicular to unit `axis`.
fn disk_point(centre: Vec3, axis: Vec3, radius: f32, u: Vec2) -> Vec3 {
    let frame = Frame::from_normal(axis);
    let d = concentric_disk(u) * radius;
    centre + frame.tangent * d.x + frame.bitangent * d.y
}

/// A direction uniformly inside the cone of half-angle `outer` about unit `axis`.
fn uniform_cone(axis: Vec3, outer: f32, u: Vec2) -> Vec3 {
    let cos = 1.0 - u.x * (1.0 - outer.cos());
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = TAU * u.y;
    Frame::from_normal(axis).to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos))
}

/// The light subpath: a light picked by power, a point and direction of its emission, then up
/// to `max_vertices` surface vertices.
pub fn light_subpath(
    scene: &RenderScene,
    rng: &mut impl RandomSource,
    max_vertices: u32,
    roulette: &Roulette,
    path: &mut Vec<Vertex>,
) {
    path.clear();
    let Some((entry, pick)) = scene.lights.pick_by_power(rng.next_f32()) else {
        return;
    };
    let (u_position, u_direction) = (rng.next_vec2(), rng.next_vec2());
    let (centre, radius) = scene.lights.bounding_sphere;
    let disk_pdf = 1.0 / (PI * radius * radius);
    let kind = VertexKind::Light { entry };
    // (origin vertex, ray, ray throughput, direction pdf, range of a punctual light)
    let (origin, ray, beta, pdf_direction, range) = match scene.lights.lights[entry] {
        LightEntry::Point {
            position,
            intensity,
            range,
        } => {
            let w = uniform_sphere(u_direction);
            let mut v = Vertex::new(kind, position, Vec3::ZERO, intensity / pick);
            v.pdf_fwd = pick;
            let beta = intensity / (pick * UNIFORM_SPHERE_PDF);
            (v, Ray::new(position, w), beta, UNIFORM_SPHERE_PDF, range)
        }
        LightEntry::Spot {
            position,
            axis,
            intensity,
            inner,
            outer,
            range,
        } => {
            let w = uniform_cone(axis, outer, u_direction);
            let pdf = 1.0 / (TAU * (1.0 - outer.cos()));
            let le = intensity * spot_falloff(axis.dot(w), inner, outer);
            let mut v = Vertex::new(kind, position, Vec3::ZERO, le / pick);
            v.pdf_fwd = pick;
            (v, Ray::new(position, w), le / (pick * pdf), pdf, range)
        }
        LightEntry::Directional {
            travel,
            illuminance,
        } => {
            let Some(d) = travel.try_normalize() else {
                return;
            };
            let p = disk_point(centre - d * radius, d, radius, u_position);
            let mut v = Vertex::new(kind, p, Vec3::ZERO, illuminance / (pick * disk_pdf));
            v.direction = -d;
            let beta = illuminance / (pick * disk_pdf);
            (v, Ray::new(p, d), beta, disk_pdf, None)
        }
        LightEntry::Environment => {
            let (escape, radiance, pdf) = scene.environment.sample(u_direction);
            let d = -escape;
            let p = disk_point(centre - d * radius, d, radius, u_position);
            let mut v = Vertex::new(kind, p, Vec3::ZERO, radiance / (pick * disk_pdf));
            v.direction = escape;
            v.pdf_fwd = pick * pdf;
            let beta = radiance / (pick * disk_pdf * pdf);
            (v, Ray::new(p, d), beta, disk_pdf, None)
        }
        LightEntry::Triangle {
            instance,
            triangle,
            vertices: t,
            two_sided,
        } => {
            let (b1, b2) = uniform_triangle(u_position);
            let p = t[0] * (1.0 - b1 - b2) + t[1] * b1 + t[2] * b2;
            let (Some((area, n)), Some(le)) = (
                triangle_area_normal(t),
                triangle_emission(scene, instance, triangle, (b1, b2)),
            ) else {
                return;
            };
            if le == Vec3::ZERO {
                return;
            }
            // A two-sided emitter picks a side, then a cosine-weighted direction on it.
            let (side, u, sides) = if two_sided && u_direction.x < 0.5 {
                (-n, Vec2::new(2.0 * u_direction.x, u_direction.y), 2.0)
            } else if two_sided {
                (n, Vec2::new(2.0 * u_direction.x - 1.0, u_direction.y), 2.0)
            } else {
                (n, u_direction, 1.0)
            };
            let local = cosine_hemisphere(u.min(Vec2::splat(1.0 - f32::EPSILON)));
            let w = Frame::from_normal(side).to_world(local);
            let pdf = local.z / (PI * sides);
            if pdf <= 0.0 {
                return;
            }
            let position_pdf = pick / area;
            let mut v = Vertex::new(kind, p, n, le / position_pdf);
            v.pdf_fwd = position_pdf;
            let beta = le * local.z / (position_pdf * pdf);
            let ray = Ray::new(offset_ray_origin(p, side), w);
            (v, ray, beta, pdf, None)
        }
    };
    let infinite = origin.is_infinite(scene);
    path.push(origin);
    random_walk(
        scene,
        rng,
        ray,
        beta,
        pdf_direction,
        Transport::Importance,
        max_vertices,
        roulette,
        path,
    );
    if path.len() > 1 {
        if infinite {
            // The first hit's density is the disk's, in area measure at the hit.
            let cos = path[1].normal.dot(ray.direction).abs();
            path[1].pdf_fwd = disk_pdf * cos;
        }
        if let Some(range) = range {
            let window = range_window((path[1].position - path[0].position).length(), Some(range));
            for v in &mut path[1..] {
                v.beta *= window;
            }
        }
    }
}
