//! The path tracer: the rendering equation estimated by Monte Carlo along paths from the camera.
//! At every vertex one light is picked by power and sampled (next-event estimation), the BRDF is
//! importance-sampled for the next direction, and both strategies are combined with the power
//! heuristic (Veach and Guibas 1995, "Optimally Combining Sampling Techniques for Monte Carlo
//! Rendering"), so an emitter or the sky reached by a BRDF-sampled ray is weighted against the
//! chance that light sampling would have found it. Delta lights and mirror bounces take their
//! single strategy unweighted. Inside a KHR_materials_volume mesh the throughput is attenuated
//! by Beer-Lambert's law over each segment (the medium is known from the back face a segment
//! ends on; media are not nested, and light sampled from inside one counts as occluded by its
//! boundary, which a shadow ray hits). Russian roulette (after a configurable depth) keeps the estimate
//! unbiased by dividing the survivors' throughput by their survival probability.

use chiaro_bvh::{Ray, offset_ray_origin};
use chiaro_shading::brdf::Bsdf;
use chiaro_shading::lights::{self, LightSample};
use chiaro_shading::sampling::{power_heuristic, uniform_triangle};
use glam::{Vec2, Vec3};

use crate::light_table::{LightEntry, LightSampling};
use crate::random::RandomSource;
use crate::scene::RenderScene;
use crate::surface::{SurfaceHit, emission_at, emitter_coverage, surface_at, uvs_at};

/// How paths are traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathSettings {
    /// Most surface vertices that scatter light (next-event estimation and a BRDF-sampled
    /// bounce). The ray leaving the last one is still traced for the emission or sky it reaches,
    /// with its MIS weight, so depth D holds every path of up to D bounces exactly: 0 shows
    /// emitters only, 1 is direct lighting (as Mitsuba's `max_depth` D + 1). High by default:
    /// Russian roulette ends paths.
    pub max_depth: u32,
    /// Depth from which Russian roulette may end a path; `None` turns it off.
    pub russian_roulette_from: Option<u32>,
    /// Emission plus direct light at the first hit only (what the GPU direct pass computes):
    /// the same as `max_depth` 1.
    pub direct_only: bool,
    /// How next-event estimation picks a light.
    pub light_sampling: LightSampling,
    /// Which estimator traces the paths.
    pub integrator: Integrator,
}

/// The estimator of the rendering equation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Integrator {
    /// Paths from the camera with next-event estimation and MIS (this module).
    #[default]
    Pt,
    /// Bidirectional path tracing: a camera and a light subpath, joined by every connection
    /// strategy and weighted by MIS ([`crate::bdpt`]).
    Bdpt,
    /// The path tracer's strategies with light tracing to the camera added: the bidirectional
    /// estimator's camera paths reaching emitters (s = 0), next-event estimation (s = 1) and
    /// light subpaths seen by the camera (t = 1), weighted by MIS among these alone. What a
    /// camera-path renderer would gain from light tracing (caustics seen on diffuse surfaces).
    PtLt,
    /// Primary-sample-space Metropolis light transport over the bidirectional estimator
    /// ([`crate::mlt`]): `spp` is mutations per pixel.
    Mlt,
    /// Multiplexed Metropolis light transport ([`crate::mlt`]): each mutation evaluates one
    /// connection strategy of one path length, weighted by MIS. `spp` is mutations per pixel.
    Mmlt,
    /// One strategy of the bidirectional estimator alone, unweighted: `s` light and `t` camera
    /// vertices (t >= 1, s + t >= 2), so only paths of exactly s + t - 2 bounces. Each such
    /// image is an unbiased estimate of the same light, which makes it a check of the
    /// strategy.
    BdptStrategy {
        /// Light subpath vertices.
        s: u32,
        /// Camera subpath vertices.
        t: u32,
    },
}

impl std::fmt::Display for Integrator {
    /// Its name on the command line; one strategy reads `bdpt(s, t)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Pt => f.write_str("pt"),
            Self::PtLt => f.write_str("ptlt"),
            Self::Bdpt => f.write_str("bdpt"),
            Self::Mlt => f.write_str("mlt"),
            Self::Mmlt => f.write_str("mmlt"),
            Self::BdptStrategy { s, t } => write!(f, "bdpt({s}, {t})"),
        }
    }
}

impl std::str::FromStr for Integrator {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "pt" => Ok(Self::Pt),
            "bdpt" => Ok(Self::Bdpt),
            "ptlt" => Ok(Self::PtLt),
            "mlt" => Ok(Self::Mlt),
            "mmlt" => Ok(Self::Mmlt),
            other => Err(format!(
                "unknown integrator '{other}' (expected pt, ptlt, bdpt, mlt or mmlt)"
            )),
        }
    }
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            max_depth: 64,
            russian_roulette_from: Some(3),
            direct_only: false,
            light_sampling: LightSampling::default(),
            integrator: Integrator::Pt,
        }
    }
}

/// Fraction of the distance to a sampled light point that a shadow ray tests, so the emitter
/// itself does not occlude its own sample.
pub(crate) const SHADOW_RAY_REACH: f32 = 1.0 - 1e-4;

/// The previous vertex, for MIS weights of emission found by BRDF sampling.
#[derive(Clone, Copy)]
struct Previous {
    position: Vec3,
    /// Its shading normal: light selection may depend on it.
    normal: Vec3,
    pdf: f32,
    delta: bool,
}

/// Radiance of emissive triangle `triangle` of instance `instance` at barycentrics (b1, b2) of
/// its world-space vertices (front face counter-clockwise), alpha-blended coverage included.
pub(crate) fn triangle_emission(
    scene: &RenderScene,
    instance: u32,
    triangle: u32,
    (b1, b2): (f32, f32),
) -> Option<Vec3> {
    let record = &scene.bvh.instances()[instance as usize];
    let mesh = scene.meshes.get(record.mesh)?;
    let material = scene.materials.get(record.material)?;
    // world_triangle swaps vertices 1 and 2 under a mirroring transform.
    let mirrored = record.world.matrix3.determinant() < 0.0;
    let b = if mirrored {
        Vec3::new(1.0 - b1 - b2, b2, b1)
    } else {
        Vec3::new(1.0 - b1 - b2, b1, b2)
    };
    Some(
        emission_at(scene, material, uvs_at(mesh, triangle, b))
            * emitter_coverage(scene, material, mesh, triangle, b),
    )
}

/// Samples light `entry` from `p`.
pub(crate) fn sample_light(
    scene: &RenderScene,
    entry: &LightEntry,
    p: Vec3,
    u: Vec2,
) -> Option<LightSample> {
    match *entry {
        LightEntry::Point {
            position,
            intensity,
            range,
        } => lights::sample_point(position, intensity, range, p),
        LightEntry::Spot {
            position,
            axis,
            intensity,
            inner,
            outer,
            range,
        } => lights::sample_spot(position, axis, intensity, inner, outer, range, p),
        LightEntry::Directional {
            travel,
            illuminance,
        } => Some(lights::sample_directional(travel, illuminance)),
        LightEntry::Triangle {
            instance,
            triangle,
            vertices: v,
            two_sided,
        } => {
            let (b1, b2) = uniform_triangle(u);
            let q = v[0] * (1.0 - b1 - b2) + v[1] * b1 + v[2] * b2;
            let to_light = q - p;
            let distance = to_light.length();
            if distance <= 0.0 {
                return None;
            }
            let wi = to_light / distance;
            let facing = (v[1] - v[0]).cross(v[2] - v[0]).dot(-wi);
            if facing <= 0.0 && !two_sided {
                return None;
            }
            let radiance = triangle_emission(scene, instance, triangle, (b1, b2))?;
            let pdf = lights::triangle_solid_angle_pdf(v, p, q);
            (pdf > 0.0 && pdf.is_finite()).then_some(LightSample {
                wi,
                distance,
                radiance,
                pdf,
                delta: false,
            })
        }
        LightEntry::Environment => {
            let (wi, radiance, pdf) = scene.environment.sample(u);
            (pdf > 0.0).then_some(LightSample {
                wi,
                distance: f32::INFINITY,
                radiance,
                pdf,
                delta: false,
            })
        }
    }
}

/// The shading-normal rule: a direction the BSDF reflects (above the shading normal, positive
/// `local_z`) must leave on the side the geometric normal (turned towards the viewer) faces, and
/// a transmitted one (negative `local_z`) on the other. A world direction `wi` on the wrong side
/// carries nothing, whatever the shading normal says (as Cycles does): a BSDF sample there ends
/// the path instead of crossing the surface, and a light sample there counts zero.
fn on_its_side(si: &SurfaceHit, wi: Vec3, local_z: f32) -> bool {
    let geometric = wi.dot(si.geometric_normal);
    if local_z > 0.0 {
        geometric > 0.0
    } else {
        local_z < 0.0 && geometric < 0.0
    }
}

/// The origin of a ray leaving `si` along `wi`, offset to the side `wi` goes.
pub(crate) fn leaving_origin(si: &SurfaceHit, wi: Vec3) -> Vec3 {
    if wi.dot(si.geometric_normal) >= 0.0 {
        offset_ray_origin(si.position, si.geometric_normal)
    } else {
        offset_ray_origin(si.position, -si.geometric_normal)
    }
}

/// Next-event estimate at `si`, whose BSDF for the view is `bsdf`: one light picked by power,
/// sampled, tested for visibility.
fn direct_light(
    scene: &RenderScene,
    si: &SurfaceHit,
    bsdf: &Bsdf,
    rng: &mut impl RandomSource,
) -> Vec3 {
    let (u_pick, u) = rng.next_choice_and_vec2();
    let Some((index, pick)) = scene.lights.pick(u_pick, si.position, si.frame.normal) else {
        return Vec3::ZERO;
    };
    let Some(ls) = sample_light(scene, &scene.lights.lights[index], si.position, u) else {
        return Vec3::ZERO;
    };
    let wi = si.frame.to_local(ls.wi);
    if !on_its_side(si, ls.wi, wi.z) || ls.radiance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let f = bsdf.eval(wi) * wi.z.abs();
    if f == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let shadow = Ray {
        origin: leaving_origin(si, ls.wi),
        direction: ls.wi,
        t_min: 0.0,
        t_max: if ls.distance.is_finite() {
            ls.distance * SHADOW_RAY_REACH
        } else {
            f32::INFINITY
        },
    };
    if scene.occluded(&shadow) {
        return Vec3::ZERO;
    }
    if ls.delta {
        return f * ls.radiance / pick;
    }
    let light_pdf = pick * ls.pdf;
    let weight = power_heuristic(1.0, light_pdf, 1.0, bsdf.pdf(wi));
    f * ls.radiance * weight / light_pdf
}

/// The MIS weight of emission reached by a BRDF-sampled ray whose light-sampling pdf is
/// `light_pdf` (1 for camera rays and delta bounces).
fn emission_weight(previous: Option<Previous>, light_pdf: impl FnOnce(&Previous) -> f32) -> f32 {
    match previous {
        None => 1.0,
        Some(p) if p.delta => 1.0,
        Some(p) => power_heuristic(1.0, p.pdf, 1.0, light_pdf(&p)),
    }
}

/// Radiance arriving along `ray` (a camera ray), from the numbers `rng` draws.
pub fn radiance(
    scene: &RenderScene,
    mut ray: Ray,
    rng: &mut impl RandomSource,
    settings: &PathSettings,
) -> Vec3 {
    let mut total = Vec3::ZERO;
    let mut throughput = Vec3::ONE;
    let mut previous: Option<Previous> = None;
    let last = if settings.direct_only {
        1
    } else {
        settings.max_depth
    };
    for depth in 0..=last {
        let Some(hit) = scene.closest_hit(&ray) else {
            let weight = emission_weight(previous, |_| {
                scene.lights.environment_pmf() * scene.environment.pdf(ray.direction)
            });
            total += throughput * scene.environment.radiance(ray.direction) * weight;
            break;
        };
        let si = surface_at(scene, &ray, &hit);
        if si.medium != Vec3::ZERO {
            // Beer-Lambert along the segment inside a volume.
            let distance = hit.t * ray.direction.length();
            throughput *= (-si.medium * distance).exp();
        }
        if si.emission != Vec3::ZERO {
            let weight = emission_weight(previous, |from| {
                let record = &scene.bvh.instances()[hit.instance as usize];
                let mesh = scene.meshes.get(record.mesh).expect("stored mesh");
                let v = crate::surface::world_triangle(mesh, hit.triangle, &record.world);
                scene
                    .lights
                    .triangle_pmf(hit.instance, hit.triangle, from.position, from.normal)
                    * lights::triangle_solid_angle_pdf(v, from.position, si.position)
            });
            total += throughput * si.emission * weight;
        }
        if !si.shades || depth == last {
            break;
        }
        let bsdf = Bsdf::new(&si.params, si.frame.to_local(-ray.direction));
        total += throughput * direct_light(scene, &si, &bsdf, rng);

        let (u_lobe, u) = rng.next_choice_and_vec2();
        let Some(sample) = bsdf.sample(u_lobe, u) else {
            break;
        };
        let wi = si.frame.to_world(sample.wi);
        // A direction on the wrong side of the geometric surface carries nothing (the
        // shading-normal rule): crossing the surface there would leak light.
        if !on_its_side(&si, wi, sample.wi.z) {
            break;
        }
        throughput *= sample.weight;
        if !throughput.is_finite() || throughput == Vec3::ZERO {
            break;
        }
        ray = Ray {
            origin: leaving_origin(&si, wi),
            direction: wi,
            t_min: 0.0,
            t_max: f32::INFINITY,
        };
        previous = Some(Previous {
            position: si.position,
            normal: si.frame.normal,
            pdf: sample.pdf,
            delta: sample.delta,
        });

        if let Some(from) = settings.russian_roulette_from
            && depth + 1 >= from
        {
            let survive = throughput.max_element().clamp(0.05, 1.0);
            if rng.next_f32() >= survive {
                break;
            }
            throughput /= survive;
        }
    }
    total
}
