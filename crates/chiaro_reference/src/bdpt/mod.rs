//! Bidirectional path tracing (Veach and Guibas 1994; Veach 1997, chapter 10): for every
//! sample a subpath from the camera and one from a light picked by power, joined by every
//! strategy (s light vertices, t camera vertices): s = 0, the camera path reaching an emitter
//! or the sky; s = 1, a light sampled from a camera vertex (next-event estimation); t = 1, a
//! light path vertex seen by the camera (light tracing, splatted to the pixel it lands on);
//! and the rest joined by a shadow ray. Each is weighted by the power heuristic over all the
//! strategies that make the same path ([`mis`]), so the sum is unbiased and light that camera
//! paths rarely find (through a door ajar, out of a lamp shade, focused by metal or glass) is
//! found from the light's side.
//!
//! Surfaces, textures, alpha, emitters, punctual and directional lights and an environment
//! image are the path tracer's; media attenuate every segment the way they do there. A light
//! subpath's BSDF is taken as the path tracer's in its sampling order, with importance's two
//! corrections ([`vertex::importance_factor`]): where a BSDF is not reciprocal (the clear
//! coat's and the sheen's albedo scaling by the view's angle) the two can differ slightly. A
//! light seen directly is found by the camera path alone, as in the path tracer (a point
//! light is not seen). Needs a perspective camera.

mod mis;
pub mod multiplexed;
mod vertex;
mod walk;

use chiaro_bvh::Ray;
use chiaro_shading::lights::triangle_area_normal;
use glam::{Vec2, Vec3};

use crate::integrator::{PathSettings, SHADOW_RAY_REACH, leaving_origin, sample_light};
use crate::light_table::LightEntry;
use crate::random::{RandomSource, Stream};
use crate::scene::RenderScene;
use vertex::{Vertex, VertexKind, bsdf_eval, importance_factor};
use walk::{Roulette, camera_subpath, light_subpath};

/// A light-tracing contribution to the pixel at `raster`: it adds `value` / spp to that pixel.
#[derive(Clone, Copy, Debug)]
pub struct Splat {
    /// Raster position, pixels from the top-left corner.
    pub raster: Vec2,
    /// The contribution of one light path (before division by the samples per pixel).
    pub value: Vec3,
}

impl Splat {
    /// Row-major index of the pixel it lands on in a `width` x `height` image.
    pub fn pixel(&self, width: u32, height: u32) -> usize {
        let x = (self.raster.x as u32).min(width - 1);
        let y = (self.raster.y as u32).min(height - 1);
        (y * width + x) as usize
    }
}

/// Which connection strategies a sample takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategies {
    /// Every one, weighted by MIS over all.
    All,
    /// Those of a path tracer that also traces light to the camera: the camera path reaching
    /// an emitter (s = 0), next-event estimation (s = 1) and light tracing (t = 1), weighted by
    /// MIS over these alone.
    CameraAndLightTracing,
    /// One strategy (s, t) alone, unweighted.
    One(usize, usize),
}

impl Strategies {
    /// True when strategy (s, t) is taken.
    pub fn takes(self, s: usize, t: usize) -> bool {
        match self {
            Self::All => true,
            Self::CameraAndLightTracing => s <= 1 || t == 1,
            Self::One(s1, t1) => (s, t) == (s1, t1),
        }
    }
}

/// Reusable subpath storage for one worker.
#[derive(Default)]
pub struct Subpaths {
    camera: Vec<Vertex>,
    light: Vec<Vertex>,
}

/// Unit direction from vertex `i` of `path` to the vertex before it.
fn toward_previous(scene: &RenderScene, path: &[Vertex], i: usize) -> Vec3 {
    let previous = &path[i - 1];
    if previous.is_infinite(scene) {
        previous.direction
    } else {
        (previous.position - path[i].position).normalize_or_zero()
    }
}

/// Beer-Lambert transmittance over `distance` along `w` leaving `v` (through the medium on
/// that side of its surface; none off surfaces).
fn transmittance(v: &Vertex, w: Vec3, distance: f32) -> Vec3 {
    let Some(hit) = v.hit() else {
        return Vec3::ONE;
    };
    let medium = if w.dot(hit.geometric_normal) >= 0.0 {
        hit.medium
    } else {
        hit.far_medium
    };
    if medium == Vec3::ZERO {
        Vec3::ONE
    } else {
        (-medium * distance).exp()
    }
}

/// True when nothing blocks the way from surface vertex `v` along `w` for `distance`.
fn unoccluded(scene: &RenderScene, v: &Vertex, w: Vec3, distance: f32) -> bool {
    let Some(hit) = v.hit() else {
        return false;
    };
    let ray = Ray {
        origin: leaving_origin(hit, w),
        direction: w,
        t_min: 0.0,
        t_max: if distance.is_finite() {
            distance * SHADOW_RAY_REACH
        } else {
            f32::INFINITY
        },
    };
    !scene.occluded(&ray)
}

/// The unweighted contribution of strategy (s, t), the vertex it drew afresh (s = 1: the
/// light point; t = 1: the eye) and, for t = 1, where on the image it lands.
fn connect(
    scene: &RenderScene,
    light: &[Vertex],
    camera: &[Vertex],
    (s, t): (usize, usize),
    rng: &mut impl RandomSource,
) -> Option<(Vec3, Option<Vertex>, Option<Vec2>)> {
    let pt = &camera[t - 1];
    if s == 0 {
        let le = match &pt.kind {
            VertexKind::Surface { hit, .. } => hit.emission,
            VertexKind::Environment => scene.environment.radiance(pt.direction),
            _ => Vec3::ZERO,
        };
        return (le != Vec3::ZERO).then_some((pt.beta * le, None, None));
    }
    if matches!(pt.kind, VertexKind::Environment) {
        return None;
    }
    if t == 1 {
        let qs = &light[s - 1];
        let hit = qs.hit()?;
        let to_eye = scene.camera.eye() - qs.position;
        let distance = to_eye.length();
        let w = to_eye / distance;
        let seen = scene.camera.importance(-w)?;
        let to_previous = toward_previous(scene, light, s - 1);
        let f = bsdf_eval(hit, to_previous, w)
            * importance_factor(hit, to_previous, w)
            * w.dot(hit.frame.normal).abs();
        if f == Vec3::ZERO {
            return None;
        }
        let eye = Vertex::new(
            VertexKind::Camera,
            scene.camera.eye(),
            Vec3::ZERO,
            Vec3::splat(seen.we * seen.cos / (distance * distance)),
        );
        let value = qs.beta * f * eye.beta * transmittance(qs, w, distance);
        if value == Vec3::ZERO || !unoccluded(scene, qs, w, distance) {
            return None;
        }
        return Some((value, Some(eye), Some(seen.raster)));
    }
    let hit = pt.hit()?;
    let to_previous = toward_previous(scene, camera, t - 1);
    if s == 1 {
        let (entry, pick) = scene.lights.pick_by_power(rng.next_f32())?;
        let light_entry = &scene.lights.lights[entry];
        let sample = sample_light(scene, light_entry, pt.position, rng.next_vec2())?;
        let f = bsdf_eval(hit, to_previous, sample.wi) * sample.wi.dot(hit.frame.normal).abs();
        if f == Vec3::ZERO || sample.radiance == Vec3::ZERO {
            return None;
        }
        let infinite = !sample.distance.is_finite();
        let normal = match light_entry {
            LightEntry::Triangle { vertices, .. } => {
                triangle_area_normal(*vertices).map_or(Vec3::ZERO, |(_, n)| n)
            }
            _ => Vec3::ZERO,
        };
        let position = if infinite {
            pt.position + sample.wi
        } else {
            pt.position + sample.wi * sample.distance
        };
        let mut point = Vertex::new(
            VertexKind::Light { entry },
            position,
            normal,
            sample.radiance / (sample.pdf * pick),
        );
        point.direction = sample.wi;
        point.pdf_fwd = point.pdf_light_origin(scene, pt);
        let value = pt.beta * f * point.beta * transmittance(pt, sample.wi, sample.distance);
        if value == Vec3::ZERO || !unoccluded(scene, pt, sample.wi, sample.distance) {
            return None;
        }
        return Some((value, Some(point), None));
    }
    let qs = &light[s - 1];
    let q_hit = qs.hit()?;
    let d = qs.position - pt.position;
    let distance = d.length();
    if distance <= 0.0 {
        return None;
    }
    let w = d / distance;
    let q_previous = toward_previous(scene, light, s - 1);
    let f_camera = bsdf_eval(hit, to_previous, w) * w.dot(hit.frame.normal).abs();
    let f_light = bsdf_eval(q_hit, q_previous, -w)
        * importance_factor(q_hit, q_previous, -w)
        * w.dot(q_hit.frame.normal).abs();
    let value = pt.beta * f_camera * f_light * qs.beta * transmittance(pt, w, distance)
        / (distance * distance);
    if value == Vec3::ZERO || !value.is_finite() || !unoccluded(scene, pt, w, distance) {
        return None;
    }
    Some((value, None, None))
}

/// One sample of pixel (x, y) at `jitter` within it: the radiance the strategies with a camera
/// path of two or more vertices bring to it; the light-tracing strategy's contributions (t = 1)
/// go to `splats`. `strategies` says which are taken. The camera subpath draws from
/// the stream `rng` is on (the caller draws the film position there first); the light subpath
/// and the connections start streams of their own.
#[allow(clippy::too_many_arguments)]
pub fn sample(
    scene: &RenderScene,
    pixel: (u32, u32),
    jitter: Vec2,
    rng: &mut impl RandomSource,
    settings: &PathSettings,
    strategies: Strategies,
    subpaths: &mut Subpaths,
    splats: &mut Vec<Splat>,
) -> Vec3 {
    let depth = if settings.direct_only {
        1
    } else {
        settings.max_depth
    };
    let roulette = Roulette(settings.russian_roulette_from);
    let Subpaths { camera, light } = subpaths;
    camera_subpath(scene, pixel, jitter, rng, depth + 1, &roulette, camera);
    rng.start_stream(Stream::Light);
    light_subpath(scene, rng, depth, &roulette, light);
    rng.start_stream(Stream::Connect);
    let mut total = Vec3::ZERO;
    for t in 1..=camera.len() {
        for s in 0..=light.len() {
            let bounces = (s + t) as i64 - 2;
            if bounces < 0
                || bounces > depth as i64
                || (s == 1 && t == 1)
                || !strategies.takes(s, t)
            {
                continue;
            }
            let Some((value, drawn, raster)) = connect(scene, light, camera, (s, t), rng) else {
                continue;
            };
            let weighted = match strategies {
                Strategies::One(..) => value,
                _ => value * mis::weight(scene, light, camera, (s, t), drawn.as_ref(), strategies),
            };
            match raster {
                Some(raster) => splats.push(Splat {
                    raster,
                    value: weighted,
                }),
                None => total += weighted,
            }
        }
    }
    total
}
