//! Every light of the scene in one table with a power-proportional selection distribution:
//! punctual lights (point, spot, directional), each emissive triangle of each instance, and the
//! environment. The path tracer picks one light per next-event estimate and needs, for MIS, the
//! probability with which a light it hits by BRDF sampling would have been picked.

use std::collections::HashMap;
use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use chiaro_bvh::SceneBvh;
use chiaro_scene::{Aabb, GlobalTransform, Light, LightKind, Materials, Meshes};
use chiaro_shading::color::luminance;
use chiaro_shading::distribution::Distribution1D;
use glam::Vec3;

use crate::surface::world_triangle;

/// One light.
#[derive(Clone, Debug)]
pub enum LightEntry {
    /// A point light: position, intensity (candela x colour), range.
    Point {
        position: Vec3,
        intensity: Vec3,
        range: Option<f32>,
    },
    /// A spot light: position, unit axis it points along, intensity, cone angles, range.
    Spot {
        position: Vec3,
        axis: Vec3,
        intensity: Vec3,
        inner: f32,
        outer: f32,
        range: Option<f32>,
    },
    /// A directional light: unit direction the light travels, illuminance (lux x colour).
    Directional { travel: Vec3, illuminance: Vec3 },
    /// One emissive triangle of one instance, world-space vertices (front face counter-clockwise).
    Triangle {
        instance: u32,
        triangle: u32,
        vertices: [Vec3; 3],
        two_sided: bool,
    },
    /// The environment.
    Environment,
}

/// All lights and how to pick one.
#[derive(Debug, Default)]
pub struct LightTable {
    /// The lights.
    pub lights: Vec<LightEntry>,
    selection: Option<Distribution1D>,
    triangles: HashMap<(u32, u32), usize>,
    environment: Option<usize>,
}

fn triangle_area(v: &[Vec3; 3]) -> f32 {
    0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length()
}

impl LightTable {
    /// Collects the lights of `world`; `environment_power_radiance` is the environment's mean
    /// radiance (zero leaves it out of light sampling).
    pub fn gather(world: &mut World, bvh: &SceneBvh, environment_mean: Vec3) -> Self {
        let meshes = world.resource::<Meshes>();
        let materials = world.resource::<Materials>();
        let mut lights = Vec::new();
        let mut powers = Vec::new();
        let mut triangles = HashMap::new();
        let mut bounds = Aabb::EMPTY;
        for (index, record) in bvh.instances().iter().enumerate() {
            let (Some(mesh), Some(material)) =
                (meshes.get(record.mesh), materials.get(record.material))
            else {
                continue;
            };
            bounds = bounds.union(mesh.bounds().transformed(&record.world));
            let radiance = luminance(material.emitted_radiance());
            if radiance <= 0.0 {
                continue;
            }
            let sides = if material.double_sided { 2.0 } else { 1.0 };
            for triangle in 0..mesh.triangle_count() as u32 {
                let vertices = world_triangle(mesh, triangle, &record.world);
                triangles.insert((index as u32, triangle), lights.len());
                powers.push(PI * sides * radiance * triangle_area(&vertices));
                lights.push(LightEntry::Triangle {
                    instance: index as u32,
                    triangle,
                    vertices,
                    two_sided: material.double_sided,
                });
            }
        }
        let radius = if bounds.is_empty() {
            1.0
        } else {
            (0.5 * bounds.size().length()).max(1e-3)
        };
        let mut query = world.query::<(&Light, &GlobalTransform)>();
        for (light, global) in query.iter(world) {
            let intensity = light.radiant_intensity();
            let axis = global
                .transform_vector(Vec3::NEG_Z)
                .normalize_or(Vec3::NEG_Z);
            let position = global.translation();
            let (entry, power) = match light.kind {
                LightKind::Point => (
                    LightEntry::Point {
                        position,
                        intensity,
                        range: light.range,
                    },
                    4.0 * PI * luminance(intensity),
                ),
                LightKind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => (
                    LightEntry::Spot {
                        position,
                        axis,
                        intensity,
                        inner: inner_cone_angle,
                        outer: outer_cone_angle,
                        range: light.range,
                    },
                    2.0 * PI
                        * (1.0 - (0.5 * (inner_cone_angle + outer_cone_angle)).cos())
                        * luminance(intensity),
                ),
                LightKind::Directional => (
                    LightEntry::Directional {
                        travel: axis,
                        illuminance: intensity,
                    },
                    PI * radius * radius * luminance(intensity),
                ),
            };
            if power > 0.0 && power.is_finite() {
                lights.push(entry);
                powers.push(power);
            }
        }
        let mut environment = None;
        let env_power = 4.0 * PI * PI * radius * radius * luminance(environment_mean);
        if env_power > 0.0 && env_power.is_finite() {
            environment = Some(lights.len());
            lights.push(LightEntry::Environment);
            powers.push(env_power);
        }
        Self {
            selection: Distribution1D::new(&powers),
            lights,
            triangles,
            environment,
        }
    }

    /// Picks a light: its index and the probability it was picked.
    pub fn pick(&self, u: f32) -> Option<(usize, f32)> {
        self.selection.as_ref().map(|d| d.sample(u))
    }

    /// Probability of picking the emissive triangle `triangle` of instance `instance`.
    pub fn triangle_pmf(&self, instance: u32, triangle: u32) -> f32 {
        match (&self.selection, self.triangles.get(&(instance, triangle))) {
            (Some(d), Some(&i)) => d.pmf(i),
            _ => 0.0,
        }
    }

    /// Probability of picking the environment.
    pub fn environment_pmf(&self) -> f32 {
        match (&self.selection, self.environment) {
            (Some(d), Some(i)) => d.pmf(i),
            _ => 0.0,
        }
    }
}
