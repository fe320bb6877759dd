//! Many lights over a floor: `quads` small emissive quads (one shared mesh) hanging at
//! various heights and `lights` punctual lights (two point lights for every spot light), with a
//! few spheres and boxes to catch shadows, placed by a fixed-seed generator. No environment: the
//! lights are the only illumination. `builtin:many-lights?quads=256&lights=256`.

use glam::Vec3;

use crate::components::{Camera, Light, LightKind, Projection};
use crate::error::SceneError;
use crate::material::Material;
use crate::scene_builder::{Node, SceneBuilder};
use crate::transform::Transform;

use super::shapes::{cuboid, floor, icosphere, quad};
use super::{Layout, Params};

/// Default number of emissive quads and of punctual lights.
pub const DEFAULT_LIGHTS: usize = 256;
/// Most of either accepted.
pub const MAX_LIGHTS: usize = 100_000;
/// Half the side of the lit square.
const HALF: f32 = 10.0;

pub(super) fn build(b: &mut SceneBuilder, params: &mut Params) -> Result<(), SceneError> {
    let quads = params.count("quads", DEFAULT_LIGHTS, MAX_LIGHTS)?;
    let lights = params.count("lights", DEFAULT_LIGHTS, MAX_LIGHTS)?;
    let mut layout = Layout::new(0x5EED);
    let grey = b.add_material(Material::diffuse("floor", Vec3::splat(0.6), 0.7));
    if let Some(mesh) = b.add_mesh("mesh \"floor\"", "floor", floor(2.0 * HALF + 4.0))? {
        b.add_instance("floor", mesh, grey, Transform::IDENTITY);
    }
    let sphere = b.add_mesh("mesh \"sphere\"", "sphere", icosphere(2, false))?;
    let block = b.add_mesh(
        "mesh \"block\"",
        "block",
        cuboid(Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 1.0, 0.5)),
    )?;
    let shiny = b.add_material(Material::diffuse("shiny", Vec3::splat(0.8), 0.25));
    for k in 0..16 {
        let at = Vec3::new(layout.range(-HALF, HALF), 0.0, layout.range(-HALF, HALF));
        let (mesh, material, t) = if k % 2 == 0 {
            (
                sphere,
                shiny,
                Transform::from_translation(at + Vec3::Y * 0.6).with_scale(Vec3::splat(0.6)),
            )
        } else {
            (
                block,
                grey,
                Transform::from_translation(at).with_scale(Vec3::new(
                    0.8,
                    layout.range(0.5, 2.0),
                    0.8,
                )),
            )
        };
        if let Some(mesh) = mesh {
            b.add_instance(&format!("prop {k}"), mesh, material, t);
        }
    }

    let palette: Vec<Vec3> = (0..8)
        .map(|k| {
            let hue = k as f32 / 8.0 * std::f32::consts::TAU;
            Vec3::new(hue.cos(), (hue + 2.1).cos(), (hue + 4.2).cos()) * 0.5 + 0.5
        })
        .collect();
    let emitters: Vec<_> = palette
        .iter()
        .enumerate()
        .map(|(k, c)| b.add_material(Material::emitter(&format!("emitter {k}"), *c * 20.0)))
        .collect();
    let h = 0.1;
    let tile = quad(
        [
            Vec3::new(-h, 0.0, -h),
            Vec3::new(h, 0.0, -h),
            Vec3::new(h, 0.0, h),
            Vec3::new(-h, 0.0, h),
        ],
        Vec3::NEG_Y,
    );
    if let Some(tile) = b.add_mesh("mesh \"emitter tile\"", "emitter tile", tile)? {
        for k in 0..quads {
            let at = Vec3::new(
                layout.range(-HALF, HALF),
                layout.range(1.5, 4.0),
                layout.range(-HALF, HALF),
            );
            b.add_instance(
                &format!("emitter {k}"),
                tile,
                emitters[k % emitters.len()],
                Transform::from_translation(at),
            );
        }
    }
    for k in 0..lights {
        let at = Vec3::new(
            layout.range(-HALF, HALF),
            layout.range(0.8, 3.0),
            layout.range(-HALF, HALF),
        );
        let kind = if k % 3 == 2 {
            LightKind::Spot {
                inner_cone_angle: 0.3,
                outer_cone_angle: 0.6,
            }
        } else {
            LightKind::Point
        };
        b.add_node(Node {
            name: Some(format!("light {k}")),
            transform: Transform::looking_at(at, at + Vec3::new(0.1, -1.0, 0.0), Vec3::Y),
            light: Some(Light {
                kind,
                color: palette[(k + 3) % palette.len()],
                intensity: 1.5,
                range: None,
            }),
            ..Node::default()
        });
    }
    let eye = Vec3::new(0.0, 12.0, 16.0);
    b.add_node(Node {
        name: Some("camera".into()),
        transform: Transform::looking_at(eye, Vec3::ZERO, Vec3::Y),
        camera: Some(Camera {
            projection: Projection::Perspective {
                yfov: 55f32.to_radians(),
                aspect_ratio: None,
                znear: 0.05,
                zfar: None,
            },
        }),
        ..Node::default()
    });
    Ok(())
}
