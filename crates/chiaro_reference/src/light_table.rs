//! Every light of the scene in one table: punctual lights (point, spot, directional), each
//! emissive triangle of each instance, and the environment. The path tracer picks one light per
//! next-event estimate and needs, for MIS, the probability with which a light it hits by BRDF
//! sampling would have been picked from the point it left.
//!
//! Two ways to pick ([`LightSampling`]): in proportion to power alone, or through a light tree
//! over the lights of finite extent (triangles, points, spots), which weighs each by its
//! importance to the shading point (`chiaro_shading::light_tree`); infinitely distant lights
//! (directional, environment) are then chosen among themselves by power, and together as often
//! as each of them and the tree were one light: a share of n / (n + 1) for n of them, as
//! pbrt-v4's BVH light sampler does (Pharr, Jakob and Humphreys, "Physically Based Rendering",
//! 4th ed., section 12.6.3). Not by their part of the total power: a distant light's power grows
//! with the scene's bounding radius squared, so in a scene that spreads far (hard-cases' copy
//! 1e5 units out) the sun took all but one pick in 1e8, and a 1 cm emitter of radiance 1e5 was
//! found by BRDF rays alone: heavy-tailed noise that 1024 samples a pixel did not converge.
//! Up to [`FINITE_LIGHTS_BY_POWER_MAX`] lights of finite extent get no tree: they are picked
//! among themselves by power, as the GPU frame picks up to as many emissive triangles.

use std::collections::HashMap;
use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use chiaro_bvh::SceneBvh;
use chiaro_scene::{Aabb, GlobalTransform, Light, LightKind, Materials, Meshes};
use chiaro_shading::color::luminance;
use chiaro_shading::distribution::Distribution1D;
pub use chiaro_shading::light_tree::LightSampling;
use chiaro_shading::light_tree::{LightBounds, LightTree};
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

/// Most lights of finite extent picked among themselves by power under tree sampling, without a
/// tree (the GPU frame's `AREA_LIGHTS_BY_POWER_MAX`): on the Cornell box's two emissive
/// triangles the tree's walk was about a tenth of the reference's time and lowered no noise.
pub const FINITE_LIGHTS_BY_POWER_MAX: usize = 8;

/// How a light of finite extent is picked under tree sampling.
#[derive(Debug)]
enum FinitePicker {
    /// Through a light tree, by importance to the shading point.
    Tree(LightTree),
    /// By power alone (few lights).
    Power(Distribution1D),
}

impl FinitePicker {
    fn new(bounds: &[LightBounds]) -> Option<Self> {
        if bounds.len() > FINITE_LIGHTS_BY_POWER_MAX {
            LightTree::build(bounds).map(Self::Tree)
        } else {
            let powers: Vec<f32> = bounds.iter().map(|b| b.power).collect();
            Distribution1D::new(&powers).map(Self::Power)
        }
    }

    fn pick(&self, p: Vec3, n: Vec3, u: f32) -> (usize, f32) {
        match self {
            Self::Tree(tree) => tree.pick(p, n, u),
            Self::Power(d) => d.sample(u),
        }
    }

    fn pmf(&self, i: usize, p: Vec3, n: Vec3) -> f32 {
        match self {
            Self::Tree(tree) => tree.pmf(i, p, n),
            Self::Power(d) => d.pmf(i),
        }
    }
}

/// How a light is picked, as built.
#[derive(Debug)]
enum Selection {
    /// No light at all.
    None,
    /// One power-proportional distribution over every light.
    Power(Distribution1D),
    /// A tree over the finite lights (`finite[i]` is the table index of the tree's light `i`;
    /// a power distribution where they are few) and a power distribution over the infinite
    /// ones, picked with probability `infinite_share`.
    Tree {
        tree: Option<FinitePicker>,
        finite: Vec<usize>,
        infinite: Option<(Distribution1D, Vec<usize>)>,
        infinite_share: f32,
    },
}

/// All lights and how to pick one.
#[derive(Debug)]
pub struct LightTable {
    /// The lights.
    pub lights: Vec<LightEntry>,
    selection: Selection,
    /// Emissive triangle (instance, triangle) -> table index.
    triangles: HashMap<(u32, u32), usize>,
    /// Table index -> index in the tree's light list (finite lights under tree sampling).
    tree_index: HashMap<usize, usize>,
    environment: Option<usize>,
    /// Every light in proportion to its power, whatever the selection: what a light path
    /// starts from (it has no shading point to weigh lights by).
    by_power: Option<Distribution1D>,
    /// The scene's bounding sphere (centre, radius): where light from infinitely far away
    /// enters it.
    pub bounding_sphere: (Vec3, f32),
}

fn triangle_area(v: &[Vec3; 3]) -> f32 {
    0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length()
}

impl LightTable {
    /// Collects the lights of `world`; `environment_mean` is the environment's mean radiance
    /// (zero leaves it out of light sampling; `Environment::light_sampling_radiance`).
    pub fn gather(
        world: &mut World,
        bvh: &SceneBvh,
        environment_mean: Vec3,
        sampling: LightSampling,
    ) -> Self {
        let meshes = world.resource::<Meshes>();
        let materials = world.resource::<Materials>();
        let mut lights = Vec::new();
        let mut powers = Vec::new();
        // Bounds for the light tree; `None` for infinitely distant lights.
        let mut extents: Vec<Option<LightBounds>> = Vec::new();
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
            let sides = if material.shades_both_sides() {
                2.0
            } else {
                1.0
            };
            for triangle in 0..mesh.triangle_count() as u32 {
                let vertices = world_triangle(mesh, triangle, &record.world);
                triangles.insert((index as u32, triangle), lights.len());
                let power = PI * sides * radiance * triangle_area(&vertices);
                powers.push(power);
                extents.push(Some(LightBounds::triangle(
                    vertices,
                    power,
                    material.shades_both_sides(),
                )));
                lights.push(LightEntry::Triangle {
                    instance: index as u32,
                    triangle,
                    vertices,
                    two_sided: material.shades_both_sides(),
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
            let (entry, power, extent) = match light.kind {
                LightKind::Point => {
                    let power = 4.0 * PI * luminance(intensity);
                    (
                        LightEntry::Point {
                            position,
                            intensity,
                            range: light.range,
                        },
                        power,
                        Some(LightBounds::point(position, power)),
                    )
                }
                LightKind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => {
                    let power = 2.0
                        * PI
                        * (1.0 - (0.5 * (inner_cone_angle + outer_cone_angle)).cos())
                        * luminance(intensity);
                    (
                        LightEntry::Spot {
                            position,
                            axis,
                            intensity,
                            inner: inner_cone_angle,
                            outer: outer_cone_angle,
                            range: light.range,
                        },
                        power,
                        Some(LightBounds::spot(position, axis, outer_cone_angle, power)),
                    )
                }
                LightKind::Directional => (
                    LightEntry::Directional {
                        travel: axis,
                        illuminance: intensity,
                    },
                    PI * radius * radius * luminance(intensity),
                    None,
                ),
            };
            if power > 0.0 && power.is_finite() {
                lights.push(entry);
                powers.push(power);
                extents.push(extent);
            }
        }
        let mut environment = None;
        let env_power = 4.0 * PI * PI * radius * radius * luminance(environment_mean);
        if env_power > 0.0 && env_power.is_finite() {
            environment = Some(lights.len());
            lights.push(LightEntry::Environment);
            powers.push(env_power);
            extents.push(None);
        }
        let by_power = Distribution1D::new(&powers);
        let centre = if bounds.is_empty() {
            Vec3::ZERO
        } else {
            bounds.center()
        };
        let mut tree_index = HashMap::new();
        let selection = match sampling {
            LightSampling::Power => {
                Distribution1D::new(&powers).map_or(Selection::None, Selection::Power)
            }
            LightSampling::Tree => {
                let (mut finite, mut bounds, mut infinite, mut infinite_powers) =
                    (Vec::new(), Vec::new(), Vec::new(), Vec::new());
                for (i, extent) in extents.iter().enumerate() {
                    match extent {
                        Some(b) => {
                            tree_index.insert(i, finite.len());
                            finite.push(i);
                            bounds.push(*b);
                        }
                        None => {
                            infinite.push(i);
                            infinite_powers.push(powers[i]);
                        }
                    }
                }
                let infinite_count = infinite.len() as f32;
                let infinite = Distribution1D::new(&infinite_powers).map(|d| (d, infinite));
                let tree = FinitePicker::new(&bounds);
                match (&tree, &infinite) {
                    (None, None) => Selection::None,
                    _ => Selection::Tree {
                        infinite_share: match (&tree, &infinite) {
                            (None, _) => 1.0,
                            (_, None) => 0.0,
                            _ => infinite_count / (infinite_count + 1.0),
                        },
                        tree,
                        finite,
                        infinite,
                    },
                }
            }
        };
        Self {
            selection,
            lights,
            triangles,
            tree_index,
            environment,
            by_power,
            bounding_sphere: (centre, radius),
        }
    }

    /// Picks a light in proportion to its power alone: its index and the probability.
    pub fn pick_by_power(&self, u: f32) -> Option<(usize, f32)> {
        self.by_power.as_ref().map(|d| d.sample(u))
    }

    /// Probability that [`LightTable::pick_by_power`] returns entry `index`.
    pub fn power_pmf(&self, index: usize) -> f32 {
        self.by_power.as_ref().map_or(0.0, |d| d.pmf(index))
    }

    /// The table index of emissive triangle `triangle` of instance `instance`.
    pub fn triangle_index(&self, instance: u32, triangle: u32) -> Option<usize> {
        self.triangles.get(&(instance, triangle)).copied()
    }

    /// The table index of the environment, when it is light-sampled.
    pub fn environment_index(&self) -> Option<usize> {
        self.environment
    }

    /// Picks a light for shading point `p` with normal `n` (zero: no surface to weigh by): its
    /// index and the probability it was picked.
    pub fn pick(&self, u: f32, p: Vec3, n: Vec3) -> Option<(usize, f32)> {
        match &self.selection {
            Selection::None => None,
            Selection::Power(d) => Some(d.sample(u)),
            Selection::Tree {
                tree,
                finite,
                infinite,
                infinite_share,
            } => {
                if u < *infinite_share {
                    let (d, indices) = infinite.as_ref()?;
                    let u = (u / infinite_share).min(1.0 - f32::EPSILON / 2.0);
                    let (i, pmf) = d.sample(u);
                    Some((indices[i], infinite_share * pmf))
                } else {
                    let u = ((u - infinite_share) / (1.0 - infinite_share))
                        .clamp(0.0, 1.0 - f32::EPSILON / 2.0);
                    let (i, pmf) = tree.as_ref()?.pick(p, n, u);
                    Some((finite[i], (1.0 - infinite_share) * pmf))
                }
            }
        }
    }

    /// Probability that [`LightTable::pick`] at `p`, `n` returns table entry `index`.
    fn pmf(&self, index: usize, p: Vec3, n: Vec3) -> f32 {
        match &self.selection {
            Selection::None => 0.0,
            Selection::Power(d) => d.pmf(index),
            Selection::Tree {
                tree,
                infinite,
                infinite_share,
                ..
            } => match (self.tree_index.get(&index), tree, infinite) {
                (Some(&i), Some(tree), _) => (1.0 - infinite_share) * tree.pmf(i, p, n),
                (None, _, Some((d, indices))) => indices
                    .iter()
                    .position(|&j| j == index)
                    .map_or(0.0, |k| infinite_share * d.pmf(k)),
                _ => 0.0,
            },
        }
    }

    /// Probability of picking the emissive triangle `triangle` of instance `instance` from
    /// shading point `p` with normal `n`.
    pub fn triangle_pmf(&self, instance: u32, triangle: u32, p: Vec3, n: Vec3) -> f32 {
        self.triangles
            .get(&(instance, triangle))
            .map_or(0.0, |&i| self.pmf(i, p, n))
    }

    /// Probability of picking the environment (the same from every point).
    pub fn environment_pmf(&self) -> f32 {
        self.environment
            .map_or(0.0, |i| self.pmf(i, Vec3::ZERO, Vec3::ZERO))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-sided unit triangle at height `x` along the x axis, of `power`.
    fn light(x: f32, power: f32) -> LightBounds {
        let v = [
            Vec3::new(x, 0.0, 0.0),
            Vec3::new(x + 1.0, 0.0, 0.0),
            Vec3::new(x, 1.0, 0.0),
        ];
        LightBounds::triangle(v, power, false)
    }

    #[test]
    fn few_lights_are_picked_by_power_and_many_through_a_tree() {
        let few: Vec<LightBounds> = (0..FINITE_LIGHTS_BY_POWER_MAX)
            .map(|i| light(10.0 * i as f32, 1.0 + i as f32))
            .collect();
        let picker = FinitePicker::new(&few).unwrap();
        assert!(matches!(picker, FinitePicker::Power(_)));
        let total: f32 = few.iter().map(|b| b.power).sum();
        // The same probabilities wherever the shading point is.
        for p in [Vec3::new(0.0, 0.0, 1.0), Vec3::new(70.0, 0.0, 1.0)] {
            for (i, b) in few.iter().enumerate() {
                let pmf = picker.pmf(i, p, Vec3::Z);
                assert!(
                    (pmf - b.power / total).abs() < 1e-6,
                    "light {i} at {p}: {pmf}"
                );
            }
        }
        let mut many = few.clone();
        many.push(light(100.0, 1.0));
        let picker = FinitePicker::new(&many).unwrap();
        assert!(matches!(picker, FinitePicker::Tree(_)));
        // The tree favours the light beside the point over the far, brighter one.
        let p = Vec3::new(0.5, 0.2, 1.0);
        assert!(picker.pmf(0, p, Vec3::ZERO) > picker.pmf(7, p, Vec3::ZERO));
    }
}
