//! A vertex of a camera or light subpath, and what MIS asks of it: the density with which a
//! neighbour would have been sampled from it, in area measure (Veach 1997, section 10.2; the
//! layout follows Pharr, Jakob and Humphreys, "Physically Based Rendering", 3rd ed., 16.3).

use std::f32::consts::PI;

use chiaro_shading::brdf::{self, SurfaceParams};
use chiaro_shading::frame::Frame;
use chiaro_shading::lights::triangle_area_normal;
use glam::Vec3;

use crate::light_table::LightEntry;
use crate::scene::RenderScene;
use crate::surface::SurfaceHit;

/// What a vertex is.
#[derive(Clone, Debug)]
pub enum VertexKind {
    /// The camera's eye.
    Camera,
    /// A light path's first vertex: table entry `entry`, a point on it.
    Light {
        /// Index in the light table.
        entry: usize,
    },
    /// A surface hit; `light` is its table index when it emits.
    Surface {
        /// The shading data.
        hit: Box<SurfaceHit>,
        /// Table index of the emissive triangle hit, if it emits.
        light: Option<usize>,
    },
    /// Where a camera path escaped to the environment.
    Environment,
}

/// One vertex.
#[derive(Clone, Debug)]
pub struct Vertex {
    /// What it is.
    pub kind: VertexKind,
    /// World position (for infinitely distant vertices, a point along their direction).
    pub position: Vec3,
    /// Unit geometric normal for vertices on a surface (emitters included), zero for points
    /// and infinitely distant vertices.
    pub normal: Vec3,
    /// For an infinitely distant vertex, the unit direction from the scene toward it.
    pub direction: Vec3,
    /// The subpath's throughput up to and including this vertex.
    pub beta: Vec3,
    /// Area density with which the subpath sampled this vertex.
    pub pdf_fwd: f32,
    /// Area density with which the other subpath would sample it.
    pub pdf_rev: f32,
    /// Whether the direction leaving it was drawn from a delta lobe.
    pub delta: bool,
}

impl Vertex {
    /// A vertex of `kind` with everything else zero.
    pub fn new(kind: VertexKind, position: Vec3, normal: Vec3, beta: Vec3) -> Self {
        Self {
            kind,
            position,
            normal,
            direction: Vec3::ZERO,
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            delta: false,
        }
    }

    /// True for a vertex infinitely far away (the environment, a directional light's origin).
    pub fn is_infinite(&self, scene: &RenderScene) -> bool {
        match self.kind {
            VertexKind::Environment => true,
            VertexKind::Light { entry } => matches!(
                scene.lights.lights[entry],
                LightEntry::Environment | LightEntry::Directional { .. }
            ),
            _ => false,
        }
    }

    /// True for a light whose position or direction is a delta (point, spot, directional).
    pub fn is_delta_light(&self, scene: &RenderScene) -> bool {
        match self.kind {
            VertexKind::Light { entry } => matches!(
                scene.lights.lights[entry],
                LightEntry::Point { .. } | LightEntry::Spot { .. } | LightEntry::Directional { .. }
            ),
            _ => false,
        }
    }

    /// True when a vertex lies on a surface (its cosine enters area densities).
    pub fn on_surface(&self) -> bool {
        self.normal != Vec3::ZERO
    }

    /// The surface hit, for surface vertices.
    pub fn hit(&self) -> Option<&SurfaceHit> {
        match &self.kind {
            VertexKind::Surface { hit, .. } => Some(hit),
            _ => None,
        }
    }

    /// The light table entry this vertex emits as, if any.
    pub fn light_entry(&self, scene: &RenderScene) -> Option<usize> {
        match self.kind {
            VertexKind::Light { entry } => Some(entry),
            VertexKind::Surface { light, .. } => light,
            VertexKind::Environment => scene.lights.environment_index(),
            VertexKind::Camera => None,
        }
    }

    /// Unit direction from this vertex to `next` and the squared distance (for an infinitely
    /// distant `next`, its direction and 1).
    fn toward(&self, scene: &RenderScene, next: &Vertex) -> (Vec3, f32) {
        if next.is_infinite(scene) {
            return (next.direction, 1.0);
        }
        let d = next.position - self.position;
        let d2 = d.length_squared();
        (d / d2.sqrt(), d2)
    }

    /// Converts a solid-angle density at this vertex toward `next` into an area density at
    /// `next` (unchanged for an infinitely distant `next`).
    pub fn convert_density(&self, scene: &RenderScene, pdf: f32, next: &Vertex) -> f32 {
        if next.is_infinite(scene) {
            return pdf;
        }
        let (w, d2) = self.toward(scene, next);
        let mut pdf = pdf / d2;
        if next.on_surface() {
            pdf *= next.normal.dot(w).abs();
        }
        pdf
    }

    /// Area density at `next` of sampling it from this vertex, having arrived from `prev`
    /// (a camera: from its eye; a light: by its emission).
    pub fn pdf(&self, scene: &RenderScene, prev: Option<&Vertex>, next: &Vertex) -> f32 {
        let (w, _) = self.toward(scene, next);
        let solid_angle = match &self.kind {
            VertexKind::Camera => scene.camera.direction_pdf(w),
            VertexKind::Light { .. } | VertexKind::Environment => {
                return self.pdf_light(scene, next);
            }
            VertexKind::Surface { hit, .. } => {
                let Some(prev) = prev else {
                    return 0.0;
                };
                let (wp, _) = self.toward(scene, prev);
                bsdf_pdf(hit, wp, w)
            }
        };
        self.convert_density(scene, solid_angle, next)
    }

    /// Area density at `next` of this light emitting toward it (a light path's first segment).
    pub fn pdf_light(&self, scene: &RenderScene, next: &Vertex) -> f32 {
        let (w, d2) = if self.is_infinite(scene) {
            (-self.direction, 1.0)
        } else {
            self.toward(scene, next)
        };
        let pdf = if self.is_infinite(scene) {
            let radius = scene.lights.bounding_sphere.1;
            1.0 / (PI * radius * radius)
        } else {
            let Some(entry) = self.light_entry(scene) else {
                return 0.0;
            };
            emission_direction_pdf(&scene.lights.lights[entry], self.normal, w) / d2
        };
        if next.on_surface() {
            pdf * next.normal.dot(w).abs()
        } else {
            pdf
        }
    }

    /// Density with which a light path starts at this vertex (light pick times the position's
    /// area density; for the environment, its direction's solid-angle density), seen from
    /// `next` (the vertex the light would shine on).
    pub fn pdf_light_origin(&self, scene: &RenderScene, next: &Vertex) -> f32 {
        let Some(entry) = self.light_entry(scene) else {
            return 0.0;
        };
        let pick = scene.lights.power_pmf(entry);
        match &scene.lights.lights[entry] {
            LightEntry::Environment => {
                let (w, _) = next.toward(scene, self);
                pick * scene.environment.pdf(w)
            }
            LightEntry::Directional { .. } => 0.0,
            LightEntry::Point { .. } | LightEntry::Spot { .. } => pick,
            LightEntry::Triangle { vertices, .. } => {
                triangle_area_normal(*vertices).map_or(0.0, |(area, _)| pick / area)
            }
        }
    }
}

/// Solid-angle density of a finite light emitting along unit `w` (a triangle: cosine-weighted
/// about its normal, on one side or either; a point: uniform over the sphere; a spot: uniform
/// over its outer cone).
pub fn emission_direction_pdf(light: &LightEntry, normal: Vec3, w: Vec3) -> f32 {
    match *light {
        LightEntry::Triangle { two_sided, .. } => {
            let cos = normal.dot(w);
            if two_sided {
                cos.abs() / (2.0 * PI)
            } else {
                cos.max(0.0) / PI
            }
        }
        LightEntry::Point { .. } => 1.0 / (4.0 * PI),
        LightEntry::Spot { axis, outer, .. } => {
            if axis.dot(w) >= outer.cos() {
                1.0 / (2.0 * PI * (1.0 - outer.cos()))
            } else {
                0.0
            }
        }
        LightEntry::Directional { .. } | LightEntry::Environment => 0.0,
    }
}

/// The frame, parameters and geometric normal of `hit` seen from the side `wo` lies on: the
/// hit's own when `wo` is on the side the ray arrived from, else turned over (the relative
/// IOR inverted), so that the BSDF can be asked about light crossing the surface either way.
fn oriented(hit: &SurfaceHit, wo: Vec3) -> (Frame, SurfaceParams, Vec3) {
    if wo.dot(hit.geometric_normal) >= 0.0 {
        return (hit.frame, hit.params, hit.geometric_normal);
    }
    let mut params = hit.params;
    if params.eta > 0.0 {
        params.eta = 1.0 / params.eta;
    }
    (
        Frame::from_normal(-hit.frame.normal),
        params,
        -hit.geometric_normal,
    )
}

/// Whether local directions `wo`, `wi` keep the shading-normal rule (the integrator's): both
/// on the sides their local z says, measured against the geometric normal `g`.
fn consistent(wo: Vec3, wi: Vec3, lo: Vec3, li: Vec3, g: Vec3) -> bool {
    lo.z > 0.0 && wo.dot(g) > 0.0 && (li.z > 0.0) == (wi.dot(g) > 0.0) && li.z != 0.0
}

/// The BSDF f(wo, wi) at `hit` for unit world directions (no cosine), either side.
pub fn bsdf_eval(hit: &SurfaceHit, wo: Vec3, wi: Vec3) -> Vec3 {
    if !hit.shades {
        return Vec3::ZERO;
    }
    let (frame, params, g) = oriented(hit, wo);
    let (lo, li) = (frame.to_local(wo), frame.to_local(wi));
    if !consistent(wo, wi, lo, li, g) {
        return Vec3::ZERO;
    }
    brdf::eval(&params, lo, li)
}

/// The solid-angle pdf of sampling `wi` from `wo` at `hit`, either side.
pub fn bsdf_pdf(hit: &SurfaceHit, wo: Vec3, wi: Vec3) -> f32 {
    if !hit.shades {
        return 0.0;
    }
    let (frame, params, g) = oriented(hit, wo);
    let (lo, li) = (frame.to_local(wo), frame.to_local(wi));
    if !consistent(wo, wi, lo, li, g) {
        return 0.0;
    }
    brdf::pdf(&params, lo, li)
}

/// The factor by which a light subpath's throughput differs from the BSDF's radiance form at a
/// vertex it crosses from `wo` (toward the light) to `wi`: importance is not compressed by
/// refraction, so the radiance form's 1 / eta^2 is undone where `wi` crosses into a volume
/// (Veach 1997, section 5.2), and the shading normal's adjoint correction |wo.ns| |wi.ng| /
/// (|wo.ng| |wi.ns|) is applied (Veach 1997, section 5.3).
pub fn importance_factor(hit: &SurfaceHit, wo: Vec3, wi: Vec3) -> f32 {
    let ns = hit.frame.normal;
    let ng = hit.geometric_normal;
    let denominator = wo.dot(ng).abs() * wi.dot(ns).abs();
    if denominator <= 0.0 {
        return 0.0;
    }
    let mut factor = wo.dot(ns).abs() * wi.dot(ng).abs() / denominator;
    let crosses = (wo.dot(ng) > 0.0) != (wi.dot(ng) > 0.0);
    if crosses && hit.params.eta > 0.0 {
        let eta = if wo.dot(ng) >= 0.0 {
            hit.params.eta
        } else {
            1.0 / hit.params.eta
        };
        factor *= eta * eta;
    }
    factor
}
